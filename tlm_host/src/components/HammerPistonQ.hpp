// The percussion piston of a hydraulic hammer as a rigid body (Q-type), with
// the tool and the rock below it lumped. x is the piston's lift above the
// impact position (up positive); gravity acts downwards.
//
//   ports: A (collar top, area A_A: the chamber shrinks as x grows, s = +1)
//          B (collar bottom, area A_B: the chamber grows, s = −1)
//   seal friction  F = −[(F0 + k_p·max(p_A, p_B))·tanh(v_f/v_s) + c_v·v_f],
//                  v_f = v low-pass filtered with time constant tau_f
//   top cushion    from x_cushion: one-sided k_cushion, c_cushion
//   tool           mass m_tool at height y (0 = resting on the rock), rock a
//                  compression-only spring-dashpot k_rock, c_rock; an optional
//                  feed force presses the tool down
//   impact         piston face on tool top when x < y: one-sided contact
//                  spring k_contact with the damping that gives restitution
//                  e_contact: ζ = −ln e / sqrt(π² + ln² e), c = 2ζ·sqrt(k·m_eff)
//
// Each contact onset with |v| > v_blow is a blow; its time and the piston's
// velocity just before are recorded (signals v_impact, blows) for the report.
#pragma once

#include <cmath>
#include <vector>

#include "rigid_body.hpp"

namespace tlm {

class HammerPistonQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "HammerPistonQ"; }
  void configure(ParameterSet& prm) override {
    m_ = prm.positive("m", 14.4);
    A_A_ = prm.positive("A_A", 9.17e-4);
    A_B_ = prm.positive("A_B", 4.57e-4);
    g_ = prm.real("g", 9.81);
    F0_ = prm.real("F0", 80.0);
    k_p_ = prm.real("k_p", 1e-5);
    c_v_ = prm.real("c_v", 25.0);
    v_s_ = prm.positive("v_s", 0.05);
    tau_f_ = prm.positive("tau_f", 2e-4);
    x_cushion_ = prm.real("x_cushion", 0.095);
    k_cushion_ = prm.positive("k_cushion", 1e8);
    c_cushion_ = prm.real("c_cushion", 2e4);
    m_tool_ = prm.positive("m_tool", 15.0);
    k_rock_ = prm.positive("k_rock", 1e9);
    c_rock_ = prm.real("c_rock", 9.7e4);
    F_feed_ = prm.real("F_feed", 0.0);
    k_contact_ = prm.positive("k_contact", 2e9);
    const double e = prm.real("e_contact", 0.9);
    if (!(e > 0.0 && e <= 1.0)) throw config::InputError(prm.where(), name_ + ": e_contact must be in (0, 1]");
    const double zeta = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
    c_contact_ = 2.0 * zeta * std::sqrt(k_contact_ * m_ * m_tool_ / (m_ + m_tool_));
    v_blow_ = prm.positive("v_blow", 1.0);
    x_ = prm.real("x0", 0.0);
    add_port("A", Kind::Q);
    add_port("B", Kind::Q);
    faces_ = {{0, A_A_, +1.0}, {1, A_B_, -1.0}};
    for (auto [name, value] : {std::pair<const char*, double*>{"x", &x_}, {"v", &v_}, {"y_tool", &y_},
                               {"F_contact", &F_contact_}, {"v_impact", &v_impact_}, {"blows", &blows_}})
      add_signal_output(name, value);
  }
  void initialize(double dt) override {
    dt_ = dt;
    filter_ = 1.0 - std::exp(-dt / tau_f_);
  }
  void simulate_one_step(double t) override {
    const double pA = ports_[0].node->p, pB = ports_[1].node->p;  // last step's, for the friction
    v_f_ += filter_ * (v_ - v_f_);
    double F = -(F0_ + k_p_ * std::max(pA, pB)) * std::tanh(v_f_ / v_s_) - c_v_ * v_f_ - m_ * g_;
    double B = 0.0;
    face_forces(ports_, faces_, F, B);
    F -= stop_force(x_ - x_cushion_, v_, k_cushion_, c_cushion_);
    const double overlap = y_ - x_;
    F_contact_ = stop_force(overlap, w_ - v_, k_contact_, c_contact_);
    F += F_contact_;
    if (overlap > 0.0 && overlap_prev_ <= 0.0 && std::fabs(v_ - w_) > v_blow_) {
      v_impact_ = v_;
      blows_ += 1.0;
      impacts_.push_back({t, v_});
    }
    overlap_prev_ = overlap;
    const double F_tool = stop_force(-y_, -w_, k_rock_, c_rock_) - F_contact_ - m_tool_ * g_ - F_feed_;
    v_ = (m_ * v_ + dt_ * F) / (m_ + dt_ * B);
    x_ += dt_ * v_;
    w_ += dt_ * F_tool / m_tool_;
    y_ += dt_ * w_;
    face_outputs(ports_, faces_, v_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
    out.push_back({"y_tool", "m", &y_});
    out.push_back({"F_contact", "N", &F_contact_});
    out.push_back({"v_impact", "m/s", &v_impact_});
  }
  double stable_step(std::string* why) const override {
    // Explicit one-sided springs: central-difference-like limit 2/ω.
    const double m_eff = m_ * m_tool_ / (m_ + m_tool_);
    double w = std::sqrt(k_contact_ / m_eff);
    std::string what = "piston-tool contact";
    if (std::sqrt(k_rock_ / m_tool_) > w) {
      w = std::sqrt(k_rock_ / m_tool_);
      what = "rock spring under the tool";
    }
    if (std::sqrt(k_cushion_ / m_) > w) {
      w = std::sqrt(k_cushion_ / m_);
      what = "top cushion";
    }
    if (why) *why = name_ + ": " + what;
    return 2.0 / w;
  }
  struct Impact {
    double time, velocity;
  };
  const std::vector<Impact>& impacts() const { return impacts_; }

 private:
  double m_ = 0, A_A_ = 0, A_B_ = 0, g_ = 0, F0_ = 0, k_p_ = 0, c_v_ = 0, v_s_ = 0, tau_f_ = 0;
  double x_cushion_ = 0, k_cushion_ = 0, c_cushion_ = 0, m_tool_ = 0, k_rock_ = 0, c_rock_ = 0, F_feed_ = 0;
  double k_contact_ = 0, c_contact_ = 0, v_blow_ = 0;
  double x_ = 0, v_ = 0, v_f_ = 0, y_ = 0, w_ = 0, F_contact_ = 0, v_impact_ = 0, blows_ = 0;
  double overlap_prev_ = 0, dt_ = 0, filter_ = 0;
  std::vector<HydraulicFace> faces_;
  std::vector<Impact> impacts_;
};

}  // namespace tlm
