// SignalAdd: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

// Two inputs, one output: the sum or the difference. Evaluated in the
// model's order: declare them before the signals that read them (else
// those read the previous step's value).
class SignalAdd : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalAdd"; }
  void configure(ParameterSet&) override {
    add_signal_input("u1", &u1_);
    add_signal_input("u2", &u2_);
    add_output();
  }
  void log_variables(std::vector<LogVariable>& out) override { out.push_back({"y", "", &y_}); }

 protected:
  double value(double) override { return *u1_ + *u2_; }
  const double *u1_ = nullptr, *u2_ = nullptr;
};

}  // namespace tlm
