#include "contact/contact.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace fe {

namespace {
int corners(const Segment& s) { return s.corners(); }

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

// A segment's length scale: the side of its area, or a line's length.
double segment_size(const Segment& s, const std::vector<Vec3>& x) {
  if (s.line()) return (x[static_cast<size_t>(s.n[1])] - x[static_cast<size_t>(s.n[0])]).norm();
  return std::sqrt(segment_area_vector(s, x).norm());
}

PenaltyContact::PenaltyContact(const Model& model, const ContactDef& def, double dt,
                               const std::vector<double>& nodal_mass)
    : mass_(nodal_mass), dt_(dt), sfs_(def.stiffness_factor), damping_(def.damping), fs_(def.fs), fd_(def.fd),
      dc_(def.dc), vc_(def.vc) {
  const auto& master = model.segment_sets.at(def.master_set);
  static const std::vector<Segment> none;
  const auto& slave = def.slave_nodes || def.single_surface ? none : model.segment_sets.at(def.slave_set);
  if (def.single_surface) {
    // One side: every node of the surface against its faces; each face's
    // element found once (the face's nodes are all among its eight).
    single_ = true;
    sides_.push_back(Side{master, nodes_of(master), {}, {}, {}, {}, {}, {}});
    std::map<int, std::vector<size_t>> elements_of;  // node → solids that have it
    const std::set<int> parts(def.part_ids.begin(), def.part_ids.end());
    for (size_t e = 0; e < model.solids.size(); ++e)
      if (parts.count(model.solids[e].part))
        for (int n : model.solids[e].n) elements_of[n].push_back(e);
    for (const Segment& seg : master) {
      std::array<int, 8> owner{};
      owner.fill(-1);
      for (size_t e : elements_of[seg.n[0]]) {
        const auto& en = model.solids[e].n;
        bool all = true;
        for (int k = 0; k < seg.corners(); ++k) all = all && std::find(en, en + 8, seg.n[k]) != en + 8;
        if (all) {
          std::copy(en, en + 8, owner.begin());
          break;
        }
      }
      owner_.push_back(owner);
    }
  } else if (def.slave_nodes) {
    std::vector<int> nodes;
    for (int id : model.node_sets.at(def.slave_set)) nodes.push_back(model.index_of(id, def.where));
    sides_.push_back(Side{master, nodes, {}, {}, {}, {}, {}, {}});  // one-sided: nodes against the master's segments
  } else {
    sides_.push_back(Side{master, nodes_of(slave), {}, {}, {}, {}, {}, {}});
    sides_.push_back(Side{slave, nodes_of(master), {}, {}, {}, {}, {}, {}});
  }
  for (Side& s : sides_) {
    s.friction.assign(s.nodes.size(), Vec3::Zero());
    // Lines by their first and by their second node; a vertex is where one
    // line's second node is the next one's first (the outward normal to the
    // right of n0 → n1: the body on the left).
    std::map<int, size_t> starting, ending;
    for (size_t j = 0; j < s.segments.size(); ++j)
      if (s.segments[j].line()) starting[s.segments[j].n[0]] = j, ending[s.segments[j].n[1]] = j;
    s.past.assign(s.segments.size(), {1e-6, 1e-6});
    s.corner.assign(s.segments.size(), {-1, -1});
    for (const auto& [node, a] : ending) {
      const auto next = starting.find(node);
      if (next == starting.end()) continue;
      const size_t b = next->second;
      const Vec3 da = model.x0[static_cast<size_t>(s.segments[a].n[1])] - model.x0[static_cast<size_t>(s.segments[a].n[0])];
      const Vec3 db = model.x0[static_cast<size_t>(s.segments[b].n[1])] - model.x0[static_cast<size_t>(s.segments[b].n[0])];
      s.past[a][1] = s.past[b][0] = 0.05;
      const double sin_turn = (da.x() * db.y() - da.y() * db.x()) / (da.norm() * db.norm());
      if (da.dot(db) <= 0.0 || std::fabs(sin_turn) > std::sin(10.0 * M_PI / 180.0))
        s.corner[a][1] = static_cast<int>(b), s.corner[b][0] = static_cast<int>(a);
    }
  }
  double sum = 0.0;
  int count = 0;
  for (const auto* set : {&slave, &master})
    for (const auto& s : *set) {
      sum += segment_size(s, model.x0);
      ++count;
    }
  size_ = count ? sum / count : 0.0;
}

void PenaltyContact::search(Side& s, const std::vector<Vec3>& x) {
  // Candidates: segments whose centre lies within a few element sizes.
  const double reach = 3.0 * size_;
  s.centre.resize(s.segments.size());
  s.reach2.resize(s.segments.size());
  for (size_t j = 0; j < s.segments.size(); ++j) {
    const Segment& seg = s.segments[j];
    Vec3 c = Vec3::Zero();
    double diameter = 0.0;
    const Vec3& x0 = x[static_cast<size_t>(seg.n[0])];
    for (int k = 0; k < corners(seg); ++k) {
      c += x[static_cast<size_t>(seg.n[k])];
      diameter = std::max(diameter, (x[static_cast<size_t>(seg.n[k])] - x0).norm());
    }
    s.centre[j] = c / corners(seg);
    // A touching node projects inside the segment (within its diameter of
    // corner 0) and lies at most 0.5·size behind it; 1.25× the diameter
    // leaves room for the segment's strain until the next search.
    const double r = 1.25 * diameter + 0.5 * size_;
    s.reach2[j] = r * r;
  }
  s.start.assign(1, 0);
  s.cand.clear();
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    for (size_t j = 0; j < s.segments.size(); ++j)
      if ((x[static_cast<size_t>(s.nodes[i])] - s.centre[j]).squaredNorm() < reach * reach)
        s.cand.push_back(static_cast<int>(j));
    s.start.push_back(static_cast<int>(s.cand.size()));
  }
}

