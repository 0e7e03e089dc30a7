// The exported FMI 3.0 functions: the same instance, link and state machine
// as FMI 2.0's (fmi2_functions.cpp), behind 3.0's interface. fmugen --fmi 3
// describes the FMU as co-simulation without event mode, intermediate update
// or early return; its variables are Float64 (the ports' quantities,
// server.timeout, the independent variable time), Int32 (server.port) and
// String (server.host, server.token). Every function the standard lists is
// exported; what the model description says the FMU cannot do is refused
// with a message saying which capability is false.
#include <string>
#include <utility>

#include "config/port_table.hpp"
#include "fmi3/fmi3.h"
#include "guarded.hpp"
#include "instance.hpp"

using namespace pcs_fmu;  // Instance, FmuError, the states' masks and the shell (guarded.hpp)

namespace {

template <class F>
fmi3Status guarded(fmi3Instance c, const char* fn, unsigned allowed, F&& work) {
  return pcs_fmu::guarded<fmi3Status>(c, fn, allowed, std::forward<F>(work));
}

fmi3Status unsupported(fmi3Instance c, const char* fn, const char* capability) {
  return pcs_fmu::unsupported<fmi3Status>(c, fn, capability);
}

// Every array of values is one per value reference: all variables are scalars.
void check_counts(size_t n_refs, size_t n_values) {
  if (n_refs != n_values)
    throw FmuError(fmi2Error, std::to_string(n_values) + " values for " + std::to_string(n_refs) +
                                  " value references: every variable of this FMU is a scalar");
}

// A type this FMU has no variables of: an empty call is fine, any reference is unknown.
fmi3Status none_of(fmi3Instance c, const char* fn, unsigned allowed, size_t n_refs, const char* type) {
  return guarded(c, fn, allowed, [&](Instance&) {
    if (n_refs) throw FmuError(fmi2Error, std::string("this FMU has no ") + type + " variables");
  });
}

}  // namespace

extern "C" {

const char* fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean loggingOn, size_t, const fmi3String[]) {
  return guarded(c, "fmi3SetDebugLogging", kAnyButFatal, [&](Instance& i) { i.set_logging(loggingOn); });
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean,
                                          fmi3InstanceEnvironment env, fmi3LogMessageCallback logMessage) {
  if (logMessage)
    logMessage(env, fmi3Error, "logStatusError",
               (std::string(instanceName ? instanceName : "?") +
                ": fmi3InstantiateModelExchange: this FMU supports co-simulation only")
                   .c_str());
  return nullptr;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String, fmi3String, fmi3Boolean,
                                               fmi3Boolean, fmi3InstanceEnvironment env,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback,
                                               fmi3LockPreemptionCallback, fmi3UnlockPreemptionCallback) {
  if (logMessage)
    logMessage(env, fmi3Error, "logStatusError",
               (std::string(instanceName ? instanceName : "?") +
                ": fmi3InstantiateScheduledExecution: this FMU supports co-simulation only")
                   .c_str());
  return nullptr;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean,
                                         const fmi3ValueReference[], size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment env, fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback) {
  auto complain = [&](const std::string& msg) {
    if (logMessage) logMessage(env, fmi3Error, "logStatusError", msg.c_str());
  };
  if (!instanceName || !*instanceName) {
    complain("fmi3InstantiateCoSimulation: instanceName is empty");
    return nullptr;
  }
  const std::string name = instanceName;
  if (!instantiationToken || !resourcePath) {
    complain(name + ": fmi3InstantiateCoSimulation: instantiationToken and resourcePath are required");
    return nullptr;
  }
  if (eventModeUsed) {
    complain(name + ": fmi3InstantiateCoSimulation: eventModeUsed, but hasEventMode is false in modelDescription.xml");
    return nullptr;
  }
  if (nRequiredIntermediateVariables) {
    complain(name + ": fmi3InstantiateCoSimulation: intermediate variables asked for, but providesIntermediateUpdate "
                    "is false in modelDescription.xml");
    return nullptr;
  }
  Instance::LogSink sink;
  if (logMessage)
    sink = [logMessage, env, name](fmi2Status status, const char* category, const std::string& message) {
      logMessage(env, static_cast<fmi3Status>(status), category, (name + ": " + message).c_str());
    };
  try {
    return new Instance(name, instantiationToken, resourcePath, sink, loggingOn);
  } catch (const std::exception& e) {
    complain(name + ": fmi3InstantiateCoSimulation: " + e.what());
    return nullptr;
  }
}

void fmi3FreeInstance(fmi3Instance c) { free_instance(c, "fmi3Terminate"); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean, fmi3Float64, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
  return guarded(c, "fmi3EnterInitializationMode", kEnterInit, [&](Instance& i) {
    check_start_time(startTime);
    i.set_stop_time(stopTimeDefined, stopTime);
    i.enter_initialization();
  });
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance c) {
  return guarded(c, "fmi3ExitInitializationMode", kExitInit, [](Instance& i) { i.exit_initialization(); });
}

