#include "model.hpp"

#include "config/port_table.hpp"
#include "config/nearest.hpp"
#include "config/stop_signal.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>
#include <tuple>
#include <unistd.h>

#include <filesystem>
#include <future>

#include "components/cosim/FmuQ.hpp"

namespace tlm {

using config::InputError;

const ComponentSpec* ModelSpec::find(const std::string& name) const {
  for (const auto& c : components)
    if (c.name == name) return &c;
  return nullptr;
}

ComponentSpec* ModelSpec::find(const std::string& name) {
  return const_cast<ComponentSpec*>(static_cast<const ModelSpec*>(this)->find(name));
}

// log_every as an int: 1 to 10⁹ (a larger one would wrap).
static int log_every_in_range(long n, const config::SourceLocation& where) {
  if (n < 1 || n > 1000000000L)
    throw config::InputError(where, "log_every must be from 1 to 1e9, got " + std::to_string(n));
  return static_cast<int>(n);
}

void ModelSpec::check_simulation() const {
  const config::SourceLocation& where = simulation_where;
  if (!(dt > 0.0)) throw config::InputError(where, "*SIMULATION needs 'timestep, SECONDS' > 0");
  if (!(stop_time > start_time))
    throw config::InputError(where, start_time == 0.0 ? std::string("*SIMULATION needs 'stoptime, SECONDS' > 0")
                                                      : "the stop time (" + config::shortest(stop_time) +
                                                            " s) must follow the start time (" +
                                                            config::shortest(start_time) + " s)");
  if (!((stop_time - start_time) / dt < 1e12))
    throw config::InputError(where, "stoptime / timestep is " + std::to_string((stop_time - start_time) / dt) +
                                        " steps: more than 10¹² is not a run that ends");
  if (log_every < 1) throw config::InputError(where, "log_every must be at least 1");
}

void ModelSpec::apply_override(const std::string& assignment) {
  size_t dot = assignment.find('.'), eq = assignment.find('=');
  if (dot == std::string::npos || eq == std::string::npos || dot > eq)
    throw std::invalid_argument("--set '" + assignment + "': expected COMPONENT.PARAMETER=VALUE");
  std::string comp = assignment.substr(0, dot), key = assignment.substr(dot + 1, eq - dot - 1),
              value = assignment.substr(eq + 1);
  config::SourceLocation where{"--set " + assignment, 0};
  if (comp == "simulation") {
    if (key == "timestep") dt = config::parse_real(value, where, "timestep");
    else if (key == "stoptime") stop_time = config::parse_real(value, where, "stoptime");
    else if (key == "log_every") log_every = log_every_in_range(config::parse_integer(value, where, "log_every"), where);
    else throw std::invalid_argument("--set: simulation has timestep, stoptime and log_every, not '" + key + "'");
    simulation_where = where;
    return;
  }
  ComponentSpec* c = find(comp);
  if (!c) throw std::invalid_argument("--set '" + assignment + "': no component named '" + comp + "' in " + source);
  c->params.set(key, value, where);
}

static std::string directory_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

ModelSpec parse_model(const std::string& text, const std::string& name) {
  ModelSpec m;
  m.source = name;
  for (const auto& b : config::parse_keyword_text(text, name)) {
    if (b.keyword == "*SIMULATION") {
      for (const auto& c : b.cards) {
        std::string key = config::to_lower(c.field(0, "key"));
        if (key == "timestep") m.dt = c.real(1, "timestep");
        else if (key == "stoptime") m.stop_time = c.real(1, "stoptime");
        else if (key == "log_every") m.log_every = log_every_in_range(c.integer(1, "log_every"), c.where);
        else c.fail("unknown setting '" + c.fields[0] + "': expected timestep, stoptime or log_every");
      }
    } else if (b.keyword == "*COMPONENT") {
      for (const auto& c : b.cards) {
        ComponentSpec s;
        s.where = c.where;
        s.name = c.field(0, "name");
        s.type = c.field(1, "type");
        if (s.name.empty() || s.name.find_first_of(". /") != std::string::npos)
          c.fail("component name '" + s.name + "' must be non-empty without dots, spaces or slashes");
        if (m.find(s.name)) c.fail("component '" + s.name + "' is defined twice");
        if (!component_types().count(s.type)) {
          std::string known;
          std::vector<std::string> types;
          for (const auto& [t, f] : component_types()) known += (known.empty() ? "" : ", ") + t, types.push_back(t);
          const std::string near = config::nearest(s.type, types);
          c.fail("unknown component type '" + s.type + "'" + (near.empty() ? "" : " (did you mean " + near + "?)") +
                 "; known types: " + known);
        }
        s.params.set_where(c.where);
        for (size_t i = 2; i < c.fields.size(); ++i) {
          const std::string& f = c.fields[i];
          if (f.empty()) continue;
          size_t eq = f.find('=');
          if (eq == std::string::npos) c.fail("field " + std::to_string(i + 1) + " '" + f + "': expected key=value");
          std::string key = config::trim(f.substr(0, eq)), value = config::trim(f.substr(eq + 1));
          // File parameters are relative to the model file.
          if (key == "fmu" && !value.empty() && value[0] != '/') value = directory_of(name) + value;
          s.params.set(key, value, c.where);
        }
        m.components.push_back(std::move(s));
      }
    } else if (b.keyword == "*REPORT") {
      m.report.insert(m.report.end(), b.cards.begin(), b.cards.end());
    } else if (b.keyword == "*LOG") {
      // One or more series or groups per card (System checks each against its series).
      for (const auto& c : b.cards)
        for (const std::string& f : c.fields)
          if (!f.empty()) m.log_only.emplace_back(f, c.where);
    } else if (b.keyword == "*CONNECT") {
      for (const auto& c : b.cards) m.connections.push_back({c.field(0, "port"), c.field(1, "port"), c.where});
    } else {
      b.fail("unknown keyword '" + b.keyword + "': expected *SIMULATION, *COMPONENT, *CONNECT, *REPORT or *LOG");
    }
  }
  m.simulation_where = config::SourceLocation{name, 1};
  m.check_simulation();
  return m;
}

ModelSpec read_model(const std::string& path) {
  return parse_model(config::read_text_file(path, "model"), path);
}

System::System(ModelSpec spec) : spec_(std::move(spec)) {
  spec_.check_simulation();
  for (auto& cs : spec_.components) {
    auto comp = component_types().at(cs.type)(cs.name);
    comp->configure(cs.params);
    cs.params.check_all_used(cs.name);
    if (const std::string why = comp->step_mismatch(spec_.dt); !why.empty()) throw InputError(cs.params.where(), why);
    switch (comp->kind()) {
      case Kind::Signal: signal_.push_back(comp.get()); break;
      case Kind::C: c_type_.push_back(comp.get()); break;
      case Kind::Q: q_type_.push_back(comp.get()); break;
    }
    components_.push_back(std::move(comp));
  }
  auto component_of = [&](const std::string& ref, const config::SourceLocation& where) {
    size_t dot = ref.find('.');
    if (dot == std::string::npos) throw InputError(where, "'" + ref + "': expected COMPONENT.PORT");
    Component* c = find(ref.substr(0, dot));
    if (!c) throw InputError(where, "no component named '" + ref.substr(0, dot) + "'");
    return std::make_pair(c, ref.substr(dot + 1));
  };
  auto resolve = [&](const std::string& ref, const config::SourceLocation& where) -> std::pair<Component*, Port*> {
    auto [c, name] = component_of(ref, where);
    Port* p = c->port(name);
    if (!p) {
      std::string names;
      for (const auto& q : c->ports()) names += (names.empty() ? "" : ", ") + q.name;
      for (const auto& s : c->signals()) names += (names.empty() ? "" : ", ") + s.name + (s.output ? " (signal out)" : " (signal in)");
      throw InputError(where, c->name() + " (" + c->type_name() + ") has no port '" + name + "'; its ports: " + names);
    }
    if (p->node) throw InputError(where, "port " + ref + " is connected twice");
    return {c, p};
  };
  std::vector<std::pair<Component*, Component*>> signal_edges;  // (from, to) of each signal connection
  for (const auto& con : spec_.connections) {
    // A signal connection: one output, one input.
    auto [ca0, na] = component_of(con.a, con.where);
    auto [cb0, nb] = component_of(con.b, con.where);
    SignalPort* sa = ca0->signal(na);
    SignalPort* sb = cb0->signal(nb);
    if (sa || sb) {
      if (!sa || !sb || sa->output == sb->output)
        throw InputError(con.where, "'" + con.a + "' and '" + con.b + "': a signal connection joins one signal output and one signal input");
      SignalPort* in = sa->output ? sb : sa;
      SignalPort* out = sa->output ? sa : sb;
      if (bound_.count(in)) throw InputError(con.where, "signal input " + (sa->output ? con.b : con.a) + " is connected twice");
      *in->source = out->value;
      bound_.insert(in);
      signal_edges.emplace_back(sa->output ? ca0 : cb0, sa->output ? cb0 : ca0);
      continue;
    }
    auto [ca, pa] = resolve(con.a, con.where);
    auto [cb, pb] = resolve(con.b, con.where);
    if (pa->side == pb->side)
      throw InputError(con.where, "'" + con.a + "' and '" + con.b + "' are both " +
                                      (pa->side == Kind::C ? "C-type (capacitive)" : "Q-type (resistive)") +
                                      " ports: a TLM node joins one C and one Q port; put a " +
                                      (pa->side == Kind::C ? "Q component (e.g. an orifice)" : "C component (e.g. a volume)") +
                                      " between them");
    if (pa->mechanical != pb->mechanical)
      throw InputError(con.where, "'" + con.a + "' is " + (pa->mechanical ? "a mechanical" : "a hydraulic") + " port and '" +
                                      con.b + "' " + (pb->mechanical ? "a mechanical" : "a hydraulic") +
                                      " one: a node joins ports of one kind");
    auto node = std::make_unique<HydraulicNode>();
    node->name = pa->side == Kind::C ? con.a : con.b;
    node->mechanical = pa->mechanical;
    if (node->mechanical) node->me = 1.0;  // Hopsan's NodeMechanic starts with 1 kg until a mass writes its own
    pa->node = pb->node = node.get();
    nodes_.push_back(std::move(node));
  }
  for (auto& c : components_)
    for (auto& s : c->signals())
      if (!s.output && !s.optional && !bound_.count(&s))
        throw InputError(config::SourceLocation{spec_.source, 1},
                         "signal input " + c->name() + "." + s.name + " is not connected (add it to *CONNECT)");
  for (auto& c : components_)
    for (auto& p : c->ports())
      if (!p.node)
        throw InputError(spec_.source.empty() ? config::SourceLocation{"model", 0} : config::SourceLocation{spec_.source, 1},
                         "port " + c->name() + "." + p.name + " is not connected (add it to *CONNECT)");
  if (spec_.hopsan_results) order_signals_as_hopsan(signal_edges);
  // The node guard's bounds, once the signals are connected (a source a signal drives may reach any pressure).
  double sources = 1e5;    // the highest finite source or start pressure (at least the atmosphere)
  bool unbounded = false;  // a component that drives its nodes to any pressure
  for (const auto& comp : components_) {
    const double source = comp->source_pressure();
    if (source >= 1e300)
      unbounded = true;
    else
      sources = std::max(sources, source);
  }
  highest_pressure_ = unbounded ? 1e300 : kSourceFactor * sources;
  lowest_port_pressure_ = kLowestPressure - kUndershoot * sources;
  std::set<const HydraulicNode*> fmu_nodes;  // the FMUs' hydraulic port nodes
  for (auto& c : components_)
    if (dynamic_cast<FmuQ*>(c.get())) {
      if (spec_.start_time != 0.0)
        throw InputError(spec_.simulation_where, c->name() + ": an FMU's co-simulation starts at t = 0, and this model starts at " +
                                                     config::shortest(spec_.start_time) + " s: set the start time to 0");
      for (auto& p : c->ports())
        if (!p.node->mechanical) fmu_nodes.insert(p.node);
    }
  const double inf = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const HydraulicNode* n = nodes_[i].get();
    const bool port = fmu_nodes.count(n) != 0;
    if (port) fmu_node_index_.push_back(i);
    node_lo_.push_back(port ? lowest_port_pressure_ : -inf);
    node_hi_.push_back(n->mechanical || highest_pressure_ >= 1e300 ? inf : highest_pressure_);
  }
  if (!spec_.log_only.empty()) {  // a *LOG entry that names nothing: refused now, not after the run began
    const double t = 0.0;
    logged_series(&t);
  }
}

