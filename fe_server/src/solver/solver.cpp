#include "solver/solver.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace fe {

namespace {

using Voigt = Eigen::Matrix<double, 6, 1>;

Mat83 gather(const std::vector<Vec3>& a, const SolidElement& e) {
  Mat83 out;
  for (int k = 0; k < 8; ++k) out.row(k) = a[static_cast<size_t>(e.n[k])].transpose();
  return out;
}

Mat42 gather_axi(const std::vector<Vec3>& a, const AxiElement& e) {
  Mat42 out;
  for (int k = 0; k < 4; ++k) {
    const Vec3& p = a[static_cast<size_t>(e.n[k])];
    out(k, 0) = p.x(), out(k, 1) = p.y();
  }
  return out;
}

bool in_rigid_part(const Model& m, int part) {
  auto p = m.parts.find(part);
  if (p == m.parts.end()) return false;
  auto mat = m.materials.find(p->second.material);
  return mat != m.materials.end() && mat->second.rigid;
}

// Mass that moves with node i: its rigid body's, or its own.
double moving_mass(const Model& m, int i) {
  for (const auto& b : m.rigid_bodies)
    for (int n : b.nodes)
      if (n == i) return b.mass;
  return m.fixed[static_cast<size_t>(i)].all() ? std::numeric_limits<double>::infinity()
                                               : m.mass[static_cast<size_t>(i)];
}

}  // namespace

std::string hourglass_warning(const Energies& e) {
  if (!(e.hourglass > 0.1 * std::fabs(e.internal))) return "";
  std::ostringstream s;
  s << "hourglass energy " << e.hourglass << " J is " << (e.internal != 0.0 ? 100.0 * e.hourglass / std::fabs(e.internal) : 1e9)
    << " % of the internal energy " << e.internal
    << " J (bound 10 %): zero-energy modes carry part of the deformation; refine the mesh where the load is "
       "concentrated or spread the load over several nodes";
  return s.str();
}

StableStep Solver::stable_dt(const Model& m) {
  StableStep best;
  auto consider = [&](double dt, const std::string& what) {
    if (dt < best.dt) {
      best.dt = dt;
      best.limited_by = what;
    }
  };
  for (const auto& d : m.discretes) {
    if (!(d.k > 0.0)) continue;
    // Two masses on a spring: ω² = k (1/m1 + 1/m2); stable for ω·Δt ≤ 2.
    const double inv = 1.0 / moving_mass(m, d.n1) + 1.0 / moving_mass(m, d.n2);
    if (!(inv > 0.0)) continue;
    std::ostringstream s;
    s << "discrete element " << d.id << " (" << d.where.str() << ", k = " << d.k << " N/m)";
    consider(2.0 / std::sqrt(d.k * inv), s.str());
  }
  for (const auto& e : m.bars) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const double L = (m.x0[static_cast<size_t>(e.n2)] - m.x0[static_cast<size_t>(e.n1)]).norm();
    consider(L / std::sqrt(mat.E / (mat.rho * e.mass_scale)), "bar element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")");
  }
  for (const auto& e : m.solids) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const double dt_e = hex8_stable_step(gather(m.x0, e), mat.lambda(), mat.mu(), mat.rho * e.mass_scale, m.bulk_q2);
    if (dt_e > 0.0)  // 0: inverted, which the reader refuses
      consider(dt_e, "solid element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")");
  }
  for (const auto& e : m.axis) {
    if (in_rigid_part(m, e.part)) continue;
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    bool fixed_r[4];
    for (int k = 0; k < 4; ++k) fixed_r[k] = m.fixed[static_cast<size_t>(e.n[k])][0];
    const double dt_e =
        axi4_stable_step(gather_axi(m.x0, e), mat.lambda(), mat.mu(), mat.rho * e.mass_scale, m.bulk_q2, fixed_r);
    if (dt_e > 0.0)
      consider(dt_e, "axisymmetric element " + std::to_string(e.id) + " (part " + std::to_string(e.part) + ")");
  }
  return best;
}

