// A single-acting piston on a return spring (Q-type): the chamber on port
// P1 pushes the piston towards +x with p·A, and the chamber grows as x grows
// (connect the chamber's HydraulicVolumeC with dVdx = A and x = this.x).
// The spring pulls back with F0 + k·x, a viscous force −b·v acts, and end
// stops at x_min and x_max (one-sided spring-dampers) bound the stroke.
//
// TLM equation: the face delivers q = −A·v into its node (it takes oil when
// the chamber grows) and feels p = c + Zc·q, so F = A·c − Zc·A²·v. The
// Zc·A² and b terms are integrated implicitly (rigid_body.hpp):
//   v⁺ = (m·v + Δt·F_explicit) / (m + Δt·(Zc·A² + b)),   x⁺ = x + Δt·v⁺.
#pragma once

#include "components/rigid_body.hpp"

namespace tlm {

class SpringPistonQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "SpringPistonQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void state(config::StateIO& io) override {
    io.value("x", x_);
    io.value("v", v_);
  }
  void configure(ParameterSet& prm) override {
    A_ = prm.positive("A", 1e-3, "m²");  // piston area
    m_ = prm.positive("m", 1.0, "kg");
    k_ = prm.real("k", 0.0, "N/m");  // return spring
    F0_ = prm.real("F0", 0.0, "N");  // spring preload at x = 0
    b_ = prm.real("b", 0.0, "N·s/m");  // viscous friction
    x_ = prm.real("x0", 0.0, "m");
    v_ = prm.real("v0", 0.0, "m/s");
    x_min_ = prm.real("x_min", -1e300, "m");  // end stops
    x_max_ = prm.real("x_max", 1e300, "m");
    k_stop_ = prm.positive("k_stop", 1e8, "N/m");
    c_stop_ = prm.real("c_stop", 0.0, "N·s/m");
    if (k_ < 0.0 || b_ < 0.0 || c_stop_ < 0.0)
      throw config::InputError(prm.where(), name_ + ": k, b and c_stop must not be negative");
    if (!(x_min_ < x_max_)) throw config::InputError(prm.where(), name_ + ": x_min must be below x_max");
    add_port("P1", Kind::Q);
    faces_ = {{0, A_, -1.0}};  // the chamber grows as x grows
    add_signal_output("x", &x_);
    add_signal_output("v", &v_);
  }
  void initialize(double dt) override { dt_ = dt; }
  void simulate_one_step(double) override {
    double F = -(F0_ + k_ * x_) - stop_force(x_ - x_max_, v_, k_stop_, c_stop_) +
               stop_force(x_min_ - x_, -v_, k_stop_, c_stop_);
    advance_body(ports_, faces_, m_, dt_, F, b_, x_, v_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
  }
  double stable_step(std::string* why) const override {
    // Explicit spring and stops (the viscous b is implicit).
    if (why) *why = name_ + ": spring and end stop (k + k_stop = " + std::to_string(k_ + k_stop_) + " N/m, c_stop = " +
                    std::to_string(c_stop_) + " N·s/m on " + std::to_string(m_) + " kg)";
    return spring_damper_stable_step(k_ + k_stop_, c_stop_, m_);
  }

 private:
  double A_ = 0, m_ = 0, k_ = 0, F0_ = 0, b_ = 0, x_ = 0, v_ = 0, x_min_ = 0, x_max_ = 0, k_stop_ = 0, c_stop_ = 0;
  double dt_ = 0;
  std::vector<HydraulicFace> faces_;
};

}  // namespace tlm
