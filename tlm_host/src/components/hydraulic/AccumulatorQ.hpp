// AccumulatorQ: one of the accumulators; AccumulatorBase.hpp's opening comment gives their equations and sources.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/hydraulic/AccumulatorBase.hpp"

namespace tlm {

class AccumulatorQ : public AccumulatorBase {
 public:
  using AccumulatorBase::AccumulatorBase;
  const char* type_name() const override { return "AccumulatorQ"; }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V0", 1e-3, "m³");  // the accumulator's volume
    Kca_ = prm.positive("Kca", 1e-8, "m³/(s·Pa)");  // the inlet's coefficient
    kappa_ = prm.positive("kappa", 1.2, "1");  // polytropic exponent of the gas
    p0_ = prm.positive("p0", 1e7, "Pa");  // precharge
    configure_state(prm);
  }
  void initialize(double dt) override {
    start_from_node(dt);
    D_ = delayed_part();
    Va_ = V0_ * (1.0 - x_);
  }
  void simulate_one_step(double) override {
    HydraulicNode& n = *ports_[0].node;
    const double c1 = n.c, Z1 = n.Zc;
    const double a = Kca_ * dt_ / (2.0 * V0_);
    Vector5 s;
    s << v_, x_, q1_, pa_, p1_;
    hopsan_newton(s, [&](const Vector5& y, Vector5& F, Matrix5& J) {
      const double v = y(0), x = y(1), q1 = y(2), pa = y(3), p1 = y(4);
      const double e = a * (p1 - pa) - D_;
      const double L = hopsan_limit(e, 0.0, 1.0), dL = hopsan_dx_limit(L, 0.0, 1.0), de = hopsan_dx_limit(e, 0.0, 1.0);
      const double gas = V0_ * hopsan_limit(1.0 - x, 0.1, 1.0);
      const double on = p1 > 0.0 ? 1.0 : 0.0;
      const double node = c1 + q1 * Z1 * on;
      F << v + Kca_ * (-p1 + pa) * dL / V0_, x - L, q1 + V0_ * v,
          pa - p0_ * std::pow(V0_, kappa_) / std::pow(gas, kappa_), p1 - std::max(node, 0.0);
      J(0, 3) = Kca_ * dL / V0_;
      J(0, 4) = -(Kca_ * dL / V0_);
      J(1, 3) = Kca_ * dt_ * de / (2.0 * V0_);
      J(1, 4) = -(Kca_ * dt_ * de / (2.0 * V0_));
      J(2, 0) = V0_;
      J(3, 1) = -(kappa_ * p0_ * std::pow(V0_, 1.0 + kappa_) * hopsan_dx_limit(1.0 - x, 0.1, 1.0) *
                  std::pow(gas, -1.0 - kappa_));
      J(4, 2) = -(Z1 * (node <= 0.0 ? 1e-9 : 1.0) * on);
    });
    v_ = s(0), x_ = s(1), q1_ = s(2), pa_ = s(3), p1_ = s(4);
    Va_ = V0_ * (1.0 - x_);
    D_ = delayed_part();
    n.p = p1_;
    n.q = q1_;
  }
  void state(config::StateIO& io) override {
    for (double* s : {&v_, &x_, &q1_, &pa_, &p1_, &D_, &Va_}) io.value("accumulator", *s);
  }

 private:
  // The trapezoidal rule's memory of this step, for the next.
  double delayed_part() const {
    return (-(Kca_ * dt_ * p1_ * V0_) + Kca_ * dt_ * pa_ * V0_ - 2.0 * std::pow(V0_, 2) * x_) / (2.0 * std::pow(V0_, 2));
  }
  double V0_ = 0, Kca_ = 0, kappa_ = 0, p0_ = 0, D_ = 0;
};

}  // namespace tlm
