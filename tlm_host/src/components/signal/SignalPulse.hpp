// SignalPulse: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalPulse : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalPulse"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0, "signal");
    a_ = p.real("amplitude", 1.0, "signal");
    t0_ = p.real("t0", 1.0, "s");
    t1_ = p.real("t1", 2.0, "s");
    add_output();
  }

 private:
  // Hopsan's pulse reads the step's middle, so an edge on a step's time falls on one side.
  double value(double t) override {
    const double mid = t + 0.5 * dt_;
    return mid >= t0_ && mid < t1_ ? y0_ + a_ : y0_;
  }
  double initial_value() override { return y0_; }
  double y0_ = 0, a_ = 1, t0_ = 1, t1_ = 2;
};

}  // namespace tlm
