#include "config/port_table.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace config {

const char* to_string(PortType t) {
  switch (t) {
    case PortType::Hydraulic: return "Hydraulic";
    case PortType::Mechanic: return "Mechanic";
    case PortType::Signal: return "Signal";
  }
  return "?";
}

const char* to_string(CouplingMode m) { return m == CouplingMode::Pressure ? "pressure" : "tlm"; }

namespace {
struct QuantityInfo {
  Quantity q;
  const char* symbol;
  const char* long_name;
  const char* unit;
};
constexpr QuantityInfo kQuantities[] = {
    {Quantity::Pressure, "p", "pressure", "Pa"},
    {Quantity::Flow, "q", "flow", "m3/s"},
    {Quantity::Wave, "c", "wave", "Pa"},
    {Quantity::Impedance, "Zc", "impedance", "Pa.s/m3"},
    {Quantity::Displacement, "x", "displacement", "m"},
    {Quantity::Velocity, "v", "velocity", "m/s"},
    {Quantity::Force, "F", "force", "N"},
    {Quantity::Signal, "y", "signal", "1"},
};
const QuantityInfo& info(Quantity q) {
  for (const auto& i : kQuantities)
    if (i.q == q) return i;
  return kQuantities[0];
}
}  // namespace

const char* symbol(Quantity q) { return info(q).symbol; }
const char* unit(Quantity q) { return info(q).unit; }
const char* long_name(Quantity q) { return info(q).long_name; }

const Port* PortTable::find_port(int id) const {
  for (const auto& p : ports)
    if (p.id == id) return &p;
  return nullptr;
}

std::string PortTable::canonical() const {
  char num[64];
  std::string s = "pcs-port-table-v1|model=" + model_name;
  std::snprintf(num, sizeof num, "|dt=%.17g", dt);
  s += num;
  s += std::string("|mode=") + to_string(mode) + "|subcycles=" + std::to_string(subcycles);
  if (hopsan) {  // only when set: every other table keeps its hash (and its FMUs their GUID)
    std::snprintf(num, sizeof num, "|hopsan:T=%.17g", hopsan_temperature);
    s += num;
    if (hopsan_start_pressure != 1e5) {  // only when set: FMUs of tables without it keep their GUID
      std::snprintf(num, sizeof num, ",p0=%.17g", hopsan_start_pressure);
      s += num;
    }
  }
  for (const auto& p : ports)
    s += "|port:" + std::to_string(p.id) + "," + p.label + "," + to_string(p.type);
  auto vars = [&](const char* dir, const std::vector<Variable>& vs) {
    for (const auto& v : vs) {
      std::snprintf(num, sizeof num, "%.17g", v.scale);
      s += std::string("|") + dir + ":" + std::to_string(v.port_id) + "," + symbol(v.quantity) +
           "," + num;
    }
  };
  vars("to_fe", to_fe);
  vars("to_host", to_host);
  return s;
}

uint64_t PortTable::hash() const {
  // FNV-1a, 64 bit (offset basis and prime from Fowler/Noll/Vo).
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : canonical()) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

static PortType parse_port_type(const Card& c, size_t i) {
  std::string t = to_lower(c.field(i, "type"));
  if (t == "hydraulic") return PortType::Hydraulic;
  if (t == "mechanic" || t == "mechanical") return PortType::Mechanic;
  if (t == "signal") return PortType::Signal;
  c.fail("port type '" + c.fields[i] + "': expected Hydraulic, Mechanic or Signal");
}

static Quantity parse_quantity(const Card& c, size_t i) {
  const std::string& t = c.field(i, "quantity");
  for (const auto& q : kQuantities)
    if (t == q.symbol || to_lower(t) == q.long_name) return q.q;
  c.fail("quantity '" + t +
         "': expected one of pressure (p), flow (q), wave (c), impedance (Zc), displacement (x), "
         "velocity (v), force (F), signal (y)");
}

