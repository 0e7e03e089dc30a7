#include "solver/rigid_body.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace fe {

namespace {

// Rotation by the vector θ (angle |θ| about θ/|θ|).
Eigen::Quaterniond rotation(const Vec3& theta) {
  const double angle = theta.norm();
  if (angle == 0.0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, theta / angle));
}

// Inverse on the span of a symmetric positive semi-definite matrix, zero on
// its null space (eigenvalues below 1e-12 of the largest: a body's inertia
// about an axis along which it has no extent).
Eigen::Matrix3d pseudo_inverse(const Eigen::Matrix3d& a) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a);
  const Vec3 d = eig.eigenvalues();
  const double tol = 1e-12 * d.cwiseAbs().maxCoeff();
  Vec3 inv = Vec3::Zero();
  for (int k = 0; k < 3; ++k)
    if (d[k] > tol) inv[k] = 1.0 / d[k];
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
}

}  // namespace

RigidBodies::RigidBodies(const Model& model, const std::vector<char>& live) : m_(model) {
  const bool axisymmetric = model.symmetry_axis == 1;
  for (const RigidBody& rb : model.rigid_bodies) {
    RigidBodyState s;
    s.mass = rb.mass;
    // Centre of mass and inertia: the deck's (*PART_INERTIA) or the nodes'.
    double m_nodes = 0.0;
    Vec3 first = Vec3::Zero();
    for (int i : rb.nodes) {
      const size_t k = static_cast<size_t>(i);
      m_nodes += model.mass[k];
      first += model.mass[k] * model.x0[k];
    }
    s.com0 = rb.inertia_given ? rb.com : m_nodes > 0.0 ? Vec3(first / m_nodes) : model.x0[static_cast<size_t>(rb.nodes.front())];
    if (rb.inertia_given) {
      s.inertia0 = rb.inertia;
    } else {
      for (int i : rb.nodes) {
        const size_t k = static_cast<size_t>(i);
        const Vec3 r = model.x0[k] - s.com0;
        s.inertia0 += model.mass[k] * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
      }
    }
    s.inertia0_pinv = pseudo_inverse(s.inertia0);
    // Constraints: the body's own, an SPC on any of its nodes, the 2D axisymmetric kinematics.
    Eigen::Matrix<bool, 3, 1> fixed_t = rb.fixed_translation, fixed_r = rb.fixed_rotation;
    for (int i : rb.nodes) fixed_t = fixed_t.array() || model.fixed[static_cast<size_t>(i)].array();
    if (axisymmetric) {
      fixed_t[0] = fixed_t[2] = true;
      fixed_r.setConstant(true);
    }
    for (int k = 0; k < 3; ++k) {
      s.free_translation[k] = fixed_t[k] ? 0.0 : 1.0;
      s.free_rotation[k] = fixed_r[k] ? 0.0 : 1.0;
    }
    s.rotates = !fixed_r.all() && s.inertia0_pinv.norm() > 0.0;
    s.partly_constrained_rotation = s.rotates && fixed_r.any();
    // Initial velocities: the deck's (*PART_INERTIA, when given) or the
    // nodes' momentum and angular momentum.
    Vec3 p = Vec3::Zero(), h = Vec3::Zero();
    for (int i : rb.nodes) {
      const size_t k = static_cast<size_t>(i);
      p += model.mass[k] * model.v0[k];
      h += model.mass[k] * (model.x0[k] - s.com0).cross(model.v0[k]);
    }
    const bool deck_velocity = rb.inertia_given && (rb.v0.squaredNorm() > 0.0 || rb.omega0.squaredNorm() > 0.0);
    s.v = deck_velocity ? rb.v0 : m_nodes > 0.0 ? Vec3(p / m_nodes) : Vec3::Zero();
    s.v = s.v.cwiseProduct(s.free_translation);
    s.com = s.com0;
    if (s.rotates) {
      s.omega = deck_velocity ? rb.omega0 : Vec3(s.inertia0_pinv * h);
      s.omega = s.omega.cwiseProduct(s.free_rotation);
      s.L = s.inertia0 * s.omega;
    }
    s.v_prev = s.v;
    s.omega_prev = s.omega;
    s.rotation_rate << 0.0, -s.omega.z(), s.omega.y(), s.omega.z(), 0.0, -s.omega.x(), -s.omega.y(), s.omega.x(), 0.0;
    bodies_.push_back(std::move(s));
  }
  set_live(live);
}

