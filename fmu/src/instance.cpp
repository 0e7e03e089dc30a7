#include "instance.hpp"

#include "config/token.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "socketlib/socketlib.h"

namespace pcs_fmu {

const char* to_string(State s) {
  switch (s) {
    case State::Instantiated: return "instantiated";
    case State::InitializationMode: return "initializationMode";
    case State::StepComplete: return "stepComplete";
    case State::StepFailed: return "stepFailed";
    case State::Terminated: return "terminated";
    case State::Error: return "error";
    case State::Fatal: return "fatal";
  }
  return "?";
}

std::string path_from_file_uri(const std::string& uri) {
  std::string rest;
  if (uri.rfind("file://localhost/", 0) == 0) rest = uri.substr(16);
  else if (uri.rfind("file:///", 0) == 0) rest = uri.substr(7);
  else if (uri.rfind("file:/", 0) == 0) rest = uri.substr(5);
  else throw FmuError(fmi2Error, "fmuResourceLocation '" + uri + "' is not a file: URI");
  std::string out;
  for (size_t i = 0; i < rest.size(); ++i) {
    if (rest[i] == '%' && i + 2 < rest.size()) {
      out += static_cast<char>(std::strtol(rest.substr(i + 1, 2).c_str(), nullptr, 16));
      i += 2;
    } else {
      out += rest[i];
    }
  }
  while (out.size() > 1 && out.back() == '/') out.pop_back();
#ifdef _WIN32
  // file:///C:/dir: the path is C:/dir, not /C:/dir.
  if (out.size() >= 3 && out[0] == '/' && std::isalpha(static_cast<unsigned char>(out[1])) && out[2] == ':')
    out.erase(0, 1);
#endif
  return out;
}

namespace {

Instance::LogSink fmi2_sink(const fmi2CallbackFunctions* callbacks, const std::string& name) {
  if (!callbacks || !callbacks->logger) return nullptr;
  const fmi2CallbackLogger logger = callbacks->logger;
  const fmi2ComponentEnvironment env = callbacks->componentEnvironment;
  // The message is passed as an argument, never as the format string.
  return [logger, env, name](fmi2Status status, const char* category, const std::string& message) {
    logger(env, name.c_str(), status, category, "%s", message.c_str());
  };
}

}  // namespace

Instance::Instance(std::string name, const std::string& guid, const std::string& resource_location,
                   const fmi2CallbackFunctions* callbacks, bool logging_on)
    : Instance(name, guid, path_from_file_uri(resource_location), fmi2_sink(callbacks, name), logging_on) {}

Instance::Instance(std::string name, const std::string& guid, const std::string& resource_dir, LogSink sink,
                   bool logging_on)
    : name_(std::move(name)), sink_(std::move(sink)), logging_on_(logging_on), logging_at_instantiation_(logging_on) {
  // The configuration comes from the FMU's own resources, never the working directory.
  std::string dir = resource_dir;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  try {
    table_ = config::read_port_table(dir + "/ports.cfg");
  } catch (const std::exception& e) {
    throw FmuError(fmi2Error, std::string("cannot read the port table: ") + e.what());
  }
  if (guid != config::fmu_guid(table_))
    throw FmuError(fmi2Error, "GUID '" + guid + "' does not match resources/ports.cfg (" +
                                  config::fmu_guid(table_) +
                                  "): modelDescription.xml and the resources come from different fmugen runs");
  vars_ = config::fmu_variables(table_);
  inputs_.assign(table_.to_fe.size(), 0.0);
  outputs_.assign(table_.to_host.size(), 0.0);
  timeout_ = table_.timeout;
}

void Instance::log(fmi2Status status, const char* category, const std::string& message) const {
  bool always = status == fmi2Error || status == fmi2Fatal || status == fmi2Warning;
  if (!sink_ || !(always || logging_on_)) return;
  sink_(status, category, message);
}

const config::FmuVariable& Instance::variable(fmi2ValueReference vr) const {
  for (const auto& v : vars_)
    if (v.value_reference == vr) return v;
  throw FmuError(fmi2Error, "unknown value reference " + std::to_string(vr));
}

double Instance::get_real(fmi2ValueReference vr) const {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::Real) throw FmuError(fmi2Error, v.name + " is not a Real");
  if (v.causality == config::FmuCausality::Input) return inputs_[static_cast<size_t>(v.wire_index)];
  // Hopsan's node variables: the pressure the port's characteristic gives
  // for the flow of the last step (p = c + Zc·q, as a Q component solves
  // its node; before the first step its start value), and constants.
  if (v.derived == config::FmuVariable::Derived::Pressure)
    return step_ == 0 ? v.constant : inputs_[static_cast<size_t>(v.wire_c)] +
           inputs_[static_cast<size_t>(v.wire_zc)] * outputs_[static_cast<size_t>(v.wire_q)];
  if (v.derived == config::FmuVariable::Derived::Constant) return v.constant;
  if (v.causality == config::FmuCausality::Output) return outputs_[static_cast<size_t>(v.wire_index)];
  return timeout_;
}