fmi3Status fmi3Terminate(fmi3Instance c) {
  return guarded(c, "fmi3Terminate", kTerminate, [](Instance& i) { i.terminate(); });
}

fmi3Status fmi3Reset(fmi3Instance c) {
  return guarded(c, "fmi3Reset", kAnyButFatal, [](Instance& i) { i.reset(); });
}

fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
  return guarded(c, "fmi3GetFloat64", kGet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k)
      values[k] = vr[k] == config::kVrTime ? i.last_successful_time() : i.get_real(vr[k]);
  });
}

fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 values[],
                          size_t nValues) {
  return guarded(c, "fmi3SetFloat64", kSet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k) {
      if (vr[k] == config::kVrTime) throw FmuError(fmi2Error, "time is the independent variable: it cannot be set");
      i.set_real(vr[k], values[k]);
    }
    i.inputs_set();
  });
}

fmi3Status fmi3GetInt32(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, fmi3Int32 values[],
                        size_t nValues) {
  return guarded(c, "fmi3GetInt32", kGet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k) values[k] = i.get_integer(vr[k]);
  });
}

fmi3Status fmi3SetInt32(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 values[],
                        size_t nValues) {
  return guarded(c, "fmi3SetInt32", kSet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k) i.set_integer(vr[k], values[k]);
  });
}

fmi3Status fmi3GetString(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, fmi3String values[],
                         size_t nValues) {
  return guarded(c, "fmi3GetString", kGet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k) values[k] = i.get_string(vr[k]);
  });
}

fmi3Status fmi3SetString(fmi3Instance c, const fmi3ValueReference vr[], size_t nvr, const fmi3String values[],
                         size_t nValues) {
  return guarded(c, "fmi3SetString", kSet, [&](Instance& i) {
    check_counts(nvr, nValues);
    for (size_t k = 0; k < nvr; ++k) i.set_string(vr[k], values[k]);
  });
}

// The types this FMU has no variables of.
#define PCS_NONE_OF(suffix, type)                                                                              \
  fmi3Status fmi3Get##suffix(fmi3Instance c, const fmi3ValueReference[], size_t nvr, type[], size_t) {        \
    return none_of(c, "fmi3Get" #suffix, kGet, nvr, #suffix);                                                  \
  }                                                                                                            \
  fmi3Status fmi3Set##suffix(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const type[], size_t) {  \
    return none_of(c, "fmi3Set" #suffix, kSet, nvr, #suffix);                                                  \
  }
PCS_NONE_OF(Float32, fmi3Float32)
PCS_NONE_OF(Int8, fmi3Int8)
PCS_NONE_OF(UInt8, fmi3UInt8)
PCS_NONE_OF(Int16, fmi3Int16)
PCS_NONE_OF(UInt16, fmi3UInt16)
PCS_NONE_OF(UInt32, fmi3UInt32)
PCS_NONE_OF(Int64, fmi3Int64)
PCS_NONE_OF(UInt64, fmi3UInt64)
PCS_NONE_OF(Boolean, fmi3Boolean)
#undef PCS_NONE_OF

fmi3Status fmi3GetBinary(fmi3Instance c, const fmi3ValueReference[], size_t nvr, size_t[], fmi3Binary[], size_t) {
  return none_of(c, "fmi3GetBinary", kGet, nvr, "Binary");
}
fmi3Status fmi3SetBinary(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const size_t[], const fmi3Binary[],
                         size_t) {
  return none_of(c, "fmi3SetBinary", kSet, nvr, "Binary");
}
fmi3Status fmi3GetClock(fmi3Instance c, const fmi3ValueReference[], size_t nvr, fmi3Clock[]) {
  return none_of(c, "fmi3GetClock", kGet, nvr, "Clock");
}
fmi3Status fmi3SetClock(fmi3Instance c, const fmi3ValueReference[], size_t nvr, const fmi3Clock[]) {
  return none_of(c, "fmi3SetClock", kSet, nvr, "Clock");
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance c, fmi3ValueReference, size_t*) {
  return unsupported(c, "fmi3GetNumberOfVariableDependencies", "providesPerElementDependencies");
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance c, fmi3ValueReference, size_t[], fmi3ValueReference[], size_t[],
                                       fmi3DependencyKind[], size_t) {
  return unsupported(c, "fmi3GetVariableDependencies", "providesPerElementDependencies");
}

// The FE model's state lives in another process: it cannot be saved or restored here.
fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState*) {
  return unsupported(c, "fmi3GetFMUState", "canGetAndSetFMUState");
}
fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState) {
  return unsupported(c, "fmi3SetFMUState", "canGetAndSetFMUState");
}
fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState*) {
  return unsupported(c, "fmi3FreeFMUState", "canGetAndSetFMUState");
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState, size_t*) {
  return unsupported(c, "fmi3SerializedFMUStateSize", "canSerializeFMUState");
}
fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState, fmi3Byte[], size_t) {
  return unsupported(c, "fmi3SerializeFMUState", "canSerializeFMUState");
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte[], size_t, fmi3FMUState*) {
  return unsupported(c, "fmi3DeserializeFMUState", "canSerializeFMUState");
}
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                                        size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetDirectionalDerivative", "providesDirectionalDerivatives");
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3ValueReference[],
                                    size_t, const fmi3Float64[], size_t, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetAdjointDerivative", "providesAdjointDerivatives");
}
fmi3Status fmi3GetOutputDerivatives(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3Int32[],
                                    fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetOutputDerivatives", "maxOutputDerivativeOrder > 0");
}

