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
    A_A_ = prm.positive("A_A", 9.17e-4);
    A_B_ = prm.positive("A_B", 4.57e-4);
    x_ = prm.real("x0", 0.0);
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

// The same mechanics for a piston that lives in fe_server: reads the
// piston's lift, velocity and cavity pressures (FMU outputs), and offers the
// force to send through the FMU's mechanical port (signal F). Its logged
// x, v, F_contact make the percussion report work as for HammerPistonQ.
// With tool = fe the tool is in fe_server too, and its top's motion comes in
// through the signals tool_x and tool_v.
class PistonMechanicsSignal : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Signal; }
  const char* type_name() const override { return "PistonMechanicsSignal"; }
  void state(config::StateIO& io) override {
    io.value("x", x_);
    io.value("v", v_);
    io.value("F", F_);
    mech_.state(io);
  }
  void configure(ParameterSet& prm) override {
    mech_.configure(prm, name_);
    add_signal_input("x", &x_in_);
    add_signal_input("v", &v_in_);
    add_signal_input("p_A", &pA_in_);
    add_signal_input("p_B", &pB_in_);
    add_signal_output("F", &F_);
    add_signal_output("y_tool", &mech_.y);
    if (!mech_.lumped_tool) {
      add_signal_input("tool_x", &tool_x_in_);
      add_signal_input("tool_v", &tool_v_in_);
    }
  }
  void initialize(double dt) override { mech_.initialize(dt); }
  void simulate_one_step(double t) override {
    x_ = *x_in_;
    v_ = *v_in_;
    if (!mech_.lumped_tool) mech_.y = *tool_x_in_, mech_.w = *tool_v_in_;
    F_ = mech_.step(t, x_, v_, *pA_in_, *pB_in_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"x", "m", &x_});
    out.push_back({"v", "m/s", &v_});
    out.push_back({"F", "N", &F_});
    out.push_back({"y_tool", "m", &mech_.y});
    out.push_back({"F_contact", "N", &mech_.F_contact});
  }
  double stable_step(std::string* why) const override { return mech_.stable_step(why, name_); }

 private:
  PercussionMechanics mech_;
  const double *x_in_ = nullptr, *v_in_ = nullptr, *pA_in_ = nullptr, *pB_in_ = nullptr;
  const double *tool_x_in_ = nullptr, *tool_v_in_ = nullptr;
  double x_ = 0, v_ = 0, F_ = 0;
};

}  // namespace tlm
