// Hydraulic hose (C-type) with the equations of Hopsan's HydraulicHose, for
// Hopsan models (hopsan_loader.cpp maps it; our own LaminarLineC lumps the
// laminar resistance at the ends).
//
// A transmission line of length l, diameter d, wave speed a = √(β/ρ) and
// delay T = l/a, with distributed friction after Krus et al.: the waves
// leaving each end, c + 2·Zc0·q, travel through a ring of whole steps (the
// delay's steps rounded, NT = T/Δt + 1/2 kept unrounded in the filters),
// then through two first-order filters that spread them as the line's
// viscous and wall friction do,
//   (1 + s/W2)/(1 + s/W1),  W1 = 1/(κ·T_N),  W2 = W1·e^(R/(2·Zc0)),
//   (1 + s/W4)/(1 + s/W3),  W3 = R_w/(2·Zc0·T_N),  W4 = W3·e^(R_w/(2·Zc0)),
// (bilinear.hpp; κ = 1.25, T_N = NT·Δt, R the line's resistance, R_w its
// wall's: 128·η·l/(π·d⁴) with η the oil's or the wall's viscosity). The
// resistance follows the flow: laminar below Re = 2300, else Blasius,
// f = 0.079·Re^(−1/4) with R = 1.75·32·ρ·f·l·|q|/(π²·d⁵), averaged with the
// last step's; its pressure drop enters each end through first-order
// recursions with the coefficients 1/(2κNT + 1) and −(2κNT − 1)/(2κNT + 1).
// Zc = Zc0 + R/(2κNT + 1) at each end, Zc0 = ρ·a/A_c with A_c = A·T/T_N.
#pragma once

#include <cmath>
#include <vector>

#include "components/bilinear.hpp"
#include "component.hpp"