void RigidBodies::set_live(const std::vector<char>& live) {
  for (size_t b = 0; b < bodies_.size(); ++b) {
    RigidBodyState& s = bodies_[b];
    s.live.clear();
    s.interior.clear();
    for (int i : m_.rigid_bodies[b].nodes) (live[static_cast<size_t>(i)] ? s.live : s.interior).push_back(i);
  }
}

void RigidBodies::initial_velocities(std::vector<Vec3>& v) const {
  for (size_t b = 0; b < bodies_.size(); ++b) {
    const RigidBodyState& s = bodies_[b];
    for (int i : m_.rigid_bodies[b].nodes) {
      const size_t k = static_cast<size_t>(i);
      v[k] = s.v + s.omega.cross(m_.x0[k] - s.com0);
    }
  }
}

void RigidBodies::sum_loads(const std::vector<Vec3>& f_int, const std::vector<Vec3>& f_ext,
                            const std::vector<Vec3>& f_con, const std::vector<Vec3>& x) {
  for (RigidBodyState& s : bodies_) {
    Vec3 f = Vec3::Zero(), mo = Vec3::Zero();
    for (int i : s.live) {
      const size_t k = static_cast<size_t>(i);
      const Vec3 fi = f_ext[k] + f_int[k] + f_con[k];
      f += fi;
      if (s.rotates) mo += (x[k] - s.com).cross(fi);
    }
    s.force = f;
    s.moment = mo;
  }
}

Vec3 RigidBodies::angular_velocity(RigidBodyState& s, double dt) const {
  // The rotation at mid-step, t_n + Δt/2, predicted with ω_{n-1/2}.
  const Eigen::Matrix3d Qm = (rotation(0.5 * dt * s.omega_prev) * s.q).toRotationMatrix();
  if (!s.partly_constrained_rotation) return Qm * s.inertia0_pinv * Qm.transpose() * s.L;
  // Some global rotations held: solve the free rows of I·ω = L with the
  // held components zero; their reaction moments take the rest of L.
  Eigen::Matrix3d a = Qm * s.inertia0 * Qm.transpose();
  Vec3 rhs = s.L;
  for (int k = 0; k < 3; ++k)
    if (s.free_rotation[k] == 0.0) {
      a.row(k).setZero();
      a.col(k).setZero();
      a(k, k) = 1.0;
      rhs[k] = 0.0;
    }
  const Vec3 w = pseudo_inverse(a) * rhs;
  s.L = Qm * s.inertia0 * Qm.transpose() * w;
  return w;
}

void RigidBodies::scale_velocities(double factor, const std::vector<Vec3>& x, std::vector<Vec3>& v) {
  for (RigidBodyState& s : bodies_) {
    s.v *= factor, s.L *= factor, s.omega *= factor;
    if (factor == 0.0) {
      s.v_prev.setZero(), s.omega_prev.setZero();
      s.rotation_rate.setZero();
    }
    set_live_velocities(s, x, v);
  }
}

void RigidBodies::set_live_velocities(const RigidBodyState& s, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                                      std::vector<Vec3>* v_prev) const {
  for (int i : s.live) {
    const size_t k = static_cast<size_t>(i);
    if (v_prev) (*v_prev)[k] = v[k];
    v[k] = s.rotates ? Vec3(s.v + s.omega.cross(x[k] - s.com)) : s.v;
  }
}

