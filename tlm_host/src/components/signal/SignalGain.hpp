// SignalGain: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalGain : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalGain"; }
  void configure(ParameterSet& p) override {
    k_ = p.real("k", 1.0, "1");
    add_signal_input("u", &u_);
    add_output();
  }

 private:
  double value(double) override { return k_ * *u_; }
  double k_ = 1.0;
  const double* u_ = nullptr;
};

}  // namespace tlm
