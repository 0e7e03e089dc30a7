// One FMU instance: the FMI 2.0 co-simulation state machine, the variables
// derived from the port table, and the coupling client. No global state, so
// any number of instances live in one process.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "coupling_client.hpp"
#include "fmi2/fmi2.h"

namespace pcs_fmu {

// The instance states of FMI 2.0 co-simulation (spec. 4.2.4) that a
// synchronous FMU can be in.
enum class State : unsigned {
  Instantiated = 1u << 0,
  InitializationMode = 1u << 1,
  StepComplete = 1u << 2,
  StepFailed = 1u << 3,
  Terminated = 1u << 4,
  Error = 1u << 5,
  Fatal = 1u << 6,
};
const char* to_string(State s);

// A failure inside an fmi2 call: becomes `status` at the C boundary.
class FmuError : public std::runtime_error {
 public:
  FmuError(fmi2Status status, const std::string& message)
      : std::runtime_error(message), status_(status) {}
  fmi2Status status() const { return status_; }

 private:
  fmi2Status status_;
};

class Instance {
 public:
  // Where the instance's messages go: (status, category, message). FMI 2.0
  // and 3.0 differ only in the callback's shape (fmi3Status has fmi2's values).
  using LogSink = std::function<void(fmi2Status, const char*, const std::string&)>;
  // FMI 2.0: the resources as a file: URI, the importer's callbacks.
  Instance(std::string name, const std::string& guid, const std::string& resource_location,
           const fmi2CallbackFunctions* callbacks, bool logging_on);
  // Any version: the resources folder as a path, a sink for the messages.
  Instance(std::string name, const std::string& token, const std::string& resource_dir, LogSink sink,
           bool logging_on);

  const std::string& name() const { return name_; }
  State state() const { return state_; }
  void set_state(State s) { state_ = s; }
  void set_logging(bool on) { logging_on_ = on; }
  // Log through the importer's callback. Errors and warnings always go out;
  // other categories only while logging is on.
  void log(fmi2Status status, const char* category, const std::string& message) const;

  void enter_initialization();
  void exit_initialization();  // connects and shakes hands
  void do_step(double t, double h);
  // The stop time the importer announced (fmi2SetupExperiment): a run that
  // terminates before it is warned about (the importer stopped early).
  void set_stop_time(bool defined, double stop) {
    stop_time_defined_ = defined;
    stop_time_ = stop;
  }
  void terminate();
  // Checkpoint and restart (pcs_fmu_checkpoint / pcs_fmu_resume, beyond
  // FMI): the server saves its state after the steps done so far and
  // returns its file; a new instance resumes at a step (before
  // fmi2ExitInitializationMode, which then sends RESUME instead of starting
  // at step 0).
  std::string checkpoint();
  void set_resume_step(uint64_t step);
  // After initialization: wait for the server's answer to the RESUME.
  void confirm_resume();
  uint64_t steps_done() const { return step_; }
  // The server got a stop signal and asks for a checkpoint (it keeps
  // serving for a grace period): pcs_fmu_stop_requested.
  bool stop_requested() const { return client_ && client_->stop_requested(); }
  // The same, asked by the importer (pcs_fmu_stop_requested): an importer
  // that asks can checkpoint; one that never asks is warned at the request.
  bool importer_asks_stop_requested() {
    importer_asks_ = true;
    return stop_requested();
  }
  void reset();
  // The link is told why (ABORT) before an instance goes to its error state.
  void abort_link(const std::string& reason);

  double get_real(fmi2ValueReference vr) const;
  void set_real(fmi2ValueReference vr, double v);
  // After a call that set values: in a session of several FMUs, changed
  // inputs go to fe_server now (a sequential importer steps another FMU
  // before this one).
  void inputs_set();
  int get_integer(fmi2ValueReference vr) const;
  void set_integer(fmi2ValueReference vr, int v);
  const char* get_string(fmi2ValueReference vr) const;
  void set_string(fmi2ValueReference vr, const char* v);
  double last_successful_time() const { return time_; }

 private:
  const config::FmuVariable& variable(fmi2ValueReference vr) const;
  void resolve_endpoint(std::string& host, int& port, std::string& token) const;

  std::string name_;
  LogSink sink_;
  bool logging_on_ = false;
  bool logging_at_instantiation_ = false;  // fmi2Reset returns to it
  State state_ = State::Instantiated;

  config::PortTable table_;
  std::vector<config::FmuVariable> vars_;
  std::vector<double> inputs_;   // host units, to_fe order
  bool inputs_changed_ = false;  // an input was set since the inputs last went out
  void scale_inputs();  // inputs_ (host units) scaled into wire_in_ (wire units)
  void send_inputs();
  std::vector<double> outputs_;  // host units, to_host order
  std::vector<double> wire_in_, wire_out_;
  std::string host_, token_;
  int port_ = 0;
  double timeout_ = 60.0;
  uint64_t step_ = 0;
  uint64_t resume_step_ = 0;
  bool importer_asks_ = false, stop_warned_ = false;
  bool stop_time_defined_ = false;
  double stop_time_ = 0.0;
  bool resume_ = false;
  double time_ = 0.0;
  std::unique_ptr<CouplingClient> client_;
};

// Path of a "file:" URI (file:///a/b, file:/a/b, file://localhost/a/b), with
// %XX escapes decoded. Throws FmuError for anything else.
std::string path_from_file_uri(const std::string& uri);

}  // namespace pcs_fmu
