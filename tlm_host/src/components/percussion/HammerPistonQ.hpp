// The percussion piston of a hydraulic hammer as a rigid body (Q-type), with
// the tool and the rock below it lumped (PercussionMechanics). x is the
// piston's lift above the impact position (up positive); gravity acts downwards.
//
//   ports: A (collar top, area A_A: the chamber shrinks as x grows, s = +1)
//          B (collar bottom, area A_B: the chamber grows, s = −1)
// Each contact onset with the piston coming down faster than v_blow is a
// blow; its time and velocity are recorded for the report.
#pragma once

#include "components/percussion/PercussionMechanics.hpp"

namespace tlm {

class HammerPistonQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "HammerPistonQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void state(config::StateIO& io) override {
    io.value("x", x_);
    io.value("v", v_);
    mech_.state(io);
  }
  void configure(ParameterSet& prm) override {
    mech_.configure(prm, name_);
    A_A_ = prm.positive("A_A", 9.17e-4, "m²");
    A_B_ = prm.positive("A_B", 4.57e-4, "m²");
    x_ = prm.real("x0", 0.0, "m");
    add_port("A", Kind::Q);
    add_port("B", Kind::Q);
    faces_ = {{0, A_A_, +1.0}, {1, A_B_, -1.0}};
    for (auto [name, value] : {std::pair<const char*, double*>{"x", &x_}, {"v", &v_}, {"y_tool", &mech_.y},
                               {"F_contact", &mech_.F_contact}, {"v_impact", &mech_.v_impact}, {"blows", &mech_.blows}})
      add_signal_output(name, value);
  }
  void initialize(double dt) override {
    dt_ = dt;
    mech_.initialize(dt);
  }
  void simulate_one_step(double t) override {
    const double pA = ports_[0].node->p, pB = ports_[1].node->p;  // last step's, for the friction
    advance_body(ports_, faces_, mech_.m, dt_, mech_.step(t, x_, v_, pA, pB), 0.0, x_, v_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
    out.push_back({"y_tool", "m", &mech_.y});
    out.push_back({"F_contact", "N", &mech_.F_contact});
    out.push_back({"v_impact", "m/s", &mech_.v_impact});
  }
  double stable_step(std::string* why) const override { return mech_.stable_step(why, name_); }
  const std::vector<PercussionMechanics::Impact>& impacts() const { return mech_.impacts; }

 private:
  PercussionMechanics mech_;
  double A_A_ = 0, A_B_ = 0, x_ = 0, v_ = 0, dt_ = 0;
  std::vector<HydraulicFace> faces_;
};

}  // namespace tlm
