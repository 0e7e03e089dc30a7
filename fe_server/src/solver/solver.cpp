#include "solver/solver.hpp"

#include "elements/element_blocks.hpp"
#include "elements/element_tet4.hpp"
#include "loads/cavity_load.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace fe {

namespace {

bool in_rigid_part(const Model& m, int part) {
  auto p = m.parts.find(part);
  if (p == m.parts.end()) return false;
  auto mat = m.materials.find(p->second.material);
  return mat != m.materials.end() && mat->second.rigid;
}

// Mass that moves with node i: its rigid body's, or its own; infinite for a
// node held in every DOF (fixed, or driven by a prescribed motion: the
// motion, not the node's inertia, decides it).
double moving_mass(const Model& m, int i) {
  for (const auto& b : m.rigid_bodies)
    for (int n : b.nodes)
      if (n == i) return b.mass;
  Eigen::Matrix<bool, 3, 1> held = m.fixed[static_cast<size_t>(i)];
  for (const auto& p : m.prescribed)
    if (std::find(p.nodes.begin(), p.nodes.end(), i) != p.nodes.end()) held[p.dof] = true;
  return held.all() ? std::numeric_limits<double>::infinity() : m.mass[static_cast<size_t>(i)];
}

// Node lists of the per-node passes, by what reaches the nodes.
struct NodeReach {
  std::vector<char> internal, contact, loading, history;
};

NodeReach node_reach(const Model& m) {
  const size_t n = m.x0.size();
  NodeReach r{std::vector<char>(n, 0), std::vector<char>(n, 0), std::vector<char>(n, 0), std::vector<char>(n, 0)};
  auto mark_segments = [&](std::vector<char>& to, int set) {
    auto it = m.segment_sets.find(set);
    if (it == m.segment_sets.end()) return;
    for (const Segment& seg : it->second)
      for (int k = 0; k < seg.corners(); ++k) to[static_cast<size_t>(seg.n[k])] = 1;
  };
  auto mark_node_set = [&](std::vector<char>& to, int set, const config::SourceLocation& where) {
    auto it = m.node_sets.find(set);
    if (it == m.node_sets.end()) return;
    for (int id : it->second) to[static_cast<size_t>(m.index_of(id, where))] = 1;
  };
  for (const auto& d : m.discretes) r.internal[static_cast<size_t>(d.n1)] = r.internal[static_cast<size_t>(d.n2)] = 1;
  for (const auto& e : m.bars)
    if (!in_rigid_part(m, e.part)) r.internal[static_cast<size_t>(e.n1)] = r.internal[static_cast<size_t>(e.n2)] = 1;
  for (const auto& e : m.solids)
    if (!in_rigid_part(m, e.part))
      for (int k : e.n) r.internal[static_cast<size_t>(k)] = 1;
  for (const auto& e : m.axis)
    if (!in_rigid_part(m, e.part))
      for (int k : e.n) r.internal[static_cast<size_t>(k)] = 1;
  for (const auto& c : m.contacts) {
    if (c.slave_nodes)
      mark_node_set(r.contact, c.slave_set, c.where);
    else
      mark_segments(r.contact, c.slave_set);
    mark_segments(r.contact, c.master_set);
  }
  for (const auto& ls : m.loading_sets) {
    if (ls.body)
      for (int i : ls.body_nodes) r.loading[static_cast<size_t>(i)] = 1;
    else if (ls.force)
      mark_node_set(r.loading, ls.segment_set, ls.where);
    else
      mark_segments(r.loading, ls.segment_set);
    if (ls.reference_node >= 0) r.loading[static_cast<size_t>(ls.reference_node)] = 1;
  }
  for (const auto& p : m.prescribed)  // their reaction joins the loads
    for (int i : p.nodes) r.loading[static_cast<size_t>(i)] = 1;
  for (const auto& l : m.nodal_loads)
    for (int i : l.nodes) r.loading[static_cast<size_t>(i)] = 1;
  for (const auto& d : m.mass_damping) {
    if (d.all_nodes) r.loading.assign(n, 1);
    for (int i : d.nodes) r.loading[static_cast<size_t>(i)] = 1;
  }
  for (const auto& p : m.segment_pressures)
    for (const Segment& seg : p.segments)
      for (int k = 0; k < seg.corners(); ++k) r.loading[static_cast<size_t>(seg.n[k])] = 1;
  for (const auto& l : m.body_loads) {  // gravity loads every node (of its parts)
    if (l.all_nodes) r.loading.assign(n, 1);
    for (int i : l.nodes) r.loading[static_cast<size_t>(i)] = 1;
  }
  for (int i : m.history_nodes) r.history[static_cast<size_t>(i)] = 1;
  return r;
}

std::vector<int> listed(const std::vector<char>& flags) {
  std::vector<int> out;
  for (size_t i = 0; i < flags.size(); ++i)
    if (flags[i]) out.push_back(static_cast<int>(i));
  return out;
}

}  // namespace

std::string hourglass_warning(const Energies& e) {
  std::ostringstream s;
  for (size_t p = 0; p < e.part_ids.size(); ++p) {
    const double through = e.part_loading[p];
    if (!(through > 1e-6 * e.scale) || !(e.part_hourglass[p] > 0.1 * through)) continue;
    if (s.tellp() > 0) s << "; ";
    s << "part " << e.part_ids[p] << ": hourglass energy " << e.part_hourglass[p] << " J is "
      << 100.0 * e.part_hourglass[p] / through << " % of the internal work put into it, " << through << " J";
  }
  if (s.tellp() == 0) return "";
  s << " (bound 10 %): zero-energy modes carry part of the deformation; refine the mesh where the load is "
       "concentrated or spread the load over several nodes";
  return s.str();
}

StableStep Solver::stable_dt(const Model& m) {
  StableStep best;
  auto consider = [&](double dt, const std::string& what, const char* kind = "", int id = 0) {
    if (dt < best.dt) {
      best.dt = dt;
      best.limited_by = what;
      best.element_kind = kind;
      best.element_id = id;
    }
  };
  for (const auto& d : m.discretes) {
    if (!(d.k > 0.0)) continue;
    // Two masses on a spring: ω² = k (1/m1 + 1/m2); stable for ω·Δt ≤ 2.
    const double inv = 1.0 / moving_mass(m, d.n1) + 1.0 / moving_mass(m, d.n2);
    if (!(inv > 0.0)) continue;
    std::ostringstream s;
    s << "discrete element " << d.id << " (" << d.where.str() << ", k = " << d.k << " N/m)";
    consider(2.0 / std::sqrt(d.k * inv), s.str(), "discrete", d.id);
  }
  for (const auto& e : m.bars) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const double L = (m.x0[static_cast<size_t>(e.n2)] - m.x0[static_cast<size_t>(e.n1)]).norm();
    consider(L / std::sqrt(mat.E / (mat.rho * e.mass_scale)),
             "bar element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")", "beam", e.id);
  }
  for (const auto& e : m.solids) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const double dt_e =
        solid_stable_step(hex8_gather(m.x0, e), e, mat.lambda(), mat.mu(), mat.rho * e.mass_scale, m.bulk_q2,
                          m.parts.at(e.part).stiffness_damping);
    if (dt_e > 0.0)  // 0: inverted, which the reader refuses
      consider(dt_e, "solid element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")", "solid", e.id);
  }
  for (const auto& e : m.axis) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    bool fixed_r[4];
    for (int k = 0; k < 4; ++k) fixed_r[k] = m.fixed[static_cast<size_t>(e.n[k])][0];
    const double dt_e =
        axi4_stable_step(axi4_gather(m.x0, e), mat.lambda(), mat.mu(), mat.rho * e.mass_scale, m.bulk_q2, fixed_r,
                         m.parts.at(e.part).stiffness_damping);
    if (dt_e > 0.0)
      consider(dt_e, "axisymmetric element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")", "shell",
               e.id);
  }
  return best;
}

