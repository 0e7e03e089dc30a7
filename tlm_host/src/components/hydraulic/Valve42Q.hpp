// Valve42Q: one of the directional valves; DirectionalValveQ.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>

#include "component.hpp"
#include "components/hydraulic/DirectionalValveQ.hpp"

namespace tlm {

class Valve42Q : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "Valve42Q"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    for (const char* port : {"PP", "PT", "PA", "PB"}) add_port(port, Kind::Q);
    const double f_pa = prm.real("f_pa", 1.0, "1"), f_pb = prm.real("f_pb", 1.0, "1");
    const double f_at = prm.real("f_at", 1.0, "1"), f_bt = prm.real("f_bt", 1.0, "1");
    edges_ = {{0, 2, f_pa, 0.0, 1}, {0, 3, f_pb, 0.0, 0}, {2, 1, f_at, 0.0, 0}, {3, 1, f_bt, 0.0, 1}};
    xv_lo_ = 0.0, xv_hi_ = xv_max_;
    add_signal_input("in", &in_);
  }

 private:
  double command() const override { return *in_ > 0.5 ? xv_max_ : 0.0; }
  // Hopsan's 4/2 valve starts its spool at its command input's first value, held within its travel.
  double initial_spool() const override { return std::clamp(*in_, 0.0, xv_max_); }
};

}  // namespace tlm
