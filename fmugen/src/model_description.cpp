#include "model_description.hpp"

#include <cstdio>
#include <sstream>

namespace fmugen {

namespace {

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      case '\'': o += "&apos;"; break;
      default: o += c;
    }
  }
  return o;
}

// SI base-unit exponents of the units the port table uses (FMI 2.0 2.2.2).
struct UnitDef {
  const char* name;
  int kg, m, s, K;
};
constexpr UnitDef kUnits[] = {
    {"Pa", 1, -1, -2, 0}, {"m3/s", 0, 3, -1, 0}, {"Pa.s/m3", 1, -4, -1, 0}, {"m", 0, 1, 0, 0},
    {"m/s", 0, 1, -1, 0}, {"N", 1, 1, -2, 0},    {"s", 0, 0, 1, 0},         {"K", 0, 0, 0, 1},
    {"W", 1, 2, -3, 0},
};

const char* causality_name(config::FmuCausality c) {
  switch (c) {
    case config::FmuCausality::Input: return "input";
    case config::FmuCausality::Output: return "output";
    case config::FmuCausality::Parameter: return "parameter";
  }
  return "local";
}

}  // namespace

std::string model_description_xml(const config::PortTable& t, const std::string& description) {
  const auto vars = config::fmu_variables(t);
  std::ostringstream x;
  char num[64];
  std::snprintf(num, sizeof num, "%.17g", t.dt);
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"" << xml_escape(t.model_name)
    << "\" guid=\"" << config::fmu_guid(t) << "\"\n  description=\"" << xml_escape(description)
    << "\"\n  generationTool=\"pcs fmugen\" variableNamingConvention=\"structured\" "
       "numberOfEventIndicators=\"0\">\n";
  // needsExecutionTool: the FMU couples to a running fe_server.
  x << "  <CoSimulation modelIdentifier=\"" << xml_escape(t.model_name)
    << "\" needsExecutionTool=\"true\" canHandleVariableCommunicationStepSize=\"false\"\n"
       "    canInterpolateInputs=\"false\" maxOutputDerivativeOrder=\"0\" "
       "canRunAsynchronuously=\"false\"\n"
       "    canBeInstantiatedOnlyOncePerProcess=\"false\" "
       "canNotUseMemoryManagementFunctions=\"true\"\n"
       "    canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" "
       "providesDirectionalDerivative=\"false\"/>\n";
  x << "  <UnitDefinitions>\n";
  for (const auto& u : kUnits) {
    x << "    <Unit name=\"" << u.name << "\"><BaseUnit";
    if (u.kg) x << " kg=\"" << u.kg << "\"";
    if (u.m) x << " m=\"" << u.m << "\"";
    if (u.s) x << " s=\"" << u.s << "\"";
    if (u.K) x << " K=\"" << u.K << "\"";
    x << "/></Unit>\n";
  }
  x << "  </UnitDefinitions>\n";
  x << "  <LogCategories>\n"
       "    <Category name=\"logStatusError\" description=\"errors\"/>\n"
       "    <Category name=\"logStatusWarning\" description=\"warnings\"/>\n"
       "    <Category name=\"logStatusFatal\" description=\"fatal errors\"/>\n"
       "    <Category name=\"logCoupling\" description=\"connection and handshake\"/>\n"
       "  </LogCategories>\n";
  // A stop time of 1000 coupling steps: a short run for an importer's
  // defaults (FMPy's simulate_fmu without arguments), to be set by the user.
  char stop[64];
  std::snprintf(stop, sizeof stop, "%.17g", 1000.0 * t.dt);
  x << "  <DefaultExperiment startTime=\"0\" stopTime=\"" << stop << "\" stepSize=\"" << num << "\"/>\n";
  x << "  <ModelVariables>\n";
  for (size_t i = 0; i < vars.size(); ++i) {
    const auto& v = vars[i];
    bool parameter = v.causality == config::FmuCausality::Parameter;
    x << "    <!-- index " << i + 1 << " -->\n"
      << "    <ScalarVariable name=\"" << xml_escape(v.name) << "\" valueReference=\""
      << v.value_reference << "\" causality=\"" << causality_name(v.causality)
      << "\" variability=\"" << (parameter ? "fixed" : "continuous") << "\""
      << (v.initial.empty() ? "" : " initial=\"" + v.initial + "\"") << "\n      description=\""
      << xml_escape(v.description) << "\">\n      ";
    switch (v.type) {
      case config::FmuType::Real:
        x << "<Real";
        if (!v.unit.empty() && v.unit != "1") x << " unit=\"" << xml_escape(v.unit) << "\"";
        break;
      case config::FmuType::Integer: x << "<Integer"; break;
      case config::FmuType::String: x << "<String"; break;
    }
    // Outputs have a start only where it holds before the first step (initial="exact").
    bool has_start = v.causality != config::FmuCausality::Output || !v.initial.empty();
    if (has_start) x << " start=\"" << xml_escape(v.start) << "\"";
    x << "/>\n    </ScalarVariable>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].causality == config::FmuCausality::Output)
      x << "      <Unknown index=\"" << i + 1 << "\"/>\n";
  x << "    </Outputs>\n";
  // Outputs are "calculated" (the default for continuous outputs), so they
  // are initial unknowns; an "exact" one (a start value) is not. The schema
  // wants no InitialUnknowns element rather than an empty one.
  std::ostringstream unknowns;
  for (size_t i = 0; i < vars.size(); ++i)
    if (vars[i].causality == config::FmuCausality::Output && vars[i].initial.empty())
      unknowns << "      <Unknown index=\"" << i + 1 << "\"/>\n";
  if (!unknowns.str().empty()) x << "    <InitialUnknowns>\n" << unknowns.str() << "    </InitialUnknowns>\n";
  x << "  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

std::string external_dependencies_text(const config::PortTable& t) {
  std::ostringstream s;
  s << "This FMU is a co-simulation front end: the structural model runs in a separate\n"
       "process, fe_server, which must be running before fmi2ExitInitializationMode.\n\n"
       "  fe_server --model DECK.k --ports ports.cfg --listen HOST:PORT [--token-file FILE]\n\n"
       "The FMU connects to the address given by its parameters server.host and\n"
       "server.port (environment PCS_SERVER_HOST / PCS_SERVER_PORT as fallback, then\n"
       "the 'server' line of resources/ports.cfg";
  if (!t.server.empty()) s << ": " << t.server;
  s << ").\nA session token is passed in server.token (or $PCS_TOKEN, or a file named by $PCS_TOKEN_FILE).\n"
       "Both sides must use the same port table (resources/ports.cfg); the handshake\n"
       "refuses a mismatch. Coupling: "
    << config::to_string(t.mode) << " mode, time step " << t.dt << " s, " << t.subcycles
    << " FE step(s) per coupling step.\n";
  if (t.hopsan)
    s << "\nHopsan: load this FMU in an FMIWrapperQ component and set its parameter\n"
         "portspecs to\n\n  "
      << config::hopsan_portspecs(t)
      << "\n\nEach hydraulic port is Hopsan's NodeHydraulic: q (flow out of the FMU into the\n"
         "node), p = c + Zc*q, T (the oil's temperature, constant: the model is isothermal),\n"
         "c and Zc (Hopsan's wave variable and impedance, in), Qdot (heat flow, 0).\n";
  return s.str();
}

}  // namespace fmugen
