// The user-load hook: a one-method interface, called once per FE step at
// stage 2 of the explicit step (after internal forces, before contact and
// accelerations) with the positions x_n and the velocities v_{n-1/2}. It adds
// its external forces to f_ext. The solver accounts their work.
//
// A load whose force depends on the velocity it produces (a TLM port:
// p = c + Zc·q with q from the velocity at t_n, v_n = ½(v_{n-1/2} + v_{n+1/2}))
// also answers apply_implicit, called at stage 6, after the velocity
// predictor: it gets v_{n-1/2}, the predicted v_{n+1/2} (every other force
// applied) and the mobility of the nodes, and returns nodal forces; the
// solver adds them to f_ext and to the velocities. Solving for the force
// with the corrected velocity is what makes such a port unconditionally
// stable (see cavity_load.hpp).
#pragma once

#include <vector>

#include "config/checkpoint.hpp"
#include "model/model.hpp"

namespace fe {

// How the end-of-step velocity answers a force added at stage 6: a force f
// on node i changes the velocity of everything that moves with i (its rigid
// body, or the node alone) by h·free∘f/m. Groups 0..N-1 are the nodes that
// are not in a rigid body; group N + b is rigid body b.
struct Mobility {
  double h = 0.0;                        // the step of the velocity update (Δt, Δt/2 on the first step)
  // v_n = (1 − theta)·v_{n-1/2} + theta·v_{n+1/2}: ½, and 0 on the first step, where v_0 is known.
  double theta = 0.5;
  const std::vector<int>* group = nullptr;       // per node
  const std::vector<double>* inv_mass = nullptr; // per group, 1/kg (0: massless or immovable)
  const std::vector<Vec3>* free = nullptr;       // per group: 1 for a DOF that can move, 0 for a fixed one
};

struct NodalForce {
  int node = 0;
  Vec3 f = Vec3::Zero();
};

class UserLoad {
 public:
  virtual ~UserLoad() = default;
  virtual void apply(double t, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                     std::vector<Vec3>& f_ext) = 0;
  // The nodes this load adds forces to or reads x and v of (appended to
  // `nodes`), so that the solver's per-node passes and the rigid bodies'
  // live nodes cover them and nothing more. false: any node may be loaded
  // (the solver then keeps every node current, at O(mesh) per step).
  virtual bool loaded_nodes(std::vector<int>& /*nodes*/) const { return false; }
  // Stage 6 (see above). `v_old` is v_{n-1/2} (v_0 on the first step),
  // `v_pred` is v_{n+1/2} without this load's forces.
  virtual void apply_implicit(const Mobility&, const std::vector<Vec3>& /*v_old*/, const std::vector<Vec3>& /*v_pred*/,
                              std::vector<NodalForce>& /*out*/) {}
  // Save or restore what the load carries from one step to the next
  // (config/checkpoint.hpp); a load without such state says so with an
  // empty body. Pure, so a new load cannot forget its state.
  virtual void state(config::StateIO& io) = 0;
};

}  // namespace fe
