// SignalSoftStep: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalSoftStep : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalSoftStep"; }
  void configure(ParameterSet& p) override {
    t0_ = p.real("t0", 1.0, "s");
    t1_ = p.real("t1", 2.0, "s");
    y0_ = p.real("y0", 0.0, "signal");
    a_ = p.real("amplitude", 1.0, "signal");
    if (!(t1_ > t0_)) throw config::InputError(p.where(), name_ + ": t1 must follow t0 (the soft step's end after its start)");
    add_output();
  }

 private:
  double value(double t) override {
    if (t < t0_) return y0_;
    if (t >= t1_) return y0_ + a_;
    // Hopsan's form: a half sine from −π/2, its frequency π/(t1 − t0).
    return y0_ + 0.5 * a_ * std::sin((t - t0_) * (M_PI / (t1_ - t0_)) - M_PI / 2.0) + a_ * 0.5;
  }
  double initial_value() override { return y0_; }
  double t0_ = 1, t1_ = 2, y0_ = 0, a_ = 1;
};

}  // namespace tlm
