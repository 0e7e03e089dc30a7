// Two-node 1D bar (truss, *SECTION_BEAM ELFORM 3): axial force only, from a
// hypoelastic update of the axial force with the elongation rate.
#pragma once

#include <vector>

#include "elements/element_work.hpp"
#include "model/model.hpp"

namespace fe {

// The bars' state: axial force per element, N (tension positive), and what
// is resolved once: the bars of deformable parts, each bar's section area
// and axial stiffness E·A.
struct BarState {
  std::vector<double> force;
  std::vector<int> elements;
  std::vector<double> area, EA;
  explicit BarState(const Model& m);
};

// Updates the axial forces over a step dt and adds them to f; internal work to w.
void bar_forces(const Model& m, BarState& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                std::vector<Vec3>& f, ElementWork& w);

}  // namespace fe