bool project_onto_segment(const Segment& seg, const Vec3& point, const std::vector<Vec3>& x, double window, double& g,
                          Vec3& n, double w[4], const std::array<double, 2>& past, double* t_out) {
  const int nc = corners(seg);
  if (seg.line()) {  // 2D: the outward normal lies to the right of n0 → n1 in the x–y plane
    const Vec3& a = x[static_cast<size_t>(seg.n[0])];
    const Vec3 d = x[static_cast<size_t>(seg.n[1])] - a;
    const double len2 = d.squaredNorm();
    if (!(len2 > 0.0)) return false;
    n = Vec3(d.y(), -d.x(), 0.0) / std::sqrt(len2);
    g = (point - a).dot(n);
    if (std::fabs(g) > window) return false;
    const double t = (point - a).dot(d) / len2;
    if (t < -past[0] || t > 1.0 + past[1]) return false;
    if (t_out) *t_out = t;
    w[1] = std::clamp(t, 0.0, 1.0), w[0] = 1.0 - w[1], w[2] = w[3] = 0.0;
    return true;
  }
  const Vec3 area = segment_area_vector(seg, x);
  const double a = area.norm();
  if (!(a > 0.0)) return false;
  n = area / a;
  Vec3 centre = Vec3::Zero();
  for (int k = 0; k < nc; ++k) centre += x[static_cast<size_t>(seg.n[k])];
  centre /= nc;
  g = (point - centre).dot(n);
  if (std::fabs(g) > window) return false;  // too far in front, or too deep to be this segment
  const Vec3 p = point - g * n;
  // Weights over the segment's corners: split the quad into two triangles.
  double t[3];
  for (int k = 0; k < 4; ++k) w[k] = 0.0;
  const Vec3& x0 = x[static_cast<size_t>(seg.n[0])];
  const Vec3& x1 = x[static_cast<size_t>(seg.n[1])];
  const Vec3& x2 = x[static_cast<size_t>(seg.n[2])];
  const Vec3& x3 = x[static_cast<size_t>(seg.n[3])];
  int tri[3] = {0, 1, 2};
  if (barycentric(p, x0, x1, x2, t)) {
  } else if (nc == 4 && barycentric(p, x0, x2, x3, t)) {
    tri[1] = 2, tri[2] = 3;
  } else {
    return false;
  }
  // The gap and the normal of the triangle the point lies over, not of the
  // quad's mean plane: a warped quad (a face in an hourglass mode) is
  // δ/4 off its mean plane at every corner, so a node resting on a corner
  // would read a gap of δ/4 and be pushed by k·δ/4, work that no potential
  // stores (it made energy where two meshes meet node on node: 3 % at 40 m/s
  // on 5 mm hexes, fed into the hourglass modes). Over the triangle the gap
  // is zero at its corners and along its edges, so the triangulated surface
  // the weights describe is the one the gap is measured from.
  if (nc == 4) {
    const Vec3& ta = x[static_cast<size_t>(seg.n[tri[0]])];
    const Vec3& tb = x[static_cast<size_t>(seg.n[tri[1]])];
    const Vec3& tc = x[static_cast<size_t>(seg.n[tri[2]])];
    const Vec3 nt = (tb - ta).cross(tc - ta);
    const double len = nt.norm();
    if (len > 0.0) {
      n = nt / len;
      g = (point - ta).dot(n);
      if (std::fabs(g) > window) return false;
      barycentric(point - g * n, ta, tb, tc, t);  // the same triangle: at most round-off outside
    }
  }
  for (int k = 0; k < 3; ++k) w[tri[k]] = std::max(t[k], 0.0);
  const double sum = w[0] + w[1] + w[2] + w[3];
  for (int k = 0; k < 4; ++k) w[k] /= sum;
  return true;
}