Solver::Solver(const Model& model, double dt, const Domain& domain, const Partition* partition)
    : dom_(domain),
      part_(partition ? *partition : partition_elements(model, domain.size(), domain.rank())),
      m_(model),
      dt_(dt),
      bodies_(model, std::vector<char>(model.x0.size(), 0)),
      hex8_(model, part_.serial() ? nullptr : &part_.solid, part_.rank),
      axi4_(model, part_.serial() ? nullptr : &part_.axi, part_.rank),
      bars_(model, part_.serial() ? nullptr : &part_.bar, part_.rank) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::runtime_error("FE time step must be positive");
  if (part_.ranks != domain.size() || part_.rank != domain.rank() ||
      (!part_.serial() && (part_.solid.size() != model.solids.size() || part_.axi.size() != model.axis.size() ||
                           part_.bar.size() != model.bars.size())))
    throw std::logic_error("Solver: the partition is not one of this model on these ranks");
  if (!model.x0.empty()) {
    box_lo_ = box_hi_ = model.x0.front();
    for (const Vec3& x : model.x0) box_lo_ = box_lo_.cwiseMin(x), box_hi_ = box_hi_.cwiseMax(x);
    box_size_ = (box_hi_ - box_lo_).norm();
  }
  const StableStep crit = stable_dt(model);
  // 1e-12 relative: mass scaling sets the density for exactly dt = TSSFAC·Δt_e,
  // and the round-off of that density must not refuse its own step.
  if (dt > model.dt_scale * crit.dt * (1.0 + 1e-12)) {
    std::ostringstream s;
    s << "FE time step " << dt << " s exceeds the stable step " << crit.dt << " s × safety factor " << model.dt_scale
      << " (TSSFAC), limited by " << crit.limited_by
      << ": lower the coupling time step, raise the subcycles in the port configuration, or allow mass scaling "
         "(*CONTROL_TIMESTEP DT2MS < 0)";
    throw std::runtime_error(s.str());
  }
  dt_cap_ = dt_last_ = dt;
  for (const MassDamping& d : model.mass_damping) {
    double D = std::fabs(d.value);
    if (d.curve_id != 0) {  // the curve's largest value, as Curve::value scales and offsets it
      const Curve& c = model.curves.at(d.curve_id);
      for (double o : c.o) D = std::max(D, std::fabs(d.sf * (c.sfo * o + c.offo)));
    }
    D *= d.scale.cwiseAbs().maxCoeff();
    // The explicit damper −D·m·v decays a velocity by (1 − D·Δt) per step: at
    // D·Δt ≥ 1 it would reverse it.
    if (D * dt >= 1.0) {
      std::ostringstream s;
      s << d.where.str() << ": mass damping D = " << D << " 1/s with the FE step " << dt
        << " s reverses velocities (D·Δt ≥ 1): lower D below " << 1.0 / dt << " 1/s";
      throw std::runtime_error(s.str());
    }
  }
  if (!hex8_.elements.empty() || !axi4_.elements.empty()) {
    for (const auto& [pid, part] : model.parts) energies_.part_ids.push_back(pid);
    energies_.part_hourglass.assign(model.parts.size(), 0.0);
    energies_.part_loading.assign(model.parts.size(), 0.0);
    energies_.part_internal.assign(model.parts.size(), 0.0);
    part_internal_step_.assign(model.parts.size(), 0.0);
    part_hourglass_step_.assign(model.parts.size(), 0.0);
  }
  const size_t n = model.x0.size();
  x_ = model.x0;
  v_ = model.v0;
  mass_ = model.mass;
  for (auto* a : {&f_int_, &f_ext_, &f_ext_prev_, &f_con_, &f_con_prev_}) a->assign(n, Vec3::Zero());
  x_prev_ = x_;
  body_of_.assign(n, -1);
  for (size_t b = 0; b < model.rigid_bodies.size(); ++b)
    for (int i : model.rigid_bodies[b].nodes) body_of_[static_cast<size_t>(i)] = static_cast<int>(b);
  for (size_t k = 0; k < model.prescribed.size(); ++k) {
    const PrescribedMotion& p = model.prescribed[k];
    if (p.rigid_part == 0) continue;
    int body = -1;
    for (const auto& e : model.solids)
      if (e.part == p.rigid_part) body = body_of_[static_cast<size_t>(e.n[0])];
    for (const auto& e : model.axis)
      if (e.part == p.rigid_part) body = body_of_[static_cast<size_t>(e.n[0])];
    if (body < 0)
      throw std::runtime_error(p.where.str() + ": part " + std::to_string(p.rigid_part) + " has no rigid body elements to move");
    rigid_motions_.push_back({k, static_cast<size_t>(body), 0.0, 0.0, 0.0});
  }
  for (const PrescribedMotion& p : model.prescribed)
    for (int i : p.nodes)
      if (body_of_[static_cast<size_t>(i)] >= 0)
        throw std::runtime_error(p.where.str() + ": node " + std::to_string(model.node_ids[static_cast<size_t>(i)]) +
                                 " belongs to a rigid body: prescribe a node joined to the body by a spring, or "
                                 "a node of a deformable part");
  // The mass a body load accelerates: a node's own, scaled on a rigid body
  // so that its nodes carry the body's mass (*PART_INERTIA may differ from
  // the mesh's).
  if (!model.body_loads.empty()) {
    body_load_mass_ = model.mass;
    for (const auto& rb : model.rigid_bodies) {
      double sum = 0.0;
      for (int i : rb.nodes) sum += model.mass[static_cast<size_t>(i)];
      for (int i : rb.nodes)
        body_load_mass_[static_cast<size_t>(i)] =
            sum > 0.0 ? model.mass[static_cast<size_t>(i)] * rb.mass / sum : rb.mass / static_cast<double>(rb.nodes.size());
    }
  }
  // A body moves as one: its nodes start with v_c + ω × r.
  bodies_.initial_velocities(v_);
  v_prev_ = v_;
  // Free nodes: 1/m on each DOF that can move, 0 on a fixed one (their
  // velocity starts and stays zero): a, the boundary conditions and v in one multiply.
  inv_mass_free_.assign(n, Vec3::Zero());
  for (size_t i = 0; i < n; ++i)
    if (body_of_[i] < 0) {
      free_.push_back(static_cast<int>(i));
      for (int k = 0; k < 3; ++k) {
        if (model.fixed[i][k]) v_[i][k] = 0.0;
        inv_mass_free_[i][k] = model.fixed[i][k] || !(mass_[i] > 0.0) ? 0.0 : 1.0 / mass_[i];
      }
    }
  free_runs_ = runs_of(free_);
  for (const TieDef& d : model.ties) build_ties(d);
  build_node_lists();
  // Mobility of stage 6: a node alone, or its body's translation.
  group_.resize(n);
  group_inv_mass_.assign(n + model.rigid_bodies.size(), 0.0);
  group_free_.assign(n + model.rigid_bodies.size(), Vec3::Ones());
  for (size_t i = 0; i < n; ++i) {
    const int b = body_of_[i];
    group_[i] = b >= 0 ? static_cast<int>(n) + b : static_cast<int>(i);
    if (b < 0) {
      group_inv_mass_[i] = mass_[i] > 0.0 ? 1.0 / mass_[i] : 0.0;
      for (int k = 0; k < 3; ++k) group_free_[i][k] = model.fixed[i][k] ? 0.0 : 1.0;
    }
  }
  for (size_t b = 0; b < bodies_.size(); ++b) {
    group_inv_mass_[n + b] = 1.0 / bodies_[b].mass;
    group_free_[n + b] = bodies_[b].free_translation;
  }
  group_force_.assign(group_free_.size(), Vec3::Zero());
  group_moment_.assign(bodies_.size(), Vec3::Zero());
  group_touched_.assign(group_free_.size(), 0);
  // Contact sees the mass that moves with each node (a rigid body's whole mass).
  contact_mass_ = mass_;
  for (size_t i = 0; i < n; ++i)
    if (body_of_[i] >= 0) contact_mass_[i] = model.rigid_bodies[static_cast<size_t>(body_of_[i])].mass;
  // Cross sections: the slots of their elements' corners on the cut.
  std::vector<int> hex_pos(model.solids.size(), -1), axi_pos(model.axis.size(), -1);
  for (size_t k = 0; k < hex8_.elements.size(); ++k) hex_pos[static_cast<size_t>(hex8_.elements[k])] = static_cast<int>(k);
  for (size_t k = 0; k < axi4_.elements.size(); ++k) axi_pos[static_cast<size_t>(axi4_.elements[k])] = static_cast<int>(k);
  for (const CrossSection& cs : model.cross_sections) {
    // The slots of this rank's elements (across ranks the others' forces
    // come in the exchange of stage 1); the check is on every element.
    SectionSlots slots;
    bool any_on_cut = false;
    auto on_cut = [&](int node) { return std::binary_search(cs.nodes.begin(), cs.nodes.end(), node); };
    for (int e : cs.solids)
      for (int a = 0; a < 8; ++a)
        if (on_cut(model.solids[static_cast<size_t>(e)].n[a])) {
          any_on_cut = true;
          if (hex_pos[static_cast<size_t>(e)] >= 0) slots.hex.push_back(24 * hex_pos[static_cast<size_t>(e)] + 3 * a);
        }
    for (int e : cs.axis)
      for (int a = 0; a < 4; ++a)
        if (on_cut(model.axis[static_cast<size_t>(e)].n[a])) {
          any_on_cut = true;
          if (axi_pos[static_cast<size_t>(e)] >= 0) slots.axi.push_back(8 * axi_pos[static_cast<size_t>(e)] + 2 * a);
        }
    for (int e : cs.bars) {
      const bool here = part_.owns_bar(static_cast<size_t>(e));
      for (int end : {0, 1})
        if (on_cut(end == 0 ? model.bars[static_cast<size_t>(e)].n1 : model.bars[static_cast<size_t>(e)].n2)) {
          any_on_cut = true;
          if (here) slots.bar_ends.emplace_back(e, end);
        }
    }
    if (!any_on_cut)
      throw std::runtime_error(cs.where.str() + ": cross section " + std::to_string(cs.id) +
                               ": none of its elements has a node on the cut (NSID)");
    sections_.push_back(std::move(slots));
  }
  section_total_.assign(sections_.size(), Vec3::Zero());
  for (const auto& c : model.contacts) {
    contacts_.push_back(std::make_unique<PenaltyContact>(model, c, dt, contact_mass_));
    contacts_.back()->refuse_initial_penetration(model, c, x_);
  }
}

