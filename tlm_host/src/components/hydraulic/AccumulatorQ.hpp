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
//
// PistonAccumulatorQ (Hopsan's HydraulicPistonAckumulator): a piston of area
// Ap, mass ML and friction Bp over a gas column of stroke SL precharged to
// p0: ML·ẍ + Bp·ẋ = Ap·(p1 − pa), x within [0, SL],
//   pa = p0·(Ap·SL)^κ / (Ap·max(SL − x, 0.001·SL))^κ,  q1 = −Ap·v,
//   p1 = max(c1 + Zc1·q1, 0);
// x by the bilinear (trapezoidal) rule of the second-order motion (its
// memory two steps deep), v by that of the first-order one, and the five
// equations in (x, v, q1, pa, p1) by the same two damped Newton iterations.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "component.hpp"

namespace tlm {

using Vector5 = Eigen::Matrix<double, 5, 1>;
using Matrix5 = Eigen::Matrix<double, 5, 5>;

// Two Newton iterations damped as Hopsan's EquationSystemSolver damps them
// (weights 1 and 0.67), on s; `system(s, F, J)` gives the residuals and
// the Jacobian at s.
template <class System>
void hopsan_newton(Vector5& s, const System& system) {
  for (const double weight : {1.0, 0.67}) {
    Vector5 F;
    Matrix5 J = Matrix5::Identity();
    system(s, F, J);
    s -= weight * J.partialPivLu().solve(F);
  }
}

inline double hopsan_limit(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }
// A limit's derivative in Hopsan's generated code: 1e-9 at and beyond its bounds.
inline double hopsan_dx_limit(double x, double lo, double hi) { return x >= hi || x <= lo ? 1e-9 : 1.0; }

// What both accumulators share: the port, the start values of the gas
// pressure and the charge and its rate, the outputs Hopsan gives them
// (Va, pa, xmp, vmp), and the node's pressure and flow at the start.
class AccumulatorBase : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  // The gas's start pressure (asked once, after configure).
  double source_pressure() const override { return pa_; }

 protected:
  void configure_state(ParameterSet& prm) {
    pa_ = prm.real("pa0", 1e7);  // Pa, the gas's start pressure
    x_ = prm.real("x0", 0.0);    // the start charge (a fraction, or the piston's position in m)
    v_ = prm.real("v0", 0.0);    // its start rate
    add_port("P1", Kind::Q);
    add_signal_output("Va", &Va_);
    add_signal_output("pa", &pa_);
    add_signal_output("xmp", &x_);
    add_signal_output("vmp", &v_);
  }
  void start_from_node(double dt) {
    dt_ = dt;
    p1_ = ports_[0].node->p;
    q1_ = ports_[0].node->q;
  }
  double dt_ = 0, v_ = 0, x_ = 0, q1_ = 0, pa_ = 0, p1_ = 0, Va_ = 0;
};

class AccumulatorQ : public AccumulatorBase {
 public:
  using AccumulatorBase::AccumulatorBase;
  const char* type_name() const override { return "AccumulatorQ"; }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V0", 1e-3);      // m³, the accumulator's volume
    Kca_ = prm.positive("Kca", 1e-8);    // m³/(s·Pa), the inlet's coefficient
    kappa_ = prm.positive("kappa", 1.2); // polytropic exponent of the gas
    p0_ = prm.positive("p0", 1e7);       // Pa, precharge
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

class PistonAccumulatorQ : public AccumulatorBase {
 public:
  using AccumulatorBase::AccumulatorBase;
  const char* type_name() const override { return "PistonAccumulatorQ"; }
  void configure(ParameterSet& prm) override {
    Ap_ = prm.positive("Ap", 1e-3);       // m², piston area
    SL_ = prm.positive("SL", 0.5);        // m, stroke
    Bp_ = prm.real("Bp", 10.0);           // N·s/m, friction
    ML_ = prm.positive("ML", 1.0);        // kg, the piston's mass
    kappa_ = prm.positive("kappa", 1.2);  // polytropic exponent of the gas
    p0_ = prm.positive("p0", 1e7);        // Pa, precharge
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
