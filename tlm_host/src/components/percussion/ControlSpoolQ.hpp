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

namespace tlm {

// A spool's forces apart from its pilot faces and viscous friction b·v:
// smoothed Coulomb friction and the two end stops. Shared by ControlSpoolQ
// and SpoolMechanicsSignal (spool in fe_server), so both model the same law.
struct SpoolMechanics {
  double m = 0, F_c = 0, v_s = 0, b = 0, stroke = 0, k_stop = 0, c_stop = 0;
  void configure(ParameterSet& prm) {
    m = prm.positive("m", 0.2);
    stroke = prm.positive("stroke", 8e-3);
    F_c = prm.real("F_c", 10.0);
    v_s = prm.positive("v_s", 0.01);
    b = prm.real("b", 15.0);
    k_stop = prm.positive("k_stop", 5e7);
    c_stop = prm.real("c_stop", 5e3);
  }
  double force(double x, double v) const {
    double F = -F_c * std::tanh(v / v_s);
    F += stop_force(-x, -v, k_stop, c_stop);          // stop at x = 0 pushes +x
    F -= stop_force(x - stroke, v, k_stop, c_stop);   // stop at the stroke pushes −x
    return F;
  }
  double stable_step() const { return spring_damper_stable_step(k_stop, c_stop, m); }
};

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
    A_s_ = prm.positive("A_s", 1.2e-4);
    A_c_ = prm.positive("A_c", 2.4e-4);
    x_ = prm.real("x0", 0.0);
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

// The same spool living in fe_server: reads its position and velocity (FMU
// outputs x, v) and offers friction (Coulomb and viscous) and the end-stop
// forces, F, to send through the FMU's mechanical port. The pilot faces are
// loaded in fe_server. The forces lag the FE motion by one coupling step;
// the stop's ω·Δt = sqrt(k_stop/m)·Δt stays below 0.16 up to Δt = 10 us.
class SpoolMechanicsSignal : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Signal; }
  const char* type_name() const override { return "SpoolMechanicsSignal"; }
  void state(config::StateIO& io) override {
    io.value("x", x_);
    io.value("v", v_);
    io.value("F", F_);
  }
  void configure(ParameterSet& prm) override {
    mech_.configure(prm);
    add_signal_input("x", &x_in_);
    add_signal_input("v", &v_in_);
    add_signal_output("F", &F_);
  }
  void initialize(double) override {}
  void simulate_one_step(double) override {
    x_ = *x_in_;
    v_ = *v_in_;
    F_ = mech_.force(x_, v_) - mech_.b * v_;
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
    out.push_back({"F", "N", &F_});
  }
  double stable_step(std::string* why) const override {
    if (why) *why = name_ + ": end stop k_stop, c_stop on mass m (explicit, lagged one step)";
    return mech_.stable_step();
  }

 private:
  SpoolMechanics mech_;
  const double *x_in_ = nullptr, *v_in_ = nullptr;
  double x_ = 0, v_ = 0, F_ = 0;
};

}  // namespace tlm
