// CylinderQ: one of the cylinders; CylinderC.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <cmath>

#include "component.hpp"
#include "components/bilinear.hpp"

namespace tlm {

class CylinderQ : public Component {
 public:
  using Component::Component;
  Kind kind() const override { return Kind::Q; }
  const char* type_name() const override { return "CylinderQ"; }
  // Moves oil by force or displacement: a node's pressure has no bound from the sources.
  double source_pressure() const override { return 1e300; }
  void configure(ParameterSet& prm) override {
    A1_ = prm.positive("A_1", 1e-4, "m²");
    A2_ = prm.positive("A_2", 1e-4, "m²");
    Bp_ = prm.real("B_p", 0.0, "N·s/m");  // the piston's friction
    Bl_ = prm.real("B_l", 0.0, "N·s/m");  // the load's
    kl_ = prm.real("k_l", 100.0, "N/m");  // the load's stiffness
    m_ = prm.positive("m_l", 0.05, "kg");  // the load's inertia
    sl_ = prm.positive("s_l", 0.01, "m");  // stroke
    add_port("P1", Kind::Q);
    add_port("P2", Kind::Q);
    add_port("P3", Kind::Q, true);
  }
  void initialize(double dt) override {
    HydraulicNode& n3 = *ports_[2].node;
    const double num_x[3] = {1.0, 0.0, 0.0}, den_x[3] = {kl_, Bl_ + Bp_, m_};
    x_filter_.limits(0.0, sl_);
    x_filter_.set(dt, num_x, den_x);
    x_filter_.reset(0.0, n3.x);
    v_filter_.set(dt, 1.0, 0.0, Bl_ + Bp_, m_);
    v_filter_.reset(0.0, n3.q);
  }
  void simulate_one_step(double) override {
    HydraulicNode& n1 = *ports_[0].node;
    HydraulicNode& n2 = *ports_[1].node;
    HydraulicNode& n3 = *ports_[2].node;
    double c1 = n1.c, Z1 = n1.Zc, c2 = n2.c, Z2 = n2.Zc;
    const double c3 = n3.c, Z3 = n3.Zc;
    double p1 = 0, q1 = 0, p2 = 0, q2 = 0, x3 = 0, v3 = 0;
    bool cav1 = false, cav2 = false;
    for (bool again = true; again;) {
      again = false;
      const BilinearSecondOrder x_before = x_filter_;
      const BilinearFirstOrder v_before = v_filter_;
      const double cx1 = A1_ * c1 - A2_ * c2, Zx1 = A1_ * A1_ * Z1 + A2_ * A2_ * Z2;
      const double damping = Bl_ + Bp_ + Zx1 + Z3;
      const double den_x[3] = {kl_, damping, m_};
      x_filter_.set_den(den_x);
      x3 = x_filter_.update(cx1 - c3);
      if (x_filter_.saturated()) {
        v_filter_.reset(0.0, 0.0);
        v3 = 0.0;
      } else {
        v_filter_.set_den(damping, m_);
        v3 = v_filter_.update(cx1 - c3 - kl_ * x3);
      }
      q1 = A1_ * -v3;
      q2 = A2_ * v3;
      p1 = c1 + Z1 * q1;
      p2 = c2 + Z2 * q2;
      if (p1 < 0.0) {
        p1 = 0.0, c1 = 0.0, Z1 = 0.0;
        if (!cav1) cav1 = again = true;
      }
      if (p2 < 0.0) {
        p2 = 0.0, c2 = 0.0, Z2 = 0.0;
        if (!cav2) cav1 = again = true;  // Hopsan's flag (see above)
      }
      if (again) x_filter_ = x_before, v_filter_ = v_before;
    }
    n1.p = p1, n1.q = q1;
    n2.p = p2, n2.q = q2;
    n3.p = c3 + Z3 * v3, n3.x = x3, n3.q = v3;
  }
  void state(config::StateIO& io) override {
    x_filter_.state(io);
    v_filter_.state(io);
  }

 private:
  double A1_ = 0, A2_ = 0, Bp_ = 0, Bl_ = 0, kl_ = 0, m_ = 0, sl_ = 0;
  BilinearSecondOrder x_filter_;
  BilinearFirstOrder v_filter_;
};

}  // namespace tlm