void RigidBodies::advance_velocities(double h, double dt, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                                     std::vector<Vec3>& v_prev) {
  for (RigidBodyState& s : bodies_) {
    s.v_prev = s.v;
    s.omega_prev = s.omega;
    s.v += (h / s.mass) * s.force.cwiseProduct(s.free_translation);
    if (s.rotates) {
      s.L += h * s.moment.cwiseProduct(s.free_rotation);
      s.omega = angular_velocity(s, dt);
    }
    set_live_velocities(s, x, v, &v_prev);
  }
}

void RigidBodies::add_impulse(size_t b, const Vec3& f, const Vec3& moment, double h, double dt,
                              const std::vector<Vec3>& x, std::vector<Vec3>& v) {
  RigidBodyState& s = bodies_[b];
  s.v += (h / s.mass) * f.cwiseProduct(s.free_translation);
  if (s.rotates) {
    s.L += h * moment.cwiseProduct(s.free_rotation);
    s.omega = angular_velocity(s, dt);
  }
  set_live_velocities(s, x, v);
}

void RigidBodies::advance_positions(double dt, std::vector<Vec3>& x, std::vector<Vec3>& v, std::vector<Vec3>& x_prev) {
  for (RigidBodyState& s : bodies_) {
    s.com += dt * s.v;
    if (!s.rotates) {
      // A body that only translates: the same update as a free node's.
      for (int i : s.live) {
        const size_t k = static_cast<size_t>(i);
        x_prev[k] = x[k];
        x[k] += dt * s.v;
      }
      continue;
    }
    s.Q_prev = s.Q;
    s.q = (rotation(dt * s.omega) * s.q).normalized();
    s.Q = s.q.toRotationMatrix();
    // Positions placed on the body; velocities the chord of the step,
    // formed from the change of rotation (no cancellation of large coordinates).
    s.rotation_rate = (s.Q - s.Q_prev) / dt;
    for (int i : s.live) {
      const size_t k = static_cast<size_t>(i);
      const Vec3 r0 = m_.x0[k] - s.com0;
      x_prev[k] = x[k];
      x[k] = s.com + s.Q * r0;
      v[k] = s.v + s.rotation_rate * r0;
    }
  }
}

double RigidBodies::kinetic_energy(bool first_step) const {
  double ke = 0.0;
  for (const RigidBodyState& s : bodies_) {
    const Vec3 vn = first_step ? s.v_prev : Vec3(0.5 * (s.v_prev + s.v));
    ke += 0.5 * s.mass * vn.squaredNorm();
    if (s.rotates) {
      const Vec3 wn = first_step ? s.omega_prev : Vec3(0.5 * (s.omega_prev + s.omega));
      ke += 0.5 * wn.dot(s.Q * s.inertia0 * s.Q.transpose() * wn);
    }
  }
  return ke;
}

void RigidBodies::place_interior(std::vector<Vec3>& x, std::vector<Vec3>& v) const {
  for (const RigidBodyState& s : bodies_) {
    for (int i : s.interior) {
      const size_t k = static_cast<size_t>(i);
      const Vec3 r0 = m_.x0[k] - s.com0;
      x[k] = s.com + s.Q * r0;
      v[k] = s.v + s.rotation_rate * r0;
    }
  }
}

}  // namespace fe

namespace fe {

void RigidBodies::state(config::StateIO& io) {
  io.expect("rigid bodies", bodies_.size(), "the number of rigid bodies");
  for (RigidBodyState& b : bodies_) {
    io.value("body com", b.com);
    io.value("body q", b.q.coeffs());
    io.value("body Q", b.Q);
    io.value("body Q_prev", b.Q_prev);
    io.value("body rotation_rate", b.rotation_rate);
    io.value("body v", b.v);
    io.value("body v_prev", b.v_prev);
    io.value("body L", b.L);
    io.value("body omega", b.omega);
    io.value("body omega_prev", b.omega_prev);
    io.value("body force", b.force);
    io.value("body moment", b.moment);
  }
}

}  // namespace fe
