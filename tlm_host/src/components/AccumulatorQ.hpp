// Gas accumulator (Q-type) with the equations of Hopsan's
// HydraulicAckumulator, for Hopsan models (hopsan_loader.cpp maps it; our own
// GasAccumulatorC is a C-type gas volume).
//
// A bladder of volume V0 precharged to p0 holds the oil fraction x (the
// state of charge, 0 to 1); oil enters through a laminar inlet Kca:
//   dx/dt = v = Kca·(p1 − pa)/V0,  x held within [0, 1],
//   pa = p0·V0^κ / (V0·max(1 − x, 0.1))^κ   (polytropic gas, at most 90 % oil),
//   q1 = −V0·v                                (the flow leaves the node),
//   p1 = max(c1 + Zc1·q1·[p1 > 0], 0)         (the node's characteristic).
// x is integrated with the trapezoidal rule,
//   x_k = Kca·Δt·(p1 − pa)_k/(2V0) − D_{k−1},
//   D_{k−1} = [Kca·Δt·(pa − p1)·V0 − 2V0²·x]_{k−1} / (2V0²),
// and the five equations in (v, x, q1, pa, p1) are solved each step by two
// damped Newton iterations (weights 1 and 0.67) from the last step's values,
// with the Jacobian Hopsan's generated code uses (a limit's derivative is
// 1e-9 at and beyond its bounds). The accumulator takes this step once in
// its initialization too, as Hopsan's does.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "component.hpp"

namespace tlm {

class AccumulatorQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "AccumulatorQ"; }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V0", 1e-3);      // m³, the accumulator's volume
    Kca_ = prm.positive("Kca", 1e-8);    // m³/(s·Pa), the inlet's coefficient
    kappa_ = prm.positive("kappa", 1.2); // polytropic exponent of the gas
    p0_ = prm.positive("p0", 1e7);       // Pa, precharge
    pa_ = prm.real("pa0", 1e7);          // Pa, the gas's start pressure
    x_ = prm.real("x0", 0.0);            // start state of charge
    v_ = prm.real("v0", 0.0);            // 1/s, its start rate
    add_port("P1", Kind::Q);
    add_signal_output("Va", &Va_);
    add_signal_output("pa", &pa_);
    add_signal_output("xmp", &x_);
    add_signal_output("vmp", &v_);
  }
  void initialize(double dt) override {
    dt_ = dt;
    const HydraulicNode& n = *ports_[0].node;
    p1_ = n.p;
    q1_ = n.q;
    D_ = delayed_part();
    Va_ = V0_ * (1.0 - x_);
  }
  void simulate_one_step(double) override {
    HydraulicNode& n = *ports_[0].node;
    const double c1 = n.c, Z1 = n.Zc;
    const double a = Kca_ * dt_ / (2.0 * V0_);
    for (const double weight : {1.0, 0.67}) {
      const double e = a * (p1_ - pa_) - D_;
      const double L = limit(e, 0.0, 1.0), dL = dx_limit(L, 0.0, 1.0), de = dx_limit(e, 0.0, 1.0);
      const double gas = V0_ * limit(1.0 - x_, 0.1, 1.0);
      const double on = p1_ > 0.0 ? 1.0 : 0.0;
      const double node = c1 + q1_ * Z1 * on;
      Eigen::Matrix<double, 5, 1> F;
      F << v_ + Kca_ * (-p1_ + pa_) * dL / V0_, x_ - L, q1_ + V0_ * v_,
          pa_ - p0_ * std::pow(V0_, kappa_) / std::pow(gas, kappa_), p1_ - std::max(node, 0.0);
      Eigen::Matrix<double, 5, 5> J = Eigen::Matrix<double, 5, 5>::Identity();
      J(0, 3) = Kca_ * dL / V0_;
      J(0, 4) = -(Kca_ * dL / V0_);
      J(1, 3) = Kca_ * dt_ * de / (2.0 * V0_);
      J(1, 4) = -(Kca_ * dt_ * de / (2.0 * V0_));
      J(2, 0) = V0_;
      J(3, 1) = -(kappa_ * p0_ * std::pow(V0_, 1.0 + kappa_) * dx_limit(1.0 - x_, 0.1, 1.0) *
                  std::pow(gas, -1.0 - kappa_));
      J(4, 2) = -(Z1 * (node <= 0.0 ? 1e-9 : 1.0) * on);
      const Eigen::Matrix<double, 5, 1> step = J.partialPivLu().solve(F);
      v_ -= weight * step(0);
      x_ -= weight * step(1);
      q1_ -= weight * step(2);
      pa_ -= weight * step(3);
      p1_ -= weight * step(4);
    }
    Va_ = V0_ * (1.0 - x_);
    D_ = delayed_part();
    n.p = p1_;
    n.q = q1_;
  }
  void state(config::StateIO& io) override {
    for (double* s : {&v_, &x_, &q1_, &pa_, &p1_, &D_, &Va_}) io.value("accumulator", *s);
  }

 private:
  static double limit(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }
  static double dx_limit(double x, double lo, double hi) { return x >= hi || x <= lo ? 1e-9 : 1.0; }
  // The trapezoidal rule's memory of this step, for the next.
  double delayed_part() const {
    return (-(Kca_ * dt_ * p1_ * V0_) + Kca_ * dt_ * pa_ * V0_ - 2.0 * std::pow(V0_, 2) * x_) / (2.0 * std::pow(V0_, 2));
  }
  double V0_ = 0, Kca_ = 0, kappa_ = 0, p0_ = 0, dt_ = 0;
  double v_ = 0, x_ = 0, q1_ = 0, pa_ = 0, p1_ = 0, D_ = 0, Va_ = 0;
};

}  // namespace tlm
