// SignalSineWave: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalSineWave : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalSineWave"; }
  void configure(ParameterSet& p) override {
    f_ = p.real("f", 1.0, "Hz");
    a_ = p.real("amplitude", 1.0, "signal");
    t_offset_ = p.real("t_offset", 0.0, "s");
    t0_ = p.real("t0", 0.0, "s");
    add_output();
  }

 private:
  double value(double t) override { return t < t0_ ? 0.0 : a_ * std::sin((t - t0_ - t_offset_) * 2.0 * M_PI * f_); }
  double f_ = 1, a_ = 1, t_offset_ = 0, t0_ = 0;
};

}  // namespace tlm