void Solver::build_node_lists() {
  const size_t n = m_.x0.size();
  NodeReach r = node_reach(m_);
  // A user load declares its nodes; one that does not may load any node.
  std::vector<int> declared;
  const bool load_declared = !user_load_ || user_load_->loaded_nodes(declared);
  if (user_load_) {
    if (load_declared)
      for (int i : declared) r.loading[static_cast<size_t>(i)] = 1;
    else
      r.loading.assign(n, 1);
  }
  int_nodes_ = listed(r.internal);
  con_nodes_ = listed(r.contact);
  ext_nodes_ = user_load_ || !m_.prescribed.empty() || !m_.body_loads.empty() || !m_.segment_pressures.empty() ||
                       !m_.mass_damping.empty() || !m_.nodal_loads.empty()
                   ? listed(r.loading)
                   : std::vector<int>();
  std::vector<char> live(n, 0), active(n, 0);
  for (size_t i = 0; i < n; ++i) {
    live[i] = r.internal[i] || r.contact[i] || r.loading[i] || r.history[i];
    active[i] = body_of_[i] < 0 || live[i];
  }
  bodies_.set_live(live);
  if (dom_.parallel()) {
    // Global: everything but element forces reads or loads them.
    std::vector<char> global(n, 0);
    for (size_t i = 0; i < n; ++i)
      global[i] = r.contact[i] || r.loading[i] || r.history[i] || (body_of_[i] >= 0 && live[i]);
    for (const Tie& t : ties_) {
      global[static_cast<size_t>(t.slave)] = 1;
      for (int k = 0; k < t.corners; ++k) global[static_cast<size_t>(t.master[k])] = 1;
    }
    for (const auto& d : m_.discretes) global[static_cast<size_t>(d.n1)] = global[static_cast<size_t>(d.n2)] = 1;
    for (const auto& cs : m_.cross_sections)
      for (int i : cs.nodes) global[static_cast<size_t>(i)] = 1;
    for (int e : m_.history_bars)
      global[static_cast<size_t>(m_.bars[static_cast<size_t>(e)].n1)] =
          global[static_cast<size_t>(m_.bars[static_cast<size_t>(e)].n2)] = 1;
    plan_ranks(global);
    auto held = [&](size_t i) {
      const auto& s = sharers_[i];
      return std::binary_search(s.begin(), s.end(), dom_.rank());
    };
    // This rank's nodes only; f_int is zeroed on the shared ones too (the
    // exchange writes their totals there).
    for (size_t i = 0; i < n; ++i) {
      active[i] = active[i] && held(i);
      r.internal[i] = held(i) && (r.internal[i] || sharers_[i].size() > 1);
    }
    int_nodes_ = listed(r.internal);
    free_.clear();
    mass_ke_.assign(n, 0.0);
    for (size_t i = 0; i < n; ++i)
      if (body_of_[i] < 0 && held(i)) {
        free_.push_back(static_cast<int>(i));
        if (sharers_[i].front() == dom_.rank()) mass_ke_[i] = mass_[i];  // counted by the lowest rank that holds it
      }
    free_runs_ = runs_of(free_);
  }
  active_ = listed(active);
  interior_placed_ = false;
}

void Solver::plan_ranks(const std::vector<char>& global) {
  const size_t n = m_.x0.size();
  const int ranks = dom_.size(), me = dom_.rank();
  sharers_.assign(n, {});
  auto add = [&](int node, int rank) {
    auto& s = sharers_[static_cast<size_t>(node)];
    auto at = std::lower_bound(s.begin(), s.end(), rank);
    if (at == s.end() || *at != rank) s.insert(at, rank);
  };
  for (size_t e = 0; e < m_.solids.size(); ++e)
    if (part_.solid[e] >= 0)
      for (int k : m_.solids[e].n) add(k, part_.solid[e]);
  for (size_t e = 0; e < m_.axis.size(); ++e)
    if (part_.axi[e] >= 0)
      for (int k : m_.axis[e].n) add(k, part_.axi[e]);
  for (size_t e = 0; e < m_.bars.size(); ++e)
    if (part_.bar[e] >= 0) add(m_.bars[e].n1, part_.bar[e]), add(m_.bars[e].n2, part_.bar[e]);
  std::vector<int> all(static_cast<size_t>(ranks));
  for (int q = 0; q < ranks; ++q) all[static_cast<size_t>(q)] = q;
  for (size_t i = 0; i < n; ++i) {
    if (global[i]) sharers_[i] = all;
    if (sharers_[i].empty()) sharers_[i] = {0};  // a node of nothing (or a rigid body's interior): rank 0's
  }
  // The exchange: per peer the shared nodes in ascending order, and per
  // shared node where each rank's partial force will be, in rank order.
  ex_ = Exchange{};
  std::vector<int> peer_index(static_cast<size_t>(ranks), -1);
  for (size_t i = 0; i < n; ++i) {
    const auto& s = sharers_[i];
    if (s.size() < 2 || !std::binary_search(s.begin(), s.end(), me)) continue;
    ex_.shared.push_back(static_cast<int>(i));
    for (int q : s)
      if (q != me && peer_index[static_cast<size_t>(q)] < 0) peer_index[static_cast<size_t>(q)] = 0;
  }
  for (int q = 0; q < ranks; ++q)
    if (peer_index[static_cast<size_t>(q)] == 0) {
      peer_index[static_cast<size_t>(q)] = static_cast<int>(ex_.peers.size());
      ex_.peers.push_back(q);
    }
  ex_.nodes.assign(ex_.peers.size(), {});
  ex_.first.push_back(0);
  for (int i : ex_.shared) {
    for (int q : sharers_[static_cast<size_t>(i)]) {
      if (q == me) {
        ex_.sources.emplace_back(-1, 0);
        continue;
      }
      auto& list = ex_.nodes[static_cast<size_t>(peer_index[static_cast<size_t>(q)])];
      ex_.sources.emplace_back(peer_index[static_cast<size_t>(q)], 3 * list.size());
      list.push_back(i);
    }
    ex_.first.push_back(ex_.sources.size());
  }
  ex_.send.resize(ex_.peers.size());
  ex_.recv.resize(ex_.peers.size());
  for (size_t k = 0; k < ex_.peers.size(); ++k) {
    ex_.send[k].assign(3 * ex_.nodes[k].size(), 0.0);
    ex_.recv[k].assign(3 * ex_.nodes[k].size(), 0.0);
  }
}

template <class F>
void Solver::for_each_node(const std::vector<int>& nodes, F&& f) {
  const size_t n = nodes.size(), blocks = (n + kNodeBlock - 1) / kNodeBlock;
  auto block = [&](size_t b) {
    const size_t end = std::min(n, (b + 1) * kNodeBlock);
    for (size_t k = b * kNodeBlock; k < end; ++k) f(static_cast<size_t>(nodes[k]));
  };
  run_blocks(blocks, blocks > 1 ? pool_.get() : nullptr, block);
}

Solver::NodeRuns Solver::runs_of(const std::vector<int>& nodes) {
  NodeRuns r;
  for (size_t k = 0; k < nodes.size(); ++k) {
    if (k % kNodeBlock == 0) r.block_start.push_back(r.runs.size());
    const size_t i = static_cast<size_t>(nodes[k]);
    if (k % kNodeBlock != 0 && r.runs.back().second == i)
      ++r.runs.back().second;
    else
      r.runs.emplace_back(i, i + 1);
  }
  r.block_start.push_back(r.runs.size());
  return r;
}

template <class R>
void Solver::for_each_run(const NodeRuns& r, R&& run) {
  const size_t blocks = r.block_start.size() - 1;
  auto block = [&](size_t b) {
    for (size_t k = r.block_start[b]; k < r.block_start[b + 1]; ++k) run(b, r.runs[k].first, r.runs[k].second);
  };
  run_blocks(blocks, blocks > 1 ? pool_.get() : nullptr, block);
}

template <class G>
double Solver::sum_over(const std::vector<int>& nodes, G&& g) {
  const size_t n = nodes.size(), blocks = (n + kNodeBlock - 1) / kNodeBlock;
  if (partial_.size() < blocks) partial_.resize(blocks);  // grows once, to the longest list
  auto block = [&](size_t b) {
    const size_t end = std::min(n, (b + 1) * kNodeBlock);
    double sum = 0.0;
    for (size_t k = b * kNodeBlock; k < end; ++k) sum += g(static_cast<size_t>(nodes[k]));
    partial_[b] = sum;
  };
  run_blocks(blocks, blocks > 1 ? pool_.get() : nullptr, block);
  double total = 0.0;
  for (size_t b = 0; b < blocks; ++b) total += partial_[b];
  return total;
}

void Solver::set_threads(int threads) {
  pool_ = threads > 1 ? std::make_unique<ThreadPool>(threads) : nullptr;
}

int Solver::threads() const { return pool_ ? pool_->threads() : 1; }

void Solver::set_user_load(UserLoad* load) {
  // Its nodes become live from here on; a rigid body's interior nodes are
  // only current at t = 0 (and x_prev_ with them), so the hook is set before the first step.
  if (n_ > 0) throw std::logic_error("Solver::set_user_load after the first step");
  user_load_ = load;
  build_node_lists();
}

const std::vector<Vec3>& Solver::x() const {
  if (!interior_placed_) {
    bodies_.place_interior(x_, v_);
    interior_placed_ = true;
  }
  return x_;
}

const std::vector<Vec3>& Solver::v() const {
  x();
  return v_;
}

double Solver::max_penetration() const {
  double p = 0.0;
  for (const auto& c : contacts_) p = std::max(p, c->max_penetration());
  return p;
}

double Solver::bar_stress(size_t e) const { return bars_.force[e] / bars_.area[e]; }

Vec3 Solver::section_force(size_t k) const { return dom_.parallel() ? section_total_[k] : local_section_force(k); }