void Instance::set_real(fmi2ValueReference vr, double value) {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::Real) throw FmuError(fmi2Error, v.name + " is not a Real");
  if (v.causality == config::FmuCausality::Output)
    throw FmuError(fmi2Error, "cannot set output " + v.name);
  if (!std::isfinite(value))
    throw FmuError(fmi2Error, v.name + " set to a non-finite value at step " + std::to_string(step_));
  if (v.causality == config::FmuCausality::Input) {
    inputs_[static_cast<size_t>(v.wire_index)] = value;
    inputs_changed_ = true;
    return;
  }
  if (state_ != State::Instantiated && state_ != State::InitializationMode)
    throw FmuError(fmi2Error, "parameter " + v.name + " can only be set before initialization ends");
  if (!(value > 0.0)) throw FmuError(fmi2Error, "server.timeout must be positive");
  timeout_ = value;
}

int Instance::get_integer(fmi2ValueReference vr) const {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::Integer) throw FmuError(fmi2Error, v.name + " is not an Integer");
  return port_;
}

void Instance::set_integer(fmi2ValueReference vr, int value) {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::Integer) throw FmuError(fmi2Error, v.name + " is not an Integer");
  if (state_ != State::Instantiated && state_ != State::InitializationMode)
    throw FmuError(fmi2Error, "parameter " + v.name + " can only be set before initialization ends");
  if (value < 0 || value > 65535) throw FmuError(fmi2Error, "server.port must be 0..65535");
  port_ = value;
}

const char* Instance::get_string(fmi2ValueReference vr) const {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::String) throw FmuError(fmi2Error, v.name + " is not a String");
  // The token is write-only: an importer that logs what it reads (fmusim's
  // --log-fmi-calls, a GUI's parameter table) must never show it.
  return vr == config::kVrServerHost ? host_.c_str() : "";
}

void Instance::set_string(fmi2ValueReference vr, const char* value) {
  const auto& v = variable(vr);
  if (v.type != config::FmuType::String) throw FmuError(fmi2Error, v.name + " is not a String");
  if (state_ != State::Instantiated && state_ != State::InitializationMode)
    throw FmuError(fmi2Error, "parameter " + v.name + " can only be set before initialization ends");
  (vr == config::kVrServerHost ? host_ : token_) = value ? value : "";
}