bool PenaltyContact::project(const Side& s, size_t j, size_t node, const std::vector<Vec3>& x, double window,
                             Contact& c) const {
  const Segment& seg = s.segments[j];
  for (int k = 0; k < corners(seg); ++k)
    if (static_cast<size_t>(seg.n[k]) == node) return false;
  double t = 0.5;
  if (!project_onto_segment(seg, x[node], x, window, c.g, c.n, c.w, s.past[j], &t)) return false;
  if (!seg.line() || (t >= 0.0 && t <= 1.0)) return true;
  const int next = s.corner[j][t < 0.0 ? 0 : 1];
  if (next < 0) return true;
  // Past the end at a corner: beside the body if farther in front of the
  // next line than pressed into this one (the two bodies' corners of one
  // radius part by nanometres as the faces tilt).
  const Segment& other = s.segments[static_cast<size_t>(next)];
  const Vec3& a = x[static_cast<size_t>(other.n[0])];
  const Vec3 d = x[static_cast<size_t>(other.n[1])] - a;
  const double len = d.norm();
  if (!(len > 0.0)) return true;  // a line of no length turns nothing
  const double beside = (x[node] - a).dot(Vec3(d.y(), -d.x(), 0.0)) / len;
  return beside <= std::max(-c.g, 1e-6 * len);
}

