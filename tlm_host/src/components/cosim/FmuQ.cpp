#include "components/cosim/FmuQ.hpp"

#include "config/port_table.hpp"
#include "socketlib/socketlib.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>

namespace tlm {

static bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void FmuQ::configure(ParameterSet& prm) {
  std::string path = prm.text("fmu", "");
  server_ = prm.text("server", "");
  token_ = prm.text("token", "");
  verbose_ = prm.real("verbose", 0.0, "0/1") != 0.0;
  // Loaded from a Hopsan model (FMIWrapperQ): Hopsan's names for the
  // signals, and the port specifications Hopsan maps the node onto.
  const bool hopsan_names = prm.real("hopsan_names", 0.0, "0/1") != 0.0;
  const std::string portspecs = prm.text("portspecs", "");
  if (path.empty())
    throw config::InputError(prm.where(), name_ + ": no FMU given (parameter fmu=PATH or --fmu PATH)");
  try {
    archive_ = std::make_shared<FmuArchive>(path);
  } catch (const std::exception& e) {
    throw config::InputError(prm.where(), name_ + ": " + e.what());
  }
  fmu_ = std::make_unique<FmuInstance>(archive_, name_, verbose_);
  const auto& md = archive_->description();
  for (const auto& v : md.variables) {
    if (v.causality != "output" || !ends_with(v.name, ".q")) continue;
    const std::string label = v.name.substr(0, v.name.size() - 2);
    HydraulicPort hp;
    hp.vr_q = v.value_reference;
    const FmuScalar* p = md.find(label + ".p");
    const FmuScalar* c = md.find(label + ".c");
    const FmuScalar* zc = md.find(label + ".Zc");
    if (c && zc && c->causality == "input" && zc->causality == "input") {
      hp.tlm = true;
      hp.vr_c = c->value_reference;
      hp.vr_Zc = zc->value_reference;
    } else if (p && p->causality == "input") {
      hp.vr_p = p->value_reference;
      if (zc && zc->causality == "input") hp.zc_check = true, hp.vr_Zc = zc->value_reference;
    } else {
      throw config::InputError(prm.where(), name_ + ": FMU output " + v.name + " has neither the input " + label +
                                                ".p nor the inputs " + label + ".c and " + label + ".Zc");
    }
    hp.port = ports_.size();
    add_port(label, Kind::Q);
    hports_.push_back(hp);
  }
  if (hports_.empty()) throw config::InputError(prm.where(), name_ + ": the FMU has no hydraulic port (no output named L.q)");
  if (!portspecs.empty()) check_hopsan_portspecs(portspecs, prm.where());
  for (const auto& v : md.variables)
    if (v.causality == "output" && v.type == "Real") outputs_.push_back({v.name, v.value_reference, 0.0, v.unit});
  if (!hopsan_names) {
    for (auto& hp : hports_) add_signal_output(ports_[hp.port].name + ".p_node", &hp.p_node);
    // Every output is also a signal ("piston.cavity.x" can drive a chamber or a groove).
    for (auto& o : outputs_) add_signal_output(o.name, &o.value);
  } else {
    // As FMIWrapperQ: the outputs no port reads are signals, named with
    // every character but letters, digits and '_' made '_' ("cavity_x").
    for (auto& o : outputs_)
      if (!port_variable(o.name)) add_signal_output(hopsan_name(o.name), &o.value);
  }
  // Real inputs that no hydraulic port uses (a mechanical port's force, ...) are signal inputs.
  for (const auto& v : md.variables) {
    if (v.causality != "input" || v.type != "Real") continue;
    bool hydraulic = false;
    for (const auto& hp : hports_)
      hydraulic |= v.value_reference == hp.vr_p || v.value_reference == hp.vr_c || v.value_reference == hp.vr_Zc;
    if (!hydraulic) signal_inputs_.push_back({v.value_reference, nullptr});
  }
  size_t k = 0;
  for (const auto& v : md.variables) {
    if (k >= signal_inputs_.size()) break;
    if (v.value_reference == signal_inputs_[k].vr)
      add_signal_input(hopsan_names ? hopsan_name(v.name) : v.name, &signal_inputs_[k++].value);
  }
}

using config::kHopsanNodeHydraulic;  // the variable FMIWrapperQ maps onto each of the node's slots

bool FmuQ::port_variable(const std::string& name) const {
  for (const auto& port : ports_)
    for (const char* v : kHopsanNodeHydraulic)
      if (name == port.name + "." + v) return true;
  return false;
}

std::string FmuQ::hopsan_name(std::string name) {
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') ch = '_';
  return name;
}

// FMIWrapperQ's portspecs ("NodeHydraulic:label,q,p,T,c,Zc,Qdot", ports
// separated by ';'): Hopsan maps the listed variables onto its node's slots by
// position, so each must be the port's own variable of that slot, or Hopsan
// and this host would read different things.
void FmuQ::check_hopsan_portspecs(const std::string& specs, const config::SourceLocation& where) const {
  std::set<std::string> seen;
  size_t start = 0;
  while (start <= specs.size()) {
    const size_t end = std::min(specs.find(';', start), specs.size());
    const std::string spec = specs.substr(start, end - start);
    start = end + 1;
    if (spec.empty()) continue;
    const size_t colon = spec.find(':');
    const std::string node = spec.substr(0, colon);
    if (colon == std::string::npos || node != "NodeHydraulic")
      throw config::InputError(where, name_ + ": portspecs '" + spec + "': only NodeHydraulic ports are read (" +
                                          (colon == std::string::npos ? "no node type" : node) + ")");
    std::vector<std::string> fields(1);
    for (char ch : spec.substr(colon + 1))
      if (ch == ',')
        fields.emplace_back();
      else
        fields.back().push_back(ch);
    const std::string& label = fields[0];
    bool known = false;
    for (const auto& hp : hports_) known |= ports_[hp.port].name == label;
    if (!known) throw config::InputError(where, name_ + ": portspecs names port '" + label + "', which the FMU does not have");
    if (fields.size() != 7)
      throw config::InputError(where, name_ + ": portspecs of port '" + label + "' lists " + std::to_string(fields.size() - 1) +
                                          " variables; NodeHydraulic has 6 (q, p, T, c, Zc, Qdot)");
    for (size_t j = 0; j < 6; ++j)
      if (fields[j + 1] != label + "." + kHopsanNodeHydraulic[j])
        throw config::InputError(where, name_ + ": portspecs of port '" + label + "' maps " + fields[j + 1] +
                                            " onto Hopsan's slot " + kHopsanNodeHydraulic[j] + "; expected " + label + "." +
                                            kHopsanNodeHydraulic[j] + " (fmugen prints the portspecs)");
    seen.insert(label);
  }
  for (const auto& hp : hports_)
    if (!seen.count(ports_[hp.port].name))
      throw config::InputError(where, name_ + ": portspecs leaves out port '" + ports_[hp.port].name + "'");
}

void FmuQ::initialize(double dt) {
  dt_ = dt;
  if (!server_.empty()) {
    char host[256];
    int port = 0;
    if (sl_parse_endpoint(server_.c_str(), host, sizeof host, &port) != SL_OK)
      throw FmuError(name_ + ": server '" + server_ + "' is not HOST:PORT");
    if (port < 1 || port > 65535)
      throw FmuError(name_ + ": server '" + server_ + "': the port must be from 1 to 65535");
    fmu_->set_string(fmu_->vr("server.host"), host);
    fmu_->set_integer(fmu_->vr("server.port"), port);
  }
  if (!token_.empty()) fmu_->set_string(fmu_->vr("server.token"), token_);
  fmu_->setup_experiment(0.0, 0.0);
  fmu_->enter_initialization();
  send_inputs();
  if (resume_step_ >= 0) fmu_->resume(static_cast<unsigned long long>(resume_step_));
  fmu_->exit_initialization();  // connects to fe_server (RESUME on a restart)
}

std::string FmuQ::step_mismatch(double dt) const {
  const auto& md = archive_->description();
  const double coupling = md.default_step;
  // Only ours: another FMU's stepSize is a suggestion, not its clock.
  if (!md.find("server.port") || !(coupling > 0.0)) return "";
  if (std::fabs(dt - coupling) <= 1e-9 * coupling) return "";
  char msg[700];
  std::snprintf(msg, sizeof msg,
                "%s: the host's time step %g s is not the FMU's coupling step %g s (its stepSize, the port table's "
                "'timestep'): the host would hold fe_server's inputs over %.6g coupling steps while its TLM lines "
                "assume a delay of one host step. Set *SIMULATION 'timestep, %g' (or --set simulation.timestep=%g), or "
                "generate the FMU from a port table with 'timestep, %g'",
                name_.c_str(), dt, coupling, dt / coupling, coupling, coupling, dt);
  return msg;
}

void FmuQ::send_inputs() {
  // One call: in a session of several FMUs each call that sets inputs sends
  // them to fe_server (fmu/src/instance.hpp, inputs_set).
  in_vr_.clear();
  in_value_.clear();
  auto set = [&](unsigned vr, double v) {
    in_vr_.push_back(vr);
    in_value_.push_back(v);
  };
  for (const auto& s : signal_inputs_) set(s.vr, *s.value);
  for (const auto& hp : hports_) {
    const HydraulicNode& n = *ports_[hp.port].node;
    if (hp.tlm) {
      set(hp.vr_c, n.c);
      set(hp.vr_Zc, n.Zc);
    } else {
      set(hp.vr_p, n.c + n.Zc * hp.q);  // the last step's flow: one step delay
      if (hp.zc_check) set(hp.vr_Zc, n.Zc);  // the chamber's stiffness, for the server's check
    }
  }
  fmu_->set_reals(in_vr_, in_value_);
}

void FmuQ::simulate_one_step(double t) {
  if (!inputs_sent_) send_inputs();
  inputs_sent_ = false;
  fmu_->do_step(t, dt_);
  for (auto& hp : hports_) {
    HydraulicNode& n = *ports_[hp.port].node;
    hp.q = fmu_->get_real(hp.vr_q);
    n.q = hp.q;
    n.p = n.c + n.Zc * hp.q;
    hp.p_node = n.p;
  }
  for (auto& o : outputs_) o.value = fmu_->get_real(o.vr);
}

void FmuQ::state(config::StateIO& io) {
  io.expect("fmu ports", hports_.size(), name_ + ": the FMU's hydraulic ports");
  for (auto& hp : hports_) {
    io.value("q", hp.q);
    io.value("p_node", hp.p_node);
  }
  io.expect("fmu outputs", outputs_.size(), name_ + ": the FMU's outputs");
  for (auto& o : outputs_) io.value("output", o.value);
}

void FmuQ::finalize() {
  if (fmu_) fmu_->terminate();
}

void FmuQ::log_variables(std::vector<LogVariable>& out) {
  for (const auto& o : outputs_) out.push_back({o.name, o.unit, &o.value});
}

}  // namespace tlm
