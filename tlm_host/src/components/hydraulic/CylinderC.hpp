// Hydraulic cylinders between hydraulic nodes and a mechanical TLM node
// (node.hpp: F = c + Zc·v), with the equations of Hopsan's default library
// so that Hopsan models of cylinders run here as in Hopsan
// (hopsan_loader.cpp maps them):
//
// CylinderC (Hopsan's HydraulicCylinderC), a C component: chambers 1 and 2
// (ports P1, P2, one connection each) of volumes V_1 − A_1·x3 and
// V_2 + A_2·(s_l + x3) behind a piston on the mechanical port P3 (x3 from 0
// at one end to −s_l at the other). Each chamber is a TLM volume of three
// ports, its hydraulic port, the piston (flow A·v3) and the internal leakage
// c_leak·(p1 − p2) between them, damped with α = 0.1 (as
// HydraulicVolumeC, with Zc = 3/2·β·Δt/(V·(1 − α))); the piston sees
// c3 = A_1·ci1 − A_2·ci2 and Zc3 = A_1²·Zc1 + A_2²·Zc2 + B_p. A chamber is
// never smaller than β·Δt²·A²/(0.1·me), me the equivalent mass the
// mechanical node carries. End stops (use_sl): outside the stroke a spring
// as stiff as the step allows, Zx = 0.1·me/Δt, pushes the piston back,
// filtered with 0.5. Hopsan's filter reads its previous value from an
// uninitialised variable; here it is kept from the last step (results differ
// from Hopsan's only after an end stop is reached).
//
// CylinderQ (Hopsan's HydraulicCylinderQ), a Q component: a cylinder with
// its load (m_l, B_l, k_l) inside, between the chambers' C components on P1
// and P2 and a C component on the mechanical port P3. The load's position
// and velocity solve
//   x3 = (A1·c1 − A2·c2 − c3) / (m_l·s² + (B_l + B_p + Zx1 + Zx3)·s + k_l),
//   v3 = (A1·c1 − A2·c2 − c3 − k_l·x3) / (m_l·s + B_l + B_p + Zx1 + Zx3),
// with Zx1 = A1²·Zc1 + A2²·Zc2, bilinear as the mass's, x3 held within
// [0, s_l] (v3 = 0 there); q1 = −A1·v3, q2 = A2·v3. Where a chamber's
// pressure would fall below zero it is taken at 0 Pa and the step solved
// again; as in Hopsan, chamber 2's cavitation sets chamber 1's flag (so a
// later one in chamber 1 is not solved again in that step).
//
#pragma once

#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/bilinear.hpp"

