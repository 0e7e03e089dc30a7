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
//
// Chamber: with dVdx ≠ 0 the volume is V = V0 + dVdx·x for a signal x (a
// piston position); only the compliance follows V, the displaced volume
// arrives as the piston port's flow. V is kept above V_min.
//
// Cavitation: p_m is never let below the vapour pressure p_vap. When it
// would be, every c_i is lifted by the same amount, i.e. vapour fills the
// missing oil volume instead of a negative pressure being stored; each entry
// into that state is counted and reported.
#pragma once

#include <algorithm>
#include <iostream>

#include "component.hpp"

namespace tlm {

class HydraulicVolumeC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "HydraulicVolumeC"; }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V", 1e-3);         // m³ (at x = 0 for a chamber)
    beta_ = prm.positive("beta", 1.4e9);   // Pa, effective bulk modulus
    p0_ = prm.real("p0", 1e5);             // Pa, initial pressure
    alpha_ = prm.real("alpha", 0.0);
    p_vap_ = prm.real("p_vap", 5e3);       // Pa abs (0.05 bar)
    dVdx_ = prm.real("dVdx", 0.0);         // m², chamber volume change per unit of x
    V_min_ = prm.positive("V_min", 1e-3 * V0_);
    if (alpha_ < 0.0 || alpha_ >= 1.0) throw config::InputError(prm.where(), name_ + ": alpha must be in [0, 1)");
    const double n = prm.positive("ports", 2);
    for (int i = 1; i <= static_cast<int>(n); ++i) add_port("P" + std::to_string(i), Kind::C);
    if (dVdx_ != 0.0) add_signal_input("x", &x_);
  }
  void initialize(double dt) override {
    dt_ = dt;
    update_impedance();
    for (auto& port : ports_) {
      port.node->c = p0_;
      port.node->Zc = Zc_;
      port.node->p = p0_;
      port.node->q = 0.0;
    }
    p_mean_ = p0_;
    stored_ = V_ * p0_ * p0_ / (2.0 * beta_);
  }
  void simulate_one_step(double) override {
    double sum = 0.0;
    for (auto& port : ports_) sum += port.node->c + 2.0 * Zc_ * port.node->q;
    const double p_wave = sum / static_cast<double>(ports_.size());
    // c_new = 2·p_m − (c + 2·Zc·q) has mean p_m, so lifting every c_new by
    // the same amount lifts the volume's pressure to p_vap.
    const double lift = p_wave < p_vap_ ? p_vap_ - p_wave : 0.0;
    if (lift > 0.0 && !cavitating_) ++cavitation_events_;
    cavitating_ = lift > 0.0;
    p_mean_ = p_wave + lift;
    const double Zc_arrived = Zc_;  // the impedance the last flows met
    update_impedance();
    for (auto& port : ports_) {
      HydraulicNode& nd = *port.node;
      const double c_new = 2.0 * p_wave - nd.c - 2.0 * Zc_arrived * nd.q + lift;
      nd.c = alpha_ * nd.c + (1.0 - alpha_) * c_new;
      nd.Zc = Zc_;
    }
    // Compression energy of the oil, V·p²/(2β) (linear compressibility, from p = 0).
    stored_ = V_ * p_mean_ * p_mean_ / (2.0 * beta_);
  }
  void finalize() override {
    if (cavitation_events_ > 0)
      std::cerr << "tlm_host: " << name_ << ": pressure reached the vapour pressure " << cavitation_events_
                << " time(s) (cavitation; the volume was held at p_vap)\n";
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"p_mean", "Pa", &p_mean_});
    out.push_back({"E_stored", "J", &stored_});
    if (dVdx_ != 0.0) out.push_back({"V", "m3", &V_});
  }
  long cavitation_events() const { return cavitation_events_; }

 private:
  void update_impedance() {
    V_ = x_ ? std::max(V_min_, V0_ + dVdx_ * *x_) : V0_;
    Zc_ = static_cast<double>(ports_.size()) * beta_ * dt_ / (2.0 * V_ * (1.0 - alpha_));
  }
  double V0_ = 0, beta_ = 0, p0_ = 0, alpha_ = 0, p_vap_ = 0, dVdx_ = 0, V_min_ = 0;
  double V_ = 0, Zc_ = 0, p_mean_ = 0, dt_ = 0, stored_ = 0;
  const double* x_ = nullptr;
  bool cavitating_ = false;
  long cavitation_events_ = 0;
};

}  // namespace tlm
