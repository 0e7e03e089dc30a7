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
// The time a signal sees is the end of the coming step, t + Δt, so a step at
// t_step acts on the step that ends there.
#pragma once

#include "components/bilinear.hpp"

#include <algorithm>

#include <cmath>

#include "component.hpp"
#include "table.hpp"

namespace tlm {

class SignalComponent : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Signal; }
  void initialize(double dt) override {
    dt_ = dt;
    y_ = value(0.0);
  }
  void simulate_one_step(double t) override { y_ = value(t + dt_); }
  // The output is the whole state (a low-pass filter's memory; the
  // sources' value is a function of t).
  void state(config::StateIO& io) override { io.value("y", y_); }

 protected:
  virtual double value(double t) = 0;
  void add_output() { add_signal_output("y", &y_); }
  double y_ = 0.0, dt_ = 0.0;
};

class SignalStep : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalStep"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0);
    y1_ = p.real("y1", 1.0);
    t_step_ = p.real("t_step", 0.0);
    add_output();
  }

 private:
  double value(double t) override { return t >= t_step_ ? y1_ : y0_; }
  double y0_ = 0, y1_ = 0, t_step_ = 0;
};

class SignalRamp : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalRamp"; }
  void configure(ParameterSet& p) override {
    y0_ = p.real("y0", 0.0);
    y1_ = p.real("y1", 1.0);
    t0_ = p.real("t0", 0.0);
    t1_ = p.real("t1", 1.0);
    if (!(t1_ > t0_)) throw config::InputError(p.where(), name_ + ": t1 must be after t0");
    add_output();
  }

 private:
  double value(double t) override {
    if (t <= t0_) return y0_;
    if (t >= t1_) return y1_;
    return y0_ + (y1_ - y0_) * (t - t0_) / (t1_ - t0_);
  }
  double y0_ = 0, y1_ = 0, t0_ = 0, t1_ = 0;
};

class SignalTable : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalTable"; }
  void configure(ParameterSet& p) override {
    table_ = Table(p.text("table", ""), p.where(), name_ + ": table");
    add_output();
  }

 private:
  double value(double t) override { return table_(t); }
  Table table_;
};

class SignalGain : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalGain"; }
  void configure(ParameterSet& p) override {
    k_ = p.real("k", 1.0);
    add_signal_input("u", &u_);
    add_output();
  }

 private:
  double value(double) override { return k_ * *u_; }
  double k_ = 1.0;
  const double* u_ = nullptr;
};

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

class SignalSubtract : public SignalAdd {
 public:
  using SignalAdd::SignalAdd;
  const char* type_name() const override { return "SignalSubtract"; }

 private:
  double value(double) override { return *u1_ - *u2_; }
};

class SignalLowPass : public SignalComponent {
 public:
  using SignalComponent::SignalComponent;
  const char* type_name() const override { return "SignalLowPass"; }
  void configure(ParameterSet& p) override {
    tau_ = p.positive("tau", 1e-3);
    y_ = p.real("y0", 0.0);
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
    k_ = p.real("k", 1.0);
    w_num_ = p.positive("omega_num", 1e10);  // rad/s
    w_den_ = p.positive("omega_den", 1e3);   // rad/s
    filter_.limits(p.real("y_min", -1.5e300), p.real("y_max", 1.5e300));
    y0_ = p.real("y0", 0.0);
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
