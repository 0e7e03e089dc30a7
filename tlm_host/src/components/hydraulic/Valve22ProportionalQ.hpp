// Valve22ProportionalQ: one of the directional valves; DirectionalValveQ.hpp's opening comment gives their equations and sources.
#pragma once

#include <algorithm>

#include "component.hpp"
#include "components/hydraulic/DirectionalValveQ.hpp"

namespace tlm {

class Valve22ProportionalQ : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "Valve22ProportionalQ"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    for (const char* port : {"PP", "PA"}) add_port(port, Kind::Q);
    edges_ = {{0, 1, prm.real("f", 1.0, "1"), 0.0, 1}};
    xv_lo_ = 0.0, xv_hi_ = xv_max_;
    add_signal_input("in", &in_);
  }

 private:
  double command() const override { return std::clamp(*in_, 0.0, xv_max_); }
  double initial_spool() const override { return std::clamp(xv_, 0.0, xv_max_); }
};

}  // namespace tlm
