// Coupling stability estimate, printed before a co-simulation starts.
//
// A rigid piston of mass m on a chamber of volume V (bulk modulus β) through
// a wetted area A oscillates at ω² = β·A²/(V·m). The two coupling modes
// differ in kind:
//  - pressure coupling holds the host's pressure, computed from the last
//    step's flow, over the coupling step T: a delayed loop. The stability
//    map (bench/RESULTS.md: m = 0.05–5 kg, V = 0.1–100 cm³) measures its
//    limit between ω·T = 1.33 and 1.46 in every case; the estimate asks
//    ω·T ≤ 1, i.e. V ≥ β·A²·T²/m, a margin of 1.33–1.46 on the measured limit;
//  - TLM coupling solves p = c + Zc·q implicitly on the FE side
//    (cavity_load.hpp) and is stable for any T and V. The step sets the
//    accuracy instead: the frequency error of the stability map grows as
//    about kTlmErrorPerOmegaT2·(ω·T)², so the estimate prints the chamber
//    for which it stays below 1 %.
// fe_server knows m, A and T but not the host's V or β, so it prints the
// smallest chamber volume per port (at a stated β).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "model/model.hpp"

namespace fe {

struct PortStability {
  std::string label;
  int port_id = 0;
  double mass = 0.0;            // kg moving with the port's surface (its rigid body, else its nodes)
  double area = 0.0;            // m², the surface's area (bounds ignored)
  double v_min_pressure = 0.0;  // m³, smallest chamber for ω·T ≤ 1 in pressure coupling
  double v_accurate_tlm = 0.0;  // m³, smallest chamber for a 1 % frequency error in TLM coupling
};

// Frequency error of TLM coupling per (ω·T)², measured on the stability map
// (bench/RESULTS.md): |Δf/f| ≈ kTlmErrorPerOmegaT2·(ω·T)².
constexpr double kTlmErrorPerOmegaT2 = 0.2;
// The largest ω·T a TLM port may run at without --allow-coarse-coupling:
// where the estimate above reaches a 10 % frequency error (ω·T ≈ 0.71).
// Beyond it the step is no longer a model of the chamber (ω·T = 529 drifted
// to −66 mm against a 1 µm amplitude, exit 0, before this guard).
constexpr double kMaxTlmFrequencyError = 0.10;
inline double max_tlm_omega_t() { return std::sqrt(kMaxTlmFrequencyError / kTlmErrorPerOmegaT2); }
// The largest ω·T a pressure-coupled port may run at without
// --allow-coarse-coupling, when its table sends the host's Zc: the
// estimate's ω·T ≤ 1, a margin of 1.33–1.46 on the limit the stability map
// measured (the held pressure diverges beyond it: the one-DOF piston on
// 0.01 cm³ at 10 µs, ω·T = 1.7, swung to −133 bar within steps).
constexpr double kMaxPressureOmegaT = 1.0;

// Per hydraulic port of the table, at bulk modulus beta.
std::vector<PortStability> coupling_stability(const Model& model, const config::PortTable& table, double beta);

// One line per port, as fe_server prints it before a session.
std::string coupling_stability_text(const std::vector<PortStability>& ports, const config::PortTable& table,
                                    double beta);

}  // namespace fe
