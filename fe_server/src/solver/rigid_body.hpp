// Rigid bodies integrated as bodies: six DOFs each (centre-of-mass
// translation and rotation), stepped with the solver's central differences,
// at a cost proportional to the nodes that carry loads, not to the mesh.
//
// A body's state is its centre of mass x_c (at t_n), its velocity v_c and
// angular momentum L (at t_{n+1/2}) and its rotation Q from the initial
// configuration (a unit quaternion). A node of the body sits at
// x_i = x_c + Q·(X_i − X_c) with X its initial position. Each step:
//   force  F = Σ f_i and moment M = Σ (x_i − x_c) × f_i over the body's
//          live nodes (every other node of a rigid body carries no force:
//          rigid elements have no force loop, and loads, contacts and
//          springs only act on live nodes);
//   v_c   += h·F/m, L += h·M, with the constrained DOFs held at zero;
//   ω      = I⁻¹·L with the world inertia at the mid-step rotation
//          (I = Q J Qᵀ, J the inertia at t = 0): angular momentum is
//          conserved exactly when no moment acts, and the kinetic energy of a
//          free body to second order in ω·Δt;
//   x_c   += Δt·v_c, Q ← exp(Δt·ω)·Q (an exact rotation by Δt·ω).
// The live nodes' positions are then placed and their velocities set to the
// chord (x_{n+1} − x_n)/Δt, so that every node moves as the solver's own
// update x_{n+1} = x_n + Δt·v_{n+1/2} would move it.
//
// Live nodes are those something reads or loads: discrete elements,
// contacts, loading sets (and their reference nodes), history nodes, and
// nodes shared with deformable elements. The others are placed only on
// request (place_interior), e.g. for a field snapshot.
//
// In a 2D axisymmetric model a body can only move along the axis (a ring
// has no net radial force and cannot rotate about an in-plane axis).
//
// A body with no extent along an axis (nodes on a line, one node) has no
// inertia about it: that rotation is held, as a constrained one is.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "config/checkpoint.hpp"
#include "model/model.hpp"

namespace fe {

struct RigidBodyState {
  double mass = 0.0;
  Vec3 com0 = Vec3::Zero();                          // X_c
  Eigen::Matrix3d inertia0 = Eigen::Matrix3d::Zero();  // J about X_c, global axes at t = 0
  Eigen::Matrix3d inertia0_pinv = Eigen::Matrix3d::Zero();  // its (pseudo-)inverse
  Vec3 free_translation = Vec3::Ones();  // 1: free, 0: constrained, global axes
  Vec3 free_rotation = Vec3::Ones();     // global axes
  bool rotates = false;                  // some rotation free and with inertia
  bool partly_constrained_rotation = false;
  Vec3 com = Vec3::Zero();                                // x_c at t_n
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // Q at t_n
  Eigen::Matrix3d Q = Eigen::Matrix3d::Identity(), Q_prev = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d rotation_rate = Eigen::Matrix3d::Zero();  // (Q − Q_prev)/Δt: a node's chord velocity is v_c + this·r0
  Vec3 v = Vec3::Zero(), v_prev = Vec3::Zero();          // v_c at t_{n+1/2} and t_{n-1/2}
  Vec3 L = Vec3::Zero();                                  // angular momentum at t_{n+1/2}
  Vec3 omega = Vec3::Zero(), omega_prev = Vec3::Zero();  // ω at t_{n+1/2} and t_{n-1/2}
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();      // summed this step
  std::vector<int> live, interior;                         // node indices
};

class RigidBodies {
 public:
  // live[i]: node i is read or loaded by something (see above).
  RigidBodies(const Model& model, const std::vector<char>& live);
  // New live nodes (a user load set after construction).
  void set_live(const std::vector<char>& live);

  size_t size() const { return bodies_.size(); }
  // Every body's motion (checkpoints; the mass properties come from the model).
  void state(config::StateIO& io);
  const RigidBodyState& operator[](size_t b) const { return bodies_[b]; }
  // v_0 of every node of every body: v_c + ω × r.
  void initial_velocities(std::vector<Vec3>& v) const;

  // Stage 4: sum each body's force and moment from its live nodes.
  void sum_loads(const std::vector<Vec3>& f_int, const std::vector<Vec3>& f_ext, const std::vector<Vec3>& f_con,
                 const std::vector<Vec3>& x);
  // Stage 5: v_c and L (h = Δt, Δt/2 on the first step), ω, and the live
  // nodes' predicted velocities v_c + ω × (x_i − x_c), their old ones kept
  // in v_prev (the same pass).
  void advance_velocities(double h, double dt, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                          std::vector<Vec3>& v_prev);
  // Stage 6: force f and moment about x_c acting on body b for h more,
  // then its live nodes' velocities again.
  void add_impulse(size_t b, const Vec3& f, const Vec3& moment, double h, double dt, const std::vector<Vec3>& x,
                   std::vector<Vec3>& v);
  // Stage 8: x_c, Q, and the live nodes' positions and chord velocities,
  // their old positions kept in x_prev (the same pass).
  void advance_positions(double dt, std::vector<Vec3>& x, std::vector<Vec3>& v, std::vector<Vec3>& x_prev);
  // Dynamic relaxation: every body's v_c, L and ω times `factor` (0: at
  // rest, both half steps), and its live nodes' velocities with them.
  void scale_velocities(double factor, const std::vector<Vec3>& x, std::vector<Vec3>& v);
  // Kinetic energy at t_n from the mean of the half-step velocities (the
  // initial ones on the first step).
  double kinetic_energy(bool first_step) const;
  // The positions (t_n) and chord velocities (t_{n-1/2}) of the bodies'
  // nodes that are not live; at t = 0 the initial v_c + ω × r.
  void place_interior(std::vector<Vec3>& x, std::vector<Vec3>& v) const;

 private:
  // ω = I⁻¹·L with I at the rotation of t_n + dt/2 (estimated with ω_{n-1/2}).
  Vec3 angular_velocity(RigidBodyState& s, double dt) const;
  void set_live_velocities(const RigidBodyState& s, const std::vector<Vec3>& x, std::vector<Vec3>& v,
                           std::vector<Vec3>* v_prev = nullptr) const;

  const Model& m_;
  std::vector<RigidBodyState> bodies_;
};

}  // namespace fe
