// First- and second-order transfer functions discretized with the bilinear
// (Tustin) transform, s → (2/Δt)·(z − 1)/(z + 1), in the form HopsanCore's
// FirstOrderTransferFunction and SecondOrderTransferFunction use (their
// coefficients multiplied through by Δt and Δt², the sum multiplied by the
// reciprocal of the leading one), so that components mapped from Hopsan step
// as Hopsan's do. Outputs are held within [lo, hi].
//
// First order, (n0 + n1·s)/(d0 + d1·s):
//   y_k = [(n0Δt + 2n1)·u_k + (n0Δt − 2n1)·u_{k−1} − (d0Δt − 2d1)·y_{k−1}] / (d0Δt + 2d1)
// Second order, (n0 + n1·s + n2·s²)/(d0 + d1·s + d2·s²), with
//   a0 = x0Δt² + 2x1Δt + 4x2,  a1 = 2x0Δt² − 8x2,  a2 = x0Δt² − 2x1Δt + 4x2
// for the numerator (x = n) and the denominator (x = d):
//   y_k = [a0ⁿ·u_k + a1ⁿ·u_{k−1} + a2ⁿ·u_{k−2} − a1ᵈ·y_{k−1} − a2ᵈ·y_{k−2}] / a0ᵈ
#pragma once

#include <algorithm>

#include "config/checkpoint.hpp"

namespace tlm {

class BilinearFirstOrder {
 public:
  void set(double dt, double n0, double n1, double d0, double d1) {
    dt_ = dt;
    cu0_ = n0 * dt - 2.0 * n1;
    cu1_ = n0 * dt + 2.0 * n1;
    set_den(d0, d1);
  }
  void set_den(double d0, double d1) {
    cy0_ = d0 * dt_ - 2.0 * d1;
    cy1_ = d0 * dt_ + 2.0 * d1;
  }
  void limits(double lo, double hi) { lo_ = lo, hi_ = hi; }
  // Start (or restart, at a stop) from input u and output y.
  void reset(double u, double y) { u1_ = u, y1_ = std::max(std::min(y, hi_), lo_); }
  double update(double u) {
    y1_ = std::max(std::min(1.0 / cy1_ * (cu1_ * u + cu0_ * u1_ - cy0_ * y1_), hi_), lo_);
    u1_ = u;
    return y1_;
  }
  double value() const { return y1_; }
  void state(config::StateIO& io) {
    io.value("u1", u1_);
    io.value("y1", y1_);
  }

 private:
  double dt_ = 0, cu0_ = 0, cu1_ = 0, cy0_ = 0, cy1_ = 0, u1_ = 0, y1_ = 0;
  double lo_ = -1.5e300, hi_ = 1.5e300;
};

class BilinearSecondOrder {
 public:
  void set(double dt, const double n[3], const double d[3]) {
    dt_ = dt;
    cu_[0] = n[0] * dt * dt + 2.0 * n[1] * dt + 4.0 * n[2];
    cu_[1] = 2.0 * n[0] * dt * dt - 8.0 * n[2];
    cu_[2] = n[0] * dt * dt - 2.0 * n[1] * dt + 4.0 * n[2];
    set_den(d);
  }
  void set_den(const double d[3]) {
    cy_[0] = d[0] * dt_ * dt_ + 2.0 * d[1] * dt_ + 4.0 * d[2];
    cy_[1] = 2.0 * d[0] * dt_ * dt_ - 8.0 * d[2];
    cy_[2] = d[0] * dt_ * dt_ - 2.0 * d[1] * dt_ + 4.0 * d[2];
  }
  void limits(double lo, double hi) { lo_ = lo, hi_ = hi; }
  // Start from input u, output y and the output's rate dy (y_{−1} = y − dy·Δt);
  // restart at a stop with the rate 0.
  void reset(double u, double y, double dy = 0.0) {
    u1_ = u2_ = u;
    y1_ = std::max(std::min(y, hi_), lo_);
    y2_ = y1_ - dy * dt_;
  }
  double update(double u) {
    double y = 1.0 / cy_[0] * (cu_[0] * u + cu_[1] * u1_ + cu_[2] * u2_ - cy_[1] * y1_ - cy_[2] * y2_);
    saturated_ = y >= hi_ || y <= lo_;  // at a limit counts, as in Hopsan
    y = std::max(std::min(y, hi_), lo_);
    u2_ = u1_, u1_ = u;
    y2_ = y1_, y1_ = y;
    return y;
  }
  double value() const { return y1_; }
  bool saturated() const { return saturated_; }
  void state(config::StateIO& io) {
    for (double* v : {&u1_, &u2_, &y1_, &y2_}) io.value("filter", *v);
  }

 private:
  double dt_ = 0, cu_[3] = {0, 0, 0}, cy_[3] = {0, 0, 0}, u1_ = 0, u2_ = 0, y1_ = 0, y2_ = 0;
  double lo_ = -1.5e300, hi_ = 1.5e300;
  bool saturated_ = false;
};

}  // namespace tlm