// Hopsan steps its signal components in the order of their connections,
// each after those feeding it (ours step in the model's order): the same
// order here, by Kahn's algorithm, ties in the model's order. Components in
// a loop (an algebraic loop, which Hopsan warns of) keep the model's order
// after the others.
void System::order_signals_as_hopsan(const std::vector<std::pair<Component*, Component*>>& edges) {
  std::map<Component*, int> waiting;  // inputs from signal components not yet placed
  for (Component* c : signal_) waiting[c] = 0;
  for (const auto& [from, to] : edges)
    if (waiting.count(from) && waiting.count(to)) ++waiting[to];
  std::vector<Component*> ordered;
  std::set<Component*> placed;
  while (ordered.size() < signal_.size()) {
    Component* next = nullptr;
    for (Component* c : signal_)
      if (!placed.count(c) && waiting[c] == 0) {
        next = c;
        break;
      }
    if (!next) break;  // the rest are in a loop
    ordered.push_back(next);
    placed.insert(next);
    for (const auto& [from, to] : edges)
      if (from == next && waiting.count(to)) --waiting[to];
  }
  for (Component* c : signal_)
    if (!placed.count(c)) ordered.push_back(c);
  signal_ = ordered;
}

System::~System() = default;

std::vector<std::string> System::stability_warnings(double dt) const {
  std::vector<std::string> out;
  for (const auto& c : components_) {
    std::string why;
    const double limit = c->stable_step(&why);
    if (dt > limit) {
      std::ostringstream s;
      s << "time step " << dt << " s exceeds the stable step " << limit << " s of " << why
        << "; lower simulation.timestep";
      out.push_back(s.str());
    }
  }
  return out;
}

