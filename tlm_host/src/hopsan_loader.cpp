#include "hopsan_loader.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <muParser.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>

namespace tlm {

namespace {

// One Hopsan component type and how it becomes ours. Hopsan's parameter
// names as its current files write them: "X" for a constant, "X#Value" for
// an input variable's default, "P1#Pressure" for a port's start value
// (Hopsan's default library, componentLibraries/defaultLibrary). Older
// files write "::" for "#" and may omit "#Value"; both are read.
struct Mapping {
  const char* ours;
  // Hopsan name → our key, with Hopsan's default (what Hopsan uses when the
  // file does not list the parameter: ours may differ). An empty key: read
  // for a sum below, not passed on.
  struct Param {
    const char* hopsan;
    const char* key;
    double hopsan_default;
  };
  std::vector<Param> params;
  std::vector<std::pair<const char*, const char*>> fixed = {};  // our key → value
  std::set<std::string> ignored = {};  // Hopsan parameters without effect on the result (animation)
  const char* note = "";               // how ours differs by design; "" if it does not
  std::map<std::string, std::string> ports = {};  // Hopsan port → ours, where they differ
  // Our key ← the sum of two Hopsan parameters (a step's final value: base + amplitude).
  std::vector<std::pair<const char*, std::pair<const char*, const char*>>> sums = {};
  // Our key for the start pressure: every hydraulic port's start pressure
  // in the file must agree (ours starts the component at one pressure);
  // none given: Hopsan's default, 1e5 Pa. nullptr: start pressures are
  // outputs the component overwrites in its first step (Q types, sources).
  const char* start_pressure = nullptr;
  // Hopsan parameters read only at one value (what ours implements), with why.
  std::vector<std::pair<std::pair<const char*, double>, const char*>> only = {};
  // A Hopsan multiport (one port name taking any number of connections):
  // the k-th connection becomes our port P<k>, their count our `ports`.
  const char* multiport = nullptr;
};

const char* const kCavitationNote =
    "its oil is conserved when the pressure falls to the vapour pressure (the void is tracked); Hopsan's "
    "volume lets the pressure go below it";

// Hopsan's directional valves as one of ours (DirectionalValveQ.hpp): the
// spool's parameters every one of them has, its metering edges' between
// (fractions and overlaps), the command `in` read from what it connects to.
// The 4/2 valve's spool starts at its command's first value (Valve42Q), the
// others' at xv, its output's start.
Mapping spool_valve(const char* ours, std::vector<Mapping::Param> edges) {
  Mapping v{ours, {{"C_q#Value", "C_q", 0.67}, {"rho#Value", "rho", 870.0}, {"d#Value", "d", 0.01}}, {}, {"in#Value"}};
  v.params.insert(v.params.end(), edges.begin(), edges.end());
  v.params.insert(v.params.end(), {{"x_vmax#Value", "x_vmax", 0.01},
                                   {"omega_h", "omega_h", 100.0},
                                   {"delta_h", "delta_h", 1.0},
                                   {"xv#Value", "xv0", 0.0}});
  return v;
}

// Hopsan's pressure-controlled valves as PressureControlledValveQ: `ports`
// 2 or 4 metered ports, normally open or closed, the switching 4/2 valve.
Mapping pilot_valve(const char* ports, const char* normally_open, const char* switching) {
  const bool four = ports[0] == '4', cross = switching[0] == '1';
  Mapping v{"PressureControlledValveQ",
            {{"Fs_min#Value", "Fs_min", 1e5},
             {"Fs_max#Value", "Fs_max", 1e6},
             {"C_q#Value", "C_q", 0.67},
             {"rho#Value", "rho", 870.0},
             {"d#Value", "d", 0.01},
             {"f_pa#Value", "f_pa", 1.0},
             {"x_vmax#Value", "x_vmax", 0.01},
             {"omega_h", "omega_h", 100.0},
             {"delta_h", "delta_h", 1.0}},
            {{"ports", ports}, {"normally_open", normally_open}, {"switching", switching}},
            {"x_v#Value"},
            "",
            {{"x_v", "xv"}}};
  if (four) v.params.push_back({"f_bt#Value", "f_bt", 1.0});
  else v.ignored.insert("f_bt#Value");
  if (cross) v.params.insert(v.params.end(), {{"f_pb#Value", "f_pb", 1.0}, {"f_at#Value", "f_at", 1.0}});
  return v;
}

// Hopsan's multiport pressure source and tank as PressureSourceC with one
// port per connection (its `p` an input variable on the source, a constant
// on the tank).
Mapping multiport_source(const char* pressure) {
  Mapping v{"PressureSourceC", {{pressure, "p", 1e5}, {"MP#Flow", "q0", 0.0}}};
  v.multiport = "MP";
  return v;
}

const std::map<std::string, Mapping>& mappings() {
  static const std::map<std::string, Mapping> m = {
      {"HydraulicVolume",
       {"HydraulicVolumeC",
        {{"V", "V", 1e-3}, {"Beta_e", "beta", 1e9}, {"alpha#Value", "alpha", 0.1}},
        {{"ports", "2"}},
        {"P_high"},
        kCavitationNote,
        {},
        {},
        "p0"}},
      {"HydraulicVolumeMultiPort",
       {"HydraulicVolumeC",
        {{"V#Value", "V", 1e-3}, {"Beta_e#Value", "beta", 1e9}, {"alpha#Value", "alpha", 0.1}},
        {},
        {"P_high"},
        kCavitationNote,
        {},
        {},
        "p0",
        {},
        "P1"}},
      {"HydraulicTLMlossless",
       {"LosslessLineC",
        {{"Z_c#Value", "Zc", 1e9}, {"deltat", "delay", 0.1}},
        {},
        {},
        "",
        {},
        {},
        "p0",
        {{{"alpha#Value", 0.0}, "ours is lossless: no low-pass filter on the waves"}}}},
      // Hopsan's orifices clamp a pressure that would fall below zero (node.hpp).
      {"HydraulicHose",
       {"HoseC",
        {{"rho#Value", "rho", 870.0},
         {"eta#Value", "eta", 0.03},
         {"d#Value", "d", 0.03},
         {"l#Value", "l", 1.0},
         {"beta_e", "beta_e", 1e9},
         {"eta_w", "eta_w", 0.03}},
        {},
        {},
        "",
        {},
        {},
        "p0"}},
      {"HydraulicTurbulentOrifice",
       {"HydraulicTurbulentOrificeQ",
        {{"A#Value", "A", 1e-5}, {"C_q#Value", "Cd", 0.67}, {"rho#Value", "rho", 870}},
        {{"hopsan_cavitation", "1"}}}},
      {"HydraulicLaminarOrifice", {"LaminarOrificeQ", {{"Kc#Value", "Kc", 1e-11}}, {{"hopsan_cavitation", "1"}}}},
      {"HydraulicPressureSourceC", {"PressureSourceC", {{"p#Value", "p", 1e5}, {"P1#Flow", "q0", 0.0}}}},
      {"HydraulicTankC", {"PressureSourceC", {{"p", "p", 1e5}, {"P1#Flow", "q0", 0.0}}}},
      {"HydraulicMultiPressureSourceC", multiport_source("p#Value")},
      {"HydraulicMultiTankC", multiport_source("p")},
      {"HydraulicFlowSourceQ", {"FlowSourceQ", {{"q#Value", "q", 1e-3}}, {{"hopsan_cavitation", "1"}}}},
      // Signals (Hopsan evaluates them at the step's end time, as ours do).
      {"SignalConstant", {"SignalStep", {{"y#Value", "y0", 1.0}, {"y#Value", "y1", 1.0}}}},  // its port is y, as ours
      {"SignalStep",
       {"SignalStep",
        {{"y_0#Value", "y0", 0.0}, {"t_step#Value", "t_step", 1.0}, {"y_A#Value", "", 1.0}},
        {},
        {},
        "",
        {{"out", "y"}},
        {{"y1", {"y_0#Value", "y_A#Value"}}}}},
      {"SignalRamp",
       {"SignalRamp",
        {{"y_0#Value", "y0", 0.0}, {"t_start#Value", "t0", 1.0}, {"t_end#Value", "t1", 2.0}, {"y_A#Value", "", 1.0}},
        {},
        {},
        "",
        {{"out", "y"}},
        {{"y1", {"y_0#Value", "y_A#Value"}}}}},
      {"SignalGain", {"SignalGain", {{"k#Value", "k", 1.0}}, {}, {"in#Value"}, "", {{"in", "u"}, {"out", "y"}}}},
      {"SignalAdd",
       {"SignalAdd", {}, {}, {"in1#Value", "in2#Value"}, "", {{"in1", "u1"}, {"in2", "u2"}, {"out", "y"}}}},
      {"SignalMultiply",
       {"SignalMultiply", {}, {}, {"in1#Value", "in2#Value"}, "", {{"in1", "u1"}, {"in2", "u2"}, {"out", "y"}}}},
      {"SignalSubtract",
       {"SignalSubtract", {}, {}, {"in1#Value", "in2#Value"}, "", {{"in1", "u1"}, {"in2", "u2"}, {"out", "y"}}}},
      {"SignalIntegrator2",
       {"SignalIntegrator", {{"out#Value", "y0", 0.0}}, {}, {"in#Value"}, "", {{"in", "u"}, {"out", "y"}}}},
      {"SignalRateLimiter",
       {"SignalRateLimiter",
        {{"c_up#Value", "rate_up", 1.0}, {"c_down#Value", "rate_down", -1.0}},
        {},
        {"in#Value", "in_bottom#Value"},  // read from what it connects to; in_bottom: an older file's port
        "",
        {{"in", "u"}, {"out", "y"}}}},
      {"SignalSoftStep",
       {"SignalSoftStep",
        {{"t_start#Value", "t0", 1.0},
         {"t_end#Value", "t1", 2.0},
         {"y_0#Value", "y0", 0.0},
         {"y_A#Value", "amplitude", 1.0}},
        {},
        {},
        "",
        {{"out", "y"}}}},
      {"SignalSineWave",
       {"SignalSineWave",
        {{"f#Value", "f", 1.0},
         {"y_A#Value", "amplitude", 1.0},
         {"y_offset#Value", "t_offset", 0.0},
         {"t_start#Value", "t0", 0.0}},
        {},
        {},
        "",
        {{"out", "y"}}}},
      {"SignalPulse",
       {"SignalPulse",
        {{"y_0#Value", "y0", 0.0},
         {"y_A#Value", "amplitude", 1.0},
         {"t_start#Value", "t0", 1.0},
         {"t_end#Value", "t1", 2.0}},
        {},
        {},
        "",
        {{"out", "y"}}}},
      // Translational mechanics (TranslationalMassQ.hpp: Hopsan's equations).
      {"MechanicTranslationalMass",
       {"TranslationalMassQ",
        {{"m", "m", 100.0},
         {"B#Value", "B", 10.0},
         {"k#Value", "k", 0.0},
         {"x_min#Value", "x_min", -1e300},
         {"x_max#Value", "x_max", 1e300}}}},  // its ports' start positions: see q_type below
      {"HydraulicCylinderC",
       {"CylinderC",
        {{"A_1#Value", "A_1", 1e-3},
         {"A_2#Value", "A_2", 1e-3},
         {"s_l#Value", "s_l", 1.0},
         {"V_1#Value", "V_1", 3e-4},
         {"V_2#Value", "V_2", 3e-4},
         {"B_p#Value", "B_p", 1000.0},
         {"Beta_e#Value", "Beta_e", 1e9},
         {"c_leak#Value", "c_leak", 1e-11},
         {"use_sl", "use_sl", 1.0},
         {"P1#Pressure", "p1_0", 1e5},
         {"P2#Pressure", "p2_0", 1e5}},
        {},
        {"q_leak#Value"},  // an output's start value, overwritten in the first step
        "after an end stop is reached: Hopsan's stop filter starts from an uninitialised value, ours from its "
        "last one"}},
      {"HydraulicCylinderQ",
       {"CylinderQ",
        {{"A_1#Value", "A_1", 1e-4},
         {"A_2#Value", "A_2", 1e-4},
         {"B_p#Value", "B_p", 0.0},
         {"B_l#Value", "B_l", 0.0},
         {"k_l#Value", "k_l", 100.0},
         {"m_l", "m_l", 0.05},
         {"s_l", "s_l", 0.01}}}},
      {"MechanicForceTransformer", {"ForceSourceC", {{"F#Value", "F", 0.0}}}},
      {"HydraulicPressureReliefValve",
       {"PressureReliefValveQ",
        {{"p_max#Value", "p_max", 2e7},
         {"tao#Value", "tao", 0.01},
         {"p_h#Value", "p_h", 5e5},
         {"k_cs", "k_cs", 1e-8},
         {"k_cf", "k_cf", 1e-8},
         {"q_nom", "q_nom", 1e-3}},
        {},
        {"xv#Value"}}},  // an output's start value: the valve starts shut, as Hopsan's
      {"HydraulicAckumulator",
       {"AccumulatorQ",
        {{"V0#Value", "V0", 1e-3},
         {"Kca#Value", "Kca", 1e-8},
         {"kappa#Value", "kappa", 1.2},
         {"p0#Value", "p0", 1e7},
         {"pa#Value", "pa0", 1e7},
         {"xmp#Value", "x0", 0.0},
         {"vmp#Value", "v0", 0.0}},
        {},
        {"Va#Value"}}},  // computed from the state of charge
      {"HydraulicPistonAckumulator",
       {"PistonAccumulatorQ",
        {{"Ap#Value", "Ap", 1e-3},
         {"SL#Value", "SL", 0.5},
         {"Bp#Value", "Bp", 10.0},
         {"ML#Value", "ML", 1.0},
         {"kappa#Value", "kappa", 1.2},
         {"p0#Value", "p0", 1e7},
         {"pa#Value", "pa0", 1e7},
         {"xmp#Value", "x0", 0.0},
         {"vmp#Value", "v0", 0.0}},
        {},
        {"Va#Value"}}},  // computed from the piston's position
      // Directional valves (DirectionalValveQ.hpp: Hopsan's equations).
      {"Hydraulic43Valve", spool_valve("Valve43Q", {{"f_pa#Value", "f_pa", 1.0},
                                                    {"f_pb#Value", "f_pb", 1.0},
                                                    {"f_at#Value", "f_at", 1.0},
                                                    {"f_bt#Value", "f_bt", 1.0},
                                                    {"x_pa#Value", "x_pa", -1e-6},
                                                    {"x_pb#Value", "x_pb", -1e-6},
                                                    {"x_at#Value", "x_at", -1e-6},
                                                    {"x_bt#Value", "x_bt", -1e-6}})},
      {"Hydraulic22DirectionalValve", spool_valve("Valve22Q", {{"f#Value", "f", 1.0}})},
      {"Hydraulic33Valve", spool_valve("Valve33Q", {{"f_pa#Value", "f_pa", 1.0},
                                                    {"f_at#Value", "f_at", 1.0},
                                                    {"x_pa#Value", "x_pa", -1e-6},
                                                    {"x_at#Value", "x_at", -1e-6}})},
      {"Hydraulic22Valve", spool_valve("Valve22ProportionalQ", {{"f#Value", "f", 1.0}})},
      {"Hydraulic42DirectionalValve", spool_valve("Valve42Q", {{"f_pa#Value", "f_pa", 1.0},
                                                               {"f_pb#Value", "f_pb", 1.0},
                                                               {"f_at#Value", "f_at", 1.0},
                                                               {"f_bt#Value", "f_bt", 1.0}})},
      {"Hydraulic32DirectionalValve", spool_valve("Valve32Q", {{"f#Value", "f", 1.0}})},
      // Pressure-controlled valves (PressureControlledValveQ.hpp: Hopsan's
      // equations); the spool's start value has no effect (Hopsan's filter
      // starts at 0), nor have f_bt on the 2/2 valves or f_pb, f_at on the
      // 4/2 valves but the switching one (Hopsan lists and never reads them).
      {"HydraulicPressureControlled22Valve", pilot_valve("2", "0", "0")},
      {"HydraulicPressureControlled22Valve2", pilot_valve("2", "1", "0")},
      {"HydraulicPressureControlled42Valve", pilot_valve("4", "0", "0")},
      {"HydraulicPressureControlled42Valve2", pilot_valve("4", "1", "0")},
      {"HydraulicPressureControlled42Valve3", pilot_valve("4", "0", "1")},
      {"SignalFirstOrderFilter",
       {"SignalFirstOrderFilter",
        {{"k", "k", 1.0},
         {"omega_num", "omega_num", 1e10},
         {"omega_den", "omega_den", 1e3},
         {"y_min", "y_min", -1.5e300},
         {"y_max", "y_max", 1.5e300},
         {"out#Value", "y0", 0.0}},
        {},
        {"in#Value"},  // the input's default: read from what it connects to
        "",
        {{"in", "u"}, {"out", "y"}}}},
  };
  return m;
}

// A typename "Pcs<Type>" names one of tlm_host's own components (Pcs: this
// project), read with our parameter names: for what Hopsan's library has no
// counterpart of (the hammer's piston, its control spool, tabulated edges).
// Hopsan itself runs such a model only with a component library providing
// these types.
constexpr const char* kOwnPrefix = "Pcs";

// The types whose Hopsan components step once in their initialize()
// (ComponentSpec::initial_step).
const std::set<std::string> kStepInInitialize = {"HydraulicTurbulentOrifice",
                                                 "HydraulicFlowSourceQ",
                                                 "HydraulicPressureSourceC",
                                                 "SignalStep",
                                                 "SignalGain",
                                                 "SignalAdd",
                                                 "SignalMultiply",
                                                 "SignalSubtract",
                                                 "Hydraulic22DirectionalValve",
                                                 "Hydraulic22Valve",
                                                 "HydraulicAckumulator",
                                                 "HydraulicPistonAckumulator"};

// Hopsan's sensors read a node (hydraulic or translational); their nodes are logged anyway.
const std::set<std::string> kSensors = {"HydraulicPressureSensor", "HydraulicFlowSensor", "HydraulicNodeSensor",
                                        "MechanicPositionSensor", "MechanicSpeedSensor", "MechanicForceSensor"};
// Scopes: a sink only displays the signals wired to it in Hopsan's GUI (and
// logs them, as our results log every signal's source), so it is left out
// with its connections.
const std::set<std::string> kSinks = {"SignalSink"};

std::string attr(xmlNode* n, const char* name) {
  xmlChar* v = xmlGetProp(n, reinterpret_cast<const xmlChar*>(name));
  if (!v) return "";
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

bool is(xmlNode* n, const char* name) {
  return n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, reinterpret_cast<const xmlChar*>(name)) == 0;
}

xmlNode* child(xmlNode* n, const char* name) {
  for (xmlNode* c = n->children; c; c = c->next)
    if (is(c, name)) return c;
  return nullptr;
}

bool number(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && std::isfinite(v);
}

std::string text_of(double v) {
  char num[64];
  std::snprintf(num, sizeof num, "%.17g", v);
  return num;
}

// Hopsan's current spelling of a parameter name: "::" → "#", and a bare
// input-variable name gets its "#Value" where the mapping knows it so.
std::string current_name(std::string name, const Mapping* mp) {
  for (size_t at = name.find("::"); at != std::string::npos; at = name.find("::", at)) name.replace(at, 2, "#");
  if (mp && name.find('#') == std::string::npos) {
    const std::string input = name + "#Value";
    for (const auto& prm : mp->params)
      if (input == prm.hopsan) return input;
    for (const auto& [only, why] : mp->only)
      if (input == only.first) return input;
  }
  return name;
}

// A parameter's value as Hopsan evaluates it (libNumHop, in HopsanCore's
// parameter evaluation): a number, a system parameter's name, or an
// expression of numbers and system parameters with + - * / ^, parentheses and
// cmath's functions. Evaluated with muparser (Debian's libmuparser-dev),
// which agrees with libNumHop on every expression libNumHop accepts that was
// tried (HopsanLoader.ExpressionsEvaluateAsHopsansDo); NumHop's own
// functions muparser lacks (atan2, ceil, floor, fmod, pow) are added.
// References to a component's own parameters (self.X) are not read yet.
class Expressions {
 public:
  std::map<std::string, double> variables;  // the system parameters so far

