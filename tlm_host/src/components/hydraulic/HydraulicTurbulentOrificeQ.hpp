// Turbulent orifice (Q-type): q = Cd·A·sqrt(2·|Δp|/ρ)·sign(Δp), solved
// exactly against the TLM characteristics of both nodes.
//
// With q_o the flow from port 1 to port 2, node 1 sees q = −q_o and node 2
// q = +q_o (flow into their C elements), so
//   p1 = c1 − Zc1·q_o,   p2 = c2 + Zc2·q_o,   Δp = (c1 − c2) − (Zc1 + Zc2)·q_o.
// Let K = Cd·A·sqrt(2/ρ), D = |c1 − c2|, Z = Zc1 + Zc2, s = sign(c1 − c2)
// and x = |q_o|. Then x = K·sqrt(D − Z·x), i.e. x² + K²·Z·x − K²·D = 0, whose
// non-negative root is
//   x = ( −K²·Z + sqrt(K⁴·Z² + 4·K²·D) ) / 2     (→ K·sqrt(D) as Z → 0),
// and q_o = s·x. The flow never reverses Δp, so the orifice cannot add energy.
#pragma once

#include <cmath>

#include "component.hpp"

namespace tlm {

inline double turbulent_orifice_flow(double c1, double c2, double Zc1, double Zc2, double K) {
  const double D = std::fabs(c1 - c2);
  const double Z = Zc1 + Zc2;
  const double K2 = K * K;
  // The root written as 2·K²·D / (K²·Z + sqrt(K⁴·Z² + 4·K²·D)) avoids the
  // cancellation of the textbook form when K²·Z is large.
  const double den = K2 * Z + std::sqrt(K2 * K2 * Z * Z + 4.0 * K2 * D);
  const double x = den > 0.0 ? 2.0 * K2 * D / den : 0.0;
  return c1 >= c2 ? x : -x;
}

class HydraulicTurbulentOrificeQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "HydraulicTurbulentOrificeQ"; }
  void state(config::StateIO& io) override {
    io.value("q", q_);
    io.value("dissipated", dissipated_);
  }
  void configure(ParameterSet& prm) override {
    Cd_ = prm.positive("Cd", 0.67, "1");
    A_ = prm.positive("A", 1e-5, "m²");
    rho_ = prm.positive("rho", 870.0, "kg/m³");
    hopsan_cavitation_ = prm.real("hopsan_cavitation", 0.0, "0/1") != 0.0;  // node.hpp: for Hopsan models
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
  }
  void initialize(double dt) override {
    K_ = Cd_ * A_ * std::sqrt(2.0 / rho_);
    dt_ = dt;
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    if (hopsan_cavitation_) {
      q_ = set_through_flow_hopsan(n1, n2, [this](double c1, double c2, double Z1, double Z2) {
        return turbulent_orifice_flow(c1, c2, Z1, Z2, K_);
      });
    } else {
      q_ = turbulent_orifice_flow(n1.c, n2.c, n1.Zc, n2.Zc, K_);
      set_through_flow(n1, n2, q_);
    }
    dissipated_ += q_ * (n1.p - n2.p) * dt_;  // always ≥ 0: q runs down Δp
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"q", "m3/s", &q_});
    out.push_back({"E_loss", "J", &dissipated_});
  }

 private:
  double Cd_ = 0, A_ = 0, rho_ = 0, K_ = 0, q_ = 0, dt_ = 0, dissipated_ = 0;
  bool hopsan_cavitation_ = false;
};

}  // namespace tlm