Solver::Solver(const Model& model, double dt) : m_(model), dt_(dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::runtime_error("FE time step must be positive");
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
  const size_t n = model.x0.size();
  x_ = model.x0;
  v_ = model.v0;
  mass_ = model.mass;
  for (auto* a : {&a_, &f_int_, &f_ext_, &f_ext_prev_, &f_con_, &f_con_prev_}) a->assign(n, Vec3::Zero());
  x_prev_ = x_;
  sigma_.assign(model.solids.size(), Voigt::Zero());
  bar_force_.assign(model.bars.size(), 0.0);
  solid_active_.resize(model.solids.size());
  solid_material_.resize(model.solids.size());
  hourglass_coef_.resize(model.solids.size());
  for (size_t e = 0; e < model.solids.size(); ++e) {
    const SolidElement& el = model.solids[e];
    solid_active_[e] = !in_rigid_part(model, el.part);
    solid_material_[e] = &model.materials.at(model.parts.at(el.part).material);
    Mat83 xe = gather(model.x0, el), b;
    double volume = 0.0;
    hex8_gradients(xe, b, volume);
    const Material& mat = *solid_material_[e];
    hourglass_coef_[e] = model.hourglass_q * mat.rho * mat.wave_speed() * std::cbrt(volume * volume) / 4.0;
  }
  axi_sigma_.assign(model.axis.size(), Voigt::Zero());
  axi_active_.resize(model.axis.size());
  axi_const_.resize(model.axis.size());
  for (size_t e = 0; e < model.axis.size(); ++e) {
    const AxiElement& el = model.axis[e];
    axi_active_[e] = !in_rigid_part(model, el.part);
    const Material& mat = model.materials.at(model.parts.at(el.part).material);
    Axi4Geometry g;
    axi4_geometry(gather_axi(model.x0, el), g);
    axi_const_[e] = {mat.lambda(), mat.mu(), mat.rho, mat.wave_speed(),
                     axi4_hourglass_coefficient(g, model.hourglass_q, mat.rho, mat.wave_speed())};
  }
  body_of_.assign(n, -1);
  body_fixed_.assign(model.rigid_bodies.size(), Eigen::Matrix<bool, 3, 1>(false, false, false));
  for (size_t b = 0; b < model.rigid_bodies.size(); ++b) {
    // A body moves as one: mass-weighted initial velocity, and a DOF fixed on
    // any of its nodes is fixed for the whole body.
    Vec3 p = Vec3::Zero();
    for (int i : model.rigid_bodies[b].nodes) {
      body_of_[static_cast<size_t>(i)] = static_cast<int>(b);
      p += model.mass[static_cast<size_t>(i)] * model.v0[static_cast<size_t>(i)];
      for (int k = 0; k < 3; ++k) body_fixed_[b][k] = body_fixed_[b][k] || model.fixed[static_cast<size_t>(i)][k];
    }
    const Vec3 vb = p / model.rigid_bodies[b].mass;
    for (int i : model.rigid_bodies[b].nodes) v_[static_cast<size_t>(i)] = vb;
  }
  v_prev_ = v_;
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
  for (size_t b = 0; b < model.rigid_bodies.size(); ++b) {
    const double mb = model.rigid_bodies[b].mass;
    group_inv_mass_[n + b] = mb > 0.0 ? 1.0 / mb : 0.0;
    for (int k = 0; k < 3; ++k) group_free_[n + b][k] = body_fixed_[b][k] ? 0.0 : 1.0;
  }
  group_force_.assign(group_free_.size(), Vec3::Zero());
  // Contact sees the mass that moves with each node (a rigid body's whole mass).
  std::vector<double> contact_mass = mass_;
  for (size_t i = 0; i < n; ++i)
    if (body_of_[i] >= 0) contact_mass[i] = model.rigid_bodies[static_cast<size_t>(body_of_[i])].mass;
  contact_mass_ = contact_mass;
  for (const auto& c : model.contacts) {
    contacts_.push_back(std::make_unique<PenaltyContact>(model, c, dt, contact_mass_));
    contacts_.back()->refuse_initial_penetration(model, c, x_);
  }
}

double Solver::max_penetration() const {
  double p = 0.0;
  for (const auto& c : contacts_) p = std::max(p, c->max_penetration());
  return p;
}

