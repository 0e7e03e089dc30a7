// SpoolMechanics: the control spool's friction and end stops, shared by
// ControlSpoolQ (whose opening comment describes the spool) and SpoolMechanicsSignal.
#pragma once

#include <cmath>

#include "components/rigid_body.hpp"

namespace tlm {

// A spool's forces apart from its pilot faces and viscous friction b·v:
// smoothed Coulomb friction and the two end stops. Shared by ControlSpoolQ
// and SpoolMechanicsSignal (spool in fe_server), so both model the same law.
struct SpoolMechanics {
  double m = 0, F_c = 0, v_s = 0, b = 0, stroke = 0, k_stop = 0, c_stop = 0;
  void configure(ParameterSet& prm) {
    m = prm.positive("m", 0.2, "kg");
    stroke = prm.positive("stroke", 8e-3, "m");
    F_c = prm.real("F_c", 10.0, "N");
    v_s = prm.positive("v_s", 0.01, "m/s");
    b = prm.real("b", 15.0, "N·s/m");
    k_stop = prm.positive("k_stop", 5e7, "N/m");
    c_stop = prm.real("c_stop", 5e3, "N·s/m");
  }
  double force(double x, double v) const {
    double F = -F_c * std::tanh(v / v_s);
    F += stop_force(-x, -v, k_stop, c_stop);          // stop at x = 0 pushes +x
    F -= stop_force(x - stroke, v, k_stop, c_stop);   // stop at the stroke pushes −x
    return F;
  }
  double stable_step() const { return spring_damper_stable_step(k_stop, c_stop, m); }
};

}  // namespace tlm
