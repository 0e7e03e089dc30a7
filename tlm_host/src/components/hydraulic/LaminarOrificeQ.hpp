// Laminar orifice or leakage path (Q-type): q = Kc·(p1 − p2), flow 1 → 2.
// With p1 = c1 − Zc1·q and p2 = c2 + Zc2·q (q leaves node 1, enters node 2):
//   q = Kc·(c1 − c2) / (1 + Kc·(Zc1 + Zc2)),
// exact, and the flow always runs down the pressure difference it leaves.
#pragma once

#include "component.hpp"

namespace tlm {

class LaminarOrificeQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "LaminarOrificeQ"; }
  void state(config::StateIO& io) override {
    io.value("q", q_);
    io.value("dissipated", dissipated_);
  }
  void configure(ParameterSet& prm) override {
    Kc_ = prm.real("Kc", "m³/(s·Pa)");
    if (Kc_ < 0.0) throw config::InputError(prm.where(), name_ + ": Kc must not be negative");
    hopsan_cavitation_ = prm.real("hopsan_cavitation", 0.0, "0/1") != 0.0;  // node.hpp: for Hopsan models
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
  }
  void initialize(double dt) override { dt_ = dt; }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    auto flow = [this](double c1, double c2, double Z1, double Z2) { return Kc_ * (c1 - c2) / (1.0 + Kc_ * (Z1 + Z2)); };
    if (hopsan_cavitation_) {
      q_ = set_through_flow_hopsan(n1, n2, flow);
    } else {
      q_ = flow(n1.c, n2.c, n1.Zc, n2.Zc);
      set_through_flow(n1, n2, q_);
    }
    dissipated_ += q_ * (n1.p - n2.p) * dt_;
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"q", "m3/s", &q_});
    out.push_back({"E_loss", "J", &dissipated_});
  }

 private:
  double Kc_ = 0.0, q_ = 0.0, dt_ = 0.0, dissipated_ = 0.0;
  bool hopsan_cavitation_ = false;
};

}  // namespace tlm
