// Coupling stability estimate, printed before a co-simulation starts.
//
// A rigid piston of mass m on a chamber of volume V (bulk modulus β) through
// a wetted area A oscillates at ω² = β·A²/(V·m). The two coupling modes
// fail in different ways:
//  - pressure coupling holds the host's pressure over the coupling step T
//    while the structure moves, a zero-order hold with one step of delay.
//    The estimate asks ω·T ≤ 1 (the explicit-coupling rule of thumb; an
//    undamped delayed loop has no strict bound, the host's volume damps it),
//    i.e. V ≥ β·A²·T²/m;
//  - TLM coupling applies p = c + Zc·q in every FE step, a damper Zc·A² on
//    the piston that central difference integrates explicitly: stable for
//    Zc·A²·Δt_FE/m < 2. A two-port host volume has Zc = β·T/V
//    (HydraulicVolumeC), so V ≥ β·A²·T·Δt_FE/(2·m).
// fe_server knows m, A, T and Δt_FE but not the host's V or β, so it prints
// the smallest stable chamber volume per port (at a stated β).
#pragma once

#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "model.hpp"

namespace fe {

struct PortStability {
  std::string label;
  double mass = 0.0;            // kg moving with the port's surface (its rigid body, else its nodes)
  double area = 0.0;            // m², the surface's area (bounds ignored)
  double v_min_pressure = 0.0;  // m³, smallest chamber for ω·T ≤ 1 in pressure coupling
  double v_min_tlm = 0.0;       // m³, smallest chamber for a stable TLM damper
};

// Per hydraulic port of the table, at bulk modulus beta.
std::vector<PortStability> coupling_stability(const Model& model, const config::PortTable& table, double beta);

// One line per port, as fe_server prints it before a session.
std::string coupling_stability_text(const std::vector<PortStability>& ports, const config::PortTable& table,
                                    double beta);

}  // namespace fe
