#include "loads/cavity_load.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <map>
#include <set>

namespace fe {

static int corners(const Segment& s) { return s.corners(); }

// A loading set with cavity bounds along the axis (ZMIN or ZMAX given).
static bool bounded(const LoadingSet& set) { return set.z_min > -1e299 || set.z_max < 1e299; }

double wetted_fraction(const Segment& s, const std::vector<Vec3>& x, double lo, double hi, double ramp, int axis) {
  double zmin = 1e300, zmax = -1e300, zc = 0.0;
  const int nc = corners(s);
  for (int k = 0; k < nc; ++k) {
    const double z = x[static_cast<size_t>(s.n[k])][axis];
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
    zc += z / nc;
  }
  const double extent = zmax - zmin;
  if (extent > std::max(1e-12, ramp)) {  // a segment along z: the overlapping share of its length
    const double overlap = std::min(zmax, hi) - std::max(zmin, lo);
    return std::clamp(overlap / extent, 0.0, 1.0);
  }
  if (ramp <= 0.0) return (zc >= lo && zc <= hi) ? 1.0 : 0.0;
  // A face normal to z: ramps in over `ramp` centred on each bound.
  const double in_lo = std::clamp((zc - lo) / ramp + 0.5, 0.0, 1.0);
  const double in_hi = std::clamp((hi - zc) / ramp + 0.5, 0.0, 1.0);
  return std::min(in_lo, in_hi);
}

CavityPressureLoad::CavityPressureLoad(const Model& model, const config::PortTable& table)
    : model_(model) {
  // Rigid bodies that only translate (every rotation held, or a 2D
  // axisymmetric model: solver/rigid_body.hpp), and each node's body.
  std::vector<int> body(model.x0.size(), -1);
  std::vector<char> translating;
  for (size_t b = 0; b < model.rigid_bodies.size(); ++b) {
    for (int n : model.rigid_bodies[b].nodes) body[static_cast<size_t>(n)] = static_cast<int>(b);
    translating.push_back(model.symmetry_axis == 1 || model.rigid_bodies[b].fixed_rotation.all());
  }
  for (const auto& port : table.ports) {
    if (port.type != config::PortType::Hydraulic) continue;
    PortSurface ps;
    ps.port_id = port.id;
    // Every *USER_LOADING_SET of the port, in deck order: one cavity may
    // wet faces of several bodies (a piston's collar and the housing's bore
    // step: action and reaction through the same pressure).
    std::set<int> nodes, first_nodes;
    for (const auto& l : model.loading_sets) {
      if (l.port_id != port.id || l.force) continue;
      Vec3 total = Vec3::Zero();
      for (const auto& seg : model.segment_sets.at(l.segment_set)) {
        ps.segments.push_back(seg);
        ps.segment_set.push_back(static_cast<int>(ps.sets.size()));
        for (int k = 0; k < corners(seg); ++k) (ps.sets.empty() ? first_nodes : nodes).insert(seg.n[k]);
        total += segment_area_vector(seg, model.x0);
      }
      if (total.norm() <= 0.0)
        throw config::InputError(l.where, "segment set " + std::to_string(l.segment_set) + " has zero total area");
      if (ps.sets.empty()) ps.normal0 = total.normalized();
      ps.sets.push_back(l);
    }
    if (ps.sets.empty())
      throw config::InputError(port.where, "hydraulic port " + std::to_string(port.id) + " (" + port.label +
                                               ") has no *USER_LOADING_SET in " + model.source);
    ps.first_nodes.assign(first_nodes.begin(), first_nodes.end());
    nodes.insert(first_nodes.begin(), first_nodes.end());
    ps.nodes.assign(nodes.begin(), nodes.end());
    ps.segment_area.assign(ps.segments.size(), Vec3::Zero());
    ps.corner_weight.assign(4 * ps.segments.size(), 0.0);
    for (size_t s = 0; s < ps.segments.size(); ++s)
      segment_corner_weights(ps.segments[s], model.x0, &ps.corner_weight[4 * s]);
    for (const auto& seg : ps.segments)
      for (int k = 0; k < 4; ++k)
        ps.corner_node.push_back(k < seg.corners() ? static_cast<int>(std::lower_bound(ps.nodes.begin(), ps.nodes.end(),
                                                                                        seg.n[k]) -
                                                                       ps.nodes.begin())
                                                   : -1);
    ps.node_weight.assign(ps.nodes.size(), Vec3::Zero());
    ps.constant_weight.assign(ps.nodes.size(), Vec3::Zero());
    for (size_t s = 0; s < ps.segments.size(); ++s) {
      const Segment& seg = ps.segments[s];
      const int b = body[static_cast<size_t>(seg.n[0])];
      bool fixed = b >= 0 && translating[static_cast<size_t>(b)];
      for (int k = 1; k < seg.corners(); ++k) fixed = fixed && body[static_cast<size_t>(seg.n[k])] == b;
      ps.fixed_shape.push_back(fixed);
      ps.area0.push_back(segment_area_vector(seg, model.x0));
      if (!fixed || bounded(ps.sets[static_cast<size_t>(ps.segment_set[s])])) {
        ps.varying.push_back(static_cast<int>(s));
        continue;
      }
      ps.segment_area[s] = ps.area0[s];
      ps.constant_area += ps.area0[s];
      for (int k = 0; k < seg.corners(); ++k)
        ps.constant_weight[static_cast<size_t>(ps.corner_node[4 * s + static_cast<size_t>(k)])] +=
            ps.corner_weight[4 * s + static_cast<size_t>(k)] * ps.area0[s];
    }
    surfaces_.push_back(std::move(ps));
  }
  pressure_.assign(surfaces_.size(), 0.0);
  wave_.assign(surfaces_.size(), 0.0);
  impedance_.assign(surfaces_.size(), 0.0);
  tlm_flow_.assign(surfaces_.size(), 0.0);
  tlm_.assign(surfaces_.size(), 0);
  area_vector_.assign(surfaces_.size(), Vec3::Zero());
  for (const auto& l : model.loading_sets)
    if (!l.force && slot_of_port(l.port_id) < 0)
      throw config::InputError(l.where, "*USER_LOADING_SET names port " + std::to_string(l.port_id) +
                                            ", which is not a hydraulic port of " + table.source);
}

int CavityPressureLoad::slot_of_port(int port_id) const {
  for (size_t i = 0; i < surfaces_.size(); ++i)
    if (surfaces_[i].port_id == port_id) return static_cast<int>(i);
  return -1;
}

void CavityPressureLoad::apply(double, const std::vector<Vec3>& x, const std::vector<Vec3>&,
                               std::vector<Vec3>& f_ext) {
  for (size_t i = 0; i < surfaces_.size(); ++i) {
    PortSurface& ps = surfaces_[i];
    const int axis = model_.symmetry_axis;
    // Each loading set's bounds, shifted with its reference node.
    ps.shift.resize(ps.sets.size());
    for (size_t k = 0; k < ps.sets.size(); ++k) {
      const int ref = ps.sets[k].reference_node;
      ps.shift[k] = ref >= 0 ? x[static_cast<size_t>(ref)][axis] - model_.x0[static_cast<size_t>(ref)][axis] : 0.0;
    }
    // Wetted area vectors first, and each node's weight w_n (the TLM
    // pressure needs the flow they carry): the constant segments' share
    // summed once, the varying segments' added here.
    Vec3 total = ps.constant_area;
    std::copy(ps.constant_weight.begin(), ps.constant_weight.end(), ps.node_weight.begin());
    for (int si : ps.varying) {
      const size_t s = static_cast<size_t>(si);
      const size_t k = static_cast<size_t>(ps.segment_set[s]);
      const LoadingSet& b = ps.sets[k];
      const double shift = ps.shift[k];
      Vec3 a;
      if (ps.fixed_shape[s]) {
        a = ps.area0[s];  // its corner weights are those of the constructor
      } else {
        segment_corner_weights(ps.segments[s], x, &ps.corner_weight[4 * s]);
        a = segment_area_vector(ps.segments[s], x);
      }
      if (bounded(b)) a *= wetted_fraction(ps.segments[s], x, b.z_min + shift, b.z_max + shift, b.ramp, axis);
      ps.segment_area[s] = a;
      total += a;
      for (int c = 0; c < ps.segments[s].corners(); ++c)
        ps.node_weight[static_cast<size_t>(ps.corner_node[4 * s + static_cast<size_t>(c)])] +=
            ps.corner_weight[4 * s + static_cast<size_t>(c)] * a;
    }
    area_vector_[i] = total;
    if (tlm_[i]) continue;  // solved with the velocity of t_n, in apply_implicit
    // The pressure on each node: −p·w_n (pushes against the normal).
    for (size_t n = 0; n < ps.nodes.size(); ++n) f_ext[static_cast<size_t>(ps.nodes[n])] -= pressure_[i] * ps.node_weight[n];
  }
}

void CavityPressureLoad::build_groups(const Mobility& mob) {
  for (PortSurface& ps : surfaces_) {
    std::map<int, int> slot;  // group → index in ps.groups
    ps.node_group.clear();
    for (int n : ps.nodes) {
      const int g = (*mob.group)[static_cast<size_t>(n)];
      auto it = slot.emplace(g, static_cast<int>(ps.groups.size())).first;
      if (it->second == static_cast<int>(ps.groups.size())) ps.groups.push_back(g);
      ps.node_group.push_back(it->second);
    }
    ps.group_weight.assign(ps.groups.size(), Vec3::Zero());
  }
  for (size_t a = 0; a < surfaces_.size(); ++a)
    for (size_t b = a + 1; b < surfaces_.size(); ++b)
      for (size_t ga = 0; ga < surfaces_[a].groups.size(); ++ga)
        for (size_t gb = 0; gb < surfaces_[b].groups.size(); ++gb)
          if (surfaces_[a].groups[ga] == surfaces_[b].groups[gb]) shared_.push_back({a, b, ga, gb});
  groups_built_ = true;
}

void CavityPressureLoad::apply_implicit(const Mobility& mob, const std::vector<Vec3>& v_old,
                                        const std::vector<Vec3>& v_pred, std::vector<NodalForce>& out) {
  tlm_slots_.clear();
  for (size_t i = 0; i < surfaces_.size(); ++i)
    if (tlm_[i]) tlm_slots_.push_back(i);
  if (tlm_slots_.empty()) return;
  if (!groups_built_) build_groups(mob);
  const auto& inv_mass = *mob.inv_mass;
  const auto& free = *mob.free;
  // Weights per node and per group, and the predicted flows q̂.
  const size_t np = tlm_slots_.size();
  const Eigen::Index n_ports = static_cast<Eigen::Index>(np);
  rhs_.resize(n_ports);
  mobility_.setZero(n_ports, n_ports);
  const double a = mob.theta, b = 1.0 - mob.theta;  // v_n = b·v_{n-1/2} + a·v_{n+1/2}
  for (size_t j = 0; j < np; ++j) {
    PortSurface& ps = surfaces_[tlm_slots_[j]];  // its node weights are apply()'s
    std::fill(ps.group_weight.begin(), ps.group_weight.end(), Vec3::Zero());
    double q_pred = 0.0;
    for (size_t n = 0; n < ps.nodes.size(); ++n) {
      ps.group_weight[static_cast<size_t>(ps.node_group[n])] += ps.node_weight[n];
      const size_t node = static_cast<size_t>(ps.nodes[n]);
      q_pred += ps.node_weight[n].dot(b * v_old[node] + a * v_pred[node]);
    }
    double S = 0.0;
    for (size_t g = 0; g < ps.groups.size(); ++g) {
      const size_t G = static_cast<size_t>(ps.groups[g]);
      S += inv_mass[G] * ps.group_weight[g].dot(free[G].cwiseProduct(ps.group_weight[g]));
    }
    mobility_(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) = S;
    tlm_flow_[tlm_slots_[j]] = q_pred;  // the flow without these forces, corrected below
    rhs_(static_cast<Eigen::Index>(j)) = wave_[tlm_slots_[j]] + impedance_[tlm_slots_[j]] * q_pred;
  }
  // Couplings between ports that move together (e.g. two faces of one piston).
  for (const SharedGroup& sg : shared_) {
    if (!tlm_[sg.a] || !tlm_[sg.b]) continue;
    const Eigen::Index ja = std::find(tlm_slots_.begin(), tlm_slots_.end(), sg.a) - tlm_slots_.begin();
    const Eigen::Index jb = std::find(tlm_slots_.begin(), tlm_slots_.end(), sg.b) - tlm_slots_.begin();
    const size_t G = static_cast<size_t>(surfaces_[sg.a].groups[sg.ga]);
    const double Sab = inv_mass[G] * surfaces_[sg.a].group_weight[sg.ga].dot(
                                         free[G].cwiseProduct(surfaces_[sg.b].group_weight[sg.gb]));
    mobility_(ja, jb) += Sab;
    mobility_(jb, ja) += Sab;
  }
  // (I + a·h·Z·S)·p = c + Z·q̂
  system_.setIdentity(n_ports, n_ports);
  for (Eigen::Index j = 0; j < n_ports; ++j)
    system_.row(j) += a * mob.h * impedance_[tlm_slots_[static_cast<size_t>(j)]] * mobility_.row(j);
  if (np == 1) {
    pressure_[tlm_slots_[0]] = rhs_(0) / system_(0, 0);
  } else {
    lu_.compute(system_);
    solution_ = lu_.solve(rhs_);
    for (size_t j = 0; j < np; ++j) pressure_[tlm_slots_[j]] = solution_(static_cast<Eigen::Index>(j));
  }
  // q = q̂ − a·h·S·p: the flow the pressure was solved with.
  for (size_t j = 0; j < np; ++j)
    for (size_t k = 0; k < np; ++k)
      tlm_flow_[tlm_slots_[j]] -= a * mob.h * mobility_(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(k)) *
                                  pressure_[tlm_slots_[k]];
  for (size_t j = 0; j < np; ++j) {
    const PortSurface& ps = surfaces_[tlm_slots_[j]];
    const double p = pressure_[tlm_slots_[j]];
    for (size_t n = 0; n < ps.nodes.size(); ++n) out.push_back({ps.nodes[n], Vec3(-p * ps.node_weight[n])});
  }
}

double CavityPressureLoad::flow(int slot, const std::vector<Vec3>& v) const {
  const PortSurface& ps = surfaces_[static_cast<size_t>(slot)];
  double q = 0.0;
  for (size_t s = 0; s < ps.segments.size(); ++s) {
    const Segment& seg = ps.segments[s];
    Vec3 vm = Vec3::Zero();
    for (int k = 0; k < seg.corners(); ++k) vm += ps.corner_weight[4 * s + static_cast<size_t>(k)] * v[static_cast<size_t>(seg.n[k])];
    q += ps.segment_area[s].dot(vm);
  }
  return q;
}

double CavityPressureLoad::displacement(int slot, const std::vector<Vec3>& x) const {
  const PortSurface& ps = surfaces_[static_cast<size_t>(slot)];
  double u = 0.0;
  for (int n : ps.first_nodes) u += (x[static_cast<size_t>(n)] - model_.x0[static_cast<size_t>(n)]).dot(ps.normal0);
  return u / static_cast<double>(ps.first_nodes.size());
}

}  // namespace fe

namespace fe {

void CavityPressureLoad::state(config::StateIO& io) {
  io.expect("cavity slots", surfaces_.size(), "the number of hydraulic ports");
  io.array("cavity pressure", pressure_);
  io.array("cavity wave", wave_);
  io.array("cavity impedance", impedance_);
  io.array("cavity tlm flow", tlm_flow_);
  io.array("cavity tlm", tlm_);
  io.array("cavity area", area_vector_);
  for (PortSurface& ps : surfaces_) {
    io.list("surface segment area", ps.segment_area);
    io.list("surface shift", ps.shift);
    io.list("surface corner weight", ps.corner_weight);
  }
}

}  // namespace fe
