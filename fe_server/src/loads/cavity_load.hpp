// The co-simulation user load: each hydraulic port's pressure acts on its
// segment sets (*USER_LOADING_SET, one or more per port: a cavity may wet a
// piston's face and the housing's opposite face, action and reaction); each
// port reports the volume rate its surfaces displace, from the same area
// vectors the load used, so the hydraulic power p·q equals the power the
// pressure does on the structure.
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
//
// TLM ports are implicit. A port's surface has nodal weights w_n = Σ A_s/n_c
// over its segments (force −p·w_n, flow q = Σ w_n·v_n: the same weights, so
// p·q is the power). The port's pressure at t_n takes the flow of the
// velocity at t_n, v_n = ½(v_{n-1/2} + v_{n+1/2}), as a Q-type component
// takes the flow of its own step. With v_{n+1/2} = v̂ − h·M⁻¹·Σ_k p_k·w_k
// (v̂: the solver's prediction without these forces; M⁻¹ the lumped
// mobility, a rigid body's for its nodes) the port pressures solve the small
// system
//   (I + ½h·Z·S)·p = c + Z·q̂,   S_jk = w_j·M⁻¹·w_k,   q̂_j = w_j·½(v_{n-1/2} + v̂),
// one equation per TLM port (ports on one body couple through S_jk). For a
// single port that is the rank-one (Sherman–Morrison) update
// p = (c + Zc·q̂)/(1 + ½h·Zc·S). The port reports that same q_n to the host,
// so the host's p = c + Zc·q is the pressure that acted.
//
// Why this form (measured by bench/stability_map.py, explained by the
// linear loop model bench/coupling_loop_model.py): with q from v_{n-1/2} (an
// explicit damper Zc·A², the first implementation) TLM coupling was bounded
// like pressure coupling; with q from v_{n+1/2} alone the loop is stable for
// every coupling step but shrinks the FE side's own stable step to
// ω·Δt < √2; with v_n it is stable for every coupling step and chamber size
// up to the FE's own limit ω·Δt < 2. The coupling step then sets accuracy
// only.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "config/port_table.hpp"
#include "loads/user_load.hpp"

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
  bool loaded_nodes(std::vector<int>& nodes) const override {
    for (const PortSurface& ps : surfaces_) {
      nodes.insert(nodes.end(), ps.nodes.begin(), ps.nodes.end());
      for (const LoadingSet& l : ps.sets)
        if (l.reference_node >= 0) nodes.push_back(l.reference_node);
    }
    return true;
  }
  // The TLM ports' pressures and forces at the velocity of t_n (see above).
  void apply_implicit(const Mobility& mob, const std::vector<Vec3>& v_old, const std::vector<Vec3>& v_pred,
                      std::vector<NodalForce>& out) override;
  // The flow of the last step as the host should see it: for a TLM port the
  // q_n its pressure was solved with, else the flow of velocities v.
  double step_flow(int slot, const std::vector<Vec3>& v) const {
    return tlm_[static_cast<size_t>(slot)] ? tlm_flow_[static_cast<size_t>(slot)] : flow(slot, v);
  }

  // Volume rate displaced into the cavity by the port's surface, m³/s.
  double flow(int slot, const std::vector<Vec3>& v) const;
  // Mean displacement of the port's first surface along its normal, m.
  double displacement(int slot, const std::vector<Vec3>& x) const;
  // Wetted area the last apply() used, m².
  double area(int slot) const { return area_vector_[static_cast<size_t>(slot)].norm(); }
  // The host's last inputs and what the last apply() computed (the flows
  // and areas the outputs read).
  void state(config::StateIO& io) override;

 private:
  struct PortSurface {
    int port_id = 0;
    std::vector<Segment> segments;
    std::vector<int> nodes;  // unique nodes of the set
    std::vector<Vec3> segment_area;  // area vectors of the last apply()
    // Segments on a rigid body that cannot rotate keep their shape, area
    // vector and corner weights: those are computed once (area0) and only
    // the wetted fraction is evaluated per step.
    std::vector<char> fixed_shape;
    std::vector<Vec3> area0;
    // The port's loading sets (deck order) and, per segment, its set: each
    // set has its own cavity bounds. The first set is the port's own
    // surface: its nodes and its normal at t = 0 give the port's displacement.
    std::vector<LoadingSet> sets;
    std::vector<int> segment_set;
    std::vector<double> shift;  // per set: its bounds' shift in the last apply()
    std::vector<int> first_nodes;
    Vec3 normal0 = Vec3::UnitZ();
    // For the implicit TLM solve: per segment corner, the index into `nodes`;
    // per node its weight w_n; per mobility group (a body, or a free node)
    // the summed weight; per node the index of its group in `groups`.
    std::vector<int> corner_node;  // 4 per segment
    std::vector<double> corner_weight;  // 4 per segment: segment_corner_weights of the last apply()
    std::vector<Vec3> node_weight;  // w_n = Σ over its corners of weight·area vector, of the last apply()
    // Segments whose area vector never changes (fixed shape and no cavity
    // bounds: every step wets them whole) are summed once: their share of
    // the area and of each node's weight. apply() visits only the others.
    std::vector<int> varying;  // segment indices
    Vec3 constant_area = Vec3::Zero();
    std::vector<Vec3> constant_weight;
    std::vector<int> groups, node_group;
    std::vector<Vec3> group_weight;
  };
  // Builds the groups of every surface and the pairs of TLM surfaces that
  // share a group, on the first implicit step (the grouping never changes).
  void build_groups(const Mobility& mob);
  const Model& model_;
  std::vector<PortSurface> surfaces_;
  std::vector<double> pressure_, wave_, impedance_, tlm_flow_;
  std::vector<char> tlm_;
  std::vector<Vec3> area_vector_;
  bool groups_built_ = false;
  struct SharedGroup {
    size_t a, b;    // surfaces
    size_t ga, gb;  // group slots in each
  };
  std::vector<SharedGroup> shared_;
  std::vector<size_t> tlm_slots_;  // scratch: the TLM surfaces of this step
  Eigen::MatrixXd mobility_, system_;  // S and I + ½h·Z·S, one row per TLM port
  Eigen::VectorXd rhs_, solution_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

// Share of segment s inside the cavity bounds [lo, hi] along the axis
// (coordinate `axis`: 2 for z, 1 for y), 0..1.
double wetted_fraction(const Segment& s, const std::vector<Vec3>& x, double lo, double hi, double ramp, int axis = 2);

}  // namespace fe
