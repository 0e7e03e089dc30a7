// Turbulent orifice whose area is a table of a signal (Q-type): grooves
// opened by the piston, valve edges, ... The area table A(x) is given as
// "x1:A1; x2:A2; ..." and interpolated linearly (held outside its range);
// the flow is the exact TLM solution of HydraulicTurbulentOrificeQ.
#pragma once

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "table.hpp"

namespace tlm {

class VariableOrificeQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "VariableOrificeQ"; }
  void state(config::StateIO& io) override {
    io.value("q", q_);
    io.value("A", A_);
  }
  void configure(ParameterSet& prm) override {
    Cd_ = prm.positive("Cd", 0.67, "1");
    rho_ = prm.positive("rho", 870.0, "kg/m³");
    area_ = Table(prm.text("area", ""), prm.where(), name_ + ": area table");
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
    add_signal_input("x", &x_);
  }
  void initialize(double) override {}
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    A_ = area_(*x_);
    q_ = turbulent_orifice_flow(n1.c, n2.c, n1.Zc, n2.Zc, Cd_ * A_ * std::sqrt(2.0 / rho_));
    set_through_flow(n1, n2, q_);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"q", "m3/s", &q_});
    out.push_back({"A", "m2", &A_});
  }

 private:
  double Cd_ = 0, rho_ = 0, q_ = 0, A_ = 0;
  Table area_;
  const double* x_ = nullptr;
};

}  // namespace tlm