std::string System::check_fmu_nodes() const {
  for (size_t i : fmu_node_index_) {
    const HydraulicNode& n = *nodes_[i];
    if (!(n.p >= node_lo_[i] && n.p <= node_hi_[i] && std::isfinite(n.p + n.q + n.c + n.Zc)))
      return node_failure(n, node_lo_[i]);
  }
  return "";
}

std::string System::check_nodes() const {
  // The hot path, branch-free: x·0 is 0 for every finite x and NaN for a
  // NaN or an infinity; a pressure out of its bounds counts one.
  double bad = 0.0;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const HydraulicNode& n = *nodes_[i];
    bad += (n.p + n.q + n.c + n.Zc + n.x) * 0.0 + static_cast<double>(!(n.p >= node_lo_[i] && n.p <= node_hi_[i]));
  }
  if (bad == 0.0) return "";
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const HydraulicNode& n = *nodes_[i];
    if (!(n.p >= node_lo_[i] && n.p <= node_hi_[i] && std::isfinite(n.p + n.q + n.c + n.Zc + n.x)))
      return node_failure(n, node_lo_[i]);
  }
  return "";
}

std::string System::node_failure(const HydraulicNode& node, double lowest) const {
  const HydraulicNode* n = &node;
  const bool finite = std::isfinite(n->p) && std::isfinite(n->q) && std::isfinite(n->c) && std::isfinite(n->Zc) &&
                      std::isfinite(n->x);
  std::ostringstream s;
  s.precision(4);
  if (!finite) {
    s << "node " << n->name << " is no longer finite (" << (n->mechanical ? "F = " : "p = ") << n->p
      << (n->mechanical ? ", v = " : ", q = ") << n->q << ", c = " << n->c << ", Zc = " << n->Zc
      << "): the step is unstable for this model; lower simulation.timestep or check the parameters";
  } else if (n->p < lowest) {
    s << "the pressure at the FMU's port node " << n->name << " is " << n->p / 1e5 << " bar absolute, below "
      << lowest / 1e5 << " bar (−1 bar, less " << kUndershoot * 100
      << " % of the highest source pressure for a cavitating chamber's undershoot), where no oil is liquid: the "
         "chamber behind the port cavitates within a coupling step (Zc·q of the port's flow exceeds its pressure: "
         "the chamber is small for that flow), or the coupling step is too coarse for it (see fe_server's coupling "
         "estimate); a larger chamber or a smaller coupling step";
  } else {
    s << "the pressure at node " << n->name << " is " << n->p / 1e5 << " bar, more than " << kSourceFactor
      << " times the model's highest source or start pressure (" << highest_pressure_ / kSourceFactor / 1e5
      << " bar): nothing in a circuit driven by these sources reaches it; the step is too coarse or a parameter "
         "is off by a unit (Pa, not bar)";
  }
  return s.str();
}

