#include "model_description.hpp"

#include "config/version.hpp"

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

// UnitDefinitions, LogCategories and DefaultExperiment: the same in FMI 2.0 and 3.0.
void units_categories_experiment(std::ostringstream& x, const config::PortTable& t) {
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
  x << "  <DefaultExperiment startTime=\"0\" stopTime=\"" << config::shortest(1000.0 * t.dt) << "\" stepSize=\""
    << config::shortest(t.dt) << "\"/>\n";
}

}  // namespace

std::string default_description(const config::PortTable& t) {
  std::ostringstream d;
  d << t.model_name << ": fe_server co-simulation";
  for (const auto& p : t.ports) d << ", " << config::to_lower(config::to_string(p.type)) << " port " << p.label;
  d << " (" << config::to_string(t.mode) << " coupling, " << config::shortest(t.dt) << " s)";
  return d.str();
}

static std::string description_of(const config::PortTable& t, const std::string& description) {
  if (!description.empty()) return description;
  if (!t.description.empty()) return t.description;
  return default_description(t);
}

std::string model_description_xml(const config::PortTable& t, const std::string& description,
                                  const Generation& generation) {
  const auto vars = config::fmu_variables(t);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"" << xml_escape(t.model_name)
    << "\" guid=\"" << config::fmu_guid(t) << "\"\n  description=\"" << xml_escape(description_of(t, description))
    << "\"\n  version=\"" << xml_escape(config::project_version()) << "\" generationTool=\""
    << xml_escape(generation.tool) << "\"";
  if (!generation.date.empty()) x << " generationDateAndTime=\"" << xml_escape(generation.date) << "\"";
  x << "\n  variableNamingConvention=\"structured\" numberOfEventIndicators=\"0\">\n";
  // needsExecutionTool: the FMU couples to a running fe_server.
  x << "  <CoSimulation modelIdentifier=\"" << xml_escape(t.model_name)
    << "\" needsExecutionTool=\"true\" canHandleVariableCommunicationStepSize=\"false\"\n"
       "    canInterpolateInputs=\"false\" maxOutputDerivativeOrder=\"0\" "
       "canRunAsynchronuously=\"false\"\n"
       "    canBeInstantiatedOnlyOncePerProcess=\"false\" "
       "canNotUseMemoryManagementFunctions=\"true\"\n"
       "    canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" "
       "providesDirectionalDerivative=\"false\"/>\n";
  units_categories_experiment(x, t);
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

namespace fmugen {

std::string documentation_html(const config::PortTable& t, const std::string& description,
                               const Generation& generation) {
  const auto vars = config::fmu_variables(t);
  std::ostringstream h;
  const std::string name = xml_escape(t.model_name);
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head><meta charset=\"utf-8\"><title>" << name
    << " (FMI 2.0 co-simulation FMU)</title>\n"
       "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.4}"
       "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:.2em .5em;text-align:left}"
       "code,pre{background:#f4f4f4}</style></head>\n<body>\n";
  h << "<h1>" << name << "</h1>\n<p>" << xml_escape(description_of(t, description)) << "</p>\n";
  h << "<p>FMI 2.0 co-simulation, GUID <code>" << config::fmu_guid(t) << "</code>, made by "
    << xml_escape(generation.tool);
  if (!generation.date.empty()) h << " on " << xml_escape(generation.date);
  h << ".</p>\n";
  h << "<h2>Coupling</h2>\n<ul>\n<li>" << xml_escape(config::to_string(t.mode))
    << " mode, coupling step " << config::shortest(t.dt) << " s, " << t.subcycles
    << " FE step(s) per coupling step.</li>\n"
       "<li>A communication step must be a whole number of coupling steps; the FMU refuses any other.</li>\n"
       "<li>The start time must be 0: the FE model starts from its initial state.</li>\n</ul>\n";
  h << "<h2>Before you run it: the server and the token</h2>\n"
       "<p>The structural model runs in fe_server, which must be listening before the importer ends "
       "initialization (<code>fmi2ExitInitializationMode</code> connects). The address comes from the "
       "parameters <code>server.host</code> and <code>server.port</code>, else from "
       "<code>$PCS_SERVER_HOST</code> and <code>$PCS_SERVER_PORT</code>, else from the <code>server</code> "
       "line of <code>resources/ports.cfg</code>.</p>\n"
       "<p>The session token is never stored in the FMU. Give it in <code>server.token</code> (write-only: "
       "reading it back gives an empty string), or in <code>$PCS_TOKEN</code>, or in a file named by "
       "<code>$PCS_TOKEN_FILE</code> (readable by you only). fe_server must be started with the same token; "
       "without it the handshake is refused and the FMU says so.</p>\n"
       "<pre>"
    << xml_escape(external_dependencies_text(t)) << "</pre>\n";
  h << "<h2>Variables</h2>\n<table>\n<tr><th>name</th><th>causality</th><th>type</th><th>unit</th>"
       "<th>start</th><th>meaning</th></tr>\n";
  for (const auto& v : vars) {
    const char* type = v.type == config::FmuType::Real ? "Real" : v.type == config::FmuType::Integer ? "Integer" : "String";
    h << "<tr><td><code>" << xml_escape(v.name) << "</code></td><td>" << causality_name(v.causality) << "</td><td>"
      << type << "</td><td>" << xml_escape(v.unit.empty() ? "-" : v.unit) << "</td><td>"
      << xml_escape(v.start.empty() ? "-" : v.start) << "</td><td>" << xml_escape(v.description) << "</td></tr>\n";
  }
  h << "</table>\n";
  h << "<h2>Licences</h2>\n<p>The binary links libsodium and the GCC runtime (libstdc++, libgcc) statically; "
       "their licences are in <code>documentation/licenses/</code>.</p>\n</body>\n</html>\n";
  return h.str();
}

}  // namespace fmugen

namespace fmugen {

std::string model_description_xml3(const config::PortTable& t, const std::string& description,
                                   const Generation& generation) {
  const auto vars = config::fmu_variables(t);
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"" << xml_escape(t.model_name)
    << "\" instantiationToken=\"" << config::fmu_guid(t) << "\"\n  description=\""
    << xml_escape(description_of(t, description)) << "\"\n  version=\"" << xml_escape(config::project_version())
    << "\" generationTool=\"" << xml_escape(generation.tool) << "\"";
  if (!generation.date.empty()) x << " generationDateAndTime=\"" << xml_escape(generation.date) << "\"";
  x << "\n  variableNamingConvention=\"structured\">\n";
  // Co-simulation without event mode, intermediate update or early return:
  // each communication step is a whole number of coupling steps of the
  // table's, which fixedInternalStepSize tells the importer.
  x << "  <CoSimulation modelIdentifier=\"" << xml_escape(t.model_name)
    << "\" needsExecutionTool=\"true\" canBeInstantiatedOnlyOncePerProcess=\"false\"\n"
       "    canGetAndSetFMUState=\"false\" canSerializeFMUState=\"false\" "
       "canHandleVariableCommunicationStepSize=\"false\"\n    fixedInternalStepSize=\""
    << config::shortest(t.dt) << "\" hasEventMode=\"false\"/>\n";
  units_categories_experiment(x, t);
  x << "  <ModelVariables>\n"
    << "    <Float64 name=\"time\" valueReference=\"" << config::kVrTime
    << "\" causality=\"independent\" variability=\"continuous\" unit=\"s\"\n"
       "      description=\"simulation time: the FE model starts at 0\"/>\n";
  for (const auto& v : vars) {
    const bool parameter = v.causality == config::FmuCausality::Parameter;
    const char* element = v.type == config::FmuType::Real ? "Float64" : v.type == config::FmuType::Integer ? "Int32" : "String";
    x << "    <" << element << " name=\"" << xml_escape(v.name) << "\" valueReference=\"" << v.value_reference
      << "\" causality=\"" << causality_name(v.causality) << "\" variability=\""
      << (parameter ? "fixed" : v.type == config::FmuType::Real ? "continuous" : "discrete") << "\""
      << (v.initial.empty() ? "" : " initial=\"" + v.initial + "\"");
    if (v.type == config::FmuType::Real && !v.unit.empty() && v.unit != "1") x << " unit=\"" << xml_escape(v.unit) << "\"";
    const bool has_start = v.causality != config::FmuCausality::Output || !v.initial.empty();
    if (has_start && v.type != config::FmuType::String) x << " start=\"" << xml_escape(v.start) << "\"";
    x << "\n      description=\"" << xml_escape(v.description) << "\"";
    if (v.type == config::FmuType::String)
      x << ">\n      <Start value=\"" << xml_escape(v.start) << "\"/>\n    </String>\n";
    else
      x << "/>\n";
  }
  x << "  </ModelVariables>\n  <ModelStructure>\n";
  for (const auto& v : vars)
    if (v.causality == config::FmuCausality::Output) x << "    <Output valueReference=\"" << v.value_reference << "\"/>\n";
  for (const auto& v : vars)
    if (v.causality == config::FmuCausality::Output && v.initial.empty())
      x << "    <InitialUnknown valueReference=\"" << v.value_reference << "\"/>\n";
  x << "  </ModelStructure>\n</fmiModelDescription>\n";
  return x.str();
}

}  // namespace fmugen
