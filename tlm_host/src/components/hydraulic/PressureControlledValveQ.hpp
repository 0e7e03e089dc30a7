// PressureControlledValveQ: a valve whose spool the pressure at a pilot
// port PC moves, with the equations of Hopsan's pressure-controlled 2/2 and
// 4/2 valves (HydraulicPressureControlled22Valve, …22Valve2, …42Valve,
// …42Valve2, …42Valve3; mapped from Hopsan models, hopsan_loader.cpp).
//
// The spool's command is the pilot's wave variable c_C between two
// pressures, x_in = clamp((c_C − Fs_min)/(Fs_max − Fs_min), 0, 1)·x_vmax,
// and the spool follows it through DirectionalValveQ's second-order lag,
// held within [0, x_vmax] and started at 0 (Hopsan's filter starts there
// whatever the spool's start value). Each metering edge is a turbulent
// orifice of area f·π·d·opening, solved as in DirectionalValveQ.hpp, the
// cavitation check on the metered ports only. The pilot draws no flow:
// q_C = 0, p_C = c_C.
//
// Edges (ports PP, PA and, with four ports, PT, PB; PC last):
//   2/2:                 P→A, opening x_v (normally closed) or x_vmax − x_v (normally open)
//   4/2:                 P→A and B→T, each as the 2/2's
//   4/2 switching (…3):  P→A and B→T open with x_vmax − x_v, P→B and A→T with x_v
#pragma once

#include <algorithm>

#include "components/hydraulic/DirectionalValveQ.hpp"

namespace tlm {

class PressureControlledValveQ : public DirectionalValveQ {
 public:
  using DirectionalValveQ::DirectionalValveQ;
  const char* type_name() const override { return "PressureControlledValveQ"; }
  void configure(ParameterSet& prm) override {
    configure_common(prm);
    const int ports = prm.integer("ports", 2, 2, 4);  // the metered ports: 2 (P, A) or 4 (P, T, A, B)
    if (ports == 3) throw config::InputError(prm.where(), name_ + ": ports = 3: a pressure-controlled valve meters 2 ports (P, A) or 4 (P, T, A, B)");
    const bool open = prm.real("normally_open", 0.0, "0/1") != 0.0;
    const bool switching = prm.real("switching", 0.0, "0/1") != 0.0;
    p_min_ = prm.real("Fs_min", 1e5, "Pa");
    p_max_ = prm.real("Fs_max", 1e6, "Pa");
    if (!(p_max_ > p_min_))
      throw config::InputError(prm.where(), name_ + ": Fs_max must exceed Fs_min (the pilot pressures that open the spool)");
    const double f_pa = prm.real("f_pa", 1.0, "1"), f_bt = ports == 4 ? prm.real("f_bt", 1.0, "1") : 0.0;
    const int closed = open ? 0 : 1;  // DirectionalValveQ's edge sign: 1 opens with x_v, 0 with x_vmax − x_v
    if (ports == 2) {
      for (const char* port : {"PP", "PA"}) add_port(port, Kind::Q);
      edges_ = {{0, 1, f_pa, 0.0, closed}};
    } else {
      for (const char* port : {"PP", "PT", "PA", "PB"}) add_port(port, Kind::Q);
      if (switching) {
        const double f_pb = prm.real("f_pb", 1.0, "1"), f_at = prm.real("f_at", 1.0, "1");
        edges_ = {{0, 2, f_pa, 0.0, 0}, {0, 3, f_pb, 0.0, 1}, {2, 1, f_at, 0.0, 1}, {3, 1, f_bt, 0.0, 0}};
      } else {
        edges_ = {{0, 2, f_pa, 0.0, closed}, {3, 1, f_bt, 0.0, closed}};
      }
    }
    metered_ports_ = static_cast<size_t>(ports);
    add_port("PC", Kind::Q);
    xv_lo_ = 0.0, xv_hi_ = xv_max_, xv_ = 0.0;
  }

 private:
  double command() const override {
    const double c = ports_.back().node->c;
    return std::min(1.0, std::max(0.0, (c - p_min_) / (p_max_ - p_min_))) * xv_max_;
  }
  double p_min_ = 0, p_max_ = 0;
};

}  // namespace tlm
