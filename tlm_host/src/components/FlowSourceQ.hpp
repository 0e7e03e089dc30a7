// Ideal flow source (Q-type), e.g. a fixed-displacement pump: it pushes q_set
// into its node whatever the pressure, so p = c + Zc·q_set.
#pragma once

#include "component.hpp"

namespace tlm {

class FlowSourceQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "FlowSourceQ"; }
  void configure(ParameterSet& prm) override {
    q_ = prm.real("q");  // m³/s into the node
    add_port("P1", Kind::Q);
  }
  void initialize(double) override {}
  void simulate_one_step(double) override {
    HydraulicNode& n = *ports_[0].node;
    n.q = q_;
    n.p = n.c + n.Zc * q_;
  }

 private:
  double q_ = 0.0;
};

}  // namespace tlm
