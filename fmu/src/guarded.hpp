// The shell around every exported FMI function, for 2.0 and 3.0 alike: it
// checks that the call is legal in the instance's current state (naming the
// call that was out of sequence), runs the work, and turns every failure
// into a status with a message through the importer's logger. No exception
// crosses the C boundary. fmi3Status has fmi2Status's values (OK, Warning,
// Discard, Error, Fatal), so one shell serves both.
#pragma once

#include <new>
#include <string>

#include "instance.hpp"

namespace pcs_fmu {

constexpr unsigned bit(State s) { return static_cast<unsigned>(s); }
constexpr unsigned kAnyButFatal = bit(State::Instantiated) | bit(State::InitializationMode) |
                                  bit(State::StepComplete) | bit(State::StepFailed) |
                                  bit(State::Terminated) | bit(State::Error);
// Which states each call is legal in (FMI 2.0 co-simulation state table,
// spec. 4.2.4; FMI 3.0's Step Mode is StepComplete here).
constexpr unsigned kSetupExperiment = bit(State::Instantiated);
constexpr unsigned kEnterInit = bit(State::Instantiated);
constexpr unsigned kExitInit = bit(State::InitializationMode);
constexpr unsigned kTerminate = bit(State::StepComplete) | bit(State::StepFailed);
constexpr unsigned kGet = bit(State::InitializationMode) | bit(State::StepComplete) |
                          bit(State::StepFailed) | bit(State::Terminated) | bit(State::Error);
constexpr unsigned kSet = bit(State::Instantiated) | bit(State::InitializationMode) |
                          bit(State::StepComplete);
constexpr unsigned kDoStep = bit(State::StepComplete);
constexpr unsigned kStatus = bit(State::StepComplete) | bit(State::StepFailed) |
                             bit(State::Terminated);

// Run `work` on instance c if `allowed` contains its state.
template <class Status, class F>
Status guarded(void* c, const char* fn, unsigned allowed, F&& work) {
  if (!c) return static_cast<Status>(fmi2Error);
  auto* inst = static_cast<Instance*>(c);
  if (!(bit(inst->state()) & allowed)) {
    inst->log(fmi2Error, "logStatusError",
              std::string(fn) + " is not allowed in state " + to_string(inst->state()));
    return static_cast<Status>(fmi2Error);
  }
  try {
    work(*inst);
    return static_cast<Status>(fmi2OK);
  } catch (const FmuError& e) {
    inst->log(e.status(), "logStatusError", std::string(fn) + ": " + e.what());
    if (e.status() == fmi2Error) {
      inst->abort_link(std::string(fn) + " failed: " + e.what());
      inst->set_state(State::Error);
    }
    if (e.status() == fmi2Fatal) inst->set_state(State::Fatal);
    return static_cast<Status>(e.status());
  } catch (const std::bad_alloc&) {
    inst->log(fmi2Fatal, "logStatusFatal", std::string(fn) + ": out of memory");
    inst->set_state(State::Fatal);
    return static_cast<Status>(fmi2Fatal);
  } catch (const std::exception& e) {
    inst->log(fmi2Error, "logStatusError", std::string(fn) + ": " + e.what());
    inst->set_state(State::Error);
    return static_cast<Status>(fmi2Error);
  }
}

// A capability the model description says this FMU does not have.
template <class Status>
Status unsupported(void* c, const char* fn, const char* capability) {
  return guarded<Status>(c, fn, kAnyButFatal, [&](Instance&) {
    throw FmuError(fmi2Error, std::string("not supported (") + capability + " is false in modelDescription.xml)");
  });
}

// fmi2FreeInstance / fmi3FreeInstance: the link is told why if the session
// is still open (the importer stopped before terminating), then the instance goes.
inline void free_instance(void* c, const char* terminate) {
  if (!c) return;
  auto* inst = static_cast<Instance*>(c);
  try {
    inst->abort_link(std::string("the importer freed the FMU instance before ") + terminate +
                     " (it stopped; its log says why)");
  } catch (...) {
  }
  delete inst;
}

// The experiment's start time: the FE model starts from its initial state.
inline void check_start_time(double start) {
  if (start != 0.0) throw FmuError(fmi2Error, "startTime must be 0: the FE model starts from its initial state");
}

}  // namespace pcs_fmu