// Every series the model has, then those *LOG keeps (all without one); an
// entry that names nothing is refused at its line, before any file is
// written (the constructor checks with a placeholder time).
std::vector<System::LoggedSeries> System::logged_series(const double* time) const {
  std::vector<LoggedSeries> all{{"time", "s", time}};
  for (const auto& n : nodes_) {
    if (n->mechanical) {
      all.push_back({"nodes/" + n->name + "/F", "N", &n->p});
      all.push_back({"nodes/" + n->name + "/v", "m/s", &n->q});
      all.push_back({"nodes/" + n->name + "/x", "m", &n->x});
      continue;
    }
    all.push_back({"nodes/" + n->name + "/p", "Pa", &n->p});
    all.push_back({"nodes/" + n->name + "/q", "m3/s", &n->q});
  }
  for (auto& c : components_) {
    std::vector<LogVariable> vars;
    c->log_variables(vars);
    for (const auto& v : vars) all.push_back({"components/" + c->name() + "/" + v.name, v.unit, v.value});
  }
  std::vector<bool> kept(all.size(), spec_.log_only.empty());
  kept[0] = true;  // the time
  for (const auto& [entry, where] : spec_.log_only) {
    bool found = false;
    for (size_t i = 0; i < all.size(); ++i) {
      const std::string& n = all[i].name;
      if (n == entry || (n.size() > entry.size() && n.compare(0, entry.size(), entry) == 0 && n[entry.size()] == '/'))
        kept[i] = found = true;
    }
    if (found) continue;
    // Name the group it was meant to be in, with what that group holds.
    std::string group = entry.substr(0, entry.rfind('/') == std::string::npos ? 0 : entry.rfind('/')), here;
    for (const LoggedSeries& x : all)
      if (!group.empty() && x.name.compare(0, group.size() + 1, group + "/") == 0)
        here += (here.empty() ? "" : ", ") + x.name.substr(group.size() + 1);
    throw config::InputError(where, "*LOG: the model has no series or group '" + entry + "' (" +
                                        (here.empty() ? "series are nodes/<node>/<p, q or F, v, x> and "
                                                        "components/<component>/<variable>"
                                                      : group + " holds " + here) +
                                        ")");
  }

  std::vector<LoggedSeries> out;
  for (size_t i = 0; i < all.size(); ++i)
    if (kept[i]) out.push_back(all[i]);
  return out;
}

Component* System::find(const std::string& name) {
  for (auto& c : components_)
    if (c->name() == name) return c.get();
  return nullptr;
}

void System::exchange_state(config::StateIO& io) {
  io.expect("nodes", nodes_.size(), "the number of hydraulic nodes");
  for (auto& n : nodes_) {
    io.value("node p", n->p);
    io.value("node q", n->q);
    io.value("node c", n->c);
    io.value("node Zc", n->Zc);
    if (n->mechanical) {  // a hydraulic model's checkpoints stay as they were
      io.value("node x", n->x);
      io.value("node me", n->me);
    }
  }
  io.expect("components", components_.size(), "the number of components");
  for (auto& c : components_) {
    std::string name = c->name();
    io.expect("component", name, "the components in file order");
    c->state(io);
  }
}

