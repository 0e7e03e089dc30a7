// Translational mechanics on mechanical TLM nodes (node.hpp: F = c + Zc·v),
// with the equations of Hopsan's default library so that Hopsan models of
// loads run here as in Hopsan (hopsan_loader.cpp maps them):
//
// TranslationalMassQ (Hopsan's MechanicTranslationalMass), a Q component
// between ports P1 and P2: m·ẍ2 = F1 − F2 − B·v2 − k·x2, solved against the
// nodes' characteristics F_i = c_i + Zc_i·v_i with v1 = −v2, i.e.
//   x2 = (c1 − c2) / (m·s² + (B + Zc1 + Zc2)·s + k),
//   v2 = (c1 − c2 − k·x2) / (m·s + B + Zc1 + Zc2),
// each discretized bilinearly (bilinear.hpp) with its denominator updated to
// the impedances of the step. At a stop (x2 below x_min or above x_max) x2
// is held there, v2 = 0 and both filters restart from it. x1 = L − x2 with
// L = x1 + x2 at the start.
//
// ForceSourceC (Hopsan's MechanicForceTransformer): a C component giving
// its port the force F (a signal, or the parameter F): c = F, Zc = 0.
#pragma once

#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/bilinear.hpp"

namespace tlm {

class TranslationalMassQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "TranslationalMassQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void configure(ParameterSet& prm) override {
    m_ = prm.positive("m", 100.0, "kg");
    B_ = prm.real("B", 10.0, "N·s/m");  // viscous friction
    k_ = prm.real("k", 0.0, "N/m");  // spring to x2 = 0
    x_min_ = prm.real("x_min", -1.0e300, "m");  // stops of P2's position
    x_max_ = prm.real("x_max", 1.0e300, "m");
    x1_0_ = prm.real("x1_0", 0.0, "m");  // start positions of the ports
    x2_0_ = prm.real("x2_0", 0.0, "m");
    add_port("P1", Kind::Q, true);
    add_port("P2", Kind::Q, true);
  }
  void initialize(double dt) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    n1.x = x1_0_, n2.x = x2_0_;
    n1.q = n2.q = 0.0;  // at rest
    length_ = x1_0_ + x2_0_;
    const double num_x[3] = {1.0, 0.0, 0.0}, den_x[3] = {k_, B_, m_};
    x_filter_.set(dt, num_x, den_x);
    x_filter_.reset(n1.p - n2.p, x2_0_);
    v_filter_.set(dt, 1.0, 0.0, B_, m_);
    v_filter_.reset(n1.p - n2.p - k_ * x2_0_, 0.0);
    n1.me = n2.me = m_;
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    const double drive = n1.c - n2.c, damping = B_ + n1.Zc + n2.Zc;
    const double den_x[3] = {k_, damping, m_};
    x_filter_.set_den(den_x);
    v_filter_.set_den(damping, m_);
    double x2 = x_filter_.update(drive);
    double v2 = v_filter_.update(drive - k_ * x2);
    if (x2 < x_min_ || x2 > x_max_) {
      x2 = x2 < x_min_ ? x_min_ : x_max_;
      v2 = 0.0;
      x_filter_.reset(drive, x2);
      v_filter_.reset(drive, 0.0);
    }
    n2.x = x2, n2.q = v2;
    n1.x = length_ - x2, n1.q = -v2;
    n1.p = n1.c + n1.Zc * n1.q;
    n2.p = n2.c + n2.Zc * n2.q;
    n1.me = n2.me = m_;
  }
  void state(config::StateIO& io) override {
    x_filter_.state(io);
    v_filter_.state(io);
  }

 private:
  double m_ = 0, B_ = 0, k_ = 0, x_min_ = 0, x_max_ = 0, x1_0_ = 0, x2_0_ = 0, length_ = 0;
  BilinearSecondOrder x_filter_;
  BilinearFirstOrder v_filter_;
};

}  // namespace tlm