bool PenaltyContact::touching(const Side& s, size_t i, const std::vector<Vec3>& x, double window, bool reach_check,
                              Contact& c, size_t& seg) const {
  const size_t node = static_cast<size_t>(s.nodes[i]);
  const double shallow = kCornerDepth * size_;
  bool pressed = false, deep = false, on_or_in_front = false;
  Contact trial, deep_c;
  size_t deep_seg = 0;
  for (int ci = s.start[i]; ci < s.start[i + 1]; ++ci) {
    const size_t j = static_cast<size_t>(s.cand[static_cast<size_t>(ci)]);
    if (reach_check && (x[node] - x[static_cast<size_t>(s.segments[j].n[0])]).squaredNorm() > s.reach2[j])
      continue;  // too far to touch
    if (single_ && std::find(owner_[j].begin(), owner_[j].end(), static_cast<int>(node)) != owner_[j].end())
      continue;  // a face of one of its own elements
    if (!project(s, j, node, x, window, trial)) continue;
    if (trial.g >= 0.0) {
      on_or_in_front = true;
    } else if (-trial.g <= shallow) {
      if (!pressed || trial.g < c.g) c = trial, seg = j, pressed = true;  // the deepest of the shallow
    } else if (!deep || trial.g > deep_c.g) {
      deep_c = trial, deep_seg = j, deep = true;  // the least deep of the deep
    }
  }
  // Penalty contact keeps a pressed node shallow. At an edge struck along
  // the axis the node is pressed into the struck face and only level with
  // (or a hair inside) the side face: of the shallow faces the deepest is the
  // one pressed. A face the node is deep behind while it is shallow behind or
  // on another is the far side of a convex corner of the other body (a tool's
  // top node level with a piston's edge is not 6 mm inside the piston's
  // side): not a contact. A node deep behind faces only is a real deep
  // penetration: the shortest way out.
  if (pressed) return true;
  if (!deep || on_or_in_front) return false;
  c = deep_c, seg = deep_seg;
  return true;
}

int PenaltyContact::side_forces(Side& s, bool slave_nodes, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                std::vector<Vec3>& f) {
  Vec3& on_nodes = slave_nodes ? slave_force_ : master_force_;
  Vec3& on_segments = slave_nodes ? master_force_ : slave_force_;
  double& mass_in_contact = slave_nodes ? slave_mass_ : master_mass_;
  int active = 0;
  Contact c;
  for (size_t i = 0; i < s.nodes.size(); ++i) {
    const size_t node = static_cast<size_t>(s.nodes[i]);
    size_t j = 0;
    Vec3& ft = s.friction[i];
    const Vec3 ft_old = ft;
    ft.setZero();  // until this step finds the node pressed
    if (!touching(s, i, x, 0.5 * size_, true, c, j)) continue;
    const Segment& seg = s.segments[j];
    const int nc = corners(seg);
    double m_seg = 0.0;
    Vec3 v_seg = Vec3::Zero();
    for (int k = 0; k < nc; ++k) {
      m_seg += c.w[k] * mass_[static_cast<size_t>(seg.n[k])];
      v_seg += c.w[k] * v[static_cast<size_t>(seg.n[k])];
    }
    const double m_node = mass_[node];
    const double m_eff = (m_node > 0.0 && m_seg > 0.0) ? m_node * m_seg / (m_node + m_seg) : std::max(m_node, m_seg);
    if (!(m_eff > 0.0)) continue;
    const double k = std::min(sfs_ * 0.1, 0.2) * m_eff / (dt_ * dt_);
    const double gdot = (v[node] - v_seg).dot(c.n);
    const double F = k * (-c.g) - damping_ * 2.0 * std::sqrt(k * m_eff) * gdot;
    if (F <= 0.0) continue;
    Vec3 force = F * c.n;
    if (fs_ > 0.0 || fd_ > 0.0) {
      const Vec3 rel = v[node] - v_seg, vt = rel - rel.dot(c.n) * c.n;
      ft = ft_old - ft_old.dot(c.n) * c.n - k * dt_ * vt;  // the elastic trial, in the current plane
      const double mu = fd_ + (fs_ - fd_) * std::exp(-dc_ * vt.norm());
      double cap = mu * F;
      if (vc_ > 0.0) cap = std::min(cap, vc_ * segment_area_vector(seg, x).norm());
      const double trial = ft.norm();
      if (trial > cap) ft *= cap / trial;  // sliding
      force += ft;
    }
    f[node] += force;
    for (int k2 = 0; k2 < nc; ++k2) f[static_cast<size_t>(seg.n[k2])] -= c.w[k2] * force;
    on_nodes += force;
    on_segments -= force;
    mass_in_contact += m_node;
    if (-c.g > max_penetration_) {
      max_penetration_ = -c.g;
      deepest_node_ = static_cast<int>(node);
      for (int k2 = 0; k2 < 4; ++k2) deepest_segment_[static_cast<size_t>(k2)] = k2 < nc ? seg.n[k2] : -1;
    }
    ++active;
  }
  return active;
}

