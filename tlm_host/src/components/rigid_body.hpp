// Shared mechanics of rigid bodies with hydraulic faces (Q-type).
//
// A face of area A whose chamber shrinks as the body moves in +x (sign s = +1)
// or grows (s = −1) delivers q = s·A·v into its node and feels
// p = c + Zc·q, i.e. a force F = −s·A·p = −s·A·c − Zc·A²·v. The Zc·A² part is
// the chamber's wave impedance acting as damping; it is integrated
// implicitly so that a small, stiff chamber cannot destabilise the body:
//   v⁺ = (m·v + Δt·F_explicit) / (m + Δt·Σ Zc·A²),   x⁺ = x + Δt·v⁺.
#pragma once

#include <vector>

#include "component.hpp"

namespace tlm {

struct HydraulicFace {
  size_t port = 0;    // index into the component's ports
  double area = 0.0;  // m²
  double sign = 1.0;  // +1: the chamber shrinks when the body moves +x
};

// Explicit hydraulic force Σ −s·A·c and implicit damping Σ Zc·A².
inline void face_forces(const std::vector<Port>& ports, const std::vector<HydraulicFace>& faces, double& force,
                        double& damping) {
  for (const auto& f : faces) {
    const HydraulicNode& n = *ports[f.port].node;
    force -= f.sign * f.area * n.c;
    damping += n.Zc * f.area * f.area;
  }
}

// Write each face's flow and pressure for the new velocity.
inline void face_outputs(std::vector<Port>& ports, const std::vector<HydraulicFace>& faces, double v) {
  for (const auto& f : faces) {
    HydraulicNode& n = *ports[f.port].node;
    n.q = f.sign * f.area * v;
    n.p = n.c + n.Zc * n.q;
  }
}

// One-sided spring-damper force of an end stop or contact: it only pushes.
// `penetration` > 0 when engaged, `rate` its time derivative.
inline double stop_force(double penetration, double rate, double k, double c) {
  if (penetration <= 0.0) return 0.0;
  const double f = k * penetration + c * rate;
  return f > 0.0 ? f : 0.0;
}

}  // namespace tlm
