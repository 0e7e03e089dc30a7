// SignalRateLimiter: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalRateLimiter : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalRateLimiter"; }
  void configure(ParameterSet& p) override {
    up_ = p.real("rate_up", 1.0, "signal/s");
    down_ = p.real("rate_down", -1.0, "signal/s");
    add_signal_input("u", &u_);
    add_output();
  }

 private:
  // Toward the input, at most |rate|·Δt a step (Hopsan's form: the rate
  // chosen by the sign of the gap, then its magnitude compared).
  double value(double) override {
    const double gap = *u_ - y_;
    const double rate = gap >= 0.0 ? up_ : down_;
    return std::fabs(gap) / dt_ > std::fabs(rate) ? y_ + rate * dt_ : *u_;
  }
  double initial_value() override { return *u_; }
  double up_ = 1, down_ = -1;
  const double* u_ = nullptr;
};

}  // namespace tlm