void Solver::spring_forces() {
  spring_energy_ = 0.0;
  for (const auto& d : m_.discretes) {
    const size_t i = static_cast<size_t>(d.n1), j = static_cast<size_t>(d.n2);
    Vec3 axis = x_[j] - x_[i];
    const double len = axis.norm();
    axis /= len;
    // Tension positive: stretch plus the initial offset (LS-DYNA's OFFSET).
    const double stretch = len - d.length0 + d.offset;
    const double rate = (v_[j] - v_[i]).dot(axis);
    const double force = d.k * stretch + d.c * rate;
    f_int_[i] += force * axis;  // tension pulls node i towards j and j towards i
    f_int_[j] -= force * axis;
    spring_energy_ += 0.5 * d.k * stretch * stretch;
    damping_power_ += d.c * rate * rate;
  }
}

void Solver::bar_forces() {
  for (size_t e = 0; e < m_.bars.size(); ++e) {
    const BarElement& b = m_.bars[e];
    const Part& part = m_.parts.at(b.part);
    const Material& mat = m_.materials.at(part.material);
    if (mat.rigid) continue;
    const size_t i = static_cast<size_t>(b.n1), j = static_cast<size_t>(b.n2);
    Vec3 axis = x_[j] - x_[i];
    const double len = axis.norm();
    axis /= len;
    // Axial stress rate from the elongation rate (hypoelastic, like the solids).
    const double rate = (v_[j] - v_[i]).dot(axis) / len;
    const double old = bar_force_[e];
    bar_force_[e] += dt_ * mat.E * part.bar_area * rate;
    f_int_[i] += bar_force_[e] * axis;
    f_int_[j] -= bar_force_[e] * axis;
    energies_.internal += 0.5 * (old + bar_force_[e]) * rate * len * dt_;
  }
}

double Solver::bar_stress(size_t e) const {
  const Part& part = m_.parts.at(m_.bars[e].part);
  return bar_force_[e] / part.bar_area;
}

void Solver::solid_forces() {
  const double q1 = m_.bulk_q1, q2 = m_.bulk_q2;
  for (size_t e = 0; e < m_.solids.size(); ++e) {
    if (!solid_active_[e]) continue;
    const SolidElement& el = m_.solids[e];
    const Material& mat = *solid_material_[e];
    const Mat83 x = gather(x_, el), v = gather(v_, el);
    Mat83 b;
    double volume = 0.0;
    if (!hex8_gradients(x, b, volume)) {
      std::ostringstream s;
      s << "solid element " << el.id << " (part " << el.part << ") inverted at t = " << t_ << " s, step " << n_
        << " (volume " << volume << " m³): the mesh is too coarse for this deformation, or the step is too large";
      throw std::runtime_error(s.str());
    }
    // Rate of deformation D = sym(L), L_ij = Σ_a v_ai b_aj.
    const Eigen::Matrix3d L = v.transpose() * b;
    const Eigen::Matrix3d D = 0.5 * (L + L.transpose());
    const double trD = D.trace();
    const double lambda = mat.lambda(), mu = mat.mu();
    Voigt dsig;
    dsig << lambda * trD + 2 * mu * D(0, 0), lambda * trD + 2 * mu * D(1, 1), lambda * trD + 2 * mu * D(2, 2),
        2 * mu * D(0, 1), 2 * mu * D(1, 2), 2 * mu * D(2, 0);
    const Voigt old = sigma_[e];
    sigma_[e] += dt_ * dsig;
    // Bulk viscosity in compression (von Neumann–Richtmyer with a linear term, LS-DYNA's Q1, Q2).
    double q = 0.0;
    if (trD < 0.0) {
      const double len = hex8_characteristic_length(x, volume);
      q = mat.rho * len * (q1 * len * trD * trD - q2 * mat.wave_speed() * trD);
    }
    Eigen::Matrix3d s;
    s << sigma_[e](0) - q, sigma_[e](3), sigma_[e](5), sigma_[e](3), sigma_[e](1) - q, sigma_[e](4), sigma_[e](5),
        sigma_[e](4), sigma_[e](2) - q;
    const Mat83 f = -volume * b * s;  // f_a = −V·σ·b_a
    // Hourglass (viscous FB): f = −c_h Σ_α γ_α ⊗ q_α.
    const Eigen::Matrix<double, 4, 8> gamma = hex8_hourglass_shapes(x, b);
    const Eigen::Matrix<double, 4, 3> qa = gamma * v;
    const double c_h = hourglass_coef_[e];
    const Mat83 f_hg = -c_h * gamma.transpose() * qa;
    for (int k = 0; k < 8; ++k) f_int_[static_cast<size_t>(el.n[k])] += (f.row(k) + f_hg.row(k)).transpose();
    // Energies of this step: elastic σ:D (trapezoidal in σ), hourglass and bulk viscosity dissipation.
    const Voigt mid = 0.5 * (old + sigma_[e]);
    const double sd = mid(0) * D(0, 0) + mid(1) * D(1, 1) + mid(2) * D(2, 2) +
                      2 * (mid(3) * D(0, 1) + mid(4) * D(1, 2) + mid(5) * D(2, 0));
    energies_.internal += volume * sd * dt_;
    energies_.hourglass += c_h * qa.squaredNorm() * dt_;
    damping_power_ += -q * trD * volume;
  }
}