Vec3 Solver::local_section_force(size_t k) const {
  const SectionSlots& sl = sections_[k];
  Vec3 f = Vec3::Zero();
  for (int slot : sl.hex) f += Vec3(hex8_.force[static_cast<size_t>(slot)], hex8_.force[static_cast<size_t>(slot) + 1],
                                    hex8_.force[static_cast<size_t>(slot) + 2]);
  for (int slot : sl.axi) f += Vec3(axi4_.force[static_cast<size_t>(slot)], axi4_.force[static_cast<size_t>(slot) + 1], 0.0);
  for (const auto& [e, end] : sl.bar_ends) {
    const BarElement& b = m_.bars[static_cast<size_t>(e)];
    const Vec3 axis = (x_[static_cast<size_t>(b.n2)] - x_[static_cast<size_t>(b.n1)]).normalized();
    f += (end == 0 ? 1.0 : -1.0) * bars_.force[static_cast<size_t>(e)] * axis;  // as bar_forces adds them
  }
  return f;
}

double Solver::bar_axial_velocity(size_t e) const {
  const size_t i = static_cast<size_t>(m_.bars[e].n1), j = static_cast<size_t>(m_.bars[e].n2);
  const Vec3 axis = (x_prev_[j] - x_prev_[i]).normalized();
  return 0.5 * (velocity_at_stress_time(i) + velocity_at_stress_time(j)).dot(axis);
}

void Solver::reduce_element_work(ElementWork& w, const std::string& error) {
  // Shared nodes: this rank's partial forces to each peer, then every
  // contribution summed in rank order (the same bits on every rank).
  for (size_t k = 0; k < ex_.peers.size(); ++k) {
    double* out = ex_.send[k].data();
    for (int i : ex_.nodes[k])
      for (int c = 0; c < 3; ++c) *out++ = f_int_[static_cast<size_t>(i)][c];
  }
  dom_.exchange(ex_.peers, ex_.send, ex_.recv);
  for (size_t k = 0; k < ex_.shared.size(); ++k) {
    const size_t i = static_cast<size_t>(ex_.shared[k]);
    Vec3 sum = Vec3::Zero();
    for (size_t j = ex_.first[k]; j < ex_.first[k + 1]; ++j) {
      const auto [peer, at] = ex_.sources[j];
      sum += peer < 0 ? f_int_[i] : Vec3(ex_.recv[static_cast<size_t>(peer)][at], ex_.recv[static_cast<size_t>(peer)][at + 1],
                                         ex_.recv[static_cast<size_t>(peer)][at + 2]);
    }
    f_int_[i] = sum;
  }
  // Scalars, one row per rank: an error flag, the element energies, the
  // history elements' state (from their owner, zeros elsewhere: exact),
  // this rank's share of each cross section's force.
  std::vector<double>& row = scalars_mine_;
  row.clear();
  row.push_back(error.empty() ? 0.0 : 1.0);
  row.insert(row.end(), {w.internal, w.hourglass, w.damping_power, w.spring_energy});
  row.insert(row.end(), part_internal_step_.begin(), part_internal_step_.end());
  row.insert(row.end(), part_hourglass_step_.begin(), part_hourglass_step_.end());
  for (int el : m_.history_solids) {
    const size_t e = static_cast<size_t>(el);
    const bool mine = part_.solid[e] == dom_.rank();
    for (int c = 0; c < 6; ++c) row.push_back(mine ? hex8_.sigma[e][c] : 0.0);
    row.push_back(mine ? hex8_.plastic_strain[e] : 0.0);
  }
  for (int el : m_.history_axis) {
    const size_t e = static_cast<size_t>(el);
    const bool mine = part_.axi[e] == dom_.rank();
    for (int c = 0; c < 6; ++c) row.push_back(mine ? axi4_.sigma[e][c] : 0.0);
    row.push_back(mine ? axi4_.plastic_strain[e] : 0.0);
  }
  for (int el : m_.history_bars) row.push_back(part_.bar[static_cast<size_t>(el)] == dom_.rank() ? bars_.force[static_cast<size_t>(el)] : 0.0);
  for (size_t k = 0; k < sections_.size(); ++k) {
    const Vec3 f = local_section_force(k);
    row.insert(row.end(), {f.x(), f.y(), f.z()});
  }
  row.insert(row.end(), {w.step_limit, static_cast<double>(w.limit_kind), static_cast<double>(w.limit_element)});
  const size_t width = row.size();
  dom_.sum_in_rank_order(row, scalars_all_);
  const std::vector<double>& total = row;
  if (total[0] != 0.0) {  // the lowest rank with an error tells its message
    int from = 0;
    while (scalars_all_[static_cast<size_t>(from) * width] == 0.0) ++from;
    char text[1024] = {0};
    if (dom_.rank() == from) std::snprintf(text, sizeof text, "%s", error.c_str());
    dom_.broadcast(text, sizeof text, from);
    throw std::runtime_error(std::string(text) + " (on rank " + std::to_string(from) + ")");
  }
  size_t j = 1;
  w.internal = total[j++], w.hourglass = total[j++], w.damping_power = total[j++], w.spring_energy = total[j++];
  for (double& v : part_internal_step_) v = total[j++];
  for (double& v : part_hourglass_step_) v = total[j++];
  for (int el : m_.history_solids) {
    const size_t e = static_cast<size_t>(el);
    for (int c = 0; c < 6; ++c) hex8_.sigma[e][c] = total[j++];
    hex8_.plastic_strain[e] = total[j++];
  }
  for (int el : m_.history_axis) {
    const size_t e = static_cast<size_t>(el);
    for (int c = 0; c < 6; ++c) axi4_.sigma[e][c] = total[j++];
    axi4_.plastic_strain[e] = total[j++];
  }
  for (int el : m_.history_bars) bars_.force[static_cast<size_t>(el)] = total[j++];
  for (Vec3& f : section_total_) f = Vec3(total[j], total[j + 1], total[j + 2]), j += 3;
  // The step limit: the smallest of the ranks' (the lowest rank's on a tie), the same on every rank.
  w.step_limit = 1e300;
  for (int r = 0; r < dom_.size(); ++r) {
    const double* theirs = &scalars_all_[static_cast<size_t>(r) * width + j];
    if (theirs[0] < w.step_limit)
      w.step_limit = theirs[0], w.limit_kind = static_cast<int>(theirs[1]), w.limit_element = static_cast<long>(theirs[2]);
  }
}

void Solver::gather_fields(std::vector<Vec3>& x, std::vector<Vec3>& v, std::vector<Eigen::Matrix<double, 6, 1>>& stress,
                           std::vector<double>& plastic, bool axisymmetric) const {
  const size_t n = m_.x0.size(), ne = axisymmetric ? m_.axis.size() : m_.solids.size();
  const std::vector<Vec3>& xs = this->x();  // places the bodies' interior nodes
  auto stress_of = [&](size_t e) -> const Eigen::Matrix<double, 6, 1>& { return axisymmetric ? axi4_.sigma[e] : hex8_.sigma[e]; };
  auto plastic_of = [&](size_t e) { return axisymmetric ? axi4_.plastic_strain[e] : hex8_.plastic_strain[e]; };
  if (!dom_.parallel()) {
    x = xs, v = v_;
    stress.resize(ne), plastic.resize(ne);
    for (size_t e = 0; e < ne; ++e) stress[e] = stress_of(e), plastic[e] = plastic_of(e);
    return;
  }
  // Each value from one rank (the node's lowest holder, the element's
  // owner), zeros elsewhere: the sum at rank 0 is exact.
  std::vector<double> buf(6 * n + 7 * ne, 0.0);
  for (size_t i = 0; i < n; ++i)
    if (sharers_[i].front() == dom_.rank())
      for (int c = 0; c < 3; ++c) buf[6 * i + static_cast<size_t>(c)] = xs[i][c], buf[6 * i + 3 + static_cast<size_t>(c)] = v_[i][c];
  const std::vector<int>& owner = axisymmetric ? part_.axi : part_.solid;
  for (size_t e = 0; e < ne; ++e)
    if (owner[e] == dom_.rank()) {
      for (int c = 0; c < 6; ++c) buf[6 * n + 7 * e + static_cast<size_t>(c)] = stress_of(e)[c];
      buf[6 * n + 7 * e + 6] = plastic_of(e);
    }
  dom_.sum_at_root(buf.data(), buf.size());
  if (dom_.rank() != 0) return;
  x.resize(n), v.resize(n), stress.resize(ne), plastic.resize(ne);
  for (size_t i = 0; i < n; ++i)
    x[i] = Vec3(buf[6 * i], buf[6 * i + 1], buf[6 * i + 2]), v[i] = Vec3(buf[6 * i + 3], buf[6 * i + 4], buf[6 * i + 5]);
  for (size_t e = 0; e < ne; ++e) {
    for (int c = 0; c < 6; ++c) stress[e][c] = buf[6 * n + 7 * e + static_cast<size_t>(c)];
    plastic[e] = buf[6 * n + 7 * e + 6];
  }
}

