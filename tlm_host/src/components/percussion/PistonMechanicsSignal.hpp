// PistonMechanicsSignal: the percussion piston's law beside an FE piston; HammerPistonQ.hpp's opening
// comment gives its equations.
#pragma once

#include "components/percussion/PercussionMechanics.hpp"
#include "components/percussion/HammerPistonQ.hpp"

namespace tlm {

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
