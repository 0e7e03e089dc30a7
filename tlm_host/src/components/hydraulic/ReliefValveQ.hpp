// Pressure relief valve (Q-type) from P1 (inlet) to P2 (tank). Steady
// characteristic: q = K·max(0, Δp − p_crack), the linear override of a
// direct-acting valve (K = rated flow / override pressure). Dynamics: the
// conductance follows its target with a first-order lag of time constant
// tau (the poppet's opening time), K_eff ← K_eff + Δt/τ·(K·[Δp > p_crack] − K_eff),
// integrated exactly as K_eff ← K_target + (K_eff − K_target)·exp(−Δt/τ).
// TLM solution, with p1 = c1 − Zc1·q and p2 = c2 + Zc2·q:
//   q = K_eff·(c1 − c2 − p_crack) / (1 + K_eff·(Zc1 + Zc2)),  clamped at 0
// (the valve checks backflow).
#pragma once

#include <algorithm>
#include <cmath>

#include "component.hpp"

namespace tlm {

class ReliefValveQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "ReliefValveQ"; }
  void state(config::StateIO& io) override {
    io.value("K_eff", K_eff_);  // the opening's lag
    io.value("q", q_);
  }
  void configure(ParameterSet& prm) override {
    p_crack_ = prm.real("p_crack", "Pa");  // pressure difference at which it opens
    K_ = prm.positive("K", 6.7e-9, "m³/(s·Pa)");  // override gradient
    tau_ = prm.positive("tau", 1e-3, "s");  // opening time constant
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
  }
  void initialize(double dt) override {
    decay_ = std::exp(-dt / tau_);
    K_eff_ = 0.0;
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    // Open or close on the pressure difference of the last step.
    const double target = (n1.p - n2.p) > p_crack_ ? K_ : 0.0;
    K_eff_ = target + (K_eff_ - target) * decay_;
    q_ = std::max(0.0, K_eff_ * (n1.c - n2.c - p_crack_) / (1.0 + K_eff_ * (n1.Zc + n2.Zc)));
    set_through_flow(n1, n2, q_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"q", "m3/s", &q_});
    out.push_back({"K_eff", "m3/(s.Pa)", &K_eff_});
  }

 private:
  double p_crack_ = 0, K_ = 0, tau_ = 0, decay_ = 0, K_eff_ = 0, q_ = 0;
};

}  // namespace tlm
