// SignalFirstOrderFilter: one of the signal components; SignalComponent.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"
#include "components/signal/SignalLowPass.hpp"

namespace tlm {

// First-order filter y = k·(1 + s/ω_num)/(1 + s/ω_den)·u, discretized with
// the bilinear (Tustin) transform as Hopsan's SignalFirstOrderFilter does
// (bilinear.hpp), held within [y_min, y_max]. It starts from y0 and the
// input's value at initialization. (SignalLowPass, above, is the exact
// zero-order-hold discretization of 1/(1 + τ·s).)
class SignalFirstOrderFilter : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Signal; }
  const char* type_name() const override { return "SignalFirstOrderFilter"; }
  void configure(ParameterSet& p) override {
    k_ = p.real("k", 1.0, "1");
    w_num_ = p.positive("omega_num", 1e10, "rad/s");
    w_den_ = p.positive("omega_den", 1e3, "rad/s");
    filter_.limits(p.real("y_min", -1.5e300, "signal"), p.real("y_max", 1.5e300, "signal"));
    y0_ = p.real("y0", 0.0, "signal");
    add_signal_input("u", &u_);
    add_signal_output("y", &y_);
  }
  void initialize(double dt) override {
    filter_.set(dt, k_, k_ / w_num_, 1.0, 1.0 / w_den_);
    filter_.reset(*u_, y0_);
    y_ = filter_.value();
  }
  void simulate_one_step(double) override { y_ = filter_.update(*u_); }
  void state(config::StateIO& io) override {
    filter_.state(io);
    y_ = filter_.value();
  }

 private:
  double k_ = 1, w_num_ = 1e10, w_den_ = 1e3, y0_ = 0, y_ = 0;
  BilinearFirstOrder filter_;
  const double* u_ = nullptr;
};

}  // namespace tlm