void Solver::axi_forces() {
  // The formulas of element_axi4.hpp written out in scalars: the 2×2
  // Jacobian's inverse and the centre gradients in closed form, so the
  // compiler keeps everything in registers (measured: bench_fe, axi4).
  constexpr double kXi[4] = {-1, 1, 1, -1}, kEta[4] = {-1, -1, 1, 1}, kH[4] = {1, -1, 1, -1};
  constexpr double kTwoPi = 6.283185307179586;
  const double q1 = m_.bulk_q1, q2 = m_.bulk_q2;
  for (size_t e = 0; e < m_.axis.size(); ++e) {
    if (!axi_active_[e]) continue;
    const AxiElement& el = m_.axis[e];
    const AxiConstants& k = axi_const_[e];
    double r[4], y[4], vr[4], vy[4];
    for (int a = 0; a < 4; ++a) {
      const size_t n = static_cast<size_t>(el.n[a]);
      r[a] = x_[n].x(), y[a] = x_[n].y(), vr[a] = v_[n].x(), vy[a] = v_[n].y();
    }
    const double J00 = 0.25 * (-r[0] + r[1] + r[2] - r[3]), J01 = 0.25 * (-r[0] - r[1] + r[2] + r[3]);
    const double J10 = 0.25 * (-y[0] + y[1] + y[2] - y[3]), J11 = 0.25 * (-y[0] - y[1] + y[2] + y[3]);
    const double det = J00 * J11 - J01 * J10;
    const double r_c = 0.25 * (r[0] + r[1] + r[2] + r[3]);
    if (!(det > 0.0) || !(r_c > 0.0)) {
      std::ostringstream s;
      s << "axisymmetric element " << el.id << " (part " << el.part << ") inverted at t = " << t_ << " s, step " << n_
        << " (area " << 4.0 * det << " m²): the mesh is too coarse for this deformation, or the step is too large";
      throw std::runtime_error(s.str());
    }
    const double inv = 0.25 / det, area = 4.0 * det, volume = kTwoPi * r_c * area;
    double br[4], by[4];
    double d_rr = 0.0, d_yy = 0.0, l_ry = 0.0, l_yr = 0.0, hr = 0.0, hy = 0.0;
    for (int a = 0; a < 4; ++a) {
      br[a] = (kXi[a] * J11 - kEta[a] * J10) * inv;
      by[a] = (kEta[a] * J00 - kXi[a] * J01) * inv;
      d_rr += vr[a] * br[a], d_yy += vy[a] * by[a];
      l_ry += vr[a] * by[a], l_yr += vy[a] * br[a];
      hr += kH[a] * r[a], hy += kH[a] * y[a];
    }
    const double d_ry = 0.5 * (l_ry + l_yr);
    const double d_tt = 0.25 * (vr[0] + vr[1] + vr[2] + vr[3]) / r_c;
    const double trD = d_rr + d_yy + d_tt;
    Voigt& sig = axi_sigma_[e];
    const double o0 = sig(0), o1 = sig(1), o2 = sig(2), o3 = sig(3);
    const double lt = k.lambda * trD;
    sig(0) += dt_ * (lt + 2 * k.mu * d_rr);
    sig(1) += dt_ * (lt + 2 * k.mu * d_yy);
    sig(2) += dt_ * (lt + 2 * k.mu * d_tt);
    sig(3) += dt_ * 2 * k.mu * d_ry;
    double q = 0.0;  // bulk viscosity in compression, as for the hex8
    if (trD < 0.0) {
      const double dx1 = r[2] - r[0], dy1 = y[2] - y[0], dx2 = r[3] - r[1], dy2 = y[3] - y[1];
      const double len = area / std::sqrt(std::max(dx1 * dx1 + dy1 * dy1, dx2 * dx2 + dy2 * dy2));
      q = k.rho * len * (q1 * len * trD * trD - q2 * k.wave_speed * trD);
    }
    const double s_rr = sig(0) - q, s_yy = sig(1) - q, s_tt = sig(2) - q, s_ry = sig(3);
    // Hourglass (viscous FB), one mode: γ = h − (h·r)·b_r − (h·y)·b_y.
    double gamma[4], qr = 0.0, qy = 0.0;
    for (int a = 0; a < 4; ++a) {
      gamma[a] = kH[a] - hr * br[a] - hy * by[a];
      qr += gamma[a] * vr[a], qy += gamma[a] * vy[a];
    }
    const double hoop = volume * s_tt * 0.25 / r_c;
    for (int a = 0; a < 4; ++a) {
      Vec3& f = f_int_[static_cast<size_t>(el.n[a])];
      f.x() -= volume * (s_rr * br[a] + s_ry * by[a]) + hoop + k.hourglass * gamma[a] * qr;
      f.y() -= volume * (s_ry * br[a] + s_yy * by[a]) + k.hourglass * gamma[a] * qy;
    }
    const double sd = 0.5 * ((o0 + sig(0)) * d_rr + (o1 + sig(1)) * d_yy + (o2 + sig(2)) * d_tt) + (o3 + sig(3)) * d_ry;
    energies_.internal += volume * sd * dt_;
    energies_.hourglass += k.hourglass * (qr * qr + qy * qy) * dt_;
    damping_power_ += -q * trD * volume;
  }
}

