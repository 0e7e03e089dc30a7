// The mechanics around a hammer piston, apart from its hydraulic faces: gravity,
// seal friction, the top cushion, and the tool with the rock below it. Shared
// by HammerPistonQ (rigid piston in the host) and PistonMechanicsSignal
// (piston in fe_server, these forces sent through a mechanical port), so
// both model the same physics.
//
//   seal friction  F = −[(F0 + k_p·max(p_A, p_B))·tanh(v_f/v_s) + c_v·v_f],
//                  v_f = v low-pass filtered with time constant tau_f
//   top cushion    from x_cushion: one-sided k_cushion, c_cushion
//   tool           mass m_tool at height y (0 = resting on the rock), rock a
//                  compression-only spring-dashpot k_rock, c_rock; a feed force
//                  presses the tool down
//   impact         piston face on tool top when x < y: one-sided contact spring
//                  k_contact with the damping that gives restitution e_contact:
//                  ζ = −ln e / sqrt(π² + ln² e), c = 2ζ·sqrt(k·m_eff)
// With tool = fe the tool, the rock and the impact live in fe_server: the
// caller sets the tool's y and w from the FE before each step, no contact
// force is added, and F_contact is the lumped law's value for the FE
// overlap, kept only so that blows are detected the same way.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "components/rigid_body.hpp"

namespace tlm {

struct PercussionMechanics {
  double m = 0, g = 0, F0 = 0, k_p = 0, c_v = 0, v_s = 0, tau_f = 0;
  double x_cushion = 0, k_cushion = 0, c_cushion = 0, m_tool = 0, k_rock = 0, c_rock = 0, F_feed = 0;
  double k_contact = 0, c_contact = 0, v_blow = 0;
  bool lumped_tool = true;  // false: tool = fe
  // State.
  double v_f = 0, y = 0, w = 0, F_contact = 0, v_impact = 0, blows = 0, overlap_prev = 0, filter = 0, dt = 0;
  struct Impact {
    double time, velocity;
  };
  std::vector<Impact> impacts;

  void configure(ParameterSet& prm, const std::string& name) {
    m = prm.positive("m", 14.4, "kg");
    g = prm.real("g", 9.81, "m/s²");
    F0 = prm.real("F0", 80.0, "N");
    k_p = prm.real("k_p", 1e-5, "m²");
    c_v = prm.real("c_v", 25.0, "N·s/m");
    v_s = prm.positive("v_s", 0.05, "m/s");
    tau_f = prm.positive("tau_f", 2e-4, "s");
    x_cushion = prm.real("x_cushion", 0.095, "m");
    k_cushion = prm.positive("k_cushion", 1e8, "N/m");
    c_cushion = prm.real("c_cushion", 2e4, "N·s/m");
    const std::string tool = prm.text("tool", "lumped");
    if (tool != "lumped" && tool != "fe")
      throw config::InputError(prm.where(), name + ": tool must be 'lumped' (tool and rock here) or 'fe' (in fe_server), not '" + tool + "'");
    lumped_tool = tool == "lumped";
    m_tool = prm.positive("m_tool", 15.0, "kg");
    k_rock = prm.positive("k_rock", 1e9, "N/m");
    c_rock = prm.real("c_rock", 9.7e4, "N·s/m");
    F_feed = prm.real("F_feed", 0.0, "N");
    k_contact = prm.positive("k_contact", 2e9, "N/m");
    const double e = prm.real("e_contact", 0.9, "1");
    if (!(e > 0.0 && e <= 1.0)) throw config::InputError(prm.where(), name + ": e_contact must be in (0, 1]");
    const double zeta = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
    c_contact = 2.0 * zeta * std::sqrt(k_contact * m * m_tool / (m + m_tool));
    v_blow = prm.positive("v_blow", 1.0, "m/s");
  }
  void state(config::StateIO& io) {
    for (double* s : {&v_f, &y, &w, &F_contact, &v_impact, &blows, &overlap_prev}) io.value("mechanics", *s);
    io.list("impacts", impacts);
  }
  void initialize(double step) {
    dt = step;
    filter = 1.0 - std::exp(-step / tau_f);
  }
  // Force on the piston (all but the hydraulic faces) for piston state x, v
  // at time t; advances the tool by one step.
  double step(double t, double x, double v, double pA, double pB) {
    v_f += filter * (v - v_f);
    double F = -(F0 + k_p * std::max(pA, pB)) * std::tanh(v_f / v_s) - c_v * v_f - m * g;
    F -= stop_force(x - x_cushion, v, k_cushion, c_cushion);
    const double overlap = y - x;
    F_contact = stop_force(overlap, w - v, k_contact, c_contact);
    if (lumped_tool) F += F_contact;
    if (overlap > 0.0 && overlap_prev <= 0.0 && v < -v_blow) {
      v_impact = v;
      blows += 1.0;
      impacts.push_back({t, v});
    }
    overlap_prev = overlap;
    if (!lumped_tool) return F;
    const double F_tool = stop_force(-y, -w, k_rock, c_rock) - F_contact - m_tool * g - F_feed;
    w += dt * F_tool / m_tool;
    y += dt * w;
    return F;
  }
  double stable_step(std::string* why, const std::string& name) const {
    // Explicit one-sided spring-dampers (rigid_body.hpp).
    const double m_eff = m * m_tool / (m + m_tool);
    double dt_max = 1e300;
    std::string what;
    auto consider = [&](double step, const char* name_of) {
      if (step < dt_max) dt_max = step, what = name_of;
    };
    if (lumped_tool) {
      consider(spring_damper_stable_step(k_contact, c_contact, m_eff), "piston-tool contact");
      consider(spring_damper_stable_step(k_rock, c_rock, m_tool), "rock spring under the tool");
    }
    consider(spring_damper_stable_step(k_cushion, c_cushion, m), "top cushion");
    if (why) *why = name + ": " + what;
    return dt_max;
  }
};

}  // namespace tlm
