// SignalIntegrator: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include "component.hpp"
#include "components/signal/SignalComponent.hpp"

namespace tlm {

class SignalIntegrator : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalIntegrator"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0, "signal");
    add_signal_input("u", &u_);
    add_output();
  }
  void state(config::StateIO& io) override {
    SignalComponent::state(io);
    io.value("u_previous", u_previous_);
  }

 private:
  // The trapezoidal rule (Hopsan's Integrator: a bilinear transform of 1/s).
  double value(double) override {
    const double y = y_ + 0.5 * dt_ * (*u_ + u_previous_);
    u_previous_ = *u_;
    return y;
  }
  double initial_value() override {
    u_previous_ = *u_;
    return y0_;
  }
  double y0_ = 0, u_previous_ = 0;
  const double* u_ = nullptr;
};

}  // namespace tlm