void Solver::internal_forces() {
  for (auto& f : f_int_) f.setZero();
  damping_power_ = 0.0;
  spring_forces();
  bar_forces();
  solid_forces();
  axi_forces();
}

double Solver::step_work(const std::vector<Vec3>& f_prev, const std::vector<Vec3>& f) const {
  if (n_ == 0) return 0.0;
  double w = 0.0;
  for (size_t i = 0; i < x_.size(); ++i) w += 0.5 * (f_prev[i] + f[i]).dot(x_[i] - x_prev_[i]);
  return w;
}

void Solver::user_loads() {
  f_ext_prev_.swap(f_ext_);
  for (auto& f : f_ext_) f.setZero();
  if (user_load_) user_load_->apply(t_, x_, v_, f_ext_);
  // Their work is accounted in energy_account, once stage 7 has added the
  // forces that depend on v_{n+1/2}.
}

void Solver::contact() {
  if (contacts_.empty()) return;  // f_con_ stays zero: no per-node work in models without contact
  f_con_prev_.swap(f_con_);
  for (auto& f : f_con_) f.setZero();
  for (auto& c : contacts_) c->apply(x_, v_, f_con_, n_);
  // Energy taken by the contact: minus the work its forces did on the nodes.
  energies_.contact -= step_work(f_con_prev_, f_con_);
  double total = 0.0;
  for (const auto& f : f_con_) total += f.norm();
  contact_force_ = 0.5 * total;  // each pair appears twice (node and segment side)
}

void Solver::accelerations() {
  for (size_t i = 0; i < x_.size(); ++i) {
    if (body_of_[i] >= 0) continue;
    a_[i] = mass_[i] > 0.0 ? Vec3((f_ext_[i] + f_int_[i] + f_con_[i]) / mass_[i]) : Vec3::Zero();
  }
  for (const auto& b : m_.rigid_bodies) {
    Vec3 f = Vec3::Zero();
    for (int i : b.nodes) {
      const size_t k = static_cast<size_t>(i);
      f += f_ext_[k] + f_int_[k] + f_con_[k];
    }
    const Vec3 ab = f / b.mass;
    for (int i : b.nodes) a_[static_cast<size_t>(i)] = ab;
  }
}