// No structural parameters, clocks, event mode or model exchange.
fmi3Status fmi3EnterConfigurationMode(fmi3Instance c) {
  return unsupported(c, "fmi3EnterConfigurationMode", "a structural parameter");
}
fmi3Status fmi3ExitConfigurationMode(fmi3Instance c) {
  return unsupported(c, "fmi3ExitConfigurationMode", "a structural parameter");
}
fmi3Status fmi3GetIntervalDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3Float64[],
                                  fmi3IntervalQualifier[]) {
  return unsupported(c, "fmi3GetIntervalDecimal", "a clock");
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[],
                                   fmi3IntervalQualifier[]) {
  return unsupported(c, "fmi3GetIntervalFraction", "a clock");
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3Float64[]) {
  return unsupported(c, "fmi3GetShiftDecimal", "a clock");
}
fmi3Status fmi3GetShiftFraction(fmi3Instance c, const fmi3ValueReference[], size_t, fmi3UInt64[], fmi3UInt64[]) {
  return unsupported(c, "fmi3GetShiftFraction", "a clock");
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return unsupported(c, "fmi3SetIntervalDecimal", "a clock");
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                   const fmi3UInt64[]) {
  return unsupported(c, "fmi3SetIntervalFraction", "a clock");
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3Float64[]) {
  return unsupported(c, "fmi3SetShiftDecimal", "a clock");
}
fmi3Status fmi3SetShiftFraction(fmi3Instance c, const fmi3ValueReference[], size_t, const fmi3UInt64[],
                                const fmi3UInt64[]) {
  return unsupported(c, "fmi3SetShiftFraction", "a clock");
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance c) {
  return unsupported(c, "fmi3EvaluateDiscreteStates", "providesEvaluateDiscreteStates");
}
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean*, fmi3Boolean*, fmi3Boolean*, fmi3Boolean*,
                                    fmi3Boolean*, fmi3Float64*) {
  return unsupported(c, "fmi3UpdateDiscreteStates", "hasEventMode");
}
fmi3Status fmi3EnterEventMode(fmi3Instance c) { return unsupported(c, "fmi3EnterEventMode", "hasEventMode"); }
fmi3Status fmi3EnterStepMode(fmi3Instance c) { return unsupported(c, "fmi3EnterStepMode", "hasEventMode"); }
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) {
  return unsupported(c, "fmi3EnterContinuousTimeMode", "ModelExchange");
}
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean, fmi3Boolean*, fmi3Boolean*) {
  return unsupported(c, "fmi3CompletedIntegratorStep", "ModelExchange");
}
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64) { return unsupported(c, "fmi3SetTime", "ModelExchange"); }
fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64[], size_t) {
  return unsupported(c, "fmi3SetContinuousStates", "ModelExchange");
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetContinuousStateDerivatives", "ModelExchange");
}
fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetEventIndicators", "ModelExchange");
}
fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetContinuousStates", "ModelExchange");
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64[], size_t) {
  return unsupported(c, "fmi3GetNominalsOfContinuousStates", "ModelExchange");
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t*) {
  return unsupported(c, "fmi3GetNumberOfEventIndicators", "ModelExchange");
}
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t*) {
  return unsupported(c, "fmi3GetNumberOfContinuousStates", "ModelExchange");
}
fmi3Status fmi3ActivateModelPartition(fmi3Instance c, fmi3ValueReference, fmi3Float64) {
  return unsupported(c, "fmi3ActivateModelPartition", "ScheduledExecution");
}

// Synchronous, as FMI 2.0's: a communication step of n coupling steps is n
// exchanges with fe_server. Never an event, an early return or a request to
// terminate (a failure is an error status with its message instead).
fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean, fmi3Boolean* eventHandlingNeeded, fmi3Boolean* terminateSimulation,
                      fmi3Boolean* earlyReturn, fmi3Float64* lastSuccessfulTime) {
  if (eventHandlingNeeded) *eventHandlingNeeded = false;
  if (terminateSimulation) *terminateSimulation = false;
  if (earlyReturn) *earlyReturn = false;
  const fmi3Status s = guarded(c, "fmi3DoStep", kDoStep,
                               [&](Instance& i) { i.do_step(currentCommunicationPoint, communicationStepSize); });
  if (lastSuccessfulTime && c) *lastSuccessfulTime = static_cast<Instance*>(c)->last_successful_time();
  return s;
}

}  // extern "C"
