// The registry of component types a model file may name.
#include "component.hpp"
#include "components/cosim/FmuQ.hpp"
#include "components/hydraulic/AccumulatorQ.hpp"
#include "components/hydraulic/CylinderC.hpp"
#include "components/hydraulic/CylinderQ.hpp"
#include "components/hydraulic/FlowSourceQ.hpp"
#include "components/hydraulic/GasAccumulatorC.hpp"
#include "components/hydraulic/HoseC.hpp"
#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/hydraulic/HydraulicVolumeC.hpp"
#include "components/hydraulic/LaminarLineC.hpp"
#include "components/hydraulic/LaminarOrificeQ.hpp"
#include "components/hydraulic/LosslessLineC.hpp"
#include "components/hydraulic/PistonAccumulatorQ.hpp"
#include "components/hydraulic/PressureControlledValveQ.hpp"
#include "components/hydraulic/PressureReliefValveQ.hpp"
#include "components/hydraulic/PressureSourceC.hpp"
#include "components/hydraulic/ReliefValveQ.hpp"
#include "components/hydraulic/SpoolValveQ.hpp"
#include "components/hydraulic/Valve22ProportionalQ.hpp"
#include "components/hydraulic/Valve22Q.hpp"
#include "components/hydraulic/Valve32Q.hpp"
#include "components/hydraulic/Valve33Q.hpp"
#include "components/hydraulic/Valve42Q.hpp"
#include "components/hydraulic/Valve43Q.hpp"
#include "components/hydraulic/VariableOrificeQ.hpp"
#include "components/mechanic/ForceSourceC.hpp"
#include "components/mechanic/TranslationalMassQ.hpp"
#include "components/percussion/ControlSpoolQ.hpp"
#include "components/percussion/HammerPistonQ.hpp"
#include "components/percussion/PistonMechanicsSignal.hpp"
#include "components/percussion/SpoolMechanicsSignal.hpp"
#include "components/percussion/SpringPistonQ.hpp"
#include "components/signal/SignalAdd.hpp"
#include "components/signal/SignalFirstOrderFilter.hpp"
#include "components/signal/SignalGain.hpp"
#include "components/signal/SignalLowPass.hpp"
#include "components/signal/SignalRamp.hpp"
#include "components/signal/SignalIntegrator.hpp"
#include "components/signal/SignalMultiply.hpp"
#include "components/signal/SignalPulse.hpp"
#include "components/signal/SignalSineWave.hpp"
#include "components/signal/SignalRateLimiter.hpp"
#include "components/signal/SignalSoftStep.hpp"
#include "components/signal/SignalStep.hpp"
#include "components/signal/SignalSubtract.hpp"
#include "components/signal/SignalTable.hpp"

namespace tlm {

template <class T>
static ComponentFactory make() {
  return [](const std::string& name) { return std::make_unique<T>(name); };
}

const std::map<std::string, ComponentFactory>& component_types() {
  static const std::map<std::string, ComponentFactory> types = {
      {"PressureSourceC", make<PressureSourceC>()},
      {"HydraulicVolumeC", make<HydraulicVolumeC>()},
      {"HydraulicTurbulentOrificeQ", make<HydraulicTurbulentOrificeQ>()},
      {"FmuQ", make<FmuQ>()},
      {"FlowSourceQ", make<FlowSourceQ>()},
      {"LaminarOrificeQ", make<LaminarOrificeQ>()},
      {"ReliefValveQ", make<ReliefValveQ>()},
      {"LosslessLineC", make<LosslessLineC>()},
      {"LaminarLineC", make<LaminarLineC>()},
      {"GasAccumulatorC", make<GasAccumulatorC>()},
      {"VariableOrificeQ", make<VariableOrificeQ>()},
      {"SpoolValveQ", make<SpoolValveQ>()},
      {"ControlSpoolQ", make<ControlSpoolQ>()},
      {"HammerPistonQ", make<HammerPistonQ>()},
      {"SpringPistonQ", make<SpringPistonQ>()},
      {"PistonMechanicsSignal", make<PistonMechanicsSignal>()},
      {"SpoolMechanicsSignal", make<SpoolMechanicsSignal>()},
      {"SignalStep", make<SignalStep>()},
      {"SignalRamp", make<SignalRamp>()},
      {"SignalTable", make<SignalTable>()},
      {"SignalGain", make<SignalGain>()},
      {"SignalAdd", make<SignalAdd>()},
      {"SignalSubtract", make<SignalSubtract>()},
      {"SignalLowPass", make<SignalLowPass>()},
      {"SignalFirstOrderFilter", make<SignalFirstOrderFilter>()},
      {"SignalSoftStep", make<SignalSoftStep>()},
      {"SignalSineWave", make<SignalSineWave>()},
      {"SignalPulse", make<SignalPulse>()},
      {"SignalMultiply", make<SignalMultiply>()},
      {"SignalRateLimiter", make<SignalRateLimiter>()},
      {"SignalIntegrator", make<SignalIntegrator>()},
      {"TranslationalMassQ", make<TranslationalMassQ>()},
      {"CylinderC", make<CylinderC>()},
      {"CylinderQ", make<CylinderQ>()},
      {"ForceSourceC", make<ForceSourceC>()},
      {"Valve43Q", make<Valve43Q>()},
      {"Valve32Q", make<Valve32Q>()},
      {"Valve33Q", make<Valve33Q>()},
      {"Valve22Q", make<Valve22Q>()},
      {"Valve22ProportionalQ", make<Valve22ProportionalQ>()},
      {"Valve42Q", make<Valve42Q>()},
      {"PressureControlledValveQ", make<PressureControlledValveQ>()},
      {"PressureReliefValveQ", make<PressureReliefValveQ>()},
      {"AccumulatorQ", make<AccumulatorQ>()},
      {"PistonAccumulatorQ", make<PistonAccumulatorQ>()},
      {"HoseC", make<HoseC>()},
  };
  return types;
}

}  // namespace tlm