namespace tlm {

class CylinderC : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::C; }
  const char* type_name() const override { return "CylinderC"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void configure(ParameterSet& prm) override {
    A1_ = prm.positive("A_1", 1e-3, "m²");  // piston area of chamber 1
    A2_ = prm.positive("A_2", 1e-3, "m²");  // of chamber 2
    sl_ = prm.positive("s_l", 1.0, "m");  // stroke
    V01_ = prm.positive("V_1", 3e-4, "m³");  // dead volumes
    V02_ = prm.positive("V_2", 3e-4, "m³");
    Bp_ = prm.real("B_p", 1000.0, "N·s/m");  // viscous friction
    beta_ = prm.positive("Beta_e", 1e9, "Pa");
    c_leak_ = prm.real("c_leak", 1e-11, "m³/(s·Pa)");  // internal leakage
    stops_ = prm.real("use_sl", 1.0, "0/1") != 0.0;
    p1_0_ = prm.real("p1_0", 1e5, "Pa");  // start pressures of the chambers
    p2_0_ = prm.real("p2_0", 1e5, "Pa");
    add_port("P1", Kind::C);
    add_port("P2", Kind::C);
    add_port("P3", Kind::C, true);
    add_signal_output("q_leak", &q_leak_);
  }
  void initialize(double dt) override {
    dt_ = dt;
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    HydraulicNode& n3 = *ports_[2].node;
    const double x3 = n3.x, v3 = n3.q;
    // The chambers' smallest volume with 1 kg of load, as Hopsan's start.
    const double V1 = std::max(V01_ - A1_ * x3, beta_ * dt * dt * A1_ * A1_ / kWfak);
    const double V2 = std::max(V02_ + A2_ * (sl_ + x3), beta_ * dt * dt * A2_ * A2_ / kWfak);
    const double Zc1 = 1.5 * beta_ / V1 * dt / (1.0 - kAlpha), Zc2 = 1.5 * beta_ / V2 * dt / (1.0 - kAlpha);
    ci1_ = p1_0_ + Zc1 * v3 * A1_;
    ci2_ = p2_0_ - Zc2 * v3 * A2_;
    const double leak = c_leak_ * (p1_0_ - p2_0_);
    cl1_ = p1_0_ - Zc1 * leak;
    cl2_ = p2_0_ + Zc2 * leak;
    cx_lim_ = 0.0;
    n1.p = n1.c = p1_0_, n1.q = 0.0, n1.Zc = Zc1;
    n2.p = n2.c = p2_0_, n2.q = 0.0, n2.Zc = Zc2;
    n3.c = A1_ * ci1_ - A2_ * ci2_;
    n3.Zc = A1_ * A1_ * Zc1 + A2_ * A2_ * Zc2 + Bp_;
  }
  void simulate_one_step(double t) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    HydraulicNode& n3 = *ports_[2].node;
    const double x3 = n3.x, v3 = n3.q;
    const double me = n3.me;  // 1 kg (the node's start) until the load writes its own
    if (!(me > 0.0))
      throw std::runtime_error(name_ + ": the load on P3 gives an equivalent mass of " + std::to_string(me) +
                               " kg at t = " + std::to_string(t) + " s; it must be positive");
    q_leak_ = c_leak_ * (cl1_ - cl2_) / (1.0 + c_leak_ * (n1.Zc + n2.Zc));
    const double qi1 = v3 * A1_, qi2 = -v3 * A2_;
    const double V1 = std::max(V01_ - A1_ * x3, beta_ * dt_ * dt_ * A1_ * A1_ / (kWfak * me));
    const double V2 = std::max(V02_ + A2_ * (sl_ + x3), beta_ * dt_ * dt_ * A2_ * A2_ / (kWfak * me));
    // Each chamber: three ports (the hydraulic one, the piston, the leakage).
    auto chamber = [&](HydraulicNode& n, double V, double& ci, double qi, double& cl, double ql) {
      const double Zc = 1.5 * beta_ / V * dt_ / (1.0 - kAlpha);
      const double mean = ((ci + 2.0 * Zc * qi) + (cl + 2.0 * Zc * ql) + (n.c + 2.0 * Zc * n.q)) / 3.0;
      ci = kAlpha * ci + (1.0 - kAlpha) * (2.0 * mean - ci - 2.0 * Zc * qi);
      cl = kAlpha * cl + (1.0 - kAlpha) * (2.0 * mean - cl - 2.0 * Zc * ql);
      const bool cavitating = n.p == 0.0;
      n.c = kAlpha * n.c + (1.0 - kAlpha) * (2.0 * mean - n.c - 2.0 * Zc * n.q);
      n.Zc = Zc;
      return cavitating;
    };
    const bool cav1 = chamber(n1, V1, ci1_, qi1, cl1_, -q_leak_);
    const bool cav2 = chamber(n2, V2, ci2_, qi2, cl2_, q_leak_);
    double zx_lim = 0.0;
    if (stops_) {
      double new_cx = 0.0;
      if (-x3 > sl_ || -x3 < 0.0) {
        const double z0 = kWfak * me / dt_;
        zx_lim = z0 / (1.0 - kStopAlpha);
        new_cx = z0 * (-x3 > sl_ ? x3 + sl_ : x3) / dt_ + zx_lim * v3;
        cx_lim_ = kStopAlpha * cx_lim_ + (1.0 - kStopAlpha) * new_cx;
      } else {
        cx_lim_ = 0.0;
      }
    }
    const double c1 = cav1 ? std::max(ci1_, 0.0) : ci1_, Zc1 = cav1 ? 0.0 : n1.Zc;
    const double c2 = cav2 ? std::max(ci2_, 0.0) : ci2_, Zc2 = cav2 ? 0.0 : n2.Zc;
    n3.c = A1_ * c1 - A2_ * c2 + cx_lim_;
    n3.Zc = A1_ * A1_ * Zc1 + A2_ * A2_ * Zc2 + Bp_ + zx_lim;
  }
  void state(config::StateIO& io) override {
    for (double* v : {&ci1_, &ci2_, &cl1_, &cl2_, &cx_lim_, &q_leak_}) io.value("cylinder", *v);
  }

 private:
  static constexpr double kAlpha = 0.1;      // the chambers' wave damping
  static constexpr double kWfak = 0.1;       // the smallest chamber and the stops' stiffness
  static constexpr double kStopAlpha = 0.5;  // the stops' filter
  double A1_ = 0, A2_ = 0, sl_ = 0, V01_ = 0, V02_ = 0, Bp_ = 0, beta_ = 0, c_leak_ = 0, p1_0_ = 0, p2_0_ = 0;
  bool stops_ = true;
  double dt_ = 0, ci1_ = 0, ci2_ = 0, cl1_ = 0, cl2_ = 0, cx_lim_ = 0, q_leak_ = 0;
};

}  // namespace tlm
