// Ideal flow source (Q-type), e.g. a fixed-displacement pump: it pushes q_set
// into its node whatever the pressure, so p = c + Zc·q_set. The optional
// signal input q (e.g. a SignalTable) replaces the parameter when connected.
// With hopsan_cavitation = 1 (Hopsan models) the pressure written is held at
// 0 or above, as Hopsan's HydraulicFlowSourceQ writes it; the flow is kept.
#pragma once

#include "component.hpp"

namespace tlm {

class FlowSourceQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "FlowSourceQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void state(config::StateIO& io) override { io.value("q", q_); }
  void configure(ParameterSet& prm) override {
    q_ = prm.real("q", 0.0, "m³/s");  // into the node
    add_port("P1", Kind::Q);
    add_signal_input("q", &q_in_, &q_);
    hopsan_cavitation_ = prm.real("hopsan_cavitation", 0.0, "0/1") != 0.0;  // node.hpp: for Hopsan models
  }
  void initialize(double) override {}
  void simulate_one_step(double) override {
    HydraulicNode& n = *ports_[0].node;
    n.q = *q_in_;
    n.p = n.c + n.Zc * n.q;
    if (hopsan_cavitation_ && n.p < 0.0) n.p = 0.0;
  }

 private:
  double q_ = 0.0;
  const double* q_in_ = nullptr;
  bool hopsan_cavitation_ = false;
};

}  // namespace tlm
