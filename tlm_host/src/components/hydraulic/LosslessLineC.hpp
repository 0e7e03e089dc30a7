// Lossless transmission line (C-type), the TLM element itself (Krus et al.
// 1990): a pipe of length L, inner diameter d, with wave speed a = sqrt(β/ρ)
// and characteristic impedance Zc = ρ·a/A. With q into the line at each end:
//   c1(t) = p2(t − T) + Zc·q2(t − T),   c2(t) = p1(t − T) + Zc·q1(t − T).
// Or given as Zc and T directly (Hopsan's HydraulicTLMlossless: Z_c,
// deltat), without L, d, ρ, β.
// The delay T = L/a is rounded to a whole number n ≥ 1 of time steps (the
// rounding is reported); the wave variables wait in ring buffers of n
// entries. In the loop C → Q the newest p, q are those the Q stage wrote
// one step ago, so a value written at step k reaches the other end's c at
// step k + n: a one-step line delays by exactly one step.
//
// LaminarLineC adds laminar friction, the Hagen–Poiseuille resistance
// R = 128·μ·L/(π·d⁴) lumped as R/2 at each end of the ideal line: with
// p = p' + (R/2)·q between a port and the line's inner end,
//   p1 = c1 + (Zc + R/2)·q1,   c1(t) = p2(t − T) + (Zc − R/2)·q2(t − T),
// so in steady flow p1 − p2 = R·q exactly, and waves still travel in T.
#pragma once

#include <cmath>
#include <iostream>
#include <vector>

#include "component.hpp"

namespace tlm {

class LosslessLineC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "LosslessLineC"; }
  double source_pressure() const override { return p0_; }  // its start pressure
  void configure(ParameterSet& prm) override {
    if (prm.has("Zc") || prm.has("delay")) {  // the line by its impedance and delay
      Zc_given_ = prm.real("Zc", "Pa·s/m³");  // both required
      T_given_ = prm.real("delay", "s");
      if (!(Zc_given_ > 0.0) || !(T_given_ > 0.0))
        throw config::InputError(prm.where(), name_ + ": Zc and delay must be positive");
      p0_ = prm.real("p0", 1e5, "Pa");
      add_port("P1", Kind::C);
      add_port("P2", Kind::C);
      return;
    }
    configure_line(prm);
  }
  void initialize(double dt) override;
  void simulate_one_step(double) override;
  // The waves in flight (both delay lines) and where they start.
  void state(config::StateIO& io) override {
    io.expect("delay", static_cast<uint64_t>(n_), name_ + ": the line's delay in steps");
    io.value("head", head_);
    io.array("to1", to1_);
    io.array("to2", to2_);
  }
  long delay_steps() const { return n_; }
  double impedance() const { return Zc_; }

 protected:
  void configure_line(ParameterSet& prm) {
    L_ = prm.positive("L", 1.0, "m");
    d_ = prm.positive("d", 0.01, "m");
    rho_ = prm.positive("rho", 870.0, "kg/m³");
    beta_ = prm.positive("beta", 1.4e9, "Pa");  // effective, wall compliance included
    p0_ = prm.real("p0", 1e5, "Pa");
    add_port("P1", Kind::C);
    add_port("P2", Kind::C);
  }
  double R_half_ = 0.0;  // Pa·s/m³, half the laminar resistance (0: lossless)

 private:
  double L_ = 0, d_ = 0, rho_ = 0, beta_ = 0, p0_ = 0, Zc_ = 0;
  double Zc_given_ = 0, T_given_ = 0;  // > 0: given so, not from L, d, ρ, β
  long n_ = 1, head_ = 0;
  std::vector<double> to1_, to2_;
};

inline void LosslessLineC::initialize(double dt) {
  double T = T_given_;
  Zc_ = Zc_given_;
  if (T_given_ == 0.0) {
    const double a = std::sqrt(beta_ / rho_);
    const double area = M_PI * d_ * d_ / 4.0;
    Zc_ = rho_ * a / area;
    T = L_ / a;
  }
  n_ = std::max<long>(1, std::lround(T / dt));
  const double rounded = static_cast<double>(n_) * dt;
  if (std::fabs(rounded - T) > 0.01 * T)
    std::cerr << "tlm_host: warning: line " << name_ << ": delay " << T << " s rounded to " << n_
              << " steps = " << rounded << " s (" << 100.0 * (rounded / T - 1.0)
              << " %): shorten the time step for a truer delay\n";
  if (R_half_ > Zc_)
    std::cerr << "tlm_host: warning: line " << name_ << ": friction R/2 = " << R_half_ << " exceeds Zc = " << Zc_
              << "; lumped end friction is poor here: split the line into shorter ones\n";
  // Each buffer holds the wave leaving one end: w = p + Zc·q, at p0 and rest.
  to2_.assign(static_cast<size_t>(n_), p0_);
  to1_.assign(static_cast<size_t>(n_), p0_);
  head_ = 0;
  for (auto& port : ports_) {
    port.node->c = p0_;
    port.node->Zc = Zc_ + R_half_;
    port.node->p = p0_;
    port.node->q = 0.0;
  }
}

inline void LosslessLineC::simulate_one_step(double) {
  HydraulicNode& n1 = *ports_[0].node;
  HydraulicNode& n2 = *ports_[1].node;
  // Store the waves that just left each end, then read those that left n steps ago.
  const size_t slot = static_cast<size_t>(head_);
  const double from1 = n1.p + (Zc_ - R_half_) * n1.q, from2 = n2.p + (Zc_ - R_half_) * n2.q;
  head_ = (head_ + 1) % n_;
  to2_[slot] = from1;
  to1_[slot] = from2;
  const size_t oldest = static_cast<size_t>(head_);  // written n − 1 steps before `slot`
  n1.c = to1_[oldest];
  n2.c = to2_[oldest];
  n1.Zc = n2.Zc = Zc_ + R_half_;
}

}  // namespace tlm
