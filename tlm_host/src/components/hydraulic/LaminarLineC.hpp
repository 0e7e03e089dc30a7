// LaminarLineC: one of the lines; LosslessLineC.hpp's opening comment gives their equations and sources.
#pragma once

#include <cmath>
#include <iostream>
#include <vector>

#include "component.hpp"
#include "components/hydraulic/LosslessLineC.hpp"

namespace tlm {

class LaminarLineC : public LosslessLineC {
 public:
  using LosslessLineC::LosslessLineC;
  const char* type_name() const override { return "LaminarLineC"; }
  void configure(ParameterSet& prm) override {
    configure_line(prm);
    const double nu = prm.positive("nu", 32e-6, "m²/s");  // kinematic viscosity
    const double rho = prm.real("rho", 870.0, "kg/m³"), L = prm.real("L", 1.0, "m"), d = prm.real("d", 0.01, "m");
    R_half_ = 0.5 * 128.0 * nu * rho * L / (M_PI * d * d * d * d);
  }
};

}  // namespace tlm
