// Gas-loaded accumulator (C-type, one port), bladder or piston type.
// Gas: polytropic, p_gas = p0·(V0/(V0 − V_oil))^n for an oil volume V_oil
// above the precharge p0 (absolute pressures). Below the precharge the
// bladder lies on the poppet and only a dead oil volume V_dead with bulk
// modulus β is left: p = p0 + β·V_oil/V_dead (V_oil ≤ 0). The two branches
// meet at p0, so p(V_oil) is continuous and monotonic.
//
// TLM form: the port characteristic p = c + Zc·q with the flow q of the
// coming step. Taking the pressure at the middle of the step,
//   p ≈ p(V_oil) + p'(V_oil)·q·Δt/2   →   c = p(V_oil),  Zc = p'(V_oil)·Δt/2,
// and V_oil ← V_oil + q·Δt after the step: the oil volume is integrated
// exactly, so the accumulator conserves mass.
#pragma once

#include <cmath>

#include "component.hpp"

namespace tlm {

class GasAccumulatorC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "GasAccumulatorC"; }
  double source_pressure() const override { return std::max(p0_, p_init_); }
  void state(config::StateIO& io) override {
    io.value("V_oil", V_oil_);
    io.value("p", p_);
  }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V0", 1e-3, "m³");  // gas volume at precharge
    p0_ = prm.positive("p0", 1e6, "Pa");  // absolute, precharge
    n_ = prm.positive("n", 1.4, "1");  // polytropic exponent
    V_dead_ = prm.positive("V_dead", 1e-2 * V0_, "m³");  // oil left when the bladder is down
    beta_ = prm.positive("beta", 1.4e9, "Pa");  // oil bulk modulus in the dead volume
    p_init_ = prm.real("p_init", p0_, "Pa");  // absolute, initial oil pressure
    add_port("P1", Kind::C);
  }
  void initialize(double dt) override {
    dt_ = dt;
    V_oil_ = p_init_ > p0_ ? V0_ * (1.0 - std::pow(p0_ / p_init_, 1.0 / n_)) : (p_init_ - p0_) * V_dead_ / beta_;
    HydraulicNode& nd = *ports_[0].node;
    update(nd);
    nd.p = nd.c;
    nd.q = 0.0;
  }
  void simulate_one_step(double) override {
    HydraulicNode& nd = *ports_[0].node;
    V_oil_ += nd.q * dt_;  // the flow the Q side delivered over the last step
    update(nd);
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"V_oil", "m3", &V_oil_});
    out.push_back({"p_gas", "Pa", &p_});
  }

 private:
  void update(HydraulicNode& nd) {
    double dpdV;
    if (V_oil_ > 0.0) {
      const double Vg = V0_ - V_oil_;
      p_ = p0_ * std::pow(V0_ / Vg, n_);
      dpdV = n_ * p_ / Vg;
    } else {
      p_ = p0_ + beta_ * V_oil_ / V_dead_;
      dpdV = beta_ / V_dead_;
    }
    nd.c = p_;
    nd.Zc = 0.5 * dpdV * dt_;
  }
  double V0_ = 0, p0_ = 0, n_ = 0, V_dead_ = 0, beta_ = 0, p_init_ = 0, dt_ = 0, V_oil_ = 0, p_ = 0;
};

}  // namespace tlm
