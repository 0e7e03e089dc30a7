// The registry of component types a model file may name.
#include "component.hpp"
#include "components/AccumulatorQ.hpp"
#include "components/ControlSpoolQ.hpp"
#include "components/DirectionalValves.hpp"
#include "components/FlowSourceQ.hpp"
#include "components/FmuQ.hpp"
#include "components/GasAccumulatorC.hpp"
#include "components/HammerPistonQ.hpp"
#include "components/HoseC.hpp"
#include "components/HydraulicTurbulentOrificeQ.hpp"
#include "components/HydraulicVolumeC.hpp"
#include "components/LaminarOrificeQ.hpp"
#include "components/LosslessLineC.hpp"
#include "components/PressureReliefValveQ.hpp"
#include "components/PressureSourceC.hpp"
#include "components/ReliefValveQ.hpp"
#include "components/SignalSources.hpp"
#include "components/SpoolValveQ.hpp"
#include "components/SpringPistonQ.hpp"
#include "components/Translational.hpp"
#include "components/VariableOrificeQ.hpp"

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
      {"TranslationalMassQ", make<TranslationalMassQ>()},
      {"CylinderC", make<CylinderC>()},
      {"CylinderQ", make<CylinderQ>()},
      {"ForceSourceC", make<ForceSourceC>()},
      {"Valve43Q", make<Valve43Q>()},
      {"Valve32Q", make<Valve32Q>()},
      {"PressureReliefValveQ", make<PressureReliefValveQ>()},
      {"AccumulatorQ", make<AccumulatorQ>()},
      {"PistonAccumulatorQ", make<PistonAccumulatorQ>()},
      {"HoseC", make<HoseC>()},
  };
  return types;
}

}  // namespace tlm