void Solver::gather_velocities(std::vector<Vec3>& v) const {
  const std::vector<Vec3>& vs = this->v();  // places the bodies' interior nodes
  if (!dom_.parallel()) {
    v = vs;
    return;
  }
  const size_t n = vs.size();
  std::vector<double> buf(3 * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    if (sharers_[i].front() == dom_.rank())
      for (int c = 0; c < 3; ++c) buf[3 * i + static_cast<size_t>(c)] = vs[i][c];
  dom_.sum_at_root(buf.data(), buf.size());
  if (dom_.rank() != 0) return;
  v.resize(n);
  for (size_t i = 0; i < n; ++i) v[i] = Vec3(buf[3 * i], buf[3 * i + 1], buf[3 * i + 2]);
}

void Solver::internal_forces() {
  for_each_node(int_nodes_, [&](size_t i) { f_int_[i].setZero(); });
  ElementWork w;
  std::fill(part_internal_step_.begin(), part_internal_step_.end(), 0.0);
  std::fill(part_hourglass_step_.begin(), part_hourglass_step_.end(), 0.0);
  w.part_internal = &part_internal_step_;
  w.part_hourglass = &part_hourglass_step_;
  std::string error;
  try {
    if (part_.owns_discretes()) discrete_forces(m_, x_, v_, f_int_, w);
    bar_forces(m_, bars_, x_, v_, dt_, f_int_, w);
    hex8_forces(m_, hex8_, x_, v_, dt_, f_int_, w, pool_.get());
    axi4_forces(m_, axi4_, x_, v_, dt_, f_int_, w, pool_.get());
  } catch (const InvertedElement& e) {
    std::ostringstream s;
    // A volume that is not a number is a state gone non-finite (a load or a
    // velocity of the last step), not a crushed element: named as such.
    const std::string first = first_non_finite();
    if (!first.empty() && first.find("another rank") == std::string::npos)
      s << "the FE state is no longer finite at t = " << t_ << " s, step " << n_ << " (" << e.element << ": "
        << e.measure << first << "): check the loads (in a co-simulation, the host's values) and the step";
    else
      s << e.element << " inverted at t = " << t_ << " s, step " << n_ << " (" << e.measure
        << "): the mesh is too coarse for this deformation, or the step is too large";
    error = s.str();
  }
  if (dom_.parallel())
    reduce_element_work(w, error);
  else if (!error.empty())
    throw std::runtime_error(error);
  energies_.internal += w.internal;
  energies_.hourglass += w.hourglass;
  for (size_t p = 0; p < part_internal_step_.size(); ++p) {
    energies_.part_hourglass[p] += part_hourglass_step_[p];
    energies_.part_internal[p] += part_internal_step_[p];
    if (part_internal_step_[p] > 0.0) energies_.part_loading[p] += part_internal_step_[p];
  }
  damping_power_ = w.damping_power;
  energies_.spring = w.spring_energy;
  step_limit_ = w.step_limit, limit_kind_ = w.limit_kind, limit_element_ = w.limit_element;
}

std::string Solver::limiting_element() const {
  if (limit_kind_ == 1) {
    const SolidElement& e = m_.solids[static_cast<size_t>(limit_element_)];
    return "solid element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")";
  }
  if (limit_kind_ == 2) {
    const AxiElement& e = m_.axis[static_cast<size_t>(limit_element_)];
    return "axisymmetric element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")";
  }
  return "no element";
}

void Solver::choose_step() {
  dt_last_ = dt_;
  // TSSFAC times the smallest current stable step, never above the step
  // the run was started with (the user's, or the coupling step over its
  // subcycles): a model whose elements never shrink keeps that step to the bit.
  const double limit = m_.dt_scale * step_limit_;
  double next = std::min(dt_cap_, limit);
  if (next < kMinStepShare * dt_cap_) {
    std::ostringstream s;
    s << "at t = " << t_ << " s, step " << n_ << ": the stable step has fallen to " << step_limit_ << " s, "
      << step_limit_ / dt_cap_ * 100.0 << " % of the step the run started with (" << dt_cap_ << " s), limited by "
      << limiting_element()
      << ", which is being crushed: the run would take ever more steps for ever less time. Refine the mesh where it "
         "flattens, or check the loads";
    throw std::runtime_error(s.str());
  }
  if (next < dt_) ++shrunk_steps_;
  last_of_horizon_ = false;
  if (horizon_ > t_) {
    // Land on the horizon: the remaining time in a whole number of steps
    // of at most `next`. A run at its start step keeps it exactly.
    const double remaining = horizon_ - t_;
    const double whole = std::round(remaining / dt_cap_);
    if (next == dt_cap_ && whole >= 1.0 && std::fabs(remaining / dt_cap_ - whole) < 1e-6) {
      last_of_horizon_ = whole == 1.0;
    } else {
      const double k = std::max(1.0, std::ceil(remaining / next - 1e-9));
      next = remaining / k;
      last_of_horizon_ = k == 1.0;
    }
  }
  dt_ = next;
}

double Solver::step_work(const std::vector<Vec3>& f_prev, const std::vector<Vec3>& f,
                         const std::vector<int>& nodes) {
  if (n_ == 0) return 0.0;
  return sum_over(nodes, [&](size_t i) { return 0.5 * (f_prev[i] + f[i]).dot(x_[i] - x_prev_[i]); });
}

void Solver::user_loads() {
  f_ext_prev_.swap(f_ext_);
  for_each_node(ext_nodes_, [&](size_t i) { f_ext_[i].setZero(); });
  if (user_load_) user_load_->apply(t_, x_, v_, f_ext_);
  body_loads();
  segment_pressures();
  nodal_loads();
  damping();
  // Their work is accounted in external_work, once stage 6 has added the
  // forces that depend on v_{n+1/2}.
}

bool Solver::curve_acts(int curve_id) const {
  const int sidr = m_.curves.at(curve_id).sidr;
  return relaxing_ ? sidr >= 1 : sidr != 1;
}

void Solver::body_loads() {
  for (const BodyLoad& l : m_.body_loads) {
    // In the relaxation LCIDDR if given (whatever its SIDR), else LCID if its curve acts there.
    const bool own_dr_curve = relaxing_ && l.curve_dr_id != 0;
    const int id = own_dr_curve ? l.curve_dr_id : l.curve_id;
    if (!own_dr_curve && !curve_acts(id)) continue;
    const double a = l.sf * m_.curves.at(id).value(t_);
    if (a == 0.0) continue;
    const int d = l.dof;
    for_each_node(l.all_nodes ? ext_nodes_ : l.nodes, [&](size_t i) { f_ext_[i][d] -= body_load_mass_[i] * a; });
  }
}

void Solver::nodal_loads() {
  for (const NodalLoad& l : m_.nodal_loads)
    if (curve_acts(l.curve_id)) {
      const double F = l.sf * m_.curves.at(l.curve_id).value(t_);
      for (int i : l.nodes) f_ext_[static_cast<size_t>(i)][l.dof] += F;
    }
}

void Solver::damping() {
  // −D·m·v with v = v_{n−1/2}: explicit; D·Δt < 1 (checked at construction
  // against the curve's largest value) keeps it from reversing a velocity.
  for (const MassDamping& d : m_.mass_damping) {
    if (d.curve_id != 0 && !curve_acts(d.curve_id)) continue;
    const double D = d.curve_id != 0 ? d.sf * m_.curves.at(d.curve_id).value(t_) : d.value;
    if (D == 0.0) continue;
    for_each_node(d.all_nodes ? ext_nodes_ : d.nodes, [&](size_t i) {
      if (body_of_[i] < 0) f_ext_[i] -= D * mass_[i] * d.scale.cwiseProduct(v_[i]);
    });
  }
}

void Solver::segment_pressures() {
  for (const SegmentPressure& p : m_.segment_pressures) {
    if (t_ < p.at || !curve_acts(p.curve_id)) continue;
    const double pressure = p.sf * m_.curves.at(p.curve_id).value(t_ - p.at);
    if (pressure == 0.0) continue;
    for (const Segment& seg : p.segments) {
      const Vec3 f = -pressure * segment_area_vector(seg, x_);
      double w[4];
      segment_corner_weights(seg, x_, w);
      for (int k = 0; k < seg.corners(); ++k) f_ext_[static_cast<size_t>(seg.n[k])] += w[k] * f;
    }
  }
}

void Solver::contact() {
  if (contacts_.empty()) return;  // f_con_ stays zero: no per-node work in models without contact
  f_con_prev_.swap(f_con_);
  for_each_node(con_nodes_, [&](size_t i) { f_con_[i].setZero(); });
  for (size_t k = 0; k < contacts_.size(); ++k) {
    PenaltyContact& c = *contacts_[k];
    c.apply(x_, v_, f_con_, n_);
    // A penalty contact that holds keeps its nodes shallow (bars at 20 m/s:
    // below 5 % of the element, HardCase.ImpactAtTwenty…); a node a fifth of an element
    // deep is on its way through (1000 m/s passed straight through). Every
    // rank computes the contacts alike: all stop together.
    if (c.fastest_step() > 0.5 * c.element_size() && c.fastest_node() >= 0) {
      std::ostringstream s;
      s << "at t = " << t_ << " s, step " << n_ << ": contact " << k + 1 << " (" << m_.contacts[k].where.str()
        << "): node " << m_.node_ids[static_cast<size_t>(c.fastest_node())] << " moves " << c.fastest_step() * 1e3
        << " mm per step, more than half the contact's element size " << c.element_size() * 1e3
        << " mm: it can pass through a face within one step, unseen by the contact (an impact too fast for "
           "this step); lower the step (TSSFAC) to at most "
        << dt_ * 0.5 * c.element_size() / c.fastest_step() << " s";
      throw std::runtime_error(s.str());
    }
    if (c.max_penetration() > kMaxContactDepth * c.element_size()) {
      std::ostringstream s;
      s << "at t = " << t_ << " s, step " << n_ << ": contact " << k + 1 << " (" << m_.contacts[k].where.str()
        << "): node " << m_.node_ids[static_cast<size_t>(c.deepest_node())] << " is " << c.max_penetration() * 1e3
        << " mm behind the segment of nodes";
      for (int n : c.deepest_segment())
        if (n >= 0) s << " " << m_.node_ids[static_cast<size_t>(n)];
      s << ", more than " << kMaxContactDepth * 100 << " % of the contact's element size " << c.element_size() * 1e3
        << " mm: the bodies are passing through each other (an impact too fast for a penalty contact at this "
           "step); lower the step (TSSFAC) or refine the contact faces";
      throw std::runtime_error(s.str());
    }
  }
  // Energy taken by the contact: minus the work its forces did on the nodes.
  energies_.contact -= step_work(f_con_prev_, f_con_, con_nodes_);
  contact_force_stale_ = true;
}