void Instance::resolve_endpoint(std::string& host, int& port, std::string& token) const {
  // Parameter first, then environment, then the port configuration.
  host = host_;
  port = port_;
  token = token_;
  if (host.empty())
    if (const char* e = std::getenv("PCS_SERVER_HOST")) host = e;
  if (port == 0)
    if (const char* e = std::getenv("PCS_SERVER_PORT")) port = std::atoi(e);
  if (token.empty()) {
    try {
      token = config::token_from_environment();
    } catch (const std::exception& e) {
      throw FmuError(fmi2Error, e.what());
    }
  }
  if ((host.empty() || port == 0) && !table_.server.empty()) {
    char h[256];
    int p = 0;
    if (sl_parse_endpoint(table_.server.c_str(), h, sizeof h, &p) != SL_OK)
      throw FmuError(fmi2Error, "server '" + table_.server + "' in " + table_.source +
                                    " is not HOST:PORT");
    if (host.empty()) host = h;
    if (port == 0) port = p;
  }
  if (host.empty() || port <= 0 || port > 65535)
    throw FmuError(fmi2Error,
                   "no fe_server address: set server.host and server.port, or PCS_SERVER_HOST "
                   "and PCS_SERVER_PORT, or 'server, HOST:PORT' in ports.cfg");
}

void Instance::enter_initialization() { state_ = State::InitializationMode; }

void Instance::exit_initialization() {
  std::string host, token;
  int port = 0;
  resolve_endpoint(host, port, token);
  client_ = std::make_unique<CouplingClient>(table_);
  client_->set_progress([this](bool warning, const std::string& m) {
    log(warning ? fmi2Warning : fmi2OK, "logCoupling", m);
  });
  try {
    client_->connect(host, port, token, timeout_);
  } catch (const LinkError& e) {
    throw FmuError(fmi2Error, e.what());
  }
  log(fmi2OK, "logCoupling", "connected to fe_server at " + host + ":" + std::to_string(port));
  step_ = 0;
  if (resume_) {
    try {
      client_->resume(resume_step_);
    } catch (const LinkError& e) {
      throw FmuError(fmi2Error, e.what());
    }
    step_ = resume_step_;
    time_ = static_cast<double>(resume_step_) * table_.dt;
    log(fmi2OK, "logCoupling", "resumed after step " + std::to_string(step_));
  }
  state_ = State::StepComplete;
  // Inputs set in initialization go with the first STEP: sent now, they
  // could be taken for final while a parallel importer sets others.
  inputs_changed_ = false;
}

void Instance::scale_inputs() {
  wire_in_.resize(inputs_.size());
  for (size_t i = 0; i < inputs_.size(); ++i) wire_in_[i] = inputs_[i] * table_.to_fe[i].scale;
}

void Instance::send_inputs() {
  scale_inputs();
  try {
    client_->send_inputs(step_, time_, table_.dt, wire_in_);
  } catch (const LinkError& e) {
    state_ = State::StepFailed;
    throw FmuError(fmi2Error, e.what());
  }
}

void Instance::inputs_set() {
  // A session of several FMUs: fe_server gets what the importer set before
  // it steps any FMU (coupling_client.hpp, send_inputs).
  if (!inputs_changed_) return;
  inputs_changed_ = false;
  if (state_ == State::StepComplete && client_ && client_->connected() && client_->split_session()) send_inputs();
}

