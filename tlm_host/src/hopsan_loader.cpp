#include "hopsan_loader.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>
#include <muParser.h>

#include <algorithm>
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
      {"HydraulicTurbulentOrifice",
       {"HydraulicTurbulentOrificeQ", {{"A#Value", "A", 1e-5}, {"C_q#Value", "Cd", 0.67}, {"rho#Value", "rho", 870}}}},
      {"HydraulicLaminarOrifice", {"LaminarOrificeQ", {{"Kc#Value", "Kc", 1e-11}}}},
      {"HydraulicPressureSourceC", {"PressureSourceC", {{"p#Value", "p", 1e5}}}},
      {"HydraulicTankC", {"PressureSourceC", {{"p", "p", 1e5}}}},
      {"HydraulicFlowSourceQ", {"FlowSourceQ", {{"q#Value", "q", 1e-3}}}},
      // Signals (Hopsan evaluates them at the step's end time, as ours do).
      {"SignalConstant", {"SignalStep", {{"y#Value", "y0", 1.0}, {"y#Value", "y1", 1.0}}}},
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
      {"SignalGain", {"SignalGain", {{"k#Value", "k", 1.0}}, {}, {}, "", {{"in", "u"}, {"out", "y"}}}},
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
const std::set<std::string> kStepInInitialize = {"HydraulicTurbulentOrifice", "HydraulicFlowSourceQ",
                                                 "HydraulicPressureSourceC", "SignalStep", "SignalGain"};

// Hopsan's sensors read a node; their nodes are logged anyway.
const std::set<std::string> kSensors = {"HydraulicPressureSensor", "HydraulicFlowSensor", "HydraulicNodeSensor"};

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

}  // namespace