double Solver::contact_force() const {
  if (contact_force_stale_) {
    double total = 0.0;
    for (int i : con_nodes_) total += f_con_[static_cast<size_t>(i)].norm();
    contact_force_ = 0.5 * total;
    contact_force_stale_ = false;
  }
  return contact_force_;
}

void Solver::accelerations() {
  // Free nodes: folded into velocities(). Rigid bodies: force and moment.
  bodies_.sum_loads(f_int_, f_ext_, f_con_, x_);
}

void Solver::velocities() {
  const double h = velocity_step();  // v_{1/2} = v_0 + Δt/2·a_0
  h_taken_ = h;
  // A tied slave node's force acts on its master segment's nodes (their
  // masses carry its mass: build_ties); it moves with them (stage 6c).
  for (const Tie& t : ties_) {
    const size_t s = static_cast<size_t>(t.slave);
    const Vec3 F = f_ext_[s] + f_int_[s] + f_con_[s];
    for (int k = 0; k < t.corners; ++k) f_int_[static_cast<size_t>(t.master[k])] += t.w[k] * F;
  }
  // a = (f_ext + f_int + f_con)/m, zero on fixed DOFs, and v += h·a in one pass.
  // Over flat arrays of doubles (a Vec3 is three in a row): the same
  // operations in the same order as v += h·m⁻¹∘(f_ext + f_int + f_con).
  double* v = v_.data()->data();
  double* vp = v_prev_.data()->data();
  const double *im = inv_mass_free_.data()->data(), *fe = f_ext_.data()->data(), *fi = f_int_.data()->data(),
               *fc = f_con_.data()->data();
  for_each_run(free_runs_, [&](size_t, size_t first, size_t end) {
    for (size_t j = 3 * first; j < 3 * end; ++j) {
      vp[j] = v[j];
      v[j] += h * (im[j] * ((fe[j] + fi[j]) + fc[j]));
    }
  });
  bodies_.advance_velocities(h, dt_, x_, v_, v_prev_);
  if (relaxing_) {  // dynamic relaxation: every velocity times DRFCTR
    const double f = m_.relaxation.drfctr;
    for_each_node(free_, [&](size_t i) { v_[i] *= f; });
    bodies_.scale_velocities(f, x_, v_);
  }
}

namespace {
// The shape functions N_a(ξ, η) of a 4-node segment at the foot of point p
// (Gauss–Newton on (x(ξ, η) − p)·∂x/∂ξ_i = 0 from the centre; a flat or
// gently warped quad converges in a few iterations).
void bilinear_weights(const Segment& seg, const Vec3& p, const std::vector<Vec3>& x, double w[4]) {
  static constexpr double kXi[4] = {-1, 1, 1, -1}, kEta[4] = {-1, -1, 1, 1};
  double xi = 0.0, eta = 0.0;
  for (int it = 0; it < 20; ++it) {
    Vec3 r = -p, t1 = Vec3::Zero(), t2 = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      const Vec3& xa = x[static_cast<size_t>(seg.n[a])];
      r += 0.25 * (1 + kXi[a] * xi) * (1 + kEta[a] * eta) * xa;
      t1 += 0.25 * kXi[a] * (1 + kEta[a] * eta) * xa;
      t2 += 0.25 * kEta[a] * (1 + kXi[a] * xi) * xa;
    }
    const double a11 = t1.dot(t1), a12 = t1.dot(t2), a22 = t2.dot(t2), det = a11 * a22 - a12 * a12;
    if (!(det > 0.0)) break;
    const double b1 = -r.dot(t1), b2 = -r.dot(t2);
    const double dxi = (a22 * b1 - a12 * b2) / det, deta = (a11 * b2 - a12 * b1) / det;
    xi += dxi, eta += deta;
    if (std::fabs(dxi) + std::fabs(deta) < 1e-14) break;
  }
  for (int a = 0; a < 4; ++a) w[a] = 0.25 * (1 + kXi[a] * xi) * (1 + kEta[a] * eta);
}
}  // namespace

void Solver::tied_nodes() {
  for (const Tie& t : ties_) {
    Vec3 v = Vec3::Zero();
    for (int k = 0; k < t.corners; ++k) v += t.w[k] * v_[static_cast<size_t>(t.master[k])];
    v_[static_cast<size_t>(t.slave)] = v;
  }
}

void Solver::build_ties(const TieDef& def) {
  const auto& master = m_.segment_sets.at(def.master_set);
  std::vector<int> slaves;
  if (def.slave_nodes) {
    for (int id : m_.node_sets.at(def.slave_set)) slaves.push_back(m_.index_of(id, def.where));
  } else {
    std::set<int> unique;
    for (const auto& seg : m_.segment_sets.at(def.slave_set))
      for (int k = 0; k < seg.corners(); ++k) unique.insert(seg.n[k]);
    slaves.assign(unique.begin(), unique.end());
  }
  double size = 0.0;
  for (const auto& seg : master) size += segment_size(seg, x_);
  size = master.empty() ? 0.0 : size / static_cast<double>(master.size());
  std::vector<double> added(x_.size(), 0.0);
  long free_nodes = 0;
  for (int s : slaves) {
    // The master segment the node lies on (the nearest, where it is on an edge).
    double best = 0.1 * size, g = 0.0, w[4];
    Vec3 n;
    Tie tie;
    tie.slave = s;
    for (const auto& seg : master) {
      bool own = false;
      for (int k = 0; k < seg.corners(); ++k) own = own || seg.n[k] == s;
      if (own || !project_onto_segment(seg, x_[static_cast<size_t>(s)], x_, best, g, n, w) || std::fabs(g) > best) continue;
      best = std::fabs(g);
      tie.corners = seg.corners();
      // A quad's weights are its shape functions at the node's natural
      // coordinates: the projection's triangle weights would transfer a
      // uniform stress unevenly across meshes that do not match (the patch
      // test fails by 25 % at a centre node); the shape functions pass it.
      if (tie.corners == 4) bilinear_weights(seg, x_[static_cast<size_t>(s)], x_, w);
      for (int k = 0; k < 4; ++k) tie.master[k] = seg.n[k], tie.w[k] = w[k];
    }
    if (tie.corners == 0) {
      ++free_nodes;
      continue;
    }
    auto on_a_body = [&](int i) {
      if (body_of_[static_cast<size_t>(i)] >= 0)
        throw std::runtime_error(def.where.str() + ": tied contact: node " + std::to_string(m_.node_ids[static_cast<size_t>(i)]) +
                                 " belongs to a rigid body; tie deformable parts (a rigid body's nodes move with it already)");
    };
    on_a_body(s);
    for (int k = 0; k < tie.corners; ++k) on_a_body(tie.master[k]);
    for (int k = 0; k < tie.corners; ++k) added[static_cast<size_t>(tie.master[k])] += tie.w[k] * mass_[static_cast<size_t>(s)];
    inv_mass_free_[static_cast<size_t>(s)] = Vec3::Zero();  // it moves with its segment
    ties_.push_back(tie);
  }
  for (size_t i = 0; i < added.size(); ++i)
    if (added[i] > 0.0)
      for (int k = 0; k < 3; ++k)
        inv_mass_free_[i][k] = m_.fixed[i][k] ? 0.0 : 1.0 / (mass_[i] + added[i]);
  for (const Tie& t : ties_) {  // a consistent start: the slave moves as its segment does
    Vec3 v = Vec3::Zero();
    for (int k = 0; k < t.corners; ++k) v += t.w[k] * v_[static_cast<size_t>(t.master[k])];
    v_[static_cast<size_t>(t.slave)] = v_prev_[static_cast<size_t>(t.slave)] = v;
  }
  if (free_nodes > 0)
    notes_.push_back(def.where.str() + ": tied contact: " + std::to_string(free_nodes) + " of " +
                     std::to_string(slaves.size()) + " slave nodes lie on no master segment (within " +
                     std::to_string(0.1 * size) + " m) and are not tied");
  if (free_nodes == static_cast<long>(slaves.size()))
    throw std::runtime_error(def.where.str() + ": tied contact: no slave node lies on a master segment (within " +
                             std::to_string(0.1 * size) + " m): are the sets the two faces that touch?");
}

