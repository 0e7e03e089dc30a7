// Hydraulic volume with n ports (C-type), after Krus et al. (1990) and
// Hopsan's HydraulicVolumeMultiPort.
//
// Derivation. A lossless line of volume V and delay T has impedance
// Zc = β·T/V and, with q into the line, the wave relations
//   c1(t+T) = p2(t) + Zc·q2(t),   c2(t+T) = p1(t) + Zc·q1(t).
// Lumping the volume as such an element with T = Δt and treating the n ports
// as lines meeting at a centre gives the mean incoming wave
//   p_m = (1/n) Σ_j (c_j + 2·Zc·q_j)          (c_j + 2·Zc·q_j = p_j + Zc·q_j)
// and the outgoing waves
//   c_i ← 2·p_m − (c_i + 2·Zc·q_i).
// For n = 2 this is exactly the line above. Summing over i, the mean c rises
// by 2·Zc·Σq/n per step; matching dp/dt = β·Σq/V fixes
//   Zc = n·β·Δt / (2·V).
// Optional damping of the wave variables, c_i ← α·c_i,old + (1 − α)·c_i,new,
// with Zc scaled by 1/(1 − α) to keep the capacitance; α = 0 is lossless.
#pragma once

#include "component.hpp"

namespace tlm {

class HydraulicVolumeC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "HydraulicVolumeC"; }
  void configure(ParameterSet& prm) override {
    V_ = prm.positive("V", 1e-3);         // m³
    beta_ = prm.positive("beta", 1.4e9);  // Pa, effective bulk modulus
    p0_ = prm.real("p0", 1e5);            // Pa, initial pressure
    alpha_ = prm.real("alpha", 0.0);
    if (alpha_ < 0.0 || alpha_ >= 1.0) throw config::InputError(prm.where(), name_ + ": alpha must be in [0, 1)");
    const double n = prm.positive("ports", 2);
    for (int i = 1; i <= static_cast<int>(n); ++i) add_port("P" + std::to_string(i), Kind::C);
  }
  void initialize(double dt) override {
    const double n = static_cast<double>(ports_.size());
    Zc_ = n * beta_ * dt / (2.0 * V_ * (1.0 - alpha_));
    for (auto& port : ports_) {
      port.node->c = p0_;
      port.node->Zc = Zc_;
      port.node->p = p0_;
      port.node->q = 0.0;
    }
    p_mean_ = p0_;
  }
  void simulate_one_step(double) override {
    double sum = 0.0;
    for (auto& port : ports_) sum += port.node->c + 2.0 * Zc_ * port.node->q;
    p_mean_ = sum / static_cast<double>(ports_.size());
    for (auto& port : ports_) {
      HydraulicNode& nd = *port.node;
      const double c_new = 2.0 * p_mean_ - nd.c - 2.0 * Zc_ * nd.q;
      nd.c = alpha_ * nd.c + (1.0 - alpha_) * c_new;
      nd.Zc = Zc_;
    }
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"p_mean", "Pa", &p_mean_});
  }
  double impedance() const { return Zc_; }

 private:
  double V_ = 0, beta_ = 0, p0_ = 0, alpha_ = 0, Zc_ = 0, p_mean_ = 0;
};

}  // namespace tlm
