#include "cavity_load.hpp"

#include <algorithm>
#include <set>

namespace fe {

Vec3 segment_area_vector(const Segment& s, const std::vector<Vec3>& x) {
  // Half the cross product of the diagonals: exact for a planar quad, the
  // mean area vector for a warped one, and for a triangle (n4 = n3) equal to
  // ½(x2 − x1) × (x3 − x1).
  const Vec3& a = x[static_cast<size_t>(s.n[0])];
  const Vec3& b = x[static_cast<size_t>(s.n[1])];
  const Vec3& c = x[static_cast<size_t>(s.n[2])];
  const Vec3& d = x[static_cast<size_t>(s.n[3])];
  return 0.5 * (c - a).cross(d - b);
}

static int corners(const Segment& s) { return s.n[3] == s.n[2] ? 3 : 4; }

double wetted_fraction(const Segment& s, const std::vector<Vec3>& x, double lo, double hi, double ramp) {
  double zmin = 1e300, zmax = -1e300, zc = 0.0;
  const int nc = corners(s);
  for (int k = 0; k < nc; ++k) {
    const double z = x[static_cast<size_t>(s.n[k])].z();
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
  for (const auto& port : table.ports) {
    if (port.type != config::PortType::Hydraulic) continue;
    const LoadingSet* ls = nullptr;
    for (const auto& l : model.loading_sets)
      if (l.port_id == port.id && !l.force) ls = &l;
    if (!ls)
      throw config::InputError(port.where, "hydraulic port " + std::to_string(port.id) + " (" +
                                               port.label + ") has no *USER_LOADING_SET in " +
                                               model.source);
    PortSurface ps;
    ps.port_id = port.id;
    ps.bounds = *ls;
    ps.segments = model.segment_sets.at(ls->segment_set);
    std::set<int> nodes;
    Vec3 total = Vec3::Zero();
    for (const auto& s : ps.segments) {
      for (int k = 0; k < corners(s); ++k) nodes.insert(s.n[k]);
      total += segment_area_vector(s, model.x0);
    }
    if (total.norm() <= 0.0)
      throw config::InputError(ls->where, "segment set " + std::to_string(ls->segment_set) +
                                              " has zero total area");
    ps.normal0 = total.normalized();
    ps.nodes.assign(nodes.begin(), nodes.end());
    ps.segment_area.assign(ps.segments.size(), Vec3::Zero());
    surfaces_.push_back(std::move(ps));
  }
  pressure_.assign(surfaces_.size(), 0.0);
  wave_.assign(surfaces_.size(), 0.0);
  impedance_.assign(surfaces_.size(), 0.0);
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

void CavityPressureLoad::apply(double, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                               std::vector<Vec3>& f_ext) {
  for (size_t i = 0; i < surfaces_.size(); ++i) {
    PortSurface& ps = surfaces_[i];
    const LoadingSet& b = ps.bounds;
    const double shift = b.reference_node >= 0 ? x[static_cast<size_t>(b.reference_node)].z() -
                                                     model_.x0[static_cast<size_t>(b.reference_node)].z()
                                               : 0.0;
    const bool bounded = b.z_min > -1e299 || b.z_max < 1e299;
    // Wetted area vectors first: the TLM pressure needs the flow they carry.
    Vec3 total = Vec3::Zero();
    for (size_t s = 0; s < ps.segments.size(); ++s) {
      Vec3 a = segment_area_vector(ps.segments[s], x);
      if (bounded) a *= wetted_fraction(ps.segments[s], x, b.z_min + shift, b.z_max + shift, b.ramp);
      ps.segment_area[s] = a;
      total += a;
    }
    if (tlm_[i]) pressure_[i] = wave_[i] + impedance_[i] * flow(static_cast<int>(i), v);
    for (size_t s = 0; s < ps.segments.size(); ++s) {
      const Segment& seg = ps.segments[s];
      const int nc = corners(seg);
      const Vec3 f_node = -pressure_[i] * ps.segment_area[s] / nc;  // pushes against the normal
      for (int k = 0; k < nc; ++k) f_ext[static_cast<size_t>(seg.n[k])] += f_node;
    }
    area_vector_[i] = total;
  }
}

double CavityPressureLoad::flow(int slot, const std::vector<Vec3>& v) const {
  const PortSurface& ps = surfaces_[static_cast<size_t>(slot)];
  double q = 0.0;
  for (size_t s = 0; s < ps.segments.size(); ++s) {
    const Segment& seg = ps.segments[s];
    const int nc = corners(seg);
    Vec3 vm = Vec3::Zero();
    for (int k = 0; k < nc; ++k) vm += v[static_cast<size_t>(seg.n[k])];
    q += ps.segment_area[s].dot(vm / nc);
  }
  return q;
}

double CavityPressureLoad::displacement(int slot, const std::vector<Vec3>& x) const {
  const PortSurface& ps = surfaces_[static_cast<size_t>(slot)];
  double u = 0.0;
  for (int n : ps.nodes) u += (x[static_cast<size_t>(n)] - model_.x0[static_cast<size_t>(n)]).dot(ps.normal0);
  return u / static_cast<double>(ps.nodes.size());
}

}  // namespace fe
