#include "contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>

#include "cavity_load.hpp"

namespace fe {

namespace {
int corners(const Segment& s) { return s.n[3] == s.n[2] ? 3 : 4; }

std::vector<int> nodes_of(const std::vector<Segment>& segs) {
  std::set<int> n;
  for (const auto& s : segs)
    for (int k = 0; k < corners(s); ++k) n.insert(s.n[k]);
  return {n.begin(), n.end()};
}

// Barycentric weights of p in triangle (a, b, c); false if outside (with a tolerance).
bool barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double w[3]) {
  const Vec3 v0 = b - a, v1 = c - a, v2 = p - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0.0)) return false;
  w[1] = (d11 * d20 - d01 * d21) / den;
  w[2] = (d00 * d21 - d01 * d20) / den;
  w[0] = 1.0 - w[1] - w[2];
  const double tol = -1e-6;
  return w[0] >= tol && w[1] >= tol && w[2] >= tol;
}
}  // namespace

PenaltyContact::PenaltyContact(const Model& model, const ContactDef& def, double dt,
                               const std::vector<double>& nodal_mass)
    : mass_(nodal_mass), dt_(dt), sfs_(def.stiffness_factor), damping_(def.damping) {
  const auto& master = model.segment_sets.at(def.master_set);
  static const std::vector<Segment> none;
  const auto& slave = def.slave_nodes ? none : model.segment_sets.at(def.slave_set);
  if (def.slave_nodes) {
    std::vector<int> nodes;
    for (int id : model.node_sets.at(def.slave_set)) nodes.push_back(model.index_of(id, def.where));
    sides_.push_back(Side{master, nodes, {}});  // one-sided: nodes against the master's segments
  } else {
    sides_.push_back(Side{master, nodes_of(slave), {}});
    sides_.push_back(Side{slave, nodes_of(master), {}});
  }
  double sum = 0.0;
  int count = 0;
  for (const auto* set : {&slave, &master})
    for (const auto& s : *set) {
      sum += std::sqrt(segment_area_vector(s, model.x0).norm());
      ++count;
    }
  size_ = count ? sum / count : 0.0;
}

void PenaltyContact::search(Side& s, const std::vector<Vec3>& x) {
  // Candidates: segments whose centre lies within a few element sizes.
  const double reach = 3.0 * size_;
  s.candidates.assign(s.nodes.size(), {});
  std::vector<Vec3> centre(s.segments.size());
  for (size_t j = 0; j < s.segments.size(); ++j) {
    const Segment& seg = s.segments[j];
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < corners(seg); ++k) c += x[static_cast<size_t>(seg.n[k])];
    centre[j] = c / corners(seg);
  }
  for (size_t i = 0; i < s.nodes.size(); ++i)
    for (size_t j = 0; j < s.segments.size(); ++j)
      if ((x[static_cast<size_t>(s.nodes[i])] - centre[j]).squaredNorm() < reach * reach)
        s.candidates[i].push_back(static_cast<int>(j));
}

int PenaltyContact::side_forces(Side& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                std::vector<Vec3>& f) {
  int active = 0;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    const size_t node = static_cast<size_t>(s.nodes[i]);
    for (int j : s.candidates[i]) {
      const Segment& seg = s.segments[static_cast<size_t>(j)];
      const int nc = corners(seg);
      bool shares_node = false;
      for (int k = 0; k < nc; ++k) shares_node |= static_cast<size_t>(seg.n[k]) == node;
      if (shares_node) continue;
      const Vec3 area = segment_area_vector(seg, x);
      const double a = area.norm();
      if (!(a > 0.0)) continue;
      const Vec3 n = area / a;
      Vec3 c = Vec3::Zero();
      for (int k = 0; k < nc; ++k) c += x[static_cast<size_t>(seg.n[k])];
      c /= nc;
      const double g = (x[node] - c).dot(n);
      if (g >= 0.0 || g < -0.5 * size_) continue;  // outside, or too deep to be this segment
      const Vec3 p = x[node] - g * n;
      // Weights over the segment's corners: split the quad into two triangles.
      double w4[4] = {0, 0, 0, 0}, w[3];
      const Vec3& x0 = x[static_cast<size_t>(seg.n[0])];
      const Vec3& x1 = x[static_cast<size_t>(seg.n[1])];
      const Vec3& x2 = x[static_cast<size_t>(seg.n[2])];
      const Vec3& x3 = x[static_cast<size_t>(seg.n[3])];
      if (barycentric(p, x0, x1, x2, w)) {
        w4[0] = w[0], w4[1] = w[1], w4[2] = w[2];
      } else if (nc == 4 && barycentric(p, x0, x2, x3, w)) {
        w4[0] = w[0], w4[2] = w[1], w4[3] = w[2];
      } else {
        continue;
      }
      double m_seg = 0.0;
      Vec3 v_seg = Vec3::Zero();
      for (int k = 0; k < nc; ++k) {
        m_seg += w4[k] * mass_[static_cast<size_t>(seg.n[k])];
        v_seg += w4[k] * v[static_cast<size_t>(seg.n[k])];
      }
      const double m_node = mass_[node];
      const double m_eff = (m_node > 0.0 && m_seg > 0.0) ? m_node * m_seg / (m_node + m_seg) : std::max(m_node, m_seg);
      if (!(m_eff > 0.0)) continue;
      const double k = std::min(sfs_ * 0.1, 0.2) * m_eff / (dt_ * dt_);
      const double gdot = (v[node] - v_seg).dot(n);
      const double F = k * (-g) - damping_ * 2.0 * std::sqrt(k * m_eff) * gdot;
      if (F <= 0.0) continue;
      f[node] += F * n;
      for (int k2 = 0; k2 < nc; ++k2) f[static_cast<size_t>(seg.n[k2])] -= w4[k2] * F * n;
      max_penetration_ = std::max(max_penetration_, -g);
      ++active;
      break;  // one segment per node
    }
  }
  return active;
}

int PenaltyContact::apply(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f, long step) {
  max_penetration_ = 0.0;
  int active = 0;
  for (auto& s : sides_) {
    if (step % search_interval_ == 0 || s.candidates.empty()) search(s, x);
    active += side_forces(s, x, v, f);
  }
  return active;
}

}  // namespace fe
