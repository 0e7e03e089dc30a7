// The exported FMI 2.0 functions. Each is a shell (guarded.hpp): it checks
// that the call is legal in the instance's current state, runs the work, and
// turns every failure into an fmi2Status with a message through the
// importer's logger. No exception crosses this boundary; nothing here exits
// or prints.
#include <csignal>
#include <cstring>
#include <new>
#include <utility>

#include "fmi2/fmi2.h"
#include "guarded.hpp"
#include "instance.hpp"
#include "socketlib/socketlib.h"

using namespace pcs_fmu;  // Instance, FmuError, the states' masks and the shell (guarded.hpp)

namespace {

template <class F>
fmi2Status guarded(fmi2Component c, const char* fn, unsigned allowed, F&& work) {
  return pcs_fmu::guarded<fmi2Status>(c, fn, allowed, std::forward<F>(work));
}

fmi2Status unsupported(fmi2Component c, const char* fn, const char* capability) {
  return pcs_fmu::unsupported<fmi2Status>(c, fn, capability);
}

}  // namespace

extern "C" {

const char* fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char* fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t, const fmi2String[]) {
  return guarded(c, "fmi2SetDebugLogging", kAnyButFatal,
                 [&](Instance& i) { i.set_logging(loggingOn != fmi2False); });
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions* functions,
                              fmi2Boolean, fmi2Boolean loggingOn) {
  auto complain = [&](const std::string& msg) {
    if (functions && functions->logger)
      functions->logger(functions->componentEnvironment, instanceName ? instanceName : "?",
                        fmi2Error, "logStatusError", "%s", msg.c_str());
  };
  if (!instanceName || !*instanceName) {
    complain("fmi2Instantiate: instanceName is empty");
    return nullptr;
  }
  if (fmuType != fmi2CoSimulation) {
    complain("fmi2Instantiate: this FMU supports co-simulation only");
    return nullptr;
  }
  if (!fmuGUID || !fmuResourceLocation) {
    complain("fmi2Instantiate: fmuGUID and fmuResourceLocation are required");
    return nullptr;
  }
  try {
    return new Instance(instanceName, fmuGUID, fmuResourceLocation, functions, loggingOn != fmi2False);
  } catch (const std::exception& e) {
    complain(std::string("fmi2Instantiate: ") + e.what());
    return nullptr;
  }
}

void fmi2FreeInstance(fmi2Component c) { free_instance(c, "fmi2Terminate"); }

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean, fmi2Real, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
  return guarded(c, "fmi2SetupExperiment", kSetupExperiment, [&](Instance& i) {
    check_start_time(startTime);
    i.set_stop_time(stopTimeDefined == fmi2True, stopTime);
  });
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
  return guarded(c, "fmi2EnterInitializationMode", kEnterInit,
                 [](Instance& i) { i.enter_initialization(); });
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
  return guarded(c, "fmi2ExitInitializationMode", kExitInit,
                 [](Instance& i) { i.exit_initialization(); });
}

fmi2Status fmi2Terminate(fmi2Component c) {
  return guarded(c, "fmi2Terminate", kTerminate, [](Instance& i) { i.terminate(); });
}

fmi2Status fmi2Reset(fmi2Component c) {
  return guarded(c, "fmi2Reset", kAnyButFatal, [](Instance& i) { i.reset(); });
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
  return guarded(c, "fmi2GetReal", kGet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) value[k] = i.get_real(vr[k]);
  });
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
  return guarded(c, "fmi2GetInteger", kGet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) value[k] = i.get_integer(vr[k]);
  });
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, fmi2Boolean[]) {
  return guarded(c, "fmi2GetBoolean", kGet, [&](Instance&) {
    if (nvr) throw FmuError(fmi2Error, "this FMU has no Boolean variables");
  });
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
  return guarded(c, "fmi2GetString", kGet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) value[k] = i.get_string(vr[k]);
  });
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
  return guarded(c, "fmi2SetReal", kSet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) i.set_real(vr[k], value[k]);
    i.inputs_set();
  });
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
  return guarded(c, "fmi2SetInteger", kSet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) i.set_integer(vr[k], value[k]);
  });
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference[], size_t nvr, const fmi2Boolean[]) {
  return guarded(c, "fmi2SetBoolean", kSet, [&](Instance&) {
    if (nvr) throw FmuError(fmi2Error, "this FMU has no Boolean variables");
  });
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
  return guarded(c, "fmi2SetString", kSet, [&](Instance& i) {
    for (size_t k = 0; k < nvr; ++k) i.set_string(vr[k], value[k]);
  });
}

// The FE model's state lives in another process: it cannot be saved or restored here.
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2GetFMUstate", "canGetAndSetFMUstate");
}
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate) {
  return unsupported(c, "fmi2SetFMUstate", "canGetAndSetFMUstate");
}
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate*) {
  return unsupported(c, "fmi2FreeFMUstate", "canGetAndSetFMUstate");
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate, size_t*) {
  return unsupported(c, "fmi2SerializedFMUstateSize", "canSerializeFMUstate");
}
fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate, fmi2Byte[], size_t) {
  return unsupported(c, "fmi2SerializeFMUstate", "canSerializeFMUstate");
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte[], size_t, fmi2FMUstate*) {
  return unsupported(c, "fmi2DeSerializeFMUstate", "canSerializeFMUstate");
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference[], size_t,
                                        const fmi2ValueReference[], size_t, const fmi2Real[],
                                        fmi2Real[]) {
  return unsupported(c, "fmi2GetDirectionalDerivative", "providesDirectionalDerivative");
}
fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t,
                                       const fmi2Integer[], const fmi2Real[]) {
  return unsupported(c, "fmi2SetRealInputDerivatives", "canInterpolateInputs");
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference[], size_t,
                                        const fmi2Integer[], fmi2Real[]) {
  return unsupported(c, "fmi2GetRealOutputDerivatives", "maxOutputDerivativeOrder > 0");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize, fmi2Boolean) {
  return guarded(c, "fmi2DoStep", kDoStep,
                 [&](Instance& i) { i.do_step(currentCommunicationPoint, communicationStepSize); });
}