void Instance::do_step(double t, double h) {
  // A communication step is a whole number n of the port table's coupling
  // steps (FMPy, for one, picks 2^k times the DefaultExperiment's stepSize):
  // n exchanges with fe_server, the inputs held over the interval, the
  // outputs those of the last. Anything else would desynchronise the clocks.
  const double dt = table_.dt;
  const double ratio = h / dt;
  const double n_real = std::round(ratio);
  if (!(n_real >= 1.0) || std::fabs(ratio - n_real) > 1e-6 * std::max(1.0, ratio) || n_real > 1e9) {
    char msg[320];
    const double lo = std::max(1.0, std::floor(ratio)) * dt, hi = std::max(1.0, std::ceil(ratio)) * dt;
    if (hi != lo)
      std::snprintf(msg, sizeof msg,
                    "communicationStepSize %g s is not a whole multiple of the coupling step %g s (%s): use %g s or %g s",
                    h, dt, table_.source.c_str(), lo, hi);
    else
      std::snprintf(msg, sizeof msg, "communicationStepSize %g s is not a whole multiple of the coupling step %g s (%s): use %g s",
                    h, dt, table_.source.c_str(), lo);
    throw FmuError(fmi2Error, msg);
  }
  const long n = static_cast<long>(n_real);
  scale_inputs();
  for (long k = 0; k < n; ++k) {
    const double tk = t + static_cast<double>(k) * dt;
    try {
      client_->step(step_, tk, dt, wire_in_, wire_out_);
    } catch (const LinkError& e) {
      state_ = State::StepFailed;
      throw FmuError(fmi2Error, e.what());
    }
    for (size_t i = 0; i < outputs_.size(); ++i)
      if (!std::isfinite(wire_out_[i])) {
        std::string what = table_.to_host[i].name() + " from fe_server is not finite at step " + std::to_string(step_);
        client_->abort(what);
        state_ = State::StepFailed;
        throw FmuError(fmi2Error, what);
      }
    ++step_;
  }
  for (size_t i = 0; i < outputs_.size(); ++i) outputs_[i] = wire_out_[i] * table_.to_host[i].scale;
  time_ = t + h;
  if (stop_requested() && !importer_asks_ && !stop_warned_) {
    // An importer that knows nothing of it (FMPy, fmusim, Hopsan) would step
    // on in silence until the server's grace ran out.
    stop_warned_ = true;
    log(fmi2Warning, "logCoupling",
        "fe_server got a stop signal at step " + std::to_string(step_) +
            " (SIGTERM: a batch system's wall-time limit, scancel) and asks for a checkpoint of both sides, which "
            "this importer cannot take (pcs_fmu_checkpoint is tlm_host's): fe_server ends the session when its "
            "grace runs out (fe_server --stop-grace, 20 s by default); end the run now to keep its results whole");
  }
}

std::string Instance::checkpoint() {
  try {
    return client_->checkpoint(step_);
  } catch (const LinkError& e) {
    throw FmuError(fmi2Error, e.what());
  }
}

void Instance::confirm_resume() {
  try {
    if (client_) client_->confirm_resume();
  } catch (const LinkError& e) {
    throw FmuError(fmi2Error, e.what());
  }
}

void Instance::set_resume_step(uint64_t step) {
  resume_ = true;
  resume_step_ = step;
}

void Instance::terminate() {
  // FMPy and fmusim step at their own interval and may end short of the stop
  // time (0.99968 s of a 1 s run, in silence): the results then end early.
  // Half a coupling step of slack: the time is a sum of steps.
  if (stop_time_defined_ && time_ < stop_time_ - 0.5 * table_.dt) {
    char msg[400];
    std::snprintf(msg, sizeof msg,
                  "fmi2Terminate at t = %.9g s, before the stop time %.9g s given in fmi2SetupExperiment: the importer "
                  "ended the run %.0f coupling steps early (a communication step that does not divide the run?), and "
                  "the results end there",
                  time_, stop_time_, std::floor((stop_time_ - time_) / table_.dt + 0.5));
    log(fmi2Warning, "logCoupling", msg);
  }
  if (client_) client_->bye();
  state_ = State::Terminated;
}

void Instance::abort_link(const std::string& reason) {
  if (client_) client_->abort(reason);
}

void Instance::reset() {
  if (client_) client_->bye();
  client_.reset();
  std::fill(inputs_.begin(), inputs_.end(), 0.0);
  std::fill(outputs_.begin(), outputs_.end(), 0.0);
  step_ = 0;
  time_ = 0.0;
  resume_ = false;
  resume_step_ = 0;
  // FMI 2.0 (4.2.2, fmi2Reset): "the same state as if fmi2Instantiate would
  // have been called": every variable back to its start value, the
  // parameters too (server.*), and the experiment and logging forgotten.
  host_.clear();
  std::fill(token_.begin(), token_.end(), '\0');  // the token leaves no copy behind
  token_.clear();
  port_ = 0;
  timeout_ = table_.timeout;
  stop_time_defined_ = false;
  stop_time_ = 0.0;
  importer_asks_ = stop_warned_ = false;
  logging_on_ = logging_at_instantiation_;
  state_ = State::Instantiated;
}

}  // namespace pcs_fmu