HmfModel read_hmf(const std::string& path) {
  using config::InputError;
  using config::SourceLocation;
  std::unique_ptr<xmlDoc, void (*)(xmlDoc*)> doc(xmlReadFile(path.c_str(), nullptr, XML_PARSE_NONET | XML_PARSE_NOERROR |
                                                                                     XML_PARSE_NOWARNING),
                                                 xmlFreeDoc);
  if (!doc) throw InputError({path, 1}, "not a readable XML file (a Hopsan model is XML: .hmf)");
  xmlNode* root = xmlDocGetRootElement(doc.get());
  auto where = [&](xmlNode* n) { return SourceLocation{path, static_cast<int>(xmlGetLineNo(n))}; };
  if (!root || !is(root, "hopsanmodelfile")) throw InputError({path, 1}, "not a Hopsan model file (no <hopsanmodelfile>)");
  xmlNode* system = child(root, "system");
  if (!system) throw InputError(where(root), "the model has no <system>");

  HmfModel out;
  ModelSpec& m = out.spec;
  m.source = path;
  m.simulation_where = where(system);
  // Simulation settings.
  xmlNode* sim = child(system, "simulationtime");
  if (!sim) throw InputError(where(system), "<system> has no <simulationtime>");
  double start = 0.0;
  if (!number(attr(sim, "timestep"), m.dt) || !number(attr(sim, "stop"), m.stop_time) ||
      !number(attr(sim, "start"), start))
    throw InputError(where(sim), "<simulationtime>: start, stop and timestep must be numbers");
  if (start != 0.0) throw InputError(where(sim), "<simulationtime> start " + attr(sim, "start") + ": runs start at t = 0");
  double samples = 0.0;
  if (number(attr(system, "logsamples"), samples) && samples >= 1.0) {
    const double steps = std::round(m.stop_time / m.dt);
    m.log_every = static_cast<int>(std::max(1.0, std::floor(steps / samples)));
  }
  // System parameters: numbers, or expressions of the ones before them.
  Expressions expressions;
  std::map<std::string, double>& system_params = expressions.variables;
  auto evaluate = [&](xmlNode* p, const std::string& what) {
    try {
      return expressions.evaluate(attr(p, "value"));
    } catch (const std::invalid_argument& e) {
      throw InputError(where(p), what + " = '" + attr(p, "value") + "': " + e.what());
    }
  };
  if (xmlNode* ps = child(system, "parameters"))
    for (xmlNode* p = ps->children; p; p = p->next)
      if (is(p, "parameter")) expressions.define(attr(p, "name"), evaluate(p, "system parameter '" + attr(p, "name") + "'"));
  auto value_of = [&](xmlNode* p, const std::string& component, const std::string& type) {
    return evaluate(p, component + " (" + type + "): parameter '" + attr(p, "name") + "'");
  };
  // Components.
  std::set<std::string> dropped_sensors;  // their signal must not be used
  struct Known {
    const Mapping* mapping = nullptr;  // nullptr: one of ours (Pcs…)
    size_t index = 0;                  // in m.components
    int multiport_count = 0;
  };
  std::map<std::string, Known> known;
  xmlNode* objects = child(system, "objects");
  if (objects)
    for (xmlNode* c = objects->children; c; c = c->next) {
      if (c->type != XML_ELEMENT_NODE) continue;
      const std::string name = attr(c, "name"), type = attr(c, "typename");
      if (!is(c, "component"))
        throw InputError(where(c), "'" + name + "' (<" + std::string(reinterpret_cast<const char*>(c->name)) +
                                       ">): nested subsystems and other objects are not read yet; flatten the model");
      if (name.empty() || name.find_first_of(". /#") != std::string::npos)
        throw InputError(where(c), "component name '" + name + "': ours may not contain dots, spaces, slashes or '#'");
      if (kSensors.count(type)) {
        dropped_sensors.insert(name);
        continue;
      }
      ComponentSpec s;
      s.name = name;
      s.where = where(c);
      s.params.set_where(s.where);
      xmlNode* params = child(c, "parameters");
      // One of ours, by our own names.
      if (type.rfind(kOwnPrefix, 0) == 0 && component_types().count(type.substr(3))) {
        s.type = type.substr(3);
        if (params)
          for (xmlNode* p = params->children; p; p = p->next) {
            if (!is(p, "parameter")) continue;
            s.params.set(attr(p, "name"), value_of_text(system_params)(attr(p, "value")), where(p));
          }
        known[name] = {nullptr, m.components.size()};
        m.components.push_back(std::move(s));
        continue;
      }
      if (type == "FMIWrapperQ") {
        fmu_wrapper(s, params, directory_of(path), where, value_of_text(system_params), out.notes);
        known[name] = {nullptr, m.components.size()};
        m.components.push_back(std::move(s));
        continue;
      }
      auto map = mappings().find(type);
      if (map == mappings().end()) {
        std::string mapped;
        for (const auto& [t, mp] : mappings()) mapped += (mapped.empty() ? "" : ", ") + t;
        throw InputError(where(c), "component '" + name + "' of Hopsan type " + type +
                                       " has no counterpart here yet (mapped: " + mapped + "; and tlm_host's own types as " +
                                       kOwnPrefix + "<Type>)");
      }
      const Mapping& mp = map->second;
      s.type = mp.ours;
      s.initial_step = kStepInInitialize.count(type) != 0;
      for (const auto& [key, value] : mp.fixed) s.params.set(key, value, s.where);
      // Every mapped parameter gets Hopsan's value: the file's, else Hopsan's default.
      std::map<std::string, std::pair<double, SourceLocation>> vals;
      for (const auto& prm : mp.params) vals.emplace(prm.hopsan, std::make_pair(prm.hopsan_default, s.where));
      std::optional<std::pair<double, SourceLocation>> start_p;
      if (params)
        for (xmlNode* p = params->children; p; p = p->next) {
          if (!is(p, "parameter")) continue;
          const std::string pname = current_name(attr(p, "name"), &mp);
          const size_t sep = pname.find('#');
          const std::string variable = sep == std::string::npos ? "" : pname.substr(sep + 1);
          if (mp.ignored.count(pname)) continue;
          if (auto it = vals.find(pname); it != vals.end()) {
            it->second = {value_of(p, name, type), where(p)};
            continue;
          }
          bool checked = false;
          for (const auto& [only, why] : mp.only)
            if (pname == only.first) {
              if (value_of(p, name, type) != only.second)
                throw InputError(where(p), name + " (" + type + "): parameter '" + pname + "' = '" + attr(p, "value") +
                                               "': only " + text_of(only.second) + " is read (" + why + ")");
              checked = true;
            }
          if (checked) continue;
          // A port's start value: the pressure where the component starts
          // from it; temperature and heat flow mean nothing to an
          // isothermal model; the wave variable and impedance are computed;
          // a flow must keep Hopsan's default (0) to start as Hopsan starts.
          if (variable == "Pressure") {
            if (!mp.start_pressure) continue;
            const double v = value_of(p, name, type);
            if (start_p && start_p->first != v)
              throw InputError(where(p), name + " (" + type + "): start pressure " + attr(p, "value") + " at " +
                                             pname.substr(0, sep) + " differs from " + text_of(start_p->first) +
                                             " at line " + std::to_string(start_p->second.line) + ": " + mp.ours +
                                             " starts at one pressure");
            start_p = std::make_pair(v, where(p));
            continue;
          }
          if (variable == "Temperature" || variable == "HeatFlow" || variable == "WaveVariable" ||
              variable == "CharImpedance" || variable == "CharImp")
            continue;
          if (variable == "Flow" && value_of(p, name, type) == 0.0) continue;
          throw InputError(where(p), name + " (" + type + "): parameter '" + pname + "' = '" + attr(p, "value") +
                                         "' has no counterpart in " + mp.ours);
        }
      auto set = [&](const char* key, double v, const SourceLocation& at) { s.params.set(key, text_of(v), at); };
      for (const auto& prm : mp.params)
        if (*prm.key) set(prm.key, vals.at(prm.hopsan).first, vals.at(prm.hopsan).second);
      for (const auto& [key, terms] : mp.sums)
        set(key, vals.at(terms.first).first + vals.at(terms.second).first, vals.at(terms.first).second);
      if (mp.start_pressure) set(mp.start_pressure, start_p ? start_p->first : 1e5, start_p ? start_p->second : s.where);
      for (const auto& [hopsan, ours] : mp.ports) m.result_ports[name + "." + ours] = hopsan;
      if (std::string(mp.note).size())
        out.notes.push_back(path + ":" + std::to_string(s.where.line) + ": " + name + " (" + type + " → " + mp.ours +
                            "): " + mp.note);
      known[name] = {&mp, m.components.size()};
      m.components.push_back(std::move(s));
    }
  // Connections: "component.port" pairs.
  if (xmlNode* cs = child(system, "connections"))
    for (xmlNode* c = cs->children; c; c = c->next) {
      if (!is(c, "connect")) continue;
      const std::string a = attr(c, "startcomponent"), b = attr(c, "endcomponent");
      for (const std::string& sensor : {a, b})
        if (dropped_sensors.count(sensor)) {
          const std::string port = sensor == a ? attr(c, "startport") : attr(c, "endport");
          if (port != "P1")
            throw InputError(where(c), "sensor " + sensor + ": its signal '" + port +
                                           "' is used; sensors are read only where nothing uses them (their node is logged)");
        }
      if (dropped_sensors.count(a) || dropped_sensors.count(b)) continue;  // the sensor's tap on the node
      auto ours = [&](const std::string& comp, const std::string& port) {
        auto it = known.find(comp);
        if (it == known.end() || !it->second.mapping) return comp + "." + port;
        const Mapping& mp = *it->second.mapping;
        if (mp.multiport && port == mp.multiport) {
          m.multiport_components.insert(comp);
          return comp + ".P" + std::to_string(++it->second.multiport_count);
        }
        auto renamed = mp.ports.find(port);
        return comp + "." + (renamed == mp.ports.end() ? port : renamed->second);
      };
      m.connections.push_back({ours(a, attr(c, "startport")), ours(b, attr(c, "endport")), where(c)});
    }
  for (const auto& [name, k] : known)
    if (k.mapping && k.mapping->multiport) {
      ComponentSpec& s = m.components[k.index];
      if (k.multiport_count == 0) throw InputError(s.where, name + ": its port " + k.mapping->multiport + " is not connected");
      s.params.set("ports", std::to_string(k.multiport_count), s.where);
    }
  for (const std::string& sensor : dropped_sensors)
    out.notes.push_back(path + ": " + sensor + ": a Hopsan sensor; its node's pressure and flow are in the results");
  m.hopsan_results = true;
  m.check_simulation();
  return out;
}

}  // namespace tlm