void Solver::relaxation_residual(RelaxationReport& rep) const {
  // From the forces of the last step, summed over each part's nodes (a
  // part at rest in equilibrium sums to zero; a nodal rigid body's nodes
  // count with the part their elements belong to), on the DOFs that can
  // move; a held DOF's force is a support's reaction.
  std::map<int, Vec3> by_part;
  std::vector<int> part_of(x_.size(), 0);
  for (const auto& e : m_.solids) for (int k : e.n) part_of[static_cast<size_t>(k)] = e.part;
  for (const auto& e : m_.axis) for (int k : e.n) part_of[static_cast<size_t>(k)] = e.part;
  for (const auto& e : m_.bars) part_of[static_cast<size_t>(e.n1)] = part_of[static_cast<size_t>(e.n2)] = e.part;
  std::vector<Eigen::Matrix<bool, 3, 1>> held = m_.fixed;
  for (const PrescribedMotion& p : m_.prescribed)
    for (int i : p.nodes) held[static_cast<size_t>(i)][p.dof] = true;
  for (size_t b = 0; b < bodies_.size(); ++b)
    for (int i : m_.rigid_bodies[b].nodes)
      for (int k = 0; k < 3; ++k)
        if (bodies_[b].free_translation[k] == 0.0) held[static_cast<size_t>(i)][k] = true;
  rep.load = rep.resultant = 0.0;
  // Across ranks each node counts once, at the lowest rank that holds it;
  // the parts' sums and the largest support force are then combined in
  // rank order (the same verdict on every rank).
  const bool across = dom_.parallel();
  for (size_t i = 0; i < x_.size(); ++i) {
    if (across && sharers_[i].front() != dom_.rank()) {
      if (part_of[i] != 0) by_part.emplace(part_of[i], Vec3::Zero());
      continue;
    }
    Vec3 f = f_int_[i] + f_ext_[i] + f_con_[i];
    for (int k = 0; k < 3; ++k)
      if (held[i][k]) rep.load = std::max(rep.load, std::fabs(f[k])), f[k] = 0.0;
    if (part_of[i] != 0) by_part.emplace(part_of[i], Vec3::Zero()).first->second += f;
  }
  if (across) {
    std::vector<double> mine{rep.load}, all;
    for (const auto& [part, f] : by_part) mine.insert(mine.end(), {f.x(), f.y(), f.z()});
    dom_.sum_in_rank_order(mine, all);
    for (int r = 0; r < dom_.size(); ++r) rep.load = std::max(rep.load, all[static_cast<size_t>(r) * mine.size()]);  // the largest, not the sum
    size_t j = 1;
    for (auto& [part, f] : by_part) f = Vec3(mine[j], mine[j + 1], mine[j + 2]), j += 3;
  }
  for (const auto& [part, f] : by_part)
    if (f.norm() >= rep.resultant)
      rep.resultant = f.norm(), rep.worst = "part " + std::to_string(part) + " (" + m_.parts.at(part).title + ")";
}

Solver::RelaxationReport Solver::relax(const std::function<bool(const RelaxationReport&)>& keep_going) {
  RelaxationReport rep;
  if (!m_.relaxes()) return rep;
  if (n_ > 0) throw std::logic_error("Solver::relax after the first step");

  rep.ran = true;
  const DynamicRelaxation& r = m_.relaxation;
  constexpr long kMaxSteps = 4000000;
  constexpr long kAskEvery = 64;  // keep_going: a stop signal is seen within 64 steps, whatever NRCYCK
  relaxing_ = true;
  // Converged when, at a check every NRCYCK steps, the kinetic energy is
  // below DRTOL of its peak (LS-DYNA's criterion) and the residual below
  // DRTOL of the largest support force: a slowly loaded model can be
  // slow everywhere long before it is balanced.
  while (true) {
    step();
    ++rep.steps;
    rep.peak = std::max(rep.peak, energies_.kinetic);
    if (rep.steps % kAskEvery == 0 && keep_going) {
      rep.time = t_, rep.kinetic = energies_.kinetic;
      if (!keep_going(rep)) {
        rep.stopped = true;
        break;
      }
    }
    if (rep.steps % r.nrcyck != 0) continue;
    if (rep.peak > 0.0 && energies_.kinetic < r.drtol * rep.peak) {
      relaxation_residual(rep);
      if (rep.resultant <= r.drtol * rep.load) {
        rep.converged = true;
        break;
      }
    }
    if (t_ >= r.drterm || rep.steps >= kMaxSteps) break;
  }
  rep.time = t_;
  rep.kinetic = energies_.kinetic;
  relaxation_residual(rep);
  return rep;
}

void Solver::begin_transient() {
  relaxing_ = false;
  x();  // every node placed
  for (auto& vi : v_) vi.setZero();
  bodies_.scale_velocities(0.0, x_, v_);
  v_prev_ = v_;
  x_prev_ = x_;
  t_ = 0.0;
  n_ = 0;
  // The transient's account starts here: what the relaxation dissipated or
  // the loads did is not the transient's (the stored energies stay).
  energies_.kinetic = energies_.hourglass = energies_.damping = energies_.contact = energies_.external_work = 0.0;
  energies_.scale = 0.0;
  std::fill(energies_.part_hourglass.begin(), energies_.part_hourglass.end(), 0.0);
  std::fill(energies_.part_loading.begin(), energies_.part_loading.end(), 0.0);
}

void Solver::implicit_loads() {
  if (!user_load_) return;
  implicit_forces_.clear();
  Mobility mob;
  mob.h = velocity_step();
  mob.theta = n_ == 0 ? 0.0 : 0.5;
  mob.group = &group_;
  mob.inv_mass = &group_inv_mass_;
  mob.free = &group_free_;
  user_load_->apply_implicit(mob, v_prev_, v_, implicit_forces_);
  if (implicit_forces_.empty()) return;
  // The forces join f_ext (their work is accounted with the other user
  // loads, in external_work) and correct the velocity of whatever moves
  // with their node.
  const size_t n = x_.size();
  for (const NodalForce& nf : implicit_forces_) {
    const size_t i = static_cast<size_t>(nf.node);
    f_ext_[i] += nf.f;
    const size_t g = static_cast<size_t>(group_[i]);
    if (!group_touched_[g]) {
      group_touched_[g] = 1;
      touched_groups_.push_back(static_cast<int>(g));
    }
    group_force_[g] += nf.f;
    if (g >= n && bodies_[g - n].rotates) group_moment_[g - n] += (x_[i] - bodies_[g - n].com).cross(nf.f);
  }
  // The mobility above is a body's translation: exact for loads without a
  // moment about its centre (a cavity on a body of revolution); a moment
  // still turns the body here, one step explicit.
  for (int gi : touched_groups_) {
    const size_t g = static_cast<size_t>(gi);
    if (g < n) {
      v_[g] += mob.h * group_inv_mass_[g] * group_free_[g].cwiseProduct(group_force_[g]);
    } else {
      bodies_.add_impulse(g - n, group_force_[g], group_moment_[g - n], mob.h, dt_, x_, v_);
      group_moment_[g - n].setZero();
    }
    group_force_[g].setZero();
    group_touched_[g] = 0;
  }
  touched_groups_.clear();
}

void Solver::prescribed_motions() {
  // v_{n+1/2} of a prescribed DOF from its curve: velocity at t_{n+1/2},
  // acceleration at t_n, displacement at t_{n+1}. The force that takes,
  // R = m·(v_target − v_{n−1/2})/h − (the DOF's other forces), joins f_ext,
  // so its work is booked with the loads' (a massless node: R balances the
  // others).
  const double h = velocity_step();
  for (RigidMotion& r : rigid_motions_) {
    const PrescribedMotion& p = m_.prescribed[r.motion];
    r.reaction = 0.0;
    if (t_ < p.birth || t_ > p.death || !curve_acts(p.curve_id)) continue;
    const Curve& c = m_.curves.at(p.curve_id);
    const RigidBodyState& b = bodies_[r.body];
    const int d = p.dof;
    double target;
    if (p.vad == 0)
      target = p.sf * c.value(t_ + 0.5 * dt_);
    else if (p.vad == 1)
      target = b.v_prev[d] + h * p.sf * c.value(t_);
    else
      target = (p.sf * c.value(t_ + dt_) - (b.com[d] - b.com0[d])) / dt_;
    // The impulse that brings v_c to the target this step: its force is the reaction.
    r.reaction = b.mass * (target - b.v[d]) / h;
    Vec3 f = Vec3::Zero();
    f[d] = r.reaction;
    bodies_.add_impulse(r.body, f, Vec3::Zero(), h, dt_, x_, v_);
  }
  for (const PrescribedMotion& p : m_.prescribed) {
    if (t_ < p.birth || t_ > p.death || !curve_acts(p.curve_id)) continue;
    const Curve& c = m_.curves.at(p.curve_id);
    const int d = p.dof;
    for (int node : p.nodes) {
      const size_t i = static_cast<size_t>(node);
      double target;
      if (p.vad == 0)
        target = p.sf * c.value(t_ + 0.5 * dt_);
      else if (p.vad == 1)
        target = v_prev_[i][d] + h * p.sf * c.value(t_);
      else
        target = (p.sf * c.value(t_ + dt_) - (x_[i][d] - m_.x0[i][d])) / dt_;
      const double others = f_int_[i][d] + f_ext_[i][d] + f_con_[i][d];
      f_ext_[i][d] += mass_[i] * (target - v_prev_[i][d]) / h - others;
      v_[i][d] = target;
    }
  }
}

