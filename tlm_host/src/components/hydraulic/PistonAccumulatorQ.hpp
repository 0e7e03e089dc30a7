// PistonAccumulatorQ: one of the accumulators; AccumulatorBase.hpp's opening comment gives their equations and sources.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/hydraulic/AccumulatorBase.hpp"

namespace tlm {

class PistonAccumulatorQ : public AccumulatorBase {
 public:
  using AccumulatorBase::AccumulatorBase;
  const char* type_name() const override { return "PistonAccumulatorQ"; }
  void configure(ParameterSet& prm) override {
    Ap_ = prm.positive("Ap", 1e-3, "m²");  // piston area
    SL_ = prm.positive("SL", 0.5, "m");  // stroke
    Bp_ = prm.real("Bp", 10.0, "N·s/m");  // friction
    ML_ = prm.positive("ML", 1.0, "kg");  // the piston's mass
    kappa_ = prm.positive("kappa", 1.2, "1");  // polytropic exponent of the gas
    p0_ = prm.positive("p0", 1e7, "Pa");  // precharge
    configure_state(prm);
  }
  void initialize(double dt) override {
    start_from_node(dt);
    memory();
    D12_ = D12_prev_ = D12_new_;
    Va_ = Ap_ * (SL_ - x_);
  }
  void simulate_one_step(double) override {
    HydraulicNode& n = *ports_[0].node;
    const double c1 = n.c, Z1 = n.Zc, dt2 = std::pow(dt_, 2);
    const double den2 = 4.0 * ML_ + 2.0 * Bp_ * dt_, den1 = 2.0 * ML_ + Bp_ * dt_;
    Vector5 s;
    s << x_, v_, q1_, pa_, p1_;
    hopsan_newton(s, [&](const Vector5& y, Vector5& F, Matrix5& J) {
      const double x = y(0), v = y(1), q1 = y(2), pa = y(3), p1 = y(4);
      const double E = (Ap_ * dt2 * (p1 - pa)) / den2 - D11_ - D12_;
      const double L = hopsan_limit(E, 0.0, SL_), dL = hopsan_dx_limit(L, 0.0, SL_);
      const double gas = Ap_ * hopsan_limit(SL_ - x, 0.001 * SL_, SL_);
      F << x - L, v - dL * (-((Ap_ * dt_ * (-p1 + pa)) / den1) - D21_), q1 + Ap_ * v,
          pa - (p0_ * std::pow(Ap_ * SL_, kappa_)) / std::pow(gas, kappa_), p1 - std::max(c1 + q1 * Z1, 0.0);
      J(0, 3) = (Ap_ * dt2 * hopsan_dx_limit(E, 0.0, SL_)) / den2;
      J(0, 4) = -J(0, 3);
      J(1, 3) = (Ap_ * dt_ * dL) / den1;
      J(1, 4) = -J(1, 3);
      J(2, 1) = Ap_;
      J(3, 0) = -(Ap_ * kappa_ * p0_ * std::pow(Ap_ * SL_, kappa_) * hopsan_dx_limit(SL_ - x, 0.001 * SL_, SL_) *
                  std::pow(gas, -1.0 - kappa_));
      J(4, 2) = -(Z1 * (c1 + q1 * Z1 <= 0.0 ? 1e-9 : 1.0));
    });
    x_ = s(0), v_ = s(1), q1_ = s(2), pa_ = s(3), p1_ = s(4);
    Va_ = Ap_ * (SL_ - x_);
    memory();
    D12_ = D12_prev_;  // the second-order memory is two steps deep
    D12_prev_ = D12_new_;
    n.p = p1_;
    n.q = q1_;
  }
  void state(config::StateIO& io) override {
    for (double* s : {&x_, &v_, &q1_, &pa_, &p1_, &D11_, &D12_, &D12_prev_, &D21_, &Va_}) io.value("accumulator", *s);
  }

 private:
  // The bilinear rule's memory of this step for the next ones.
  void memory() {
    const double dt2 = std::pow(dt_, 2), den2 = 4.0 * ML_ + 2.0 * Bp_ * dt_, den1 = 2.0 * ML_ + Bp_ * dt_;
    D11_ = (-2.0 * Ap_ * dt2 * p1_ + 2.0 * Ap_ * dt2 * pa_ - 8.0 * ML_ * x_) / den2;
    D12_new_ = (-(Ap_ * dt2 * p1_) + Ap_ * dt2 * pa_ + 4.0 * ML_ * x_ - 2.0 * Bp_ * dt_ * x_) / den2;
    D21_ = (-(Ap_ * dt_ * p1_) + Ap_ * dt_ * pa_ - 2.0 * ML_ * v_ + Bp_ * dt_ * v_) / den1;
  }
  double Ap_ = 0, SL_ = 0, Bp_ = 0, ML_ = 0, kappa_ = 0, p0_ = 0;
  double D11_ = 0, D12_ = 0, D12_prev_ = 0, D12_new_ = 0, D21_ = 0;
};

}  // namespace tlm
