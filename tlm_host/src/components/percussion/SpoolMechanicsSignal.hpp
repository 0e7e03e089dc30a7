// SpoolMechanicsSignal: the control spool in fe_server; ControlSpoolQ.hpp's opening comment gives the spool's equations.
#pragma once

#include <cmath>

#include "components/rigid_body.hpp"
#include "components/percussion/SpoolMechanics.hpp"

namespace tlm {

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
