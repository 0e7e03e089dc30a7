// SignalRamp: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalRamp : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalRamp"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0, "signal");
    y1_ = p.real("y1", 1.0, "signal");
    t0_ = p.real("t0", 0.0, "s");
    t1_ = p.real("t1", 1.0, "s");
    if (!(t1_ > t0_)) throw config::InputError(p.where(), name_ + ": t1 must be after t0");
    add_output();
  }

 private:
  double value(double t) override {
    if (t <= t0_) return y0_;
    if (t >= t1_) return y1_;
    return y0_ + (y1_ - y0_) * (t - t0_) / (t1_ - t0_);
  }
  double y0_ = 0, y1_ = 0, t0_ = 0, t1_ = 0;
};

}  // namespace tlm
