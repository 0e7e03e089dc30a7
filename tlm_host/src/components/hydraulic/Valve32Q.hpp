// Valve32Q: one of the directional valves; DirectionalValveQ.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/bilinear.hpp"
#include "component.hpp"
#include "components/hydraulic/DirectionalValveQ.hpp"

namespace tlm {

class Valve32Q : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "Valve32Q"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    for (const char* port : {"PP", "PT", "PA"}) add_port(port, Kind::Q);
    const double f = prm.real("f", 1.0, "1");
    edges_ = {{0, 2, f, 0.0, 1}, {2, 1, f, 0.0, 0}};
    xv_lo_ = 0.0, xv_hi_ = xv_max_;
    add_signal_input("in", &in_);
  }

 private:
  double command() const override { return *in_ > 0.5 ? xv_max_ : 0.0; }
};

}  // namespace tlm
