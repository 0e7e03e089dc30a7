// The control valve's spool as a rigid body (Q-type): mass m, stroke
// 0 ≤ x ≤ stroke (x = 0: A to tank, x = stroke: P to A), two pilot faces:
//   pilot_s (area A_s, e.g. at supply pressure) pushes towards x = 0,
//   pilot_c (area A_c, at the signal pressure) pushes towards x = stroke.
// Friction F = −(F_c·tanh(v/v_s) + b·v) (Coulomb smoothed over v_s, viscous
// implicit), end stops as one-sided spring-dampers. Flow forces neglected.
// Signal outputs x and v drive the metering edges (SpoolValveQ).
#pragma once

#include <cmath>

#include "components/rigid_body.hpp"
#include "components/percussion/SpoolMechanics.hpp"

namespace tlm {

class ControlSpoolQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "ControlSpoolQ"; }
  void state(config::StateIO& io) override {
    io.value("x", x_);
    io.value("v", v_);
  }
  void configure(ParameterSet& prm) override {
    mech_.configure(prm);
    A_s_ = prm.positive("A_s", 1.2e-4, "m²");
    A_c_ = prm.positive("A_c", 2.4e-4, "m²");
    x_ = prm.real("x0", 0.0, "m");
    add_port("pilot_s", Kind::Q);
    add_port("pilot_c", Kind::Q);
    faces_ = {{0, A_s_, +1.0}, {1, A_c_, -1.0}};
    add_signal_output("x", &x_);
    add_signal_output("v", &v_);
  }
  void initialize(double dt) override { dt_ = dt; }
  void simulate_one_step(double) override {
    advance_body(ports_, faces_, mech_.m, dt_, mech_.force(x_, v_), mech_.b, x_, v_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
  }
  double stable_step(std::string* why) const override {
    if (why) *why = name_ + ": end stop k_stop, c_stop on mass m";
    return mech_.stable_step();
  }

 private:
  SpoolMechanics mech_;
  double A_s_ = 0, A_c_ = 0;
  double x_ = 0, v_ = 0, dt_ = 0;
  std::vector<HydraulicFace> faces_;
};

}  // namespace tlm
