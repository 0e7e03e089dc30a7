// Valve33Q: one of the directional valves; DirectionalValveQ.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>

#include "component.hpp"
#include "components/hydraulic/DirectionalValveQ.hpp"

namespace tlm {

class Valve33Q : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "Valve33Q"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    for (const char* port : {"PP", "PT", "PA"}) add_port(port, Kind::Q);
    enum { P, T, A };
    edges_ = {{P, A, prm.real("f_pa", 1.0, "1"), prm.real("x_pa", -1e-6, "m"), 1},
              {A, T, prm.real("f_at", 1.0, "1"), prm.real("x_at", -1e-6, "m"), -1}};
    xv_lo_ = -xv_max_, xv_hi_ = xv_max_;
    cavitation_side_only_ = true;
    add_signal_input("in", &in_);
  }

 private:
  double command() const override { return std::clamp(*in_, -xv_max_, xv_max_); }
  double initial_spool() const override { return std::clamp(xv_, -xv_max_, xv_max_); }
};

}  // namespace tlm
