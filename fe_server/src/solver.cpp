#include "solver.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace fe {

namespace {
// Mass that moves with node i: its rigid body's, or its own.
double moving_mass(const Model& m, int i) {
  for (const auto& b : m.rigid_bodies)
    for (int n : b.nodes)
      if (n == i) return b.mass;
  return m.fixed[static_cast<size_t>(i)].all() ? std::numeric_limits<double>::infinity()
                                               : m.mass[static_cast<size_t>(i)];
}
}  // namespace

double Solver::stable_dt(const Model& m, std::string* limited_by) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& d : m.discretes) {
    if (!(d.k > 0.0)) continue;
    // Two masses on a spring: ω² = k (1/m1 + 1/m2); central difference is
    // stable for ω·Δt ≤ 2.
    double inv = 1.0 / moving_mass(m, d.n1) + 1.0 / moving_mass(m, d.n2);
    if (!(inv > 0.0)) continue;
    double dt = 2.0 / std::sqrt(d.k * inv);
    if (dt < best) {
      best = dt;
      if (limited_by) {
        std::ostringstream s;
        s << "discrete element " << d.id << " (" << d.where.str() << ", k = " << d.k << " N/m)";
        *limited_by = s.str();
      }
    }
  }
  return best;
}

Solver::Solver(const Model& model, double dt) : m_(model), dt_(dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw std::runtime_error("FE time step must be positive");
  std::string limit;
  double crit = stable_dt(model, &limit);
  if (dt > model.dt_scale * crit) {
    std::ostringstream s;
    s << "FE time step " << dt << " s exceeds the stable step " << crit << " s × safety factor "
      << model.dt_scale << " (TSSFAC), limited by " << limit
      << ": lower the coupling time step or raise the subcycles in the port configuration";
    throw std::runtime_error(s.str());
  }
  const size_t n = model.x0.size();
  x_ = model.x0;
  v_ = model.v0;
  a_.assign(n, Vec3::Zero());
  f_int_.assign(n, Vec3::Zero());
  f_ext_.assign(n, Vec3::Zero());
  f_ext_prev_.assign(n, Vec3::Zero());
  x_prev_ = x_;
  v_prev_ = v_;
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
    Vec3 vb = p / model.rigid_bodies[b].mass;
    for (int i : model.rigid_bodies[b].nodes) v_[static_cast<size_t>(i)] = vb;
  }
  v_prev_ = v_;
}

void Solver::internal_forces() {
  for (auto& f : f_int_) f.setZero();
  spring_energy_ = 0.0;
  damping_power_ = 0.0;
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

void Solver::user_loads() {
  f_ext_prev_.swap(f_ext_);
  for (auto& f : f_ext_) f.setZero();
  if (user_load_) user_load_->apply(t_, x_, v_, f_ext_);
  // Work of the external forces over the last step, trapezoidal in force.
  if (n_ > 0)
    for (size_t i = 0; i < x_.size(); ++i)
      energies_.external_work += 0.5 * (f_ext_prev_[i] + f_ext_[i]).dot(x_[i] - x_prev_[i]);
}

void Solver::accelerations() {
  // f_int holds the forces the elements exert on the nodes, so it adds to f_ext.
  for (size_t i = 0; i < x_.size(); ++i) {
    if (body_of_[i] >= 0) continue;
    a_[i] = m_.mass[i] > 0.0 ? Vec3((f_ext_[i] + f_int_[i]) / m_.mass[i]) : Vec3::Zero();
  }
  for (const auto& b : m_.rigid_bodies) {
    Vec3 f = Vec3::Zero();
    for (int i : b.nodes) f += f_ext_[static_cast<size_t>(i)] + f_int_[static_cast<size_t>(i)];
    Vec3 ab = f / b.mass;
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

void Solver::positions() {
  x_prev_ = x_;
  for (size_t i = 0; i < x_.size(); ++i) x_[i] += dt_ * v_[i];
}

void Solver::energy_account() {
  // Kinetic energy at t_n from the mean of v_{n-1/2} and v_{n+1/2}
  // (v_0 on the first step), rigid bodies once with their whole mass.
  double ke = 0.0;
  for (size_t i = 0; i < v_.size(); ++i) {
    if (body_of_[i] >= 0) continue;
    Vec3 vn = n_ == 0 ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i]));
    ke += 0.5 * m_.mass[i] * vn.squaredNorm();
  }
  for (const auto& b : m_.rigid_bodies) {
    size_t i = static_cast<size_t>(b.nodes.front());
    Vec3 vn = n_ == 0 ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i]));
    ke += 0.5 * b.mass * vn.squaredNorm();
  }
  energies_.kinetic = ke;
  energies_.internal = spring_energy_;
  if (n_ > 0) energies_.damping += damping_power_ * dt_;
  const double total = ke + spring_energy_ + energies_.damping - energies_.external_work;
  if (n_ == 0) energy0_ = total;
  energies_.balance_error = total - energy0_;
}

void Solver::step() {
  internal_forces();
  user_loads();
  contact();
  accelerations();
  boundary_conditions();
  velocities();
  energy_account();
  positions();
  t_ += dt_;
  ++n_;
}

}  // namespace fe
