// Valve43Q: one of the directional valves; DirectionalValveQ.hpp's opening comment gives their equations and sources.
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

class Valve43Q : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "Valve43Q"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    for (const char* port : {"PP", "PT", "PA", "PB"}) add_port(port, Kind::Q);
    enum { P, T, A, B };
    edges_ = {{P, A, prm.real("f_pa", 1.0, "1"), prm.real("x_pa", -1e-6, "m"), 1},
              {P, B, prm.real("f_pb", 1.0, "1"), prm.real("x_pb", -1e-6, "m"), -1},
              {A, T, prm.real("f_at", 1.0, "1"), prm.real("x_at", -1e-6, "m"), -1},
              {B, T, prm.real("f_bt", 1.0, "1"), prm.real("x_bt", -1e-6, "m"), 1}};
    xv_lo_ = -xv_max_, xv_hi_ = xv_max_;
    add_signal_input("in", &in_);
  }

 private:
  double command() const override { return std::max(std::min(*in_, xv_max_), -xv_max_); }
};

}  // namespace tlm