  Expressions() {
    parser_.DefineNameChars("0123456789_abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.");
    parser_.DefineFun("atan2", static_cast<double (*)(double, double)>(std::atan2));
    parser_.DefineFun("ceil", static_cast<double (*)(double)>(std::ceil));
    parser_.DefineFun("floor", static_cast<double (*)(double)>(std::floor));
    parser_.DefineFun("fmod", static_cast<double (*)(double, double)>(std::fmod));
    parser_.DefineFun("pow", static_cast<double (*)(double, double)>(std::pow));
  }
  void define(const std::string& name, double value) {
    variables[name] = value;
    try {
      parser_.DefineVar(name, &variables[name]);  // std::map keeps the address
    } catch (const mu::Parser::exception_type& e) {
      throw std::invalid_argument("'" + name + "' cannot name a system parameter here: " + e.GetMsg());
    }
  }
  // Throws std::invalid_argument saying what is wrong.
  double evaluate(const std::string& text) {
    double v = 0.0;
    if (number(text, v)) return v;
    if (auto it = variables.find(text); it != variables.end()) return it->second;
    if (text == "true" || text == "false") return text == "true";  // a Hopsan bool constant
    if (text.find("self.") != std::string::npos)
      throw std::invalid_argument("a component's own parameters (self.…) are not read in expressions yet");
    try {
      parser_.SetExpr(text);
      v = parser_.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw std::invalid_argument("not an expression read here (numbers, system parameters, + - * / ^, "
                                  "parentheses, cmath functions): " + e.GetMsg());
    }
    if (!std::isfinite(v)) throw std::invalid_argument("evaluates to " + text_of(v));
    return v;
  }