void System::hopsan_names(h5io::TimeSeriesWriter& out,
                          const std::function<void(const std::string&, const std::string&, const double*)>& add,
                          std::vector<const double*>& csv_sources, std::vector<std::string>& csv_header,
                          const double* time) {
  // Hopsan's CSV: the components in name order, their ports in name order,
  // each port's node variables in its node's data order (Temperature and
  // HeatFlow left out: the model is isothermal) or a signal port's Value,
  // Time last; three header lines (name, alias, unit). Its HDF5 export's
  // paths: results/<component>/<port>/<variable>. A subsystem's own ports
  // and time, and a sensor's, are not written (the same values are under
  // the names of the components at those nodes).
  std::vector<Component*> sorted;
  for (auto& c : components_) sorted.push_back(c.get());
  std::sort(sorted.begin(), sorted.end(), [](Component* a, Component* b) { return a->name() < b->name(); });
  std::vector<std::string> csv_names, csv_units;
  auto hopsan_port = [&](Component* c, const std::string& port) {
    auto it = spec_.result_ports.find(c->name() + "." + port);
    return it == spec_.result_ports.end() ? port : it->second;
  };
  csv_sources.clear();
  for (Component* c : sorted) {
    // A subsystem's component (valve$edge) is a group below its subsystem's.
    std::string group = c->name();
    std::replace(group.begin(), group.end(), '$', '/');
    // Hopsan lists a component's ports by name, each port's variables in
    // its node's data order.
    using Slot = std::tuple<std::string, std::string, const double*>;  // variable, unit, value
    std::vector<std::pair<std::string, std::vector<Slot>>> columns;
    for (const Port& p : c->ports()) {
      if (spec_.unlogged_ports.count(c->name() + "." + p.name)) continue;
      const std::string port = hopsan_port(c, p.name);
      const std::string path = "results/" + group + "/" + port + "/", node = "/nodes/" + p.node->name + "/";
      HydraulicNode& n = *p.node;
      if (n.mechanical) {
        out.add_link(path + "Velocity", node + "v");
        out.add_link(path + "Force", node + "F");
        out.add_link(path + "Position", node + "x");
        columns.push_back({port,
                           {{"Velocity", "m/s", &n.q}, {"Force", "N", &n.p}, {"Position", "m", &n.x},
                            {"WaveVariable", "N", &n.c}, {"CharImpedance", "N s/m", &n.Zc},
                            {"EquivalentMass", "kg", &n.me}}});
      } else {
        out.add_link(path + "Flow", node + "q");
        out.add_link(path + "Pressure", node + "p");
        columns.push_back({port,
                           {{"Flow", "m^3/s", &n.q}, {"Pressure", "Pa", &n.p}, {"WaveVariable", "Pa", &n.c},
                            {"CharImpedance", "Pa s/m^3", &n.Zc}}});
      }
    }
    for (const SignalPort& sp : c->signals()) {
      if (!sp.output && !bound_.count(&sp)) continue;  // an input left open: Hopsan logs it only when connected
      const double* value = sp.output ? sp.value : *sp.source;
      const std::string port = hopsan_port(c, sp.name);
      add("results/" + group + "/" + port + "/Value", "", value);
      columns.push_back({port, {{"Value", "", value}}});
    }
    std::stable_sort(columns.begin(), columns.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [port, slots] : columns)
      for (const auto& [var, unit, value] : slots) {
        csv_names.push_back(c->name() + "#" + port + "#" + var);
        csv_units.push_back(unit);
        csv_sources.push_back(value);
      }
  }
  out.add_link("results/Time", "/time");
  csv_names.push_back("Time");
  csv_units.push_back("s");
  csv_sources.push_back(time);
  csv_header.assign(3, "");
  for (size_t i = 0; i < csv_names.size(); ++i) {
    csv_header[0] += (i ? "," : "") + csv_names[i];
    csv_header[1] += i ? "," : "";
    csv_header[2] += (i ? "," : "") + csv_units[i];
  }
}

