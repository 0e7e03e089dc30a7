// SignalStep: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalStep : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalStep"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0, "signal");
    y1_ = p.real("y1", 1.0, "signal");
    t_step_ = p.real("t_step", 0.0, "s");
    add_output();
  }

 private:
  double value(double t) override { return t >= t_step_ ? y1_ : y0_; }
  double y0_ = 0, y1_ = 0, t_step_ = 0;
};

}  // namespace tlm
