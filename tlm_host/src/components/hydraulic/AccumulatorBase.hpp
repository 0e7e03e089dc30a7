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
    pa_ = prm.real("pa0", 1e7, "Pa");  // the gas's start pressure
    x_ = prm.real("x0", 0.0, "1 or m");  // the start charge (a fraction, or the piston's position in m)
    v_ = prm.real("v0", 0.0, "1/s or m/s");  // its start rate
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

}  // namespace tlm