void System::run(const std::string& out_path, bool progress) {
  const double dt = spec_.dt;
  const long steps = std::lround((spec_.stop_time - spec_.start_time) / dt);
  const double t0 = spec_.start_time;
  std::vector<FmuQ*> fmus;
  for (auto& c : components_)
    if (auto* f = dynamic_cast<FmuQ*>(c.get())) fmus.push_back(f);
  // A restart: the identity and the step first, so the FMUs can resume
  // their sessions at it while they connect (initialize()).
  const bool resume = !checkpointing_.restart.empty();
  std::unique_ptr<config::StateReader> restart;
  long first = 0;
  uint64_t resumed_rows = 0, csv_bytes = 0;
  // The series written are part of what a restart must match: a results
  // file continued with fewer (another --log) would keep the dropped ones
  // cut at the checkpoint while the rest grow, with no word.
  std::string series_names;
  {
    const double placeholder = 0.0;
    for (const LoggedSeries& x : logged_series(&placeholder)) series_names += x.name + "\n";
  }
  auto identity = [&](config::StateIO& io, long& step) {
    io.expect("kind", std::string("tlm_host"), "the checkpoint's program");
    io.expect("model digest", config::file_sha256(spec_.source), "the model file's contents (SHA-256)");
    io.expect("logged series", config::text_sha256(series_names), "the series written (*LOG, --log; SHA-256)");
    io.expect("timestep", static_cast<uint64_t>(std::llround(dt * 1e15)), "the time step in fs");
    io.value("step", step);
  };
  if (resume) {
    try {
      restart = std::make_unique<config::StateReader>(checkpointing_.restart);
      identity(*restart, first);
    } catch (const config::CheckpointError& e) {
      throw config::CheckpointError("checkpoint '" + checkpointing_.restart + "': " + e.what());
    }
    if (first < 0 || first > steps)
      throw config::CheckpointError("checkpoint '" + checkpointing_.restart + "' is after step " + std::to_string(first) +
                                    ", beyond this run's " + std::to_string(steps) + " steps");
    for (FmuQ* f : fmus) f->set_resume_step(first);
  }
  for (auto& c : components_) c->set_start_time(t0);
  if (spec_.hopsan_results) {
    // As Hopsan starts: signal, C, then Q components, each taking its
    // initial step (ComponentSpec::initial_step) right after its own
    // initialization, so a Q component starts from the C side's waves.
    for (const auto* order : {&signal_, &c_type_, &q_type_})
      for (Component* c : *order) {
        c->initialize(dt);
        if (!resume && spec_.find(c->name())->initial_step) c->simulate_one_step(t0);
      }
  } else {
    for (auto& c : components_) c->initialize(dt);
  }
  std::vector<Component*> peers;
  for (Component* c : q_type_)
    if (c->waits_on_peer()) peers.push_back(c);
  if (peers.size() > 1) {
    peers_ = std::make_unique<PeerGroup>(peers, peer_stepping_);
    q_type_.erase(std::remove_if(q_type_.begin(), q_type_.end(),
                                 [&](Component* c) { return c->waits_on_peer() && c != peers.front(); }),
                  q_type_.end());
  }
  for (const auto& w : stability_warnings(dt)) std::cerr << "tlm_host: warning: " << w << "\n";
  // A restart touches its results only once every server has agreed to
  // resume at this step (all FMUs at once: a server answers when all of its
  // FMUs are in). A refused restart leaves every file as it was.
  if (resume) {
    std::vector<std::future<void>> answers;
    for (FmuQ* f : fmus) answers.push_back(std::async(std::launch::async, [f] { f->confirm_resume(); }));
    for (auto& a : answers) a.get();
  }

  double time = t0;
  const std::vector<LoggedSeries> logged = logged_series(&time);
  h5io::TimeSeriesWriter out(out_path, 4096, 1.0, resume);
  out.set_attribute("producer", "tlm_host");
  out.set_attribute("model", spec_.source);
  out.set_attribute("timestep", dt);
  if (!spec_.log_only.empty()) out.set_attribute("logged", "only the series *LOG (or --log) names and the report's");
  std::vector<const double*> sources;
  std::vector<std::string> names;
  auto add = [&](const std::string& name, const std::string& unit, const double* value) {
    out.add_series(name, unit);
    names.push_back(name + " [" + unit + "]");
    sources.push_back(value);
  };
  for (const LoggedSeries& x : logged) add(x.name, x.unit, x.value);
  // The CSV's columns: ours, or a Hopsan model's in Hopsan's layout.
  std::vector<const double*> csv_sources = sources;
  std::vector<std::string> csv_header(1);
  for (size_t i = 0; i < names.size(); ++i) csv_header[0] += (i ? "," : "") + names[i];
  if (spec_.hopsan_results) hopsan_names(out, add, csv_sources, csv_header, &time);
  if (resume) {
    try {
      exchange_state(*restart);
      restart->value("rows", resumed_rows);
      restart->value("csv bytes", csv_bytes);
      restart->finish();
    } catch (const config::CheckpointError& e) {
      throw config::CheckpointError("checkpoint '" + checkpointing_.restart + "': " + e.what());
    }
    out.resume_at(static_cast<size_t>(resumed_rows));
  }
  out.start_writing();  // from here the file opens whatever ends the process
  std::ofstream csv;
  if (!csv_path_.empty()) {
    if (resume) {  // continue after the checkpoint's last row
      std::error_code ec;
      std::filesystem::resize_file(csv_path_, csv_bytes, ec);
      if (ec) throw std::runtime_error("cannot continue CSV file '" + csv_path_ + "': " + ec.message());
      csv.open(csv_path_, std::ios::app);
    } else {
      csv.open(csv_path_);
    }
    if (!csv) throw std::runtime_error("cannot write CSV file '" + csv_path_ + "'");
    csv.precision(12);
    if (!resume)
      for (const auto& line : csv_header) csv << line << "\n";
  }
  std::vector<double> row(sources.size());
  auto record = [&] {
    double sum = 0.0;  // a NaN or an infinity anywhere makes the sum one
    for (size_t i = 0; i < sources.size(); ++i) row[i] = *sources[i], sum += row[i] * 0.0;
    // No row with a value that is not a number: the run stops at it instead
    // (a component's own variable; the nodes are checked before the row).
    if (!(sum == 0.0))
      for (size_t i = 0; i < row.size(); ++i)
        if (!std::isfinite(row[i]))
          throw std::runtime_error("the result " + names[i] + " is no longer finite (" + std::to_string(row[i]) +
                                   "): the step is unstable for this model or a parameter is out of its range");
    out.append(row);
    if (csv.is_open()) {
      for (size_t i = 0; i < csv_sources.size(); ++i) csv << (i ? "," : "") << *csv_sources[i];
      csv << "\n";
    }
  };
  if (resume) {
    time = t0 + static_cast<double>(first) * dt;
    steps_done_ = first;
    if (progress)
      std::fprintf(stderr, "tlm_host: restarted from %s after step %ld (t = %g s); %s continues after its row %llu\n",
                   checkpointing_.restart.c_str(), first, time, out_path.c_str(),
                   static_cast<unsigned long long>(resumed_rows));
  } else {
    record();
  }

  // The FMUs' servers save theirs first (concurrently: a server with
  // several FMUs waits for all of them), then this side's state.
  auto checkpoint = [&](long k) {
    std::vector<std::future<std::string>> servers;
    for (FmuQ* f : fmus) servers.push_back(std::async(std::launch::async, [f] { return f->checkpoint(); }));
    std::string where;
    for (auto& s : servers) where += (where.empty() ? "" : ", ") + s.get();
    out.flush();
    if (csv.is_open()) csv.flush();
    config::StateWriter w;
    long step = k;
    identity(w, step);
    exchange_state(w);
    uint64_t rows = out.rows();
    uint64_t bytes = csv.is_open() ? static_cast<uint64_t>(csv.tellp()) : 0;
    w.value("rows", rows);
    w.value("csv bytes", bytes);
    w.write(checkpointing_.path);
    return checkpointing_.path + (where.empty() ? std::string() : " (fe_server: " + where + ")");
  };

  // A stop with a checkpoint ends the FMUs' sessions cleanly (BYE): their
  // servers then know the checkpoint they just wrote is the one to resume.
  auto end_sessions = [&] {
    for (FmuQ* f : fmus) f->finalize();
  };
  const bool tty = isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  auto last_report = start, last_checkpoint = start;
  long k = first;
  const Component* stepping = nullptr;  // the component in simulate_one_step, named if it throws
  try {
    for (; k < steps; ++k) {
      if (const int signo = config::stop_signal()) {
        if (checkpointing_.path.empty()) throw config::StopRequested(signo);
        const std::string saved = checkpoint(k);
        end_sessions();
        throw config::StopRequested(signo, "stopped by " + config::signal_name(signo) + " after step " +
                                               std::to_string(k) + "; checkpoint in " + saved + " (--restart " +
                                               checkpointing_.path + " continues)");
      }
      // fe_server got a stop signal (a wall-time limit on its node): both
      // sides checkpoint here, at the same step, and the run ends. Without
      // --checkpoint the host's goes next to its results.
      if (std::any_of(fmus.begin(), fmus.end(), [](FmuQ* f) { return f->server_stopping(); })) {
        if (checkpointing_.path.empty()) {
          const bool h5 = out_path.size() > 3 && out_path.compare(out_path.size() - 3, 3, ".h5") == 0;
          checkpointing_.path = (h5 ? out_path.substr(0, out_path.size() - 3) : out_path) + ".ckpt";
        }
        const std::string saved = checkpoint(k);
        end_sessions();
        throw CheckpointStop("fe_server is stopping (it got a stop signal) and asked for a checkpoint: stopped after step " +
                             std::to_string(k) + "; checkpoint in " + saved + " (--restart " + checkpointing_.path +
                             " continues, with fe_server's --restart)");
      }
      if (!checkpointing_.path.empty() && checkpointing_.every_s > 0.0 && k > first &&
          std::chrono::steady_clock::now() - last_checkpoint > std::chrono::duration<double>(checkpointing_.every_s)) {
        const std::string saved = checkpoint(k);
        if (progress) std::fprintf(stderr, "tlm_host: checkpoint after step %ld in %s\n", k, saved.c_str());
        last_checkpoint = std::chrono::steady_clock::now();
      }
      const double t = t0 + static_cast<double>(k) * dt;
      for (Component* c : signal_) {
        stepping = c;
        c->simulate_one_step(t);
      }
      for (Component* c : c_type_) {
        stepping = c;
        c->simulate_one_step(t);
      }
      for (Component* c : q_type_) {
        stepping = c;
        if (peers_ && c == peers_->members().front())
          peers_->step(t);
        else
          c->simulate_one_step(t);
      }
      stepping = nullptr;
      // The FMUs' port nodes every step (a coupling gone wrong swings there
      // first); every node before each results row and at least every
      // kGuardEvery steps (every step it cost a quarter of the monolithic
      // hammer's host step): no row holds a value beyond a bound.
      const bool row_due = (k + 1) % spec_.log_every == 0;
      if (row_due || (k + 1) % kGuardEvery == 0 || k + 1 == steps) {
        if (const std::string why = check_nodes(); !why.empty()) throw std::runtime_error(why);
      } else if (!fmu_node_index_.empty()) {
        if (const std::string why = check_fmu_nodes(); !why.empty()) throw std::runtime_error(why);
      }
      time = t0 + static_cast<double>(k + 1) * dt;
      steps_done_ = k + 1;
      if (row_due) record();
      if (progress && (k & 1023) == 0) {
        auto now = std::chrono::steady_clock::now();
        if (now - last_report > std::chrono::seconds(tty ? 1 : 10)) {
          last_report = now;
          const double elapsed = std::chrono::duration<double>(now - start).count();
          const double done = static_cast<double>(k + 1) / static_cast<double>(steps);
          std::fprintf(stderr, "%st = %.4g of %.4g s (%.0f%%), %.1f s elapsed, about %.1f s left%s",
                       tty ? "\r" : "", time, spec_.stop_time, 100.0 * done, elapsed,
                       elapsed * (1.0 - done) / done, tty ? "   " : "\n");
        }
      }
    }
  } catch (const CheckpointStop& e) {
    out.flush();
    if (csv.is_open()) csv.flush();
    throw CheckpointStop(std::string(e.what()) + "; results up to it kept in " + out_path);
  } catch (const std::exception& e) {
    out.flush();
    if (csv.is_open()) csv.flush();
    std::ostringstream s;
    s << "at step " << k << " (t = " << static_cast<double>(k) * dt << " s)";
    if (stepping) s << " in " << stepping->name() << " (" << stepping->type_name() << ")";
    s << ": " << e.what()
      << "; results up to the last completed step kept in " << out_path;
    // A signal may also show as the peer's ABORT (fe_server got it too), or
    // as a wait the signal ended in an FMU: a stop either way.
    if (const int signo = config::stop_signal())
      throw config::StopRequested(signo, "stopped by " + config::signal_name(signo) + " " + s.str());
    throw std::runtime_error(s.str());
  }
  for (auto& c : components_) c->finalize();
  out.flush();
  if (progress && tty) std::fprintf(stderr, "\n");
}

}  // namespace tlm

