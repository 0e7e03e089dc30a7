// The registry of component types a model file may name.
#include "component.hpp"
#include "components/FmuQ.hpp"
#include "components/HydraulicTurbulentOrificeQ.hpp"
#include "components/HydraulicVolumeC.hpp"
#include "components/PressureSourceC.hpp"

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
  };
  return types;
}

}  // namespace tlm
