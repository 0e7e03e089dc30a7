// Explicit central-difference time integration with lumped mass.
//
// One step, t_n → t_{n+1}, in named stages (each one function):
//   1 internal_forces      f_int(x_n, v_{n-1/2}): what the elements exert on the nodes
//   2 user_loads           f_ext(x_n, v_{n-1/2})  ← the UserLoad hook
//   3 contact              (none in this version)
//   4 accelerations        a_n = (f_ext + f_int) / m, rigid bodies as one mass
//   5 boundary_conditions  a = 0 on fixed DOFs
//   6 velocities           v_{n+1/2} = v_{n-1/2} + Δt·a_n (Δt/2 on the first step)
//   7 positions            x_{n+1} = x_n + Δt·v_{n+1/2}
//   8 energy_account       kinetic + internal + damping − external work at t_n
// The stable step is checked once at construction (fixed Δt).
#pragma once

#include <string>
#include <vector>

#include "model.hpp"
#include "user_load.hpp"

namespace fe {

struct Energies {
  double kinetic = 0.0;
  double internal = 0.0;       // springs
  double damping = 0.0;        // dissipated by dampers so far
  double external_work = 0.0;  // done by user loads so far
  // kinetic + internal + damping − external work − its value at t = 0
  double balance_error = 0.0;
};

class Solver {
 public:
  // Throws std::runtime_error naming the limiting element if dt exceeds
  // the model's stable step times its safety factor.
  Solver(const Model& model, double dt);

  void set_user_load(UserLoad* load) { user_load_ = load; }
  void step();

  double time() const { return t_; }
  long step_count() const { return n_; }
  double dt() const { return dt_; }
  const std::vector<Vec3>& x() const { return x_; }
  const std::vector<Vec3>& v() const { return v_; }  // v_{n-1/2} of the next step
  const Energies& energies() const { return energies_; }
  // Largest stable step of the model (without safety factor) and what limits it.
  static double stable_dt(const Model& model, std::string* limited_by = nullptr);

 private:
  void internal_forces();
  void user_loads();
  void contact() {}
  void accelerations();
  void boundary_conditions();
  void velocities();
  void positions();
  void energy_account();

  const Model& m_;
  double dt_;
  double t_ = 0.0;
  long n_ = 0;
  UserLoad* user_load_ = nullptr;
  // Nodal state, one array per quantity.
  std::vector<Vec3> x_, v_, a_, f_int_, f_ext_, f_ext_prev_, x_prev_;
  std::vector<int> body_of_;  // rigid body index per node, -1 if none
  std::vector<Eigen::Matrix<bool, 3, 1>> body_fixed_;
  std::vector<Vec3> v_prev_;  // v_{n-1/2}, for the kinetic energy at t_n
  double spring_energy_ = 0.0, damping_power_ = 0.0;
  Energies energies_;
  double energy0_ = 0.0;
};

}  // namespace fe