namespace tlm {

ReportSettings report_settings(ModelSpec& spec) {
  ReportSettings s;
  for (const auto& c : spec.report) {
    const std::string key = config::to_lower(c.field(0, "key"));
    if (key == "piston") s.piston = c.field(1, "component");
    else if (key == "inlet_p") s.inlet_p = c.field(1, "dataset");
    else if (key == "inlet_q") s.inlet_q = c.field(1, "dataset");
    else if (key == "peak") s.peaks.push_back({c.field(1, "label"), c.field(2, "dataset")});
    else if (key == "settle") s.settle = c.real(1, "settle");
    else if (key == "lowpass") s.lowpass = c.real(1, "lowpass");
    else if (key == "v_blow") s.v_blow = c.real(1, "v_blow");
    else c.fail("unknown report key '" + c.fields[0] + "': expected piston, inlet_p, inlet_q, peak, settle, lowpass or v_blow");
  }
  // The inlet flow must be the flow at the inlet pressure's node: a
  // component with a port connected there. A flow read elsewhere (the rig
  // scene's first version read a return restrictor's, 5–7 % below the
  // hammer's inlet flow) gives a wrong input power with no error.
  const std::string node_prefix = "nodes/", comp_prefix = "components/";
  auto ends = [](const std::string& a, const std::string& b) {
    return a.size() > b.size() && a.compare(a.size() - b.size(), b.size(), b) == 0;
  };
  if (s.inlet_p.rfind(node_prefix, 0) == 0 && ends(s.inlet_p, "/p") && s.inlet_q.rfind(comp_prefix, 0) == 0 &&
      ends(s.inlet_q, "/q")) {
    const std::string node = s.inlet_p.substr(node_prefix.size(), s.inlet_p.size() - node_prefix.size() - 2);
    const std::string comp = s.inlet_q.substr(comp_prefix.size(), s.inlet_q.size() - comp_prefix.size() - 2) + ".";
    bool adjacent = false;
    for (const ConnectionSpec& c : spec.connections)
      adjacent |= (c.a == node && c.b.rfind(comp, 0) == 0) || (c.b == node && c.a.rfind(comp, 0) == 0);
    if (!adjacent)
      for (const auto& c : spec.report)
        if (config::to_lower(c.field(0, "key")) == "inlet_q")
          throw config::InputError(c.where, "*REPORT inlet_q: " + s.inlet_q + " is not the flow at the inlet node " +
                                                node + " (inlet_p): no port of '" + comp.substr(0, comp.size() - 1) +
                                                "' is connected there; name the component that feeds that node");
  }
  ComponentSpec* piston = spec.find(s.piston);
  if (!piston && !spec.report.empty())
    throw config::InputError(spec.report.front().where, "*REPORT: no component named '" + s.piston + "'");
  if (piston) s.piston_mass = piston->params.real("m", 14.4, "kg");
  // A results file cut down by *LOG still holds what the report reads.
  if (!spec.log_only.empty() && !spec.report.empty()) {
    const config::SourceLocation where = spec.report.front().where;
    for (const char* v : {"x", "v", "F_contact"}) spec.log_only.emplace_back("components/" + s.piston + "/" + v, where);
    for (const std::string* n : {&s.inlet_p, &s.inlet_q})
      if (!n->empty()) spec.log_only.emplace_back(*n, where);
    for (const auto& peak : s.peaks) spec.log_only.emplace_back(peak.second, where);
  }
  return s;
}

}  // namespace tlm