void Solver::boundary_conditions() {
  for (size_t i = 0; i < x_.size(); ++i) {
    const auto& fixed = body_of_[i] >= 0 ? body_fixed_[static_cast<size_t>(body_of_[i])] : m_.fixed[i];
    for (int k = 0; k < 3; ++k)
      if (fixed[k]) {
        a_[i][k] = 0.0;
        v_[i][k] = 0.0;
      }
  }
}

void Solver::velocities() {
  v_prev_ = v_;
  const double h = n_ == 0 ? 0.5 * dt_ : dt_;  // v_{1/2} = v_0 + Δt/2·a_0
  for (size_t i = 0; i < v_.size(); ++i) v_[i] += h * a_[i];
}

void Solver::implicit_loads() {
  if (!user_load_) return;
  implicit_forces_.clear();
  Mobility mob;
  mob.h = n_ == 0 ? 0.5 * dt_ : dt_;
  mob.theta = n_ == 0 ? 0.0 : 0.5;
  mob.group = &group_;
  mob.inv_mass = &group_inv_mass_;
  mob.free = &group_free_;
  user_load_->apply_implicit(mob, v_prev_, v_, implicit_forces_);
  if (implicit_forces_.empty()) return;
  // The forces join f_ext (their work is accounted with the other user
  // loads, in energy_account) and correct the velocity of whatever moves
  // with their node.
  const size_t n = x_.size();
  for (const NodalForce& nf : implicit_forces_) {
    const size_t i = static_cast<size_t>(nf.node);
    f_ext_[i] += nf.f;
    const size_t g = static_cast<size_t>(group_[i]);
    if (group_force_[g].isZero()) touched_groups_.push_back(static_cast<int>(g));
    group_force_[g] += nf.f;
  }
  for (int gi : touched_groups_) {
    const size_t g = static_cast<size_t>(gi);
    const Vec3 dv = mob.h * group_inv_mass_[g] * group_free_[g].cwiseProduct(group_force_[g]);
    if (g < n) {
      v_[g] += dv;
    } else {
      for (int i : m_.rigid_bodies[g - n].nodes) v_[static_cast<size_t>(i)] += dv;
    }
    group_force_[g].setZero();
  }
  touched_groups_.clear();
}

void Solver::positions() {
  x_prev_ = x_;
  for (size_t i = 0; i < x_.size(); ++i) x_[i] += dt_ * v_[i];
}

void Solver::energy_account() {
  // Work of the user loads over the last step, f_n complete (stages 2 and 7).
  energies_.external_work += step_work(f_ext_prev_, f_ext_);
  // Kinetic energy at t_n from the mean of v_{n-1/2} and v_{n+1/2}
  // (v_0 on the first step), rigid bodies once with their whole mass.
  double ke = 0.0;
  for (size_t i = 0; i < v_.size(); ++i) {
    if (body_of_[i] >= 0) continue;
    const Vec3 vn = n_ == 0 ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i]));
    ke += 0.5 * mass_[i] * vn.squaredNorm();
  }
  for (const auto& b : m_.rigid_bodies) {
    const size_t i = static_cast<size_t>(b.nodes.front());
    const Vec3 vn = n_ == 0 ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i]));
    ke += 0.5 * b.mass * vn.squaredNorm();
  }
  energies_.kinetic = ke;
  if (n_ > 0) energies_.damping += damping_power_ * dt_;
  const Energies& e = energies_;
  const double total = ke + e.internal + spring_energy_ + e.hourglass + e.contact + e.damping - e.external_work;
  if (n_ == 0) energy0_ = total;
  energies_.balance_error = total - energy0_;
  // A blow-up ends here with its step named, before a NaN reaches a position,
  // a history row or the coupling partner.
  if (!std::isfinite(total)) {
    std::ostringstream s;
    s << "the FE state is no longer finite at t = " << t_ << " s, step " << n_ << " (kinetic energy " << ke
      << " J): the step is unstable for this model; lower the time step or check the loads (in a co-simulation, "
         "compare the chamber volumes with the coupling estimate fe_server printed before the run)";
    throw std::runtime_error(s.str());
  }
}

void Solver::step() {
  internal_forces();
  user_loads();
  contact();
  accelerations();
  boundary_conditions();
  velocities();
  implicit_loads();
  energy_account();
  positions();
  t_ += dt_;
  ++n_;
}

}  // namespace fe
