// Two-node 1D bar (truss, *SECTION_BEAM ELFORM 3): axial force only,
// N = E·A·(ℓ − L0)/L0 along the current axis, from the positions x_n alone.
// (An update with the elongation rate over the current length, as the
// solids' hypoelastic rate form does, is not the linear spring the wave
// equation assumes: at Courant number 1, where the lumped chain carries a
// rectangular pulse exactly, the compressed bars stiffen and the chain
// diverged; and the rate of v_0 on the first step added a force before
// anything had moved.)
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
  std::vector<double> length0, length;  // reference and last length, m
  // owner: as Hex8State's.
  explicit BarState(const Model& m, const std::vector<int>* owner = nullptr, int rank = 0);
};

// The axial forces at positions x, added to f; the internal work since the
// last call to w (the trapezoidal rule over the change of length).
void bar_forces(const Model& m, BarState& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                std::vector<Vec3>& f, ElementWork& w);

}  // namespace fe
