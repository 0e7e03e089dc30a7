// The control valve's spool as a rigid body (Q-type): mass m, stroke
// 0 ≤ x ≤ stroke (x = 0: A to tank, x = stroke: P to A), two pilot faces:
//   pilot_s (area A_s, e.g. at supply pressure) pushes towards x = 0,
//   pilot_c (area A_c, at the signal pressure) pushes towards x = stroke.
// Friction F = −(F_c·tanh(v/v_s) + b·v) (Coulomb smoothed over v_s, viscous
// implicit), end stops as one-sided spring-dampers. Flow forces neglected.
// Signal outputs x and v drive the metering edges (SpoolValveQ).
#pragma once

#include <cmath>

#include "rigid_body.hpp"

namespace tlm {

class ControlSpoolQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "ControlSpoolQ"; }
  void configure(ParameterSet& prm) override {
    m_ = prm.positive("m", 0.2);
    A_s_ = prm.positive("A_s", 1.2e-4);
    A_c_ = prm.positive("A_c", 2.4e-4);
    stroke_ = prm.positive("stroke", 8e-3);
    F_c_ = prm.real("F_c", 10.0);
    v_s_ = prm.positive("v_s", 0.01);
    b_ = prm.real("b", 15.0);
    k_stop_ = prm.positive("k_stop", 5e7);
    c_stop_ = prm.real("c_stop", 5e3);
    x_ = prm.real("x0", 0.0);
    add_port("pilot_s", Kind::Q);
    add_port("pilot_c", Kind::Q);
    faces_ = {{0, A_s_, +1.0}, {1, A_c_, -1.0}};
    add_signal_output("x", &x_);
    add_signal_output("v", &v_);
  }
  void initialize(double dt) override { dt_ = dt; }
  void simulate_one_step(double) override {
    double F = -F_c_ * std::tanh(v_ / v_s_);
    double B = b_;
    face_forces(ports_, faces_, F, B);
    F += stop_force(-x_, -v_, k_stop_, c_stop_);            // stop at x = 0 pushes +x
    F -= stop_force(x_ - stroke_, v_, k_stop_, c_stop_);    // stop at the stroke pushes −x
    v_ = (m_ * v_ + dt_ * F) / (m_ + dt_ * B);
    x_ += dt_ * v_;
    face_outputs(ports_, faces_, v_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
  }
  double stable_step(std::string* why) const override {
    if (why) *why = name_ + ": end stop k_stop on mass m";
    return 2.0 / std::sqrt(k_stop_ / m_);
  }

 private:
  double m_ = 0, A_s_ = 0, A_c_ = 0, stroke_ = 0, F_c_ = 0, v_s_ = 0, b_ = 0, k_stop_ = 0, c_stop_ = 0;
  double x_ = 0, v_ = 0, dt_ = 0;
  std::vector<HydraulicFace> faces_;
};

}  // namespace tlm
