// Pressure relief valve (Q-type) with the equations of Hopsan's
// HydraulicPressureReliefValve, for Hopsan models (hopsan_loader.cpp maps it;
// our own ReliefValveQ is a simpler linear-override valve).
//
// The poppet's opening x (a flow coefficient, q = x·√Δp, turbulent) follows
// a static balance through a first-order lag. With Δp = p1 − p2 of the last
// step and the nominal pressure p_nom = 7 MPa:
//   spring and flow-force gains  b1 = √p_nom/k_cs + max(Δp, 0)/(k_cf·√p_nom),
//   the lines' share             γ = 2√|Δp| / (2√|Δp| + (Zc1 + Zc2)·x_prev),
//                                b2 = γ·(Zc1 + Zc2)·√|Δp|,
//   the static opening           x_s = (γ·c1 + b2·x_prev/2 − p_max) / (b1 + b2),
// held within a hysteresis band of width p_h/(b1 + b2) around the previous
// opening, then x = x_s/(1 + s/ω) with ω = (1 + b2/b1)/τ (bilinear,
// bilinear.hpp), kept within [0, q_nom/√p_nom]. The flow then solves the
// turbulent orifice x against both nodes; where a pressure would fall below
// zero, that node is taken at 0 Pa (c = Zc = 0) and no pressure below zero
// is written (Hopsan's cavitation check).
#pragma once

#include <algorithm>
#include <cmath>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/bilinear.hpp"
#include "component.hpp"

namespace tlm {

class PressureReliefValveQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "PressureReliefValveQ"; }
  void configure(ParameterSet& prm) override {
    p_max_ = prm.real("p_max", 2e7, "Pa");  // opening pressure difference
    tau_ = prm.positive("tao", 0.01, "s");  // the poppet's time constant
    p_h_ = prm.real("p_h", 5e5, "Pa");  // hysteresis width
    k_cs_ = prm.positive("k_cs", 1e-8, "m³/(s·Pa)");  // steady characteristic from the spring
    k_cf_ = prm.positive("k_cf", 1e-8, "m³/(s·Pa)");  // from the flow forces
    q_nom_ = prm.positive("q_nom", 1e-3, "m³/s");  // fully open at p_nom
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
    add_signal_output("xv", &x_);
  }
  void initialize(double dt) override {
    dt_ = dt;
    x_max_ = q_nom_ / std::sqrt(kPnom);
    Cs_ = std::sqrt(kPnom) / k_cs_;
    Cf_ = 1.0 / (k_cf_ * std::sqrt(kPnom));
    x_ = 0.0;
    lag_.set(dt, 1.0, 0.0, 1.0, tau_);
    lag_.limits(0.0, x_max_);
    lag_.reset(0.0, 0.0);
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    const double dp = n1.p - n2.p, Z = n1.Zc + n2.Zc, root = std::sqrt(std::abs(dp));
    const double b1 = dp * Cf_ < 0.0 ? Cs_ : Cs_ + dp * Cf_;
    const double gamma = 2.0 * root + Z * x_ != 0.0 ? 2.0 * root / (2.0 * root + Z * x_) : 1.0;
    const double b2 = std::max(gamma * Z * root, 0.0);
    const double xs = (gamma * n1.c + b2 * x_ / 2.0 - p_max_) / (b1 + b2);
    const double xh = p_h_ / (b1 + b2);
    const double held = std::min(std::max(x_, xs - xh / 2.0), xs + xh / 2.0);  // the hysteresis band
    const double w = (1.0 + b2 / b1) / tau_;
    lag_.set(dt_, 1.0, 0.0, 1.0, 1.0 / w);
    x_ = lag_.update(held);
    const double x = x_;
    q_ = set_through_flow_hopsan(n1, n2, [x](double c1, double c2, double Z1, double Z2) {
      return turbulent_orifice_flow(c1, c2, Z1, Z2, x);
    });
  }
  void state(config::StateIO& io) override {
    lag_.state(io);
    x_ = lag_.value();
    io.value("q", q_);
  }
  void log_variables(std::vector<LogVariable>& out) override { out.push_back({"q", "m3/s", &q_}); }

 private:
  static constexpr double kPnom = 7e6;  // Pa, Hopsan's nominal pressure for k_cs, k_cf and q_nom
  double p_max_ = 0, tau_ = 0, p_h_ = 0, k_cs_ = 0, k_cf_ = 0, q_nom_ = 0;
  double dt_ = 0, x_max_ = 0, Cs_ = 0, Cf_ = 0, x_ = 0, q_ = 0;
  BilinearFirstOrder lag_;
};

}  // namespace tlm
