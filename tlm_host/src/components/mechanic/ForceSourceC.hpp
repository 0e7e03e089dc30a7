// ForceSourceC: one of Hopsan's translational mechanics; TranslationalMassQ.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/bilinear.hpp"

namespace tlm {

class ForceSourceC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "ForceSourceC"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void configure(ParameterSet& prm) override {
    F_ = prm.real("F", 0.0, "N");  // when the signal F is not connected
    add_port("P1", Kind::C, true);
    add_signal_input("F", &F_in_, &F_);
  }
  void initialize(double) override {
    HydraulicNode& n = *ports_[0].node;
    n.p = *F_in_;
    if (n.c == 0.0) n.c = *F_in_;
    n.Zc = 0.0;
  }
  void simulate_one_step(double) override { ports_[0].node->c = *F_in_; }
  void state(config::StateIO&) override {}

 private:
  double F_ = 0.0;
  const double* F_in_ = nullptr;
};

}  // namespace tlm