namespace tlm {

class HoseC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "HoseC"; }
  double source_pressure() const override { return p0_; }  // its start pressure
  void configure(ParameterSet& prm) override {
    rho_ = prm.positive("rho", 870.0, "kg/m³");
    eta_ = prm.positive("eta", 0.03, "N·s/m²");  // the oil's viscosity
    d_ = prm.positive("d", 0.03, "m");
    l_ = prm.positive("l", 1.0, "m");
    beta_ = prm.positive("beta_e", 1e9, "Pa");
    eta_w_ = prm.real("eta_w", 0.03, "N·s/m²");  // the wall's equivalent viscosity
    p0_ = prm.real("p0", 1e5, "Pa");  // start pressure
    add_port("P1", Kind::C);
    add_port("P2", Kind::C);
  }
  void initialize(double dt) override {
    dt_ = dt;
    R_tot_ = 128.0 * eta_ * l_ / (kPi * d_ * d_ * d_ * d_);
    RL1d_ = RL2d_ = R_tot_;
    Rw_ = 128.0 * eta_w_ * l_ / (kPi * d_ * d_ * d_ * d_);
    const double a = std::sqrt(beta_ / rho_), TL = l_ / a;
    NT_ = TL / dt + 0.5;
    ring_ = static_cast<int>(NT_ + 1);
    c1i_.assign(static_cast<size_t>(ring_) + 1, 0.0);
    c2i_.assign(static_cast<size_t>(ring_) + 1, 0.0);
    TN_ = NT_ * dt;
    const double area_c = kPi * d_ * d_ / 4.0 * TL / TN_;
    Zc0_ = rho_ * a / area_c;
    if (NT_ < 1.0) NT_ = 1.0;
    TN_ = NT_ * dt;
    const double den = 2.0 * kKappa * NT_ + 1.0;
    BC0_ = BC1_ = 1.0 / den;
    AC1_ = -(2.0 * kKappa * NT_ - 1.0) / den;
    // At rest at p0 on both sides.
    const double p = p0_, q = 0.0;
    for (int i = 1; i <= ring_; ++i) c1i_[i] = c2i_[i] = p + Zc0_ * q;
    now_ = 1;
    RQF1D_ = RQF2D_ = R_tot_ * q * (1.0 - BC0_);
    RQEF1D_ = RQEF2D_ = 0.0;
    f1_.reset(c1i_[now_], c1i_[now_]);
    f2_.reset(c2i_[now_], c2i_[now_]);
    f1w_.reset(c1i_[now_], p + Zc0_ * q);
    f2w_.reset(c2i_[now_], p + Zc0_ * q);
    for (auto& port : ports_) {
      port.node->p = p;
      port.node->q = q;
      port.node->c = p - (Zc0_ + BC0_ * R_tot_) * q;
      port.node->Zc = Zc0_ + BC0_ * R_tot_;
    }
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    const double q1 = n1.q, c1 = n1.c, q2 = n2.q, c2 = n2.c;
    now_ = now_ + 1 > ring_ ? 1 : now_ + 1;
    int then = now_ - static_cast<int>(NT_) + 1;
    if (then < 1) then += ring_;
    double RL1 = 0.0, RL2 = 0.0;
    const double RQ1 = friction(RL1, q1), RQ2 = friction(RL2, q2);
    RL1 = (RL1 + RL1d_) / 2.0;
    RL2 = (RL2 + RL2d_) / 2.0;
    RL1d_ = RL1, RL2d_ = RL2;
    const double RL = (RL1 + RL2) / 2.0;
    const double Zc1 = Zc0_ + BC0_ * RL1, Zc2 = Zc0_ + BC0_ * RL2;
    c1i_[now_] = c1 + 2.0 * Zc0_ * q1;
    c2i_[now_] = c2 + 2.0 * Zc0_ * q2;
    const double W1 = 1.0 / (kKappa * TN_), W2 = W1 * std::exp(RL / (2.0 * Zc0_));
    const double W3 = Rw_ / (2.0 * Zc0_ * TN_), W4 = W3 * std::exp(Rw_ / (2.0 * Zc0_));
    f1_.set(dt_, 1.0, 1.0 / W2, 1.0, 1.0 / W1);
    const double C1F = f1_.update(c1i_[then]);
    f2_.set(dt_, 1.0, 1.0 / W2, 1.0, 1.0 / W1);
    const double C2F = f2_.update(c2i_[then]);
    f1w_.set(dt_, 1.0, 1.0 / W4, 1.0, 1.0 / W3);
    const double C1F1 = f1w_.update(C1F);
    f2w_.set(dt_, 1.0, 1.0 / W4, 1.0, 1.0 / W3);
    const double C2F1 = f2w_.update(C2F);
    RQF1D_ = RQF1D_ + BC0_ * RL1 * q1;
    RQF2D_ = RQF2D_ + BC0_ * RL2 * q2;
    const double RQF1 = -AC1_ * RQF1D_ + BC1_ * RL1 * q1;
    const double RQF2 = -AC1_ * RQF2D_ + BC1_ * RL2 * q2;
    RQF1D_ = RQF1, RQF2D_ = RQF2;
    const double RQEF1 = -AC1_ * RQEF1D_ + (BC0_ + BC1_) * (RQ1 - RL1 * q1);
    const double RQEF2 = -AC1_ * RQEF2D_ + (BC0_ + BC1_) * (RQ2 - RL2 * q2);
    RQEF1D_ = RQEF1, RQEF2D_ = RQEF2;
    n1.c = C2F1 + RQF1 + BC0_ * (-RL1 * q1) + RQEF1;
    n2.c = C1F1 + RQF2 + BC0_ * (-RL2 * q2) + RQEF2;
    n1.Zc = Zc1;
    n2.Zc = Zc2;
  }
  void state(config::StateIO& io) override {
    io.value("now", now_);
    io.array("to1", c1i_);
    io.array("to2", c2i_);
    for (double* v : {&RL1d_, &RL2d_, &RQF1D_, &RQF2D_, &RQEF1D_, &RQEF2D_}) io.value("hose", *v);
    f1_.state(io), f2_.state(io), f1w_.state(io), f2w_.state(io);
  }

 private:
  static constexpr double kPi = 3.14159265358979323846;
  static constexpr double kKappa = 1.25;
  // The line's pressure drop at flow q, and its resistance RL (laminar below
  // Re = 2300, else Blasius' turbulent friction).
  double friction(double& RL, double q) const {
    const double Re = std::fabs(4 * rho_ * q / (kPi * d_ * eta_));
    if (Re < 2300) {
      RL = 128 * eta_ * l_ / (kPi * d_ * d_ * d_ * d_);
      return RL * q;
    }
    const double F = 0.079 * std::pow(Re, -0.25), d5 = kPi * kPi * d_ * d_ * d_ * d_ * d_;
    RL = 1.75 * 32 * rho_ * F * l_ * std::fabs(q) / d5;
    return 32 * rho_ * F * l_ * std::fabs(q) * q / d5;
  }
  double rho_ = 0, eta_ = 0, d_ = 0, l_ = 0, beta_ = 0, eta_w_ = 0, p0_ = 0, dt_ = 0;
  double R_tot_ = 0, RL1d_ = 0, RL2d_ = 0, Rw_ = 0, NT_ = 0, TN_ = 0, Zc0_ = 0, BC0_ = 0, BC1_ = 0, AC1_ = 0;
  double RQF1D_ = 0, RQF2D_ = 0, RQEF1D_ = 0, RQEF2D_ = 0;
  int ring_ = 0;
  long now_ = 1;
  std::vector<double> c1i_, c2i_;
  BilinearFirstOrder f1_, f2_, f1w_, f2w_;
};

}  // namespace tlm