fmi2Status fmi2CancelStep(fmi2Component c) {
  return guarded(c, "fmi2CancelStep", kAnyButFatal, [](Instance&) {
    throw FmuError(fmi2Error, "no step in progress: fmi2DoStep is synchronous and never returns fmi2Pending");
  });
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind, fmi2Status*) {
  return guarded(c, "fmi2GetStatus", kStatus, [](Instance&) {
    throw FmuError(fmi2Discard, "no asynchronous step: fmi2DoStep never returns fmi2Pending");
  });
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real* value) {
  return guarded(c, "fmi2GetRealStatus", kStatus, [&](Instance& i) {
    if (s != fmi2LastSuccessfulTime)
      throw FmuError(fmi2Discard, "only fmi2LastSuccessfulTime is a Real status");
    *value = i.last_successful_time();
  });
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind, fmi2Integer*) {
  return guarded(c, "fmi2GetIntegerStatus", kStatus,
                 [](Instance&) { throw FmuError(fmi2Discard, "no Integer status is defined"); });
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean* value) {
  return guarded(c, "fmi2GetBooleanStatus", kStatus, [&](Instance& i) {
    if (s != fmi2Terminated) throw FmuError(fmi2Discard, "only fmi2Terminated is a Boolean status");
    *value = i.state() == State::Terminated ? fmi2True : fmi2False;
  });
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind, fmi2String*) {
  return guarded(c, "fmi2GetStringStatus", kStatus,
                 [](Instance&) { throw FmuError(fmi2Discard, "no String status is defined"); });
}

}  // extern "C"

// Beyond FMI 2.0: checkpoint and restart of the co-simulation (tlm_host
// looks these up by name and does without them when absent; other importers
// never see them). Declared here only: the importer declares its own
// prototypes. The FMI state functions (fmi2GetFMUstate, ...) would promise
// rolling back to any saved state at any time, which a remote FE server
// restarted from a file cannot do; these promise only what is true.
extern "C" {

// Ask fe_server to save its state after the steps done so far; its file's
// path goes to path (cap bytes, NUL-terminated). In StepComplete only.
PCS_FMI2_API fmi2Status pcs_fmu_checkpoint(fmi2Component c, char* path, size_t cap) {
  return guarded(c, "pcs_fmu_checkpoint", kDoStep, [&](Instance& i) {
    const std::string p = i.checkpoint();
    if (!path || cap == 0 || p.size() >= cap) throw FmuError(fmi2Error, "the checkpoint path does not fit the buffer");
    std::memcpy(path, p.c_str(), p.size() + 1);
  });
}

// Resume a session after `step` coupling steps: before
// fmi2ExitInitializationMode, against an fe_server started with --restart
// and its checkpoint of the same step.
PCS_FMI2_API fmi2Status pcs_fmu_resume(fmi2Component c, unsigned long long step) {
  return guarded(c, "pcs_fmu_resume", kSetupExperiment | kExitInit,
                 [&](Instance& i) { i.set_resume_step(static_cast<uint64_t>(step)); });
}

// After fmi2ExitInitializationMode of a resumed instance: wait for
// fe_server's answer to the RESUME (agreed, or refused saying why), which
// otherwise comes with the first fmi2DoStep. A restarted importer calls it
// (for all its instances at once: the server answers when every FMU of the
// session has connected) before it touches its results, so that a refused
// restart leaves them as they were.
PCS_FMI2_API fmi2Status pcs_fmu_confirm_resume(fmi2Component c) {
  return guarded(c, "pcs_fmu_confirm_resume", kDoStep, [&](Instance& i) { i.confirm_resume(); });
}

// Set *requested to 1 when fe_server got a stop signal and asks the host
// for a checkpoint (then pcs_fmu_checkpoint, and the end of the session),
// else 0. After any fmi2DoStep.
PCS_FMI2_API fmi2Status pcs_fmu_stop_requested(fmi2Component c, int* requested) {
  return guarded(c, "pcs_fmu_stop_requested", kAnyButFatal, [&](Instance& i) {
    if (!requested) throw FmuError(fmi2Error, "requested is a null pointer");
    *requested = i.importer_asks_stop_requested() ? 1 : 0;
  });
}

// Hand this FMU's socketlib the importer's stop flag (a sig_atomic_t its
// signal handler sets; NULL: none). Every wait of the link then returns
// within 200 ms of a stop signal, as the importer's own waits do. The FMU
// shares no globals with the importer otherwise: its copy of socketlib is
// linked in statically with hidden symbols. Called once, after loading.
PCS_FMI2_API void pcs_fmu_set_stop_flag(const volatile sig_atomic_t* flag) {
  sl_set_stop_flag(flag);
}

}  // extern "C"