// Which quantities may cross in which direction for a port type.
static bool allowed(PortType t, Quantity q, bool to_fe) {
  using Q = Quantity;
  switch (t) {
    case PortType::Hydraulic:
      return to_fe ? (q == Q::Pressure || q == Q::Wave || q == Q::Impedance)
                   : (q == Q::Flow || q == Q::Displacement || q == Q::Velocity || q == Q::Pressure);
    case PortType::Mechanic:
      return q == Q::Force || q == Q::Displacement || q == Q::Velocity;
    case PortType::Signal:
      return q == Q::Signal;
  }
  return false;
}

static void read_variables(const Block& b, PortTable& t, std::vector<Variable>& out, bool to_fe) {
  for (const auto& c : b.cards) {
    Variable v;
    v.where = c.where;
    v.port_id = static_cast<int>(c.integer(0, "port id"));
    v.quantity = parse_quantity(c, 1);
    v.scale = c.real_or(2, "scale", 1.0);
    if (!std::isfinite(v.scale) || v.scale == 0.0) c.fail("scale factor must be finite and non-zero");
    // A scale maps a symmetric FE model's share to the whole (a half model:
    // 2 for flows and forces, 0.5 for pressures in): always positive. A
    // negative one turned a pressure into a pull (pressure x -1 put the
    // piston 8.5 km away, exit 0); a sign convention belongs to the model.
    if (v.scale < 0.0)
      c.fail("scale factor " + c.field(2, "scale") + " is negative: scales map a symmetric model's share to the whole and "
             "are positive; flip a direction in the model, not here");
    const Port* p = t.find_port(v.port_id);
    if (!p)
      c.fail("port id " + std::to_string(v.port_id) +
             " is not listed in $FMU_HOPSAN_PORTS (define the port before its variables)");
    if (!allowed(p->type, v.quantity, to_fe))
      c.fail(std::string("a ") + to_string(p->type) + " port cannot " +
             (to_fe ? "send " : "receive ") + long_name(v.quantity) +
             (to_fe ? " to the FE side" : " from the FE side"));
    v.port_label = p->label;
    // One name per FMU variable: a quantity cannot go both ways at one port.
    for (const auto* list : {&t.to_fe, &t.to_host})
      for (const auto& other : *list)
        if (other.name() == v.name())
          c.fail("variable " + v.name() + " is already listed at " + other.where.str() +
                 (list == &t.to_fe && !to_fe ? " as sent: a port cannot send and receive the same quantity" : ""));
    out.push_back(v);
  }
}

static bool has(const std::vector<Variable>& vs, int port, Quantity q) {
  for (const auto& v : vs)
    if (v.port_id == port && v.quantity == q) return true;
  return false;
}

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

