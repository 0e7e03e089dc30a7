// Shared mechanics of rigid bodies with hydraulic faces (Q-type).
//
// A face of area A whose chamber shrinks as the body moves in +x (sign s = +1)
// or grows (s = −1) delivers q = s·A·v into its node and feels
// p = c + Zc·q, i.e. a force F = −s·A·p = −s·A·c − Zc·A²·v. The Zc·A² part is
// the chamber's wave impedance acting as damping; it is integrated
// implicitly so that a small, stiff chamber cannot destabilise the body:
//   v⁺ = (m·v + Δt·F_explicit) / (m + Δt·Σ Zc·A²),   x⁺ = x + Δt·v⁺.
#pragma once

#include <cmath>
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

// Largest stable step of a spring k and damper c on a mass m integrated
// explicitly: (2/ω)·(√(1 + ζ²) − ζ), ω² = k/m, ζ = c/(2·√(k·m)), the
// central-difference limit with viscous damping (Belytschko, Liu & Moran,
// Nonlinear Finite Elements, §6.3). A strong damper lowers it below 2/ω.
inline double spring_damper_stable_step(double k, double c, double m) {
  if (!(k > 0.0) || !(m > 0.0)) return 1e300;
  const double omega = std::sqrt(k / m), zeta = c / (2.0 * std::sqrt(k * m));
  return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

// One step of a body with hydraulic faces: F and B hold the explicit force
// and the implicit damping of everything but the faces; the faces add theirs,
// then v⁺ = (m·v + Δt·F)/(m + Δt·B), x⁺ = x + Δt·v⁺, and the faces' flows
// and pressures follow from v⁺.
inline void advance_body(std::vector<Port>& ports, const std::vector<HydraulicFace>& faces, double m, double dt,
                         double F, double B, double& x, double& v) {
  face_forces(ports, faces, F, B);
  v = (m * v + dt * F) / (m + dt * B);
  x += dt * v;
  face_outputs(ports, faces, v);
}

// One-sided spring-damper force of an end stop or contact: it only pushes.
// `penetration` > 0 when engaged, `rate` its time derivative.
inline double stop_force(double penetration, double rate, double k, double c) {
  if (penetration <= 0.0) return 0.0;
  const double f = k * penetration + c * rate;
  return f > 0.0 ? f : 0.0;
}

}  // namespace tlm
