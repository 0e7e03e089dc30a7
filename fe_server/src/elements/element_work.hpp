// What the element loops hand back to the solver each step, and the error an
// inverted element raises (the solver adds the time and step to its message).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace fe {

// Increments of one step's energy account, summed over an element loop.
struct ElementWork {
  double internal = 0.0;       // elastic work of the elements this step, J
  double hourglass = 0.0;      // dissipated by hourglass control this step, J
  double damping_power = 0.0;  // dampers and bulk viscosity, W (the solver integrates it)
  double spring_energy = 0.0;  // energy stored in the springs now, J
  // The smallest current stable step (no safety factor) of the solids and
  // axisymmetric elements as deformed now, and which: kind 1 a solid, 2 an
  // axisymmetric element; `limit_element` its index in the model's list.
  // The solver takes its next step from it (solver.hpp).
  double step_limit = 1e300;
  int limit_kind = 0;
  long limit_element = -1;
  // Per part (Model::parts order), the solids' internal work and hourglass
  // energy of this step, added to where the solver points these (or not kept).
  std::vector<double>* part_internal = nullptr;
  std::vector<double>* part_hourglass = nullptr;
};

// An element whose volume or area became non-positive: `what` names it (e.g.
// "solid element 5 (part 1)") and `measure` its volume or area.
struct InvertedElement : std::runtime_error {
  InvertedElement(const std::string& which, const std::string& size)
      : std::runtime_error(which + " inverted (" + size + ")"), element(which), measure(size) {}
  std::string element, measure;
};

}  // namespace fe
