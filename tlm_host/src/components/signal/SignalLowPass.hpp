// SignalLowPass: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalLowPass : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalLowPass"; }
  void configure(ParameterSet& p) override {
    tau_ = p.positive("tau", 1e-3, "s");
    y_ = p.real("y0", 0.0, "signal");
    add_signal_input("u", &u_);
    add_output();
  }
  void initialize(double dt) override {
    dt_ = dt;
    decay_ = std::exp(-dt / tau_);
  }

 private:
  double value(double) override { return *u_ + (y_ - *u_) * decay_; }
  double tau_ = 1e-3, decay_ = 0.0;
  const double* u_ = nullptr;
};

}  // namespace tlm