PortTable parse_port_table(const std::string& text, const std::string& name) {
  PortTable t;
  t.source = name;
  bool have_dt = false;
  SourceLocation top{name, 1};
  for (const auto& b : parse_keyword_text(text, name)) {
    if (b.keyword == "$FMU_SETTINGS") {
      for (const auto& c : b.cards) {
        std::string key = to_lower(c.field(0, "key"));
        const std::string& val = c.field(1, "value");
        if (key == "model") {
          t.model_name = val;
        } else if (key == "description") {
          // Free text: the rest of the card, commas included (fields were split on them).
          t.description = val;
          for (size_t f = 2; f < c.fields.size(); ++f) t.description += ", " + c.fields[f];
        } else if (key == "server") {
          t.server = val;
        } else if (key == "timestep") {
          t.dt = c.real(1, "timestep");
          if (!(t.dt > 0.0) || !std::isfinite(t.dt)) c.fail("timestep must be positive");
          have_dt = true;
        } else if (key == "mode") {
          std::string m = to_lower(val);
          if (m == "pressure") t.mode = CouplingMode::Pressure;
          else if (m == "tlm") t.mode = CouplingMode::Tlm;
          else c.fail("mode '" + val + "': expected pressure or tlm");
        } else if (key == "subcycles") {
          long k = c.integer(1, "subcycles");
          if (k < 1 || k > 100000) c.fail("subcycles must be between 1 and 100000");
          t.subcycles = static_cast<int>(k);
        } else if (key == "host_convention") {
          const std::string v = to_lower(val);
          if (v == "hopsan") t.hopsan = true;
          else if (v != "pcs") c.fail("host_convention '" + val + "': expected pcs (the default) or hopsan");
        } else if (key == "hopsan_temperature") {
          t.hopsan_temperature = c.real(1, "hopsan_temperature");
          if (!(t.hopsan_temperature > 0.0 && t.hopsan_temperature < 1e4)) c.fail("hopsan_temperature must be in kelvin, above 0");
        } else if (key == "hopsan_start_pressure") {
          t.hopsan_start_pressure = c.real(1, "hopsan_start_pressure");
          if (!(t.hopsan_start_pressure >= 0.0 && t.hopsan_start_pressure < 1e10))
            c.fail("hopsan_start_pressure must be an absolute pressure in Pa, from 0 to 1e10");
        } else if (key == "timeout") {
          t.timeout = c.real(1, "timeout");
          if (!(t.timeout > 0.0 && t.timeout <= 1e6))
            c.fail("timeout must be from 0 to 1e6 seconds (deadlines are kept in milliseconds)");
        } else {
          c.fail("unknown setting '" + c.fields[0] +
                 "': expected model, description, server, timestep, mode, subcycles, timeout, host_convention, "
                 "hopsan_temperature or hopsan_start_pressure");
        }
      }
    } else if (b.keyword == "$FMU_HOPSAN_PORTS") {
      for (const auto& c : b.cards) {
        Port p;
        p.where = c.where;
        p.id = static_cast<int>(c.integer(0, "id"));
        p.label = c.field(1, "label");
        p.type = parse_port_type(c, 2);
        if (p.label.empty() || p.label.find_first_of(" .\"<>&'") != std::string::npos)
          c.fail("port label '" + p.label + "' must be non-empty without spaces, dots or quotes");
        for (const auto& o : t.ports) {
          if (o.id == p.id) c.fail("port id " + std::to_string(p.id) + " already used at " + o.where.str());
          if (o.label == p.label) c.fail("port label '" + p.label + "' already used at " + o.where.str());
        }
        t.ports.push_back(p);
      }
    } else if (b.keyword == "$FMU_HOPSAN_SEND") {
      read_variables(b, t, t.to_fe, true);
    } else if (b.keyword == "$FMU_HOPSAN_RECEIVE") {
      read_variables(b, t, t.to_host, false);
    } else {
      b.fail("unknown block '" + b.keyword +
             "': expected $FMU_SETTINGS, $FMU_HOPSAN_PORTS, $FMU_HOPSAN_SEND or $FMU_HOPSAN_RECEIVE");
    }
  }
  if (t.model_name.empty()) throw InputError(top, "$FMU_SETTINGS needs 'model, NAME'");
  for (char ch : t.model_name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'))
      throw InputError(top, "model name '" + t.model_name +
                                "' must contain only letters, digits and '_' (it names the FMU binary)");
  if (!have_dt) throw InputError(top, "$FMU_SETTINGS needs 'timestep, SECONDS'");
  if (t.ports.empty()) throw InputError(top, "no ports: $FMU_HOPSAN_PORTS is missing or empty");
  // Each hydraulic port must carry what its coupling mode exchanges.
  for (const auto& p : t.ports) {
    if (p.type != PortType::Hydraulic) continue;
    bool ok = t.mode == CouplingMode::Pressure
                  ? has(t.to_fe, p.id, Quantity::Pressure)
                  : has(t.to_fe, p.id, Quantity::Wave) && has(t.to_fe, p.id, Quantity::Impedance);
    if (!ok)
      throw InputError(p.where, "hydraulic port '" + p.label + "' in " + to_string(t.mode) +
                                    " mode must send " +
                                    (t.mode == CouplingMode::Pressure ? "pressure" : "wave and impedance"));
    // Pressure mode may also send the host's impedance Zc: fe_server then
    // refuses a coupling step beyond pressure coupling's stability limit
    // before the first FE step (the port stays pressure-coupled). A wave
    // there would be a TLM port in a pressure-mode table.
    if (t.mode == CouplingMode::Pressure && has(t.to_fe, p.id, Quantity::Wave))
      throw InputError(p.where, "hydraulic port '" + p.label + "' in pressure mode sends a wave: the wave and "
                                    "impedance pair is TLM coupling (mode tlm); pressure mode sends pressure, and "
                                    "impedance only for fe_server's stability check");
    if (!has(t.to_host, p.id, Quantity::Flow))
      throw InputError(p.where, "hydraulic port '" + p.label + "' must receive flow");
  }
  if (t.hopsan) {
    if (t.mode != CouplingMode::Tlm)
      throw InputError(top, "host_convention hopsan needs mode tlm: Hopsan's FMIWrapperQ is a Q-type component "
                            "that sends each port's wave variable c and impedance Zc");
    for (const auto& p : t.ports)
      if (p.type == PortType::Mechanic)
        throw InputError(p.where, "port '" + p.label + "': host_convention hopsan maps hydraulic ports (Hopsan's "
                                  "NodeHydraulic) and signals; a mechanical port (NodeMechanic: v, f, x, c, Zc, me) "
                                  "is not offered yet");
  }
  return t;
}

PortTable read_port_table(const std::string& path) {
  return parse_port_table(read_text_file(path, "port configuration"), path);
}

std::vector<FmuVariable> fmu_variables(const PortTable& t) {
  std::vector<FmuVariable> out;
  unsigned vr = 0;
  for (size_t i = 0; i < t.to_fe.size(); ++i) {
    const auto& v = t.to_fe[i];
    const bool check_only = t.mode == CouplingMode::Pressure && v.quantity == Quantity::Impedance;
    out.push_back({v.name(), vr++, FmuCausality::Input, FmuType::Real, "0", unit(v.quantity),
                   check_only ? "the host's chamber impedance at port " + v.port_label +
                                    " (Zc = beta*T/V), for the FE side's stability check of pressure coupling; 0: "
                                    "not checked"
                              : std::string(long_name(v.quantity)) + " sent to the FE model at port " + v.port_label,
                   static_cast<int>(i)});
  }
  for (size_t i = 0; i < t.to_host.size(); ++i) {
    const auto& v = t.to_host[i];
    out.push_back({v.name(), vr++, FmuCausality::Output, FmuType::Real, "", unit(v.quantity),
                   std::string(long_name(v.quantity)) + " returned by the FE model at port " +
                       v.port_label,
                   static_cast<int>(i)});
  }
  if (t.hopsan) {
    // Hopsan's node variables the FE side does not send: computed here.
    // Outputs from the wire start at 0 before the first step ("exact").
    for (auto& v : out)
      if (v.causality == FmuCausality::Output) v.start = "0", v.initial = "exact";
    auto wire = [](const std::vector<Variable>& vs, int port, Quantity q) {
      for (size_t i = 0; i < vs.size(); ++i)
        if (vs[i].port_id == port && vs[i].quantity == q) return static_cast<int>(i);
      return -1;
    };
    char num[64];
    for (const auto& p : t.ports) {
      if (p.type != PortType::Hydraulic) continue;
      if (wire(t.to_host, p.id, Quantity::Pressure) < 0) {
        std::snprintf(num, sizeof num, "%s", shortest(t.hopsan_start_pressure).c_str());
        FmuVariable pv{p.label + ".p", vr++, FmuCausality::Output, FmuType::Real, num, "Pa",
                       "pressure at port " + p.label + ", p = c + Zc*q (Hopsan's node pressure); before the first "
                       "step its start value",
                       -1};
        pv.derived = FmuVariable::Derived::Pressure, pv.constant = t.hopsan_start_pressure, pv.initial = "exact";
        pv.wire_c = wire(t.to_fe, p.id, Quantity::Wave);
        pv.wire_zc = wire(t.to_fe, p.id, Quantity::Impedance);
        pv.wire_q = wire(t.to_host, p.id, Quantity::Flow);
        out.push_back(pv);
      }
      std::snprintf(num, sizeof num, "%s", shortest(t.hopsan_temperature).c_str());
      FmuVariable T{p.label + ".T", vr++, FmuCausality::Output, FmuType::Real, num, "K",
                    "oil temperature at port " + p.label + " (isothermal: constant)", -1};
      T.derived = FmuVariable::Derived::Constant, T.constant = t.hopsan_temperature, T.initial = "exact";
      out.push_back(T);
      FmuVariable Q{p.label + ".Qdot", vr++, FmuCausality::Output, FmuType::Real, "0", "W",
                    "heat flow at port " + p.label + " (isothermal: none)", -1};
      Q.derived = FmuVariable::Derived::Constant, Q.initial = "exact";
      out.push_back(Q);
    }
  }
  out.push_back({"server.host", kVrServerHost, FmuCausality::Parameter, FmuType::String, "", "",
                 "fe_server host; empty: $PCS_SERVER_HOST, else the port configuration", -1});
  out.push_back({"server.port", kVrServerPort, FmuCausality::Parameter, FmuType::Integer, "0", "",
                 "fe_server port; 0: $PCS_SERVER_PORT, else the port configuration", -1});
  out.push_back({"server.token", kVrServerToken, FmuCausality::Parameter, FmuType::String, "", "",
                 "session token; empty: $PCS_TOKEN, else the file named by $PCS_TOKEN_FILE", -1});
  out.push_back({"server.timeout", kVrTimeout, FmuCausality::Parameter, FmuType::Real, shortest(t.timeout), "s",
                 "deadline for connect, handshake and each step's result", -1});
  return out;
}

std::string hopsan_portspecs(const PortTable& t) {
  if (!t.hopsan) return "";
  std::string s;
  for (const auto& p : t.ports) {
    if (p.type != PortType::Hydraulic) continue;
    s += (s.empty() ? "" : ";") + std::string("NodeHydraulic:") + p.label;
    for (const char* slot : kHopsanNodeHydraulic) s += "," + p.label + "." + slot;
  }
  return s;
}

std::string fmu_guid(const PortTable& t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "pcs-%016llx", static_cast<unsigned long long>(t.hash()));
  return buf;
}

