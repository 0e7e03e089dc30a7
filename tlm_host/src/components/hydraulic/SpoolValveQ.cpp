#include "components/hydraulic/SpoolValveQ.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"

namespace tlm {

void SpoolValveQ::configure(ParameterSet& prm) {
  Cd_ = prm.positive("Cd", 0.7, "1");
  rho_ = prm.positive("rho", 870.0, "kg/m³");
  area_PA_ = Table(prm.text("area_PA", ""), prm.where(), name_ + ": area_PA");
  area_AT_ = Table(prm.text("area_AT", ""), prm.where(), name_ + ": area_AT");
  add_port("P", Kind::Q);
  add_port("A", Kind::Q);
  add_port("T", Kind::Q);
  add_signal_input("x", &x_);
}

double SpoolValveQ::residual(double pA) const {
  const HydraulicNode& P = *ports_[0].node;
  const HydraulicNode& A = *ports_[1].node;
  const HydraulicNode& T = *ports_[2].node;
  const double qPA = turbulent_orifice_flow(P.c, pA, P.Zc, 0.0, K_PA_);
  const double qAT = turbulent_orifice_flow(pA, T.c, 0.0, T.Zc, K_AT_);
  return A.c + A.Zc * (qPA - qAT) - pA;
}

static double residual_callback(double pA, void* self) { return static_cast<SpoolValveQ*>(self)->residual(pA); }

void SpoolValveQ::simulate_one_step(double) {
  HydraulicNode& P = *ports_[0].node;
  HydraulicNode& A = *ports_[1].node;
  HydraulicNode& T = *ports_[2].node;
  const double k = Cd_ * std::sqrt(2.0 / rho_);
  K_PA_ = k * area_PA_(*x_);
  K_AT_ = k * area_AT_(*x_);
  double pA = A.c;
  if (A.Zc > 0.0 && (K_PA_ > 0.0 || K_AT_ > 0.0)) {
    double lo = std::min({P.c, A.c, T.c}), hi = std::max({P.c, A.c, T.c});
    if (residual(lo) <= 0.0) {
      pA = lo;
    } else if (residual(hi) >= 0.0) {
      pA = hi;
    } else {
      // Brent: bracketing, superlinear, never leaves [lo, hi].
      // GSL's error handler is off (component.cpp): every status is ours to
      // check. A residual that is not finite at the bracket (an area or a
      // coefficient so large that K·sqrt(Δp) overflows) is such a status.
      gsl_function f{&residual_callback, this};
      gsl_root_fsolver* s = solver_.get();
      auto fail = [&](int code, const char* during) {
        char numbers[200];
        std::snprintf(numbers, sizeof numbers, "bracket %.6g to %.6g Pa, K_PA %.6g, K_AT %.6g m^3/(s Pa^0.5)", lo, hi,
                      K_PA_, K_AT_);
        // The step loop names the component, the step and the time.
        throw std::runtime_error(std::string("the root finder for p_A failed ") + during + ": " + gsl_strerror(code) +
                                 " (" + numbers + "); check Cd, the area tables and the connected volumes");
      };
      int status = gsl_root_fsolver_set(s, &f, lo, hi);
      if (status != GSL_SUCCESS) fail(status, "at its start");
      const double tol = 1e-9 * std::max(1.0, hi);  // Pa: far below any physical resolution
      status = GSL_CONTINUE;
      for (int it = 0; it < 100 && status == GSL_CONTINUE; ++it) {
        const int step = gsl_root_fsolver_iterate(s);
        if (step != GSL_SUCCESS) fail(step, "in an iteration");
        ++iterations_;
        status = gsl_root_test_interval(gsl_root_fsolver_x_lower(s), gsl_root_fsolver_x_upper(s), tol, 0.0);
      }
      pA = gsl_root_fsolver_root(s);
    }
  }
  q_PA_ = turbulent_orifice_flow(P.c, pA, P.Zc, 0.0, K_PA_);
  q_AT_ = turbulent_orifice_flow(pA, T.c, 0.0, T.Zc, K_AT_);
  P.q = -q_PA_;
  P.p = P.c + P.Zc * P.q;
  T.q = q_AT_;
  T.p = T.c + T.Zc * T.q;
  A.q = q_PA_ - q_AT_;
  A.p = A.c + A.Zc * A.q;
}

void SpoolValveQ::log_variables(std::vector<LogVariable>& out) {
  out.push_back({"q_PA", "m3/s", &q_PA_});
  out.push_back({"q_AT", "m3/s", &q_AT_});
}

}  // namespace tlm