 private:
  mu::Parser parser_;
};

std::string directory_of(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// A parameter's text, a system parameter's name standing for its value.
std::function<std::string(const std::string&)> value_of_text(const std::map<std::string, double>& system_params) {
  return [&system_params](const std::string& text) {
    auto sp = system_params.find(text);
    return sp == system_params.end() ? text : text_of(sp->second);
  };
}

// Hopsan's FMU wrapper (FMIWrapperQ, a Q-type component) as our FmuQ: the
// FMU's path (relative to the model file, as Hopsan finds it), its portspecs
// (checked against the FMU by FmuQ), Hopsan's names for its signals. The
// wrapper's own settings without effect on the result are skipped; the FMU's
// parameters as FMIWrapperQ names them (server_host, server_port,
// server_token) set the server and token; any other is refused (set it in
// the port table the FMU was made from).
void fmu_wrapper(ComponentSpec& s, xmlNode* params, const std::string& model_dir,
                 const std::function<config::SourceLocation(xmlNode*)>& where,
                 const std::function<std::string(const std::string&)>& text, std::vector<std::string>& notes) {
  s.type = "FmuQ";
  s.params.set("hopsan_names", "1", s.where);
  std::string host, port;
  bool path = false;
  config::SourceLocation server_at = s.where;
  for (xmlNode* p = params ? params->children : nullptr; p; p = p->next) {
    if (!is(p, "parameter")) continue;
    const std::string pname = attr(p, "name"), value = text(attr(p, "value"));
    if (pname == "path") {
      s.params.set("fmu", !value.empty() && value[0] != '/' ? model_dir + "/" + value : value, where(p));
      path = true;
    } else if (pname == "portspecs") {
      s.params.set("portspecs", value, where(p));
    } else if (pname == "reinstantiate" || pname == "tol" || pname == "loggingOn" || pname == "visibleOutputs") {
      continue;  // an instance per run anyway; our FMU has no tolerance; logging; the GUI's
    } else if (pname == "server_host") {
      host = value, server_at = where(p);
    } else if (pname == "server_port") {
      port = value, server_at = where(p);
    } else if (pname == "server_token") {
      if (!value.empty()) {
        s.params.set("token", value, where(p));
        notes.push_back(where(p).file + ":" + std::to_string(where(p).line) + ": " + s.name +
                        ": the session token is read from the model file; $PCS_TOKEN keeps it out of files");
      }
    } else {
      throw config::InputError(where(p), s.name + " (FMIWrapperQ): parameter '" + pname + "' = '" + value +
                                             "' is not read here; set the FMU's settings in the port table it was made from");
    }
  }
  if (!path) throw config::InputError(s.where, s.name + " (FMIWrapperQ): no path to the FMU");
  if (!host.empty() && !port.empty() && port != "0") s.params.set("server", host + ":" + port, server_at);
}

using config::InputError;
using config::SourceLocation;

// Reads a Hopsan model's systems into one flat ModelSpec. A nested
// subsystem's components are named <subsystem>$<component>, as Hopsan names
// them in its results; its system ports (<systemport>) are resolved to the
// components inside that they connect to, so every connection joins two
// components' ports; its parameters are evaluated in its own scope, which
// sees its parents' (Hopsan looks a name up from the inside out).
class HmfReader {
 public:
  HmfReader(const std::string& path, HmfModel& out) : path_(path), out_(out), m_(out.spec) {}

  SourceLocation where(xmlNode* n) const { return {path_, static_cast<int>(xmlGetLineNo(n))}; }

  void read_system(xmlNode* system, const std::string& prefix, Expressions& scope) {
    if (xmlNode* ps = child(system, "parameters"))
      for (xmlNode* p = ps->children; p; p = p->next)
        if (is(p, "parameter"))
          scope.define(attr(p, "name"), evaluate(scope, p, "system parameter '" + prefix + attr(p, "name") + "'"));
    std::set<std::string> system_ports;
    if (xmlNode* objects = child(system, "objects"))
      for (xmlNode* c = objects->children; c; c = c->next)
        if (c->type == XML_ELEMENT_NODE) hopsan_names_.insert(prefix + attr(c, "name"));
    if (xmlNode* objects = child(system, "objects"))
      for (xmlNode* c = objects->children; c; c = c->next) {
        if (c->type != XML_ELEMENT_NODE) continue;
        const std::string element = reinterpret_cast<const char*>(c->name);
        if (element.size() > 6 && element.compare(element.size() - 6, 6, "widget") == 0)
          continue;  // a text box or another of the GUI's drawings: nothing to simulate
        if (is(c, "systemport")) {  // a key inside this reader only: any name
          system_ports.insert(attr(c, "name"));
          continue;
        }
        const std::string name = local_name(prefix, attr(c, "name"), c);
        if (is(c, "system")) {
          check_inherited_timestep(c);
          subsystems_.insert(prefix + name);
          Expressions inner;
          for (const auto& [k, v] : scope.variables) inner.define(k, v);
          read_system(c, prefix + name + "$", inner);
        } else if (is(c, "component") && attr(c, "disabled") == "true") {
          // Hopsan leaves a disabled component out of the simulation, and
          // its connections with it (a disabled leak once drained 0.78 l here).
          disabled_.insert(prefix + name);
          out_.notes.push_back(path_ + ": " + prefix + name + ": disabled in the model, left out with its connections");
        } else if (is(c, "component")) {
          read_component(c, prefix, scope);
        } else {
          throw InputError(where(c), "'" + name + "' (<" + std::string(reinterpret_cast<const char*>(c->name)) +
                                         ">): not a component, subsystem or system port");
        }
      }
    // A connection to one of this system's own ports belongs to whatever the
    // port connects to outside; others join two objects of this system.
    if (xmlNode* cs = child(system, "connections"))
      for (xmlNode* c = cs->children; c; c = c->next) {
        if (!is(c, "connect")) continue;
        const bool a_port = system_ports.count(attr(c, "startcomponent")) != 0;
        const bool b_port = system_ports.count(attr(c, "endcomponent")) != 0;
        End a{prefix + (a_port ? attr(c, "startcomponent") : local_name(prefix, attr(c, "startcomponent"), c)),
              attr(c, "startport")};
        End b{prefix + (b_port ? attr(c, "endcomponent") : local_name(prefix, attr(c, "endcomponent"), c)),
              attr(c, "endport")};
        if (disabled_.count(a.component) || disabled_.count(b.component)) continue;
        if (sinks_.count(a.component) || sinks_.count(b.component)) continue;  // a scope's input
        if (a_port && b_port) throw InputError(where(c), "a connection from one system port straight to another is not read");
        if (a_port)
          inside_[prefix + a.port].push_back(b);
        else if (b_port)
          inside_[prefix + b.port].push_back(a);
        else
          raw_.push_back({a, b, where(c)});
      }
  }

  // Connections between components' ports, in the order read.
  void connect() {
    for (const auto& r : raw_) {
      std::vector<End> as, bs;
      resolve(r.a, r.where, as);
      resolve(r.b, r.where, bs);
      for (const End& a : as)
        for (const End& b : bs) connect(a, b, r.where);
    }
    for (const auto& [name, k] : known_)
      if (k.mapping && k.mapping->multiport) {
        ComponentSpec& s = m_.components[k.index];
        if (k.multiport_count == 0) throw InputError(s.where, name + ": its port " + k.mapping->multiport + " is not connected");
        s.params.set("ports", std::to_string(k.multiport_count), s.where);
      }
    for (const std::string& sensor : dropped_sensors_)
      out_.notes.push_back(path_ + ": " + sensor + ": a Hopsan sensor; its node's pressure and flow are in the results");
  }

 private:
  struct End {
    std::string component, port;  // the component's full name
  };
  struct Raw {
    End a, b;
    SourceLocation where;
  };
  struct Known {
    const Mapping* mapping = nullptr;  // nullptr: one of ours (Pcs…) or an FMU
    size_t index = 0;                  // in m_.components
    int multiport_count = 0;
  };

  double evaluate(Expressions& scope, xmlNode* p, const std::string& what) {
    try {
      return scope.evaluate(attr(p, "value"));
    } catch (const std::invalid_argument& e) {
      throw InputError(where(p), what + " = '" + attr(p, "value") + "': " + e.what());
    }
  }

  void check_inherited_timestep(xmlNode* system) {
    xmlNode* sim = child(system, "simulationtime");
    double dt = 0.0;
    if (sim && attr(sim, "inherit_timestep") == "false" && number(attr(sim, "timestep"), dt) && dt != m_.dt)
      throw InputError(where(sim), "subsystem '" + attr(system, "name") + "' has its own time step " +
                                       attr(sim, "timestep") + "; every component here steps at the model's");
  }

  // A subsystem's port, followed to the components inside (through deeper
  // subsystems); a component's port as it is.
  void resolve(const End& e, const SourceLocation& at, std::vector<End>& out, int depth = 0) {
    if (!subsystems_.count(e.component)) {
      out.push_back(e);
      return;
    }
    auto it = inside_.find(e.component + "$" + e.port);
    if (it == inside_.end() || depth > 64)
      throw InputError(at, "subsystem " + e.component + " has no port '" + e.port + "' connected inside");
    for (const End& inner : it->second) resolve(inner, at, out, depth + 1);
  }

  void connect(const End& a, const End& b, const SourceLocation& at) {
    for (const End* sensor : {&a, &b})
      if (dropped_sensors_.count(sensor->component) && sensor->port != "P1")
        throw InputError(at, "sensor " + sensor->component + ": its signal '" + sensor->port +
                                 "' is used; sensors are read only where nothing uses them (their node is logged)");
    if (dropped_sensors_.count(a.component) || dropped_sensors_.count(b.component)) return;  // a sensor's tap
    m_.connections.push_back({ours(a), ours(b), at});
  }

  // Our "component.port" for a Hopsan end: renamed ports, a multiport's k-th connection.
  std::string ours(const End& e) {
    auto it = known_.find(e.component);
    if (it == known_.end() || !it->second.mapping) return e.component + "." + e.port;
    const Mapping& mp = *it->second.mapping;
    if (mp.multiport && e.port == mp.multiport) {
      const std::string port = e.component + ".P" + std::to_string(++it->second.multiport_count);
      m_.unlogged_ports.insert(port);
      return port;
    }
    auto renamed = mp.ports.find(e.port);
    return e.component + "." + (renamed == mp.ports.end() ? e.port : renamed->second);
  }

  void read_component(xmlNode* c, const std::string& prefix, Expressions& scope) {
    const std::string name = prefix + local_name(prefix, attr(c, "name"), c), type = attr(c, "typename");
    if (kSinks.count(type)) {
      sinks_.insert(name);
      out_.notes.push_back(path_ + ": " + name + ": a Hopsan scope (" + type + "), left out with its connections");
      return;
    }
    if (kSensors.count(type)) {
      dropped_sensors_.insert(name);
      return;
    }
    ComponentSpec s;
    s.name = name;
    s.where = where(c);
    s.params.set_where(s.where);
    xmlNode* params = child(c, "parameters");
    auto value_of = [&](xmlNode* p) { return evaluate(scope, p, name + " (" + type + "): parameter '" + attr(p, "name") + "'"); };
    // One of ours, by our own names.
    if (type.rfind(kOwnPrefix, 0) == 0 && component_types().count(type.substr(3))) {
      s.type = type.substr(3);
      for (xmlNode* p = params ? params->children : nullptr; p; p = p->next)
        if (is(p, "parameter")) s.params.set(attr(p, "name"), value_of_text(scope.variables)(attr(p, "value")), where(p));
      known_[name] = {nullptr, m_.components.size()};
      m_.components.push_back(std::move(s));
      return;
    }
    if (type == "FMIWrapperQ") {
      fmu_wrapper(s, params, directory_of(path_), [this](xmlNode* n) { return where(n); },
                  value_of_text(scope.variables), out_.notes);
      known_[name] = {nullptr, m_.components.size()};
      m_.components.push_back(std::move(s));
      return;
    }
    auto map = mappings().find(type);
    if (map == mappings().end()) {
      std::string mapped;
      for (const auto& [t, mp] : mappings()) mapped += (mapped.empty() ? "" : ", ") + t;
      throw InputError(where(c), "component '" + name + "' of Hopsan type " + type + " has no counterpart here yet (mapped: " +
                                     mapped + "; and tlm_host's own types as " + kOwnPrefix + "<Type>)");
    }
    const Mapping& mp = map->second;
    s.type = mp.ours;
    s.initial_step = kStepInInitialize.count(type) != 0;
    for (const auto& [key, value] : mp.fixed) s.params.set(key, value, s.where);
    // Every mapped parameter gets Hopsan's value: the file's, else Hopsan's default.
    std::map<std::string, std::pair<double, SourceLocation>> vals;
    for (const auto& prm : mp.params) vals.emplace(prm.hopsan, std::make_pair(prm.hopsan_default, s.where));
    std::optional<std::pair<double, SourceLocation>> start_p;
    // Hopsan 2.24 gives only a C-type component's power ports start values
    // (PowerPort makes a start node for C types alone): on a Q type such as a
    // mass, "P1#Position" fails to set with a warning and the component starts
    // from what its node holds. Read the same way here: ignored, and said.
    const bool q_type = component_types().at(mp.ours)("probe")->kind() == Kind::Q;
    std::string ignored_starts;
    for (xmlNode* p = params ? params->children : nullptr; p; p = p->next) {
      if (!is(p, "parameter")) continue;
      const std::string pname = current_name(attr(p, "name"), &mp);
      const size_t sep = pname.find('#');
      const std::string variable = sep == std::string::npos ? "" : pname.substr(sep + 1);
      if (mp.ignored.count(pname)) continue;
      if (auto it = vals.find(pname); it != vals.end()) {
        it->second = {value_of(p), where(p)};
        continue;
      }
      if (q_type && !variable.empty() && variable != "Value" && value_of(p) != 0.0) {
        ignored_starts += (ignored_starts.empty() ? "" : ", ") + pname + " = " + attr(p, "value");
        continue;
      }
      bool checked = false;
      for (const auto& [only, why] : mp.only)
        if (pname == only.first) {
          if (value_of(p) != only.second)
            throw InputError(where(p), name + " (" + type + "): parameter '" + pname + "' = '" + attr(p, "value") +
                                           "': only " + text_of(only.second) + " is read (" + why + ")");
          checked = true;
        }
      if (checked) continue;
      // A port's start value: the pressure where the component starts from
      // it; temperature and heat flow mean nothing to an isothermal model;
      // the wave variable and impedance are computed; a flow must keep
      // Hopsan's default (0) to start as Hopsan starts.
      if (variable == "Pressure") {
        if (!mp.start_pressure) continue;
        const double v = value_of(p);
        if (start_p && start_p->first != v)
          throw InputError(where(p), name + " (" + type + "): start pressure " + attr(p, "value") + " at " +
                                         pname.substr(0, sep) + " differs from " + text_of(start_p->first) + " at line " +
                                         std::to_string(start_p->second.line) + ": " + mp.ours + " starts at one pressure");
        start_p = std::make_pair(v, where(p));
        continue;
      }
      if (variable == "Temperature" || variable == "HeatFlow" || variable == "WaveVariable" ||
          variable == "CharImpedance" || variable == "CharImp")
        continue;
      if (variable == "EquivalentMass") continue;  // written by the mass
      if ((variable == "Flow" || variable == "Velocity" || variable == "Position" || variable == "Force") &&
          value_of(p) == 0.0)
        continue;  // Hopsan's default: ours starts there too
      throw InputError(where(p), name + " (" + type + "): parameter '" + pname + "' = '" + attr(p, "value") +
                                     "' has no counterpart in " + mp.ours);
    }
    auto set = [&](const char* key, double v, const SourceLocation& at) { s.params.set(key, text_of(v), at); };
    for (const auto& prm : mp.params)
      if (*prm.key) set(prm.key, vals.at(prm.hopsan).first, vals.at(prm.hopsan).second);
    if (type == "HydraulicTLMlossless") line_delay_as_hopsan(name, vals.at("deltat"), s);
    for (const auto& [key, terms] : mp.sums)
      set(key, vals.at(terms.first).first + vals.at(terms.second).first, vals.at(terms.first).second);
    if (mp.start_pressure) set(mp.start_pressure, start_p ? start_p->first : 1e5, start_p ? start_p->second : s.where);
    for (const auto& [hopsan, ours] : mp.ports) m_.result_ports[name + "." + ours] = hopsan;
    if (type == "HydraulicCylinderC") {  // its chambers' ports are multiports in Hopsan (one connection here)
      m_.unlogged_ports.insert(name + ".P1");
      m_.unlogged_ports.insert(name + ".P2");
    }
    if (!ignored_starts.empty())
      out_.notes.push_back(path_ + ":" + std::to_string(s.where.line) + ": " + name + " (" + type + "): " +
                           ignored_starts +
                           " ignored: Hopsan 2.24 keeps start values only on C-type components' ports and fails to "
                           "set these on a Q type, which starts from its nodes");
    if (std::string(mp.note).size())
      out_.notes.push_back(path_ + ":" + std::to_string(s.where.line) + ": " + name + " (" + type + " → " + mp.ours +
                           "): " + mp.note);
    known_[name] = {&mp, m_.components.size()};
    m_.components.push_back(std::move(s));
  }

  // Hopsan's lossless line delays its waves by deltat − Ts in a buffer of
  // int((deltat − Ts)/Ts + 0.5) values, but never fewer than one, and the
  // C–Q loop adds the step itself: deltat = Ts (or anything below 1.5·Ts)
  // delays 2 steps in Hopsan, where our line rounds deltat to the nearest
  // whole step (1). The loader gives our line Hopsan's delay in steps and
  // says so when it differs from deltat rounded.
  void line_delay_as_hopsan(const std::string& name, const std::pair<double, SourceLocation>& deltat, ComponentSpec& s) {
    const double dt = m_.dt, T = deltat.first;
    const double buffer = std::max(1.0, std::floor((T - dt) / dt + 0.5));
    const double steps = buffer + 1.0;
    if (steps == std::max(1.0, std::round(T / dt))) return;
    s.params.set("delay", text_of(steps * dt), deltat.second);
    out_.notes.push_back(path_ + ":" + std::to_string(deltat.second.line) + ": " + name +
                         " (HydraulicTLMlossless): deltat = " + text_of(T) + " s is " + text_of(T / dt) +
                         " time steps; Hopsan's line holds at least one value besides the step, so it delays " +
                         text_of(steps) + " steps (" + text_of(steps * dt) + " s), and so does ours here");
  }

  std::string path_;
  HmfModel& out_;
  ModelSpec& m_;
  std::map<std::string, Known> known_;
  std::set<std::string> dropped_sensors_;                // their signal must not be used
  std::set<std::string> sinks_;                          // scopes, left out with their connections
  // Hopsan names with characters ours cannot take (". /#$": a dot splits
  // --set's component.parameter, a space the model file's fields) become
  // one word, each such character an underscore, a number added if that
  // name is taken; said once per component.
  std::map<std::string, std::string> local_names_;  // prefix + Hopsan name → ours (without prefix)
  std::set<std::string> taken_names_;               // prefix + ours
  std::string local_name(const std::string& prefix, const std::string& hopsan, xmlNode* at) {
    if (hopsan.empty()) throw InputError(where(at), "a component without a name");
    auto it = local_names_.find(prefix + hopsan);
    if (it != local_names_.end()) return it->second;
    std::string ours = hopsan;
    for (char& ch : ours)
      if (std::string(". /#$").find(ch) != std::string::npos) ch = '_';
    if (ours != hopsan) {
      const std::string base = ours;
      for (int n = 2; taken_names_.count(prefix + ours) || hopsan_names_.count(prefix + ours); ++n)
        ours = base + "_" + std::to_string(n);
      out_.notes.push_back(path_ + ":" + std::to_string(xmlGetLineNo(at)) + ": component '" + prefix + hopsan +
                           "' is named " + prefix + ours + " here (ours are one word without dots)");
    }
    taken_names_.insert(prefix + ours);
    local_names_[prefix + hopsan] = ours;
    return ours;
  }
  std::set<std::string> hopsan_names_;  // prefix + every name as Hopsan wrote it (a renamed one must not take one)
  std::set<std::string> subsystems_;                     // full names
  std::set<std::string> disabled_;                       // full names of disabled components
  std::map<std::string, std::vector<End>> inside_;       // "<subsystem>$<port>" → what it connects to inside
  std::vector<Raw> raw_;
};

}  // namespace

std::string hopsan_mapping_markdown() {
  auto num = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  std::ostringstream md;
  md << "# Hopsan component types that tlm_host reads\n\n"
        "Generated from the loader's table (`tlm_host --hopsan-types`, tlm_host/src/hopsan_loader.cpp); the test\n"
        "`docs.hopsan_types_page_is_the_loaders_table` fails when they differ. Each row: the Hopsan type, ours, its\n"
        "parameters (Hopsan's name → ours, Hopsan's default), what ours fixes, what is read only at one value, and\n"
        "how ours differs by design. Any other type or parameter is refused at its line (docs/hopsan.md).\n\n"
        "| Hopsan type | ours | parameters (Hopsan → ours, Hopsan's default) | fixed, only | differs by design |\n"
        "|---|---|---|---|---|\n";
  for (const auto& [type, m] : mappings()) {
    std::string params;
    for (const auto& prm : m.params)
      params += (params.empty() ? "" : ", ") + std::string("`") + prm.hopsan + "`" +
                (*prm.key ? std::string(" → `") + prm.key + "`" : std::string(" (summed)")) + " (" +
                num(prm.hopsan_default) + ")";
    for (const auto& [key, parts] : m.sums)
      params += (params.empty() ? "" : ", ") + std::string("`") + parts.first + "` + `" + parts.second + "` → `" + key + "`";
    if (m.start_pressure) params += (params.empty() ? "" : ", ") + std::string("start pressure → `") + m.start_pressure + "`";
    if (m.multiport) params += (params.empty() ? "" : ", ") + std::string("multiport `") + m.multiport + "` → P1, P2, …";
    std::string fixed;
    for (const auto& [key, value] : m.fixed) fixed += (fixed.empty() ? "" : ", ") + std::string("`") + key + "` = " + value;
    for (const auto& [what, why] : m.only)
      fixed += (fixed.empty() ? "" : "; ") + std::string("`") + what.first + "` only " + num(what.second) + ": " + why;
    std::string ports;
    for (const auto& [h, o] : m.ports) ports += (ports.empty() ? "" : ", ") + h + " → " + o;
    std::string note = *m.note ? m.note : "—";
    if (!ports.empty()) note += " (ports " + ports + ")";
    md << "| `" << type << "` | `" << m.ours << "` | " << (params.empty() ? "—" : params) << " | "
       << (fixed.empty() ? "—" : fixed) << " | " << note << " |\n";
  }
  return md.str();
}

HmfModel read_hmf(const std::string& path) {
  std::unique_ptr<xmlDoc, void (*)(xmlDoc*)> doc(xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR |
                                                                                     XML_PARSE_NOWARNING),
                                                 xmlFreeDoc);
  if (!doc) {  // libxml2's own reason and line: a malformed file, an entity that would expand without end, …
    const xmlError* err = xmlGetLastError();
    std::string why = err && err->message ? err->message : "";
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throw InputError({path, err && err->line > 0 ? err->line : 1},
                     "not a readable XML file (a Hopsan model is XML: .hmf)" + (why.empty() ? "" : ": " + why));
  }
  xmlNode* root = xmlDocGetRootElement(doc.get());
  if (!root || !is(root, "hopsanmodelfile")) throw InputError({path, 1}, "not a Hopsan model file (no <hopsanmodelfile>)");
  HmfModel out;
  HmfReader reader(path, out);
  xmlNode* system = child(root, "system");
  if (!system) throw InputError(reader.where(root), "the model has no <system>");
  ModelSpec& m = out.spec;
  m.source = path;
  m.simulation_where = reader.where(system);
  // Simulation settings.
  xmlNode* sim = child(system, "simulationtime");
  if (!sim) throw InputError(reader.where(system), "<system> has no <simulationtime>");
  double start = 0.0;
  if (!number(attr(sim, "timestep"), m.dt) || !number(attr(sim, "stop"), m.stop_time) ||
      !number(attr(sim, "start"), start))
    throw InputError(reader.where(sim), "<simulationtime>: start, stop and timestep must be numbers");
  m.start_time = start;  // Hopsan's GUI often writes a negative one: the run starts there
  double samples = 0.0;
  // The number of log samples: the system's logsamples (older files) or
  // <simulationlogsettings numsamples> (Hopsan 2.x), the latter first.
  xmlNode* log = child(system, "simulationlogsettings");
  double log_start = 0.0;
  if (log && number(attr(log, "starttime"), log_start) && log_start > m.start_time)
    out.notes.push_back(path + ": <simulationlogsettings starttime=" + attr(log, "starttime") +
                        ">: the results start at the run's start here, t = " + attr(sim, "start") +
                        " s (Hopsan's from that time)");
  if ((log && number(attr(log, "numsamples"), samples) && samples >= 1.0) ||
      (number(attr(system, "logsamples"), samples) && samples >= 1.0)) {
    const double steps = std::round((m.stop_time - m.start_time) / m.dt);
    m.log_every = static_cast<int>(std::max(1.0, std::floor(steps / samples)));
  }
  Expressions top;
  reader.read_system(system, "", top);
  reader.connect();
  m.hopsan_results = true;
  m.check_simulation();
  return out;
}

}  // namespace tlm
