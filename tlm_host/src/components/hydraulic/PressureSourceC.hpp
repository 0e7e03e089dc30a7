// Ideal pressure source (C-type): an infinite capacitance holds p whatever
// the flow, so its boundary characteristic p = c + Zc·q has c = p_set, Zc = 0.
// p_set is the parameter p, or the signal connected to its input p (as
// Hopsan's HydraulicPressureSourceC reads its input variable p). q0 is the
// flow its node holds at the start, until the Q side writes its own (a
// Hopsan model's start flow on P1: Hopsan's node starts with it).
#pragma once

#include <string>

#include "component.hpp"

namespace tlm {

class PressureSourceC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "PressureSourceC"; }
  // A pressure a signal sets may be any: the node guard cannot bound it from here.
  double source_pressure() const override { return p_in_ == &p_ ? p_ : 1e300; }
  void state(config::StateIO&) override {}  // a constant pressure: nothing changes
  void configure(ParameterSet& prm) override {
    p_ = prm.real("p", "Pa");
    const int ports = prm.integer("ports", 1, 1, 1000);
    for (int k = 1; k <= ports; ++k) add_port("P" + std::to_string(k), Kind::C);
    add_signal_input("p", &p_in_, &p_);
    q0_ = prm.real("q0", 0.0, "m³/s");
  }
  void initialize(double) override {
    for (Port& port : ports_) {
      HydraulicNode& n = *port.node;
      n.c = *p_in_;
      n.Zc = 0.0;
      n.p = *p_in_;
      n.q = q0_;
    }
  }
  void simulate_one_step(double) override {
    for (Port& port : ports_) {
      port.node->c = *p_in_;
      port.node->Zc = 0.0;
    }
  }

 private:
  double p_ = 0.0, q0_ = 0.0;
  const double* p_in_ = &p_;
};

}  // namespace tlm
