// Ideal pressure source (C-type): an infinite capacitance holds p whatever
// the flow, so its boundary characteristic p = c + Zc·q has c = p_set, Zc = 0.
#pragma once

#include "component.hpp"

namespace tlm {

class PressureSourceC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "PressureSourceC"; }
  double source_pressure() const override { return p_; }
  void state(config::StateIO&) override {}  // a constant pressure: nothing changes
  void configure(ParameterSet& prm) override {
    p_ = prm.real("p", "Pa");
    add_port("P1", Kind::C);
  }
  void initialize(double) override {
    HydraulicNode& n = *ports_[0].node;
    n.c = p_;
    n.Zc = 0.0;
    n.p = p_;
    n.q = 0.0;
  }
  void simulate_one_step(double) override {
    ports_[0].node->c = p_;
    ports_[0].node->Zc = 0.0;
  }

 private:
  double p_ = 0.0;
};

}  // namespace tlm