void PenaltyContact::refuse_initial_penetration(const Model& model, const ContactDef& def,
                                                const std::vector<Vec3>& x) {
  // A node that starts behind a segment would be thrown out by the penalty
  // spring, releasing k·g²/2 of energy that is in no load: at g = 1 mm and
  // the usual k = 0.1·m/Δt² that is a launch at 0.3·g/Δt, km/s. Geometric
  // round-off (1e-6 of a segment) is allowed; anything deeper, up to two
  // segment sizes, is refused with the node and its depth.
  const double tolerance = 1e-6 * size_;
  double worst = 0.0;
  int worst_node = -1;
  Contact c;
  for (auto& s : sides_) {
    search(s, x);
    size_t j = 0;
    for (size_t i = 0; i < s.nodes.size(); ++i)
      // A single surface's own far faces lie within two sizes of its nodes
      // (a body two elements thick): there, only what the step itself would
      // take for a contact counts.
      if (touching(s, i, x, (single_ ? 0.5 : 2.0) * size_, false, c, j) && -c.g > worst) {
        worst = -c.g;
        worst_node = s.nodes[i];
      }
  }
  if (worst <= tolerance) return;
  std::ostringstream m;
  m << def.where.str() << ": contact between segment sets " << def.slave_set << " and " << def.master_set
    << " starts penetrated: node " << model.node_ids[static_cast<size_t>(worst_node)] << " is " << worst * 1e3
    << " mm behind the other surface at t = 0; move the parts apart by at least that much";
  throw std::runtime_error(m.str());
}

long PenaltyContact::steps_to_next_search(const Side& s, const std::vector<Vec3>& v) const {
  double v2 = 0.0;
  int fastest = -1;
  auto look = [&](int n) {
    const double w = v[static_cast<size_t>(n)].squaredNorm();
    if (w > v2) v2 = w, fastest = n;
  };
  for (int n : s.nodes) look(n);
  for (const Segment& seg : s.segments)
    for (int k = 0; k < corners(seg); ++k) look(seg.n[k]);
  if (std::sqrt(v2) * dt_ > fastest_step_) fastest_step_ = std::sqrt(v2) * dt_, fastest_node_ = fastest;
  const double per_step = 2.0 * std::sqrt(v2) * dt_;  // the most two nodes close in a step
  if (!(per_step > 0.0)) return search_interval_;
  const double steps = std::floor(1.25 * size_ / per_step);
  return static_cast<long>(std::clamp(steps, 1.0, static_cast<double>(search_interval_)));
}

int PenaltyContact::apply(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f, long step) {
  max_penetration_ = 0.0;
  deepest_node_ = -1;
  fastest_step_ = 0.0;
  fastest_node_ = -1;
  slave_force_ = master_force_ = Vec3::Zero();
  slave_mass_ = master_mass_ = 0.0;
  int active = 0;
  for (size_t k = 0; k < sides_.size(); ++k) {
    Side& s = sides_[k];
    if (step >= s.next_search || step < s.next_search - search_interval_ || s.start.empty()) {
      search(s, x);
      s.next_search = step + steps_to_next_search(s, v);
    }
    active += side_forces(s, k == 0, x, v, f);
  }
  return active;
}

}  // namespace fe

namespace fe {

void PenaltyContact::state(config::StateIO& io) {
  io.expect("contact sides", sides_.size(), "the sides of a contact");
  for (Side& s : sides_) {
    io.list("contact start", s.start);
    io.list("contact cand", s.cand);
    io.list("contact reach2", s.reach2);
    if (fs_ > 0.0 || fd_ > 0.0) io.array("contact friction", s.friction);  // only where there is friction: older checkpoints read
  }
  io.value("contact max_penetration", max_penetration_);
}

}  // namespace fe