void Solver::external_work() {
  // Work of the user loads over the last step, f_n complete (stages 2 and 6),
  // while x_prev_ and x_ are still x_{n-1} and x_n.
  energies_.external_work += step_work(f_ext_prev_, f_ext_, ext_nodes_);
  // A driven rigid body's reaction acts at its centre: trapezoidal over the
  // same interval, x_c(t_n) − x_c(t_{n−1}).
  for (RigidMotion& r : rigid_motions_) {
    const int d = m_.prescribed[r.motion].dof;
    const double com = bodies_[r.body].com[d];
    if (n_ > 0) energies_.external_work += 0.5 * (r.reaction_prev + r.reaction) * (com - r.com_prev);
    r.reaction_prev = r.reaction;
    r.com_prev = com;
  }
}

void Solver::positions() {
  // Kinetic energy at t_n from the mean of v_{n-1/2} and v_{n+1/2} (v_0 on
  // the first step): bodies with their rotation of t_n, so before they move;
  // the free nodes' share in the same pass as their positions.
  const bool first = n_ == 0;
  double ke = bodies_.kinetic_energy(first);
  // Across ranks each node's kinetic energy is counted by one rank, the bodies' by rank 0.
  const double* mk = dom_.parallel() ? mass_ke_.data() : mass_.data();
  if (dom_.rank() != 0) ke = 0.0;
  // Per block: the kinetic energy summed node by node in list order (a
  // fixed order: the same sum for any thread count), then x over flat
  // arrays (vectorised).
  ke_partial_.assign(free_runs_.block_start.size() - 1, 0.0);
  double* x = x_.data()->data();
  double* xp = x_prev_.data()->data();
  const double* v = v_.data()->data();
  for_each_run(free_runs_, [&](size_t b, size_t first_node, size_t end) {
    double sum = ke_partial_[b];
    for (size_t i = first_node; i < end; ++i) {
      const Vec3 vn = first ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i]));
      sum += 0.5 * mk[i] * vn.squaredNorm();
    }
    ke_partial_[b] = sum;
    for (size_t j = 3 * first_node; j < 3 * end; ++j) {
      xp[j] = x[j];
      x[j] += dt_ * v[j];
    }
  });
  double total = 0.0;
  for (double p : ke_partial_) total += p;
  ke += total;
  if (dom_.parallel()) {
    scalars_mine_.assign(1, ke);
    dom_.sum_in_rank_order(scalars_mine_, scalars_all_);
    ke = scalars_mine_[0];
  }
  energies_.kinetic = ke;
  bodies_.advance_positions(dt_, x_, v_, x_prev_);
  interior_placed_ = bodies_.size() == 0;
}

void Solver::energy_account() {
  const Energies& e = energies_;
  if (n_ > 0) energies_.damping += damping_power_ * dt_last_;  // the power of v_{n−1/2}
  const double total = e.kinetic + e.internal + e.spring + e.hourglass + e.contact + e.damping - e.external_work;
  if (n_ == 0) energy0_ = total;
  energies_.balance_error = total - energy0_;
  energies_.scale = std::max({energies_.scale, e.kinetic + e.internal + e.spring, std::fabs(e.external_work)});
  // A blow-up ends here with its step named, before a NaN reaches a history
  // row or the coupling partner.
  if (!std::isfinite(total)) {
    std::ostringstream s;
    s << "the FE state is no longer finite at t = " << t_ << " s, step " << n_ << " (kinetic energy " << e.kinetic
      << " J" << first_non_finite()
      << "): the step is unstable for this model; lower the time step or check the loads (in a co-simulation, "
         "compare the chamber volumes with the coupling estimate fe_server printed before the run)";
    throw std::runtime_error(s.str());
  }
  if (n_ % kBoxCheckEvery == 0) check_state();
}

// Only on the way out: which node went first, in the order of the deck.
std::string Solver::first_non_finite() const {
  // The state before what is derived from it: a NaN position spreads to
  // its elements' forces within the same pass.
  const std::pair<const char*, const std::vector<Vec3>*> quantities[] = {
      {"position", &x_}, {"velocity", &v_}, {"load", &f_ext_}, {"internal force", &f_int_}};
  for (const auto& [what, values] : quantities)
    for (size_t i = 0; i < values->size(); ++i)
      if (!(*values)[i].allFinite()) {
        std::ostringstream s;
        s << "; first not finite: the " << what << " of node " << m_.node_ids[i];
        return s.str();
      }
  return dom_.parallel() ? "; the first node not finite is on another rank" : "";
}

// A node that left the model's neighbourhood: a pass-through at an impact,
// an unconstrained body, units that do not fit. Far outside (more than the
// box's diagonal beyond the initial bounding box) is never a right answer
// for the bodies of a percussion unit; the run stops naming the node.
void Solver::check_state() const {
  if (box_size_ == 0.0) return;  // one node: no size to compare with
  size_t far = x_.size();
  double worst = 0.0;
  for (size_t i = 0; i < x_.size(); ++i) {
    const Vec3 out = (x_[i] - box_hi_).cwiseMax(box_lo_ - x_[i]).cwiseMax(0.0);
    const double d = out.norm();
    if (d > box_size_ && d > worst) worst = d, far = i;
  }
  if (!dom_.any(far < x_.size())) return;
  std::ostringstream s;
  s << "at t = " << t_ << " s, step " << n_ << ": ";
  if (far < x_.size())
    s << "node " << m_.node_ids[far] << " is " << worst << " outside the model's initial bounding box (["
      << box_lo_.transpose() << "] to [" << box_hi_.transpose() << "]), more than the box's diagonal " << box_size_;
  else
    s << "a node on another rank is farther outside the model's initial bounding box than its diagonal " << box_size_;
  s << ": a body passed through another (contact), flew off unconstrained, or the deck's units do not fit "
       "(check contacts, boundary conditions and units)";
  throw std::runtime_error(s.str());
}

void Solver::step() {
  internal_forces();
  choose_step();
  user_loads();
  contact();
  accelerations();
  velocities();
  implicit_loads();
  prescribed_motions();
  tied_nodes();
  external_work();
  positions();
  energy_account();
  t_ += dt_;
  ++n_;
}

}  // namespace fe

namespace fe {

void Solver::state(config::StateIO& io) {
  if (dom_.parallel())
    throw std::runtime_error("checkpoints are written by one rank only for now: run without mpirun to checkpoint");
  io.expect("nodes", x_.size(), "the number of nodes");
  io.expect("solids", hex8_.sigma.size(), "the number of solid elements");
  io.expect("axisymmetric", axi4_.sigma.size(), "the number of axisymmetric elements");
  io.expect("bars", bars_.length.size(), "the number of bar elements");
  io.expect("contacts", contacts_.size(), "the number of contacts");
  io.value("dt", dt_);
  io.value("t", t_);
  io.value("n", n_);
  io.value("relaxing", relaxing_);
  // Nodal state: the step's inputs (x_n, v_{n-1/2}) and what the next step's
  // work sums and stress-time velocities read from the last one.
  io.array("x", x_);
  io.array("v", v_);
  io.value("interior placed", interior_placed_);
  io.array("x_prev", x_prev_);
  io.array("v_prev", v_prev_);
  io.array("f_int", f_int_);
  io.array("f_ext", f_ext_);
  io.array("f_ext_prev", f_ext_prev_);
  io.array("f_con", f_con_);
  io.array("f_con_prev", f_con_prev_);
  io.array("mass", mass_);  // scaled masses, as the deck's scaling left them
  io.array("part internal step", part_internal_step_);
  io.array("part hourglass step", part_hourglass_step_);
  bodies_.state(io);
  // Element state: stresses, plastic strains and the last step's nodal
  // forces (section forces read them); bars their last length (the
  // trapezoidal work of the next step).
  io.array("hex8 sigma", hex8_.sigma);
  io.array("hex8 plastic", hex8_.plastic_strain);
  io.array("hex8 back stress", hex8_.back_stress);
  io.array("hex8 force", hex8_.force);
  io.array("axi4 sigma", axi4_.sigma);
  io.array("axi4 plastic", axi4_.plastic_strain);
  io.array("axi4 back stress", axi4_.back_stress);
  io.array("axi4 force", axi4_.force);
  io.array("bar force", bars_.force);
  io.array("bar length", bars_.length);
  for (auto& c : contacts_) c->state(io);
  io.expect("rigid motions", rigid_motions_.size(), "the number of prescribed rigid-body motions");
  for (RigidMotion& r : rigid_motions_) {
    io.value("rigid motion reaction", r.reaction);
    io.value("rigid motion reaction prev", r.reaction_prev);
    io.value("rigid motion com prev", r.com_prev);
  }
  io.value("damping power", damping_power_);
  contact_force();  // summed now if the last step left it to be asked
  io.value("contact force", contact_force_);
  contact_force_stale_ = false;
  io.value("energy kinetic", energies_.kinetic);
  io.value("energy internal", energies_.internal);
  io.value("energy spring", energies_.spring);
  io.value("energy hourglass", energies_.hourglass);
  io.value("energy contact", energies_.contact);
  io.value("energy damping", energies_.damping);
  io.value("energy external", energies_.external_work);
  io.value("energy scale", energies_.scale);
  io.array("energy part ids", energies_.part_ids);
  io.array("energy part hourglass", energies_.part_hourglass);
  io.array("energy part loading", energies_.part_loading);
  io.array("energy part internal", energies_.part_internal);
  io.value("energy balance", energies_.balance_error);
  io.value("energy0", energy0_);
}

}  // namespace fe