PortTable combine_port_tables(const std::vector<PortTable>& tables) {
  if (tables.empty()) throw std::invalid_argument("combine_port_tables: no table");
  if (tables.size() == 1) return tables.front();
  PortTable all = tables.front();
  all.model_name.clear();
  all.source.clear();
  all.ports.clear();
  all.to_fe.clear();
  all.to_host.clear();
  for (const PortTable& t : tables) {
    const SourceLocation top{t.source, 1};
    if (t.dt != all.dt || t.mode != all.mode || t.subcycles != all.subcycles)
      throw InputError(top, "timestep, mode and subcycles must equal those of " + tables.front().source +
                                " when both serve one fe_server session");
    for (const Port& p : t.ports)
      for (const Port& q : all.ports)
        if (p.id == q.id || p.label == q.label)
          throw InputError(p.where, "port " + std::to_string(p.id) + " (" + p.label + ") clashes with port " +
                                        std::to_string(q.id) + " (" + q.label + ") of " + q.where.str() +
                                        ": ports of one session need distinct ids and labels");
    all.model_name += (all.model_name.empty() ? "" : "+") + t.model_name;
    all.source += (all.source.empty() ? "" : ", ") + t.source;
    all.timeout = std::max(all.timeout, t.timeout);
    all.ports.insert(all.ports.end(), t.ports.begin(), t.ports.end());
    all.to_fe.insert(all.to_fe.end(), t.to_fe.begin(), t.to_fe.end());
    all.to_host.insert(all.to_host.end(), t.to_host.begin(), t.to_host.end());
  }
  return all;
}

}  // namespace config
