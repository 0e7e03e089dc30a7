// The co-simulation user load: each hydraulic port's pressure acts on its
// segment set (*USER_LOADING_SET); each port reports the volume rate its
// surface displaces, from the same area vectors the load used, so the
// hydraulic power p·q equals the power the pressure does on the structure.
//
// Sign convention (LS-DYNA's): a segment's normal follows its node order by
// the right-hand rule and points out of the body into the cavity; a positive
// pressure pushes against the normal. The flow q = Σ A·n·v is positive when
// the surface moves into the cavity, i.e. it pushes oil out of the cavity into
// the hydraulic node: the host's convention for flow leaving a Q component.
//
// Cavity bounds: a port may confine its pressure to z_min ≤ z ≤ z_max
// (moving with a reference node, e.g. on the housing). Each segment is then
// weighted by its wetted fraction: the share of its axial extent inside the
// bounds, or, for a face normal to z, a linear ramp of width `ramp` across
// each bound. Force and flow use the same weighted area vectors, so a
// segment sliding past a cavity edge is loaded and unloaded smoothly (no
// chatter) and p·q still equals the power on the structure.
#pragma once

#include <vector>

#include "config/port_table.hpp"
#include "user_load.hpp"

namespace fe {

class CavityPressureLoad : public UserLoad {
 public:
  // One slot per hydraulic port of the table; every hydraulic port needs a
  // *USER_LOADING_SET in the deck (an InputError names the port otherwise).
  CavityPressureLoad(const Model& model, const config::PortTable& table);

  int slot_of_port(int port_id) const;  // -1 if the port is not hydraulic
  // Pressure coupling: the host's pressure, held over the coupling step.
  void set_pressure(int slot, double p) {
    pressure_[static_cast<size_t>(slot)] = p;
    tlm_[static_cast<size_t>(slot)] = false;
  }
  // TLM coupling: the host's wave variable and impedance; each FE step then
  // applies p = c + Zc·q with the flow q of the surface's current velocity,
  // exactly as a Q-type component solves its port.
  void set_wave(int slot, double c, double Zc) {
    wave_[static_cast<size_t>(slot)] = c;
    impedance_[static_cast<size_t>(slot)] = Zc;
    tlm_[static_cast<size_t>(slot)] = true;
  }
  size_t slot_count() const { return surfaces_.size(); }
  // The pressure the last apply() used.
  double pressure(int slot) const { return pressure_[static_cast<size_t>(slot)]; }

  void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
             std::vector<Vec3>& f_ext) override;

  // Volume rate displaced into the cavity by the port's surface, m³/s.
  double flow(int slot, const std::vector<Vec3>& v) const;
  // Mean displacement of the surface along its normal, m.
  double displacement(int slot, const std::vector<Vec3>& x) const;
  // Wetted area the last apply() used, m².
  double area(int slot) const { return area_vector_[static_cast<size_t>(slot)].norm(); }

 private:
  struct PortSurface {
    int port_id = 0;
    std::vector<Segment> segments;
    std::vector<int> nodes;  // unique nodes of the set
    std::vector<Vec3> segment_area;  // area vectors of the last apply()
    Vec3 normal0 = Vec3::UnitZ();    // unit normal of the whole set at t = 0
    LoadingSet bounds;
  };
  const Model& model_;
  std::vector<PortSurface> surfaces_;
  std::vector<double> pressure_, wave_, impedance_;
  std::vector<char> tlm_;
  std::vector<Vec3> area_vector_;
};

// Area vector of a segment (|A| = area, direction = normal by node order).
Vec3 segment_area_vector(const Segment& s, const std::vector<Vec3>& x);

// Share of segment s inside the cavity bounds [lo, hi] along z (0..1).
double wetted_fraction(const Segment& s, const std::vector<Vec3>& x, double lo, double hi, double ramp);

}  // namespace fe
