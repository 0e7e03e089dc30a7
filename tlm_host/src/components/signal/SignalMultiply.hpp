// SignalMultiply: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

// Evaluated in the model's order, as SignalAdd.
class SignalMultiply : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalMultiply"; }
  void configure(ParameterSet&) override {
    add_signal_input("u1", &u1_);
    add_signal_input("u2", &u2_);
    add_output();
  }

 private:
  double value(double) override { return *u1_ * *u2_; }
  const double *u1_ = nullptr, *u2_ = nullptr;
};

}  // namespace tlm
