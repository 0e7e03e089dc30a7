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
// Cavitation conserves oil: the volume carries a vapour (void) volume
// V_void ≥ 0 beside its liquid. The incoming waves give the pressure the
// liquid would have, p_wave = p_prev + β·Σq·Δt/V; any void is refilled
// first, so the liquid's pressure is
//   p_liquid = p_wave − V_void·β/V,
// and if that is below p_vap the volume holds p_vap with
//   V_void = (p_vap − p_liquid)·V/β      (= V_void,prev + Σ(q_out − q_in)·Δt),
// else V_void = 0 and the pressure is p_liquid: liquid behaviour resumes in
// the step the void is refilled, with exactly the oil that is left over.
// Every c_i is shifted by the same amount (p_m − p_wave) to hold that
// pressure. (Lifting the pressure to p_vap without a void, as this volume
// did before, creates the missing oil out of nothing.) Each cavitation event
// is recorded with its start, duration and largest void, and reported.
#pragma once

#include <algorithm>
#include <iostream>
#include <vector>

#include "component.hpp"

namespace tlm {

class HydraulicVolumeC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "HydraulicVolumeC"; }
  double source_pressure() const override { return p0_; }
  void state(config::StateIO& io) override {
    for (double* s : {&V_, &Zc_, &p_mean_, &stored_, &void_, &t_last_}) io.value("volume", *s);
    io.value("cavitating", cavitating_);
    io.list("cavitation events", events_);
  }
  void configure(ParameterSet& prm) override {
    V0_ = prm.positive("V", 1e-3, "m³");  // at x = 0 for a chamber
    beta_ = prm.positive("beta", 1.4e9, "Pa");  // effective bulk modulus
    p0_ = prm.real("p0", 1e5, "Pa");  // initial pressure
    alpha_ = prm.real("alpha", 0.0, "1");
    p_vap_ = prm.real("p_vap", 5e3, "Pa");  // absolute (0.05 bar)
    dVdx_ = prm.real("dVdx", 0.0, "m²");  // chamber volume change per unit of x
    V_min_ = prm.positive("V_min", 1e-3 * V0_, "m³");
    if (alpha_ < 0.0 || alpha_ >= 1.0) throw config::InputError(prm.where(), name_ + ": alpha must be in [0, 1)");
    const int n = prm.integer("ports", 2, 1, 64);
    for (int i = 1; i <= n; ++i) add_port("P" + std::to_string(i), Kind::C);
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
  void simulate_one_step(double t) override {
    double sum = 0.0;
    for (auto& port : ports_) sum += port.node->c + 2.0 * Zc_ * port.node->q;
    const double p_wave = sum / static_cast<double>(ports_.size());
    // The void first (see above), at the volume and compliance the last flows met.
    const double compliance = V_ / beta_;  // m³/Pa
    const double p_liquid = p_wave - void_ / compliance;
    if (p_liquid < p_vap_) {
      void_ = (p_vap_ - p_liquid) * compliance;
      p_mean_ = p_vap_;
    } else {
      void_ = 0.0;
      p_mean_ = p_liquid;
    }
    track_events(t);
    // c_new = 2·p_m − (c + 2·Zc·q) has mean p_wave; shifting every c_new by
    // the same amount gives the volume's pressure p_m.
    const double lift = p_mean_ - p_wave;
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
    if (void_ > 0.0) events_.back().duration = t_last_ - events_.back().start;  // still cavitating at the end
    if (events_.empty()) return;
    double total = 0.0, longest = 0.0, largest = 0.0;
    for (const auto& e : events_) {
      total += e.duration;
      longest = std::max(longest, e.duration);
      largest = std::max(largest, e.max_void);
    }
    std::cerr << "tlm_host: " << name_ << ": cavitation " << events_.size() << " time(s), " << total * 1e3
              << " ms in all (longest " << longest * 1e3 << " ms, largest vapour volume " << largest * 1e6
              << " cm³; held at p_vap = " << p_vap_ << " Pa while vapour was present)\n";
    const size_t shown = std::min<size_t>(events_.size(), 5);
    for (size_t i = 0; i < shown; ++i)
      std::cerr << "tlm_host: " << name_ << ":   event " << i + 1 << ": t = " << events_[i].start << " s, "
                << events_[i].duration * 1e3 << " ms, vapour volume up to " << events_[i].max_void * 1e6 << " cm³\n";
    if (events_.size() > shown) std::cerr << "tlm_host: " << name_ << ":   ... (" << events_.size() - shown << " more)\n";
  }
  void log_variables(std::vector<LogVariable>& out) override {
    out.push_back({"p_mean", "Pa", &p_mean_});
    out.push_back({"E_stored", "J", &stored_});
    out.push_back({"V_void", "m3", &void_});
    if (dVdx_ != 0.0) out.push_back({"V", "m3", &V_});
  }
  // A stretch of time with vapour in the volume.
  struct CavitationEvent {
    double start = 0.0, duration = 0.0, max_void = 0.0;  // s, s, m³
  };
  long cavitation_events() const { return static_cast<long>(events_.size()); }
  const std::vector<CavitationEvent>& events() const { return events_; }

 private:
  void track_events(double t) {
    t_last_ = t + dt_;
    if (void_ > 0.0) {
      if (!cavitating_) events_.push_back({t + dt_, 0.0, 0.0});
      events_.back().max_void = std::max(events_.back().max_void, void_);
    } else if (cavitating_) {
      events_.back().duration = t + dt_ - events_.back().start;
    }
    cavitating_ = void_ > 0.0;
  }
  void update_impedance() {
    V_ = x_ ? std::max(V_min_, V0_ + dVdx_ * *x_) : V0_;
    Zc_ = static_cast<double>(ports_.size()) * beta_ * dt_ / (2.0 * V_ * (1.0 - alpha_));
  }
  double V0_ = 0, beta_ = 0, p0_ = 0, alpha_ = 0, p_vap_ = 0, dVdx_ = 0, V_min_ = 0;
  double V_ = 0, Zc_ = 0, p_mean_ = 0, dt_ = 0, stored_ = 0;
  double void_ = 0.0;  // m³ of vapour
  double t_last_ = 0.0;
  const double* x_ = nullptr;
  bool cavitating_ = false;
  std::vector<CavitationEvent> events_;
};

}  // namespace tlm
