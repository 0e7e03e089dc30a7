// Signal components (run first in each step): sources of a value over time
// and simple blocks acting on one input. Each has the signal output "y".
//   SignalStep      y = y0 before t_step, y1 from t_step on
//   SignalRamp      y from y0 to y1 linearly over [t0, t1], held outside
//   SignalTable     y(t) from a table "t1:y1; t2:y2; ..."
//   SignalGain      y = k·u
//   SignalAdd       y = u1 + u2
//   SignalSubtract  y = u1 − u2 (e.g. a position relative to the housing)
//   SignalLowPass   first-order lag τ·dy/dt = u − y, integrated exactly
//                   per step: y ← u + (y − u)·exp(−Δt/τ)
//   SignalSoftStep  y0 before t0, y0 + A·(1 − cos(π·(t − t0)/(t1 − t0)))/2
//                   from t0 to t1, y0 + A after (Hopsan's SignalSoftStep)
//   SignalSineWave  0 before t0, A·sin(2π·f·(t − t0 − t_offset)) after
//   SignalPulse     y0 + A while t + Δt/2 is in [t0, t1), y0 outside
//   SignalMultiply  y = u1·u2
//   SignalRateLimiter  y toward u by at most rate_up·Δt (rising) or
//                   rate_down·Δt (falling) a step; starts at u
//   SignalIntegrator   y ← y + Δt/2·(u + u_previous) (trapezoidal), from y0
// The last six carry Hopsan's equations (mapped from Hopsan models,
// hopsan_loader.cpp), each with its own first value, as Hopsan's starts it.
// The time a signal sees is the end of the coming step, t + Δt, so a step at
// t_step acts on the step that ends there.
#pragma once

#include <algorithm>
#include <cmath>

#include "components/bilinear.hpp"
#include "component.hpp"
#include "table.hpp"

namespace tlm {

class SignalComponent : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Signal; }
  void initialize(double dt) override {
    dt_ = dt;
    y_ = initial_value();
  }
  void simulate_one_step(double t) override { y_ = value(t + dt_); }
  // The output is the whole state (a low-pass filter's memory; the
  // sources' value is a function of t).
  void state(config::StateIO& io) override { io.value("y", y_); }

 protected:
  virtual double value(double t) = 0;
  // The output before the first step: the value at the start time, unless
  // the component starts otherwise.
  virtual double initial_value() { return value(start_time_); }
  void add_output() { add_signal_output("y", &y_); }
  double y_ = 0.0, dt_ = 0.0;
};

}  // namespace tlm
