// Directional valves with the equations of Hopsan's Hydraulic43Valve and
// Hydraulic32DirectionalValve (mapped from Hopsan models, hopsan_loader.cpp).
//
// The spool follows its command through a second-order lag,
// xv = 1/(1 + 2δ/ω·s + s²/ω²)·x_in, discretized bilinearly (bilinear.hpp)
// and held within its travel. Each metering edge is a turbulent orifice of
// area f·π·d·max(opening, 0), K = C_q·f·π·d·opening·√(2/ρ), and, as in
// Hopsan, solved on its own against the two nodes it joins (each edge sees
// the node impedances as if it were the only flow there; our SpoolValveQ
// solves the edges that share a node together). A port's flow is the sum of
// its edges'. Where a port's pressure would fall below zero, the edges are
// solved again with that node's c = Zc = 0 (Hopsan's cavitation check).
//
// Valve43Q (Hydraulic43Valve): ports PP, PT, PA, PB; edges P→A open for
// xv > x_pa, P→B for −xv > x_pb, A→T for −xv > x_at, B→T for xv > x_bt
// (negative overlaps: underlap); command `in` within ±x_vmax.
// Valve32Q (Hydraulic32DirectionalValve): ports PP, PT, PA; the spool goes to
// x_vmax when `in` > 0.5 and to 0 otherwise; P→A opens with xv,
// A→T with x_vmax − xv.
// Valve22Q (Hydraulic22DirectionalValve): ports P1, P2, on/off as Valve32Q;
// P1→P2 opens with xv.
// Valve33Q (Hydraulic33Valve): ports PP, PT, PA; the spool follows `in`
// within ±x_vmax; P→A opens for xv > x_pa, A→T for −xv > x_at; on
// cavitation only the spool's side's edge is solved again (Hopsan's).
// Valve22ProportionalQ (Hydraulic22Valve): ports PP, PA; the spool follows
// its command `in` held within [0, x_vmax]; P→A opens with xv.
// Valve42Q (Hydraulic42DirectionalValve): ports PP, PT, PA, PB, on/off;
// P→A and B→T open with xv, P→B and A→T with x_vmax − xv; the spool starts
// at its command's first value (within its travel), as Hopsan's.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/bilinear.hpp"
#include "component.hpp"

namespace tlm {

class DirectionalValveQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  void initialize(double dt) override {
    const double num[3] = {1.0, 0.0, 0.0}, den[3] = {1.0, 2.0 * delta_ / omega_, 1.0 / (omega_ * omega_)};
    spool_.limits(xv_lo_, xv_hi_);
    spool_.set(dt, num, den);
    const double x0 = initial_spool();
    spool_.reset(x0, x0);
    // The output shows the spool's start value until the first step (where a
    // valve starts its spool elsewhere, as Hopsan's 4/2 valve, that differs).
    xv_ = std::clamp(xv_, xv_lo_, xv_hi_);
    for (Edge& e : edges_) e.gain = Cq_ * e.f * M_PI * d_;  // K = gain·opening·√(2/ρ), in Hopsan's order
    root_ = std::sqrt(2.0 / rho_);
  }
  void simulate_one_step(double) override {
    xv_ = spool_.update(command());
    const size_t n = ports_.size();
    std::array<double, 5> c{}, Z{}, q{}, K{};  // up to 4 metered ports and a pilot
    for (size_t i = 0; i < n; ++i) c[i] = ports_[i].node->c, Z[i] = ports_[i].node->Zc;
    for (size_t k = 0; k < edges_.size(); ++k) K[k] = edges_[k].gain * std::max(opening(edges_[k]), 0.0) * root_;
    auto solve = [&](bool cavitating) {
      q.fill(0.0);
      for (size_t k = 0; k < edges_.size(); ++k) {
        const Edge& e = edges_[k];
        if (cavitating && cavitation_side_only_ && (xv_ >= 0.0) != (e.sign > 0)) continue;
        const double flow = turbulent_orifice_flow(c[e.from], c[e.to], Z[e.from], Z[e.to], K[k]);
        q[e.from] -= flow;
        q[e.to] += flow;
      }
    };
    solve(false);
    bool cavitating = false;
    for (size_t i = 0; i < std::min(n, metered_ports_); ++i)
      if (c[i] + q[i] * Z[i] < 0.0) c[i] = 0.0, Z[i] = 0.0, cavitating = true;
    if (cavitating) solve(true);
    for (size_t i = 0; i < n; ++i) {
      ports_[i].node->q = q[i];
      ports_[i].node->p = c[i] + q[i] * Z[i];
    }
  }
  void state(config::StateIO& io) override {
    spool_.state(io);
    xv_ = spool_.value();
  }

 protected:
  struct Edge {
    size_t from, to;  // port indices
    double f;         // fraction of the circumference
    double overlap;   // m (negative: underlap)
    int sign;         // opens with +xv or −xv; 0: with x_vmax − xv
    double gain = 0;  // C_q·f·π·d
  };
  virtual double command() const = 0;
  // Where the spool starts: xv0 (the start value), unless the valve starts otherwise.
  virtual double initial_spool() const { return xv_; }
  double opening(const Edge& e) const { return e.sign == 0 ? xv_max_ - xv_ : e.sign * xv_ - e.overlap; }
  void configure_common(ParameterSet& prm) {
    Cq_ = prm.real("C_q", 0.67, "1");
    rho_ = prm.positive("rho", 870.0, "kg/m³");
    d_ = prm.positive("d", 0.01, "m");  // spool diameter
    xv_max_ = prm.positive("x_vmax", 0.01, "m");
    omega_ = prm.positive("omega_h", 100.0, "rad/s");
    delta_ = prm.positive("delta_h", 1.0, "1");
    xv_ = prm.real("xv0", 0.0, "m");  // the spool's start
    add_signal_output("xv", &xv_);
  }
  std::vector<Edge> edges_;
  // Solved again on cavitation with only the edges of the spool's side (xv ≥ 0: those opening with +xv), as Hopsan's 3/3 valve.
  bool cavitation_side_only_ = false;
  // The ports an edge meters, first: the cavitation check is theirs (a pilot port after them is not).
  size_t metered_ports_ = 4;
  double Cq_ = 0, rho_ = 0, d_ = 0, xv_max_ = 0, omega_ = 0, delta_ = 0, xv_ = 0, xv_lo_ = 0, xv_hi_ = 0, root_ = 0;
  const double* in_ = nullptr;
  BilinearSecondOrder spool_;
};

}  // namespace tlm
