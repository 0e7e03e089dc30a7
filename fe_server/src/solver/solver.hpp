// Explicit central-difference time integration with lumped mass.
//
// One step, t_n → t_{n+1}, in named stages (each one function):
//   1 internal_forces      f_int(x_n, v_{n-1/2}): the force loop of each element type
//                          (elements/: springs and dampers, 1D bars, hex8,
//                          axisymmetric quads)
//   2 user_loads           f_ext(x_n, v_{n-1/2})  ← the UserLoad hook, and the
//                          deck's body loads (−m·a on every node of their parts)
//   3 contact              penalty contact forces
//   4 accelerations        a rigid body's force and moment from its live nodes
//                          (rigid_body.hpp)
//   5 velocities           v_{n+1/2} = v_{n-1/2} + Δt·(f_ext + f_int + f_contact)/m
//                          (Δt/2 on the first step), zero on fixed DOFs, in one
//                          pass; rigid bodies: v_c, L, ω
//   6 implicit_loads       forces that depend on v_{n+1/2} (TLM ports), solved with the
//                          corrected velocity and added to f_ext and v_{n+1/2}
//   6b prescribed_motions  prescribed DOFs get their curve's v_{n+1/2}; the
//                          force that takes joins f_ext (its work is the loads')
//   6c tied_nodes          a tied slave node takes its master segment's
//                          weighted velocity (its force and mass went to the
//                          segment's nodes in stage 5)
//   7 external_work        the user loads' work over the last step
//   8 positions            x_{n+1} = x_n + Δt·v_{n+1/2} and, in the same pass, the
//                          kinetic energy at t_n; rigid bodies rotate and move
//   9 energy_account       kinetic + internal + spring + hourglass + contact + damping − external work
// The step follows the model, as LS-DYNA's does with TSSFAC: the element
// loops of stage 1 measure each element's current stable step, and the step
// about to be taken is TSSFAC times the smallest, never above the step the
// solver was constructed with (choose_step). With unequal steps the
// velocities advance by the mean of the last and the next step. A horizon
// (set_horizon: a coupling step's end, the run's end) is met exactly: the
// time left in a whole number of steps. A model whose elements keep their
// size runs the constructor's step to the bit; a stable step below
// kMinStepShare of it stops the run (an element being crushed). A deck with
// a dynamic relaxation settles first (relax(), velocities × DRFCTR every
// step, the curves of that phase), then begin_transient() restarts at t = 0.
//
// Per-node passes run over the active nodes only: every node outside rigid
// bodies, and the live nodes of the bodies (those something loads or
// reads: rigid_body.hpp). A body's other nodes cost nothing per step.
//
// Across MPI ranks (parallel/domain.hpp): each rank computes the forces of
// the elements it owns (partition.hpp) and integrates the nodes it holds:
// its elements' nodes and the global nodes, those that contact, a load, a
// rigid body, a tie, a spring, a history or a cross section reads. A node
// held by several ranks is shared: at the end of stage 1 its partial
// internal forces are exchanged with the ranks that share it and summed in
// rank order, so that every rank holds the same bits for it (the halo
// exchange). Global nodes are held by every rank, so the stages that read
// them (2–9) run on every rank on identical inputs and agree without
// further messages. The energies of the elements and the kinetic energy are
// summed in rank order (the same value on every rank); the histories'
// elements and the cross sections' forces are shared with them. Results
// differ from one rank's by the order of the sums at shared nodes only
// (round-off). An inverted element on one rank ends the step on every rank
// with its message.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "config/checkpoint.hpp"
#include "contact/contact.hpp"
#include "elements/element_axi4.hpp"
#include "elements/element_bar.hpp"
#include "elements/element_discrete.hpp"
#include "elements/element_hex8.hpp"
#include "model/model.hpp"
#include "loads/user_load.hpp"
#include "parallel/domain.hpp"
#include "parallel/thread_pool.hpp"
#include "solver/partition.hpp"
#include "solver/rigid_body.hpp"

namespace fe {

struct Energies {
  double kinetic = 0.0;
  double internal = 0.0;       // elastic energy of the elements (work of their stresses)
  double spring = 0.0;         // energy stored in the discrete springs now
  double hourglass = 0.0;      // dissipated by hourglass control
  double contact = 0.0;        // stored in and dissipated by contact
  double damping = 0.0;        // dissipated by dampers and bulk viscosity
  double external_work = 0.0;  // done by user loads
  double scale = 0.0;          // the largest of kinetic + internal + spring and |external work| so far
  // Per part of solids (ids in Model::parts order): the hourglass energy and
  // the internal work put in, the sum of the steps' positive increments of
  // the part's internal energy (its peak under a growing load; every blow's
  // for a machine that strikes again and again).
  std::vector<int> part_ids;
  std::vector<double> part_hourglass, part_loading;
  std::vector<double> part_internal;  // each part's internal energy now (the sum of its steps' increments)
  // kinetic + internal + spring + hourglass + contact + damping − external work − its value at t = 0
  double balance_error = 0.0;
};

// Empty, or a warning when a part's hourglass energy exceeds 10 % of its
// internal energy: the rule of thumb of the LS-DYNA theory and user manuals,
// beyond which the zero-energy modes have taken a visible part of the
// deformation and the mesh or the load needs changing (refine, spread the
// load). Per part, so that a stiff part full of energy does not hide a
// hourglassing one. The hourglass energy is dissipated, so it accumulates;
// the internal energy of a machine that strikes again and again returns to
// nearly zero after every blow. The comparison is therefore with the energy
// that went into the part's elements (Energies::part_loading). A part that
// took less than 1e-6 of the largest energy the model held is not judged (a
// ratio of nothing: "9679 % of 3e-33 J"). Parts without solids (bars,
// springs) have no hourglass modes.
std::string hourglass_warning(const Energies& e);

// What limits the stable time step.
struct StableStep {
  double dt = 1e300;
  std::string limited_by;
  // The limiting element as LS-DYNA's glstat names it ("solid", "shell" for
  // a 2D solid, "beam", "discrete") and its id; empty and 0 if none.
  std::string element_kind;
  int element_id = 0;
};

class Solver {
 public:
  // Throws std::runtime_error naming the limiting element if dt exceeds the
  // model's stable step times its safety factor (TSSFAC).
  // domain: the ranks the model runs on (one unless fe_server runs under
  // mpirun/srun); every rank constructs the solver with the same model.
  // partition: the elements' owners (default: partition_elements); tests
  // give their own to cut a contact or a cavity on purpose.
  Solver(const Model& model, double dt, const Domain& domain = Domain::serial(), const Partition* partition = nullptr);

  // Threads for the element loops (1: this thread only). The results are
  // bit-identical for any count.
  void set_threads(int threads);
  int threads() const;
  static constexpr size_t kNodeBlock = 2048;  // nodes per task of the per-node passes
  // The hook of stages 2 and 6; its loaded_nodes() join the live nodes.
  // Before the first step (std::logic_error after it).
  void set_user_load(UserLoad* load);
  void step();

  // Dynamic relaxation (*CONTROL_DYNAMIC_RELAXATION, model/model.hpp): the
  // model settles under the loads that act in that phase, velocities scaled
  // by DRFCTR every step, until converged; then begin_transient() restarts
  // time at 0 with every node at rest in the settled state. Without a
  // relaxation in the deck relax() does nothing.
  struct RelaxationReport {
    bool ran = false, converged = false;
    long steps = 0;
    double time = 0.0;              // pseudo-time of the relaxation, s
    double kinetic = 0.0, peak = 0.0;  // kinetic energy at the end and its peak, J
    // The residual: the largest out-of-balance force summed over one part
    // (its free DOFs), and the largest force a prescribed motion or support
    // takes (the feed, a reaction) to compare it with, N. Converged: the
    // kinetic energy below DRTOL of its peak and the residual below DRTOL
    // of that force.
    double resultant = 0.0, load = 0.0;
    std::string worst;  // that part
    bool stopped = false;  // keep_going said no
  };
  // keep_going(report so far) is asked every 64 steps: false ends the
  // relaxation there (a stop signal; it may also print progress).
  RelaxationReport relax(const std::function<bool(const RelaxationReport&)>& keep_going = {});
  void begin_transient();

  // Save or restore everything step() changes (checkpoint and restart,
  // config/checkpoint.hpp): after restoring, the run continues bit for bit
  // as the saved one did. The model must be the one the state was saved
  // with (the node and element counts are checked).
  void state(config::StateIO& io);

  double time() const { return t_; }
  long step_count() const { return n_; }
  // The step just taken (after step()), the next one's upper bound.
  double dt() const { return dt_; }
  double dt_cap() const { return dt_cap_; }
  // The last step's velocity update: v_{n+1/2} − v_{n−1/2} = h·a_n.
  double velocity_step_taken() const { return h_taken_; }
  // Steps end on t exactly (a coupling step's end); reached_horizon(): the
  // last step ended there. A horizon at or before time() is none.
  void set_horizon(double t) { horizon_ = t, last_of_horizon_ = false; }
  bool reached_horizon() const { return last_of_horizon_; }
  // How many steps were shorter than the one before (the model's stable step shrank).
  long shrunk_steps() const { return shrunk_steps_; }
  // The smallest current stable step of the elements at the last step, and what.
  double current_stable_step() const { return step_limit_; }
  std::string limiting_element() const;
  // A stable step below this share of the start's stops the run.
  static constexpr double kMinStepShare = 0.01;
  // Positions x_n and velocities v_{n-1/2} (of the next step) of every node:
  // places the rigid bodies' interior nodes first (O(mesh); for field
  // snapshots and tests).
  const std::vector<Vec3>& x() const;
  const std::vector<Vec3>& v() const;
  // The same arrays without placing: current on every node that is not an
  // interior node of a rigid body, i.e. every node a load, contact, spring,
  // element or history reads. For per-step readers.
  const std::vector<Vec3>& x_live() const { return x_; }
  const std::vector<Vec3>& v_live() const { return v_; }
  const RigidBodies& bodies() const { return bodies_; }
  // Nodes the per-node passes visit (see above); for the benchmarks' counts.
  size_t active_nodes() const { return active_.size(); }
  const Energies& energies() const { return energies_; }
  // Stress (Voigt: xx, yy, zz, xy, yz, zx) of solid element e.
  const Eigen::Matrix<double, 6, 1>& stress(size_t e) const { return hex8_.sigma[e]; }
  // Effective plastic strain of solid e (0 for an elastic material).
  double plastic_strain(size_t e) const { return hex8_.plastic_strain[e]; }
  // Stress of axisymmetric element e (Voigt: rr, yy (axial), θθ (hoop), ry,
  // 0, 0), Pa: x is the radius and y the axis.
  const Eigen::Matrix<double, 6, 1>& axi_stress(size_t e) const { return axi4_.sigma[e]; }
  double axi_plastic_strain(size_t e) const { return axi4_.plastic_strain[e]; }
  // Axial stress of 1D bar element e (tension positive), Pa.
  double bar_stress(size_t e) const;
  // Force through cross section k of the model (*DATABASE_CROSS_SECTION_SET)
  // in the last step: the internal forces its elements exert on the cut's
  // nodes, N (global x, y, z; in 2D x is radial, y axial).
  Vec3 section_force(size_t k) const;
  // The state the element stresses (and section forces, contact forces and
  // energies) of the last step belong to: positions x_n at t_n = time() − dt(),
  // the step's start; and a live node's velocity there, ½(v_{n−1/2} + v_{n+1/2})
  // (v_0 on the first step).
  double stress_time() const { return t_ - dt_; }
  Vec3 velocity_at_stress_time(size_t i) const { return n_ == 1 ? v_prev_[i] : Vec3(0.5 * (v_prev_[i] + v_[i])); }
  // Mean velocity of 1D bar element e's two nodes along its axis (n1 → n2)
  // at stress_time(), m/s.
  double bar_axial_velocity(size_t e) const;
  // Total normal force of the last step, N: half the sum of |f_con| over
  // the contact nodes (each pair appears on both sides), summed when asked
  // (histories ask at their interval, not every step), on the calling
  // thread in list order: the same value for any thread count.
  double contact_force() const;
  // The contacts in deck order (their resultants: rcforc).
  const std::vector<std::unique_ptr<PenaltyContact>>& contacts() const { return contacts_; }
  // Velocities v_{n-1/2} of the last step's start (with v(), the acceleration at t_n).
  const std::vector<Vec3>& v_previous() const { return v_prev_; }
  double max_penetration() const;
  // Said once at construction, for the user (slave nodes of a tie that lie
  // on no master segment and stay free, ...); empty if nothing.
  const std::vector<std::string>& notes() const { return notes_; }
  // Tied slave nodes (*CONTACT_TIED_...), each with its master segment's
  // nodes and weights.
  struct Tie {
    int slave = 0, corners = 0;
    int master[4] = {0, 0, 0, 0};
    double w[4] = {0, 0, 0, 0};
  };
  const std::vector<Tie>& ties() const { return ties_; }
  // Largest stable step of the model (without safety factor) and what limits it.
  static StableStep stable_dt(const Model& model);

  // Across ranks: the partition, this rank's nodes, and (collective: every
  // rank calls it) the whole state at rank 0 for a field snapshot: x, v of
  // every node, stress and plastic strain of every solid (or axisymmetric
  // element). Other ranks' outputs are left empty. Serial: copies.
  const Domain& domain() const { return dom_; }
  const Partition& partition() const { return part_; }
  size_t shared_nodes() const { return ex_.shared.size(); }
  void gather_fields(std::vector<Vec3>& x, std::vector<Vec3>& v, std::vector<Eigen::Matrix<double, 6, 1>>& stress,
                     std::vector<double>& plastic, bool axisymmetric) const;
  // The same for the velocities alone (collective; serial: v()).
  void gather_velocities(std::vector<Vec3>& v) const;

 private:
  void internal_forces();
  void user_loads();
  void contact();
  void accelerations();
  void velocities();
  void implicit_loads();
  void prescribed_motions();
  void tied_nodes();
  // *BOUNDARY_PRESCRIBED_MOTION_RIGID: a rigid body's translation in one DOF
  // from its curve (stage 6b); the force that takes (its reaction, applied
  // at the centre of mass) is booked with the loads' work.
  struct RigidMotion {
    size_t motion = 0;  // in Model::prescribed
    size_t body = 0;
    double reaction = 0.0, reaction_prev = 0.0, com_prev = 0.0;
  };
  std::vector<RigidMotion> rigid_motions_;
  // The ties of one *CONTACT_TIED_ card: each slave node on the master
  // segment it lies on (within a tenth of the segments' size); nodes on
  // none are left free and said in notes().
  void build_ties(const TieDef& def);
  std::vector<Tie> ties_;
  std::vector<std::string> notes_;
  void body_loads();
  void segment_pressures();  // *LOAD_SEGMENT(_SET)
  void nodal_loads();        // *LOAD_NODE_POINT, *LOAD_NODE_SET
  void damping();            // *DAMPING_GLOBAL, *DAMPING_PART_MASS
  void relaxation_residual(RelaxationReport& rep) const;
  bool curve_acts(int curve_id) const;  // in this phase (transient or relaxation)
  bool relaxing_ = false;
  std::vector<double> body_load_mass_;  // per node: the mass a body load accelerates
  void external_work();
  void positions();
  void energy_account();
  // Work of force field f over the last step, trapezoidal: ½(f_prev + f)·(x_n − x_{n−1}).
  double step_work(const std::vector<Vec3>& f_prev, const std::vector<Vec3>& f, const std::vector<int>& nodes);
  // Live nodes, bodies' live lists, and the node lists above.
  void build_node_lists();
  // Per-node passes in fixed blocks of kNodeBlock list entries, on the
  // pool's threads when the list is long: f(i) for every node i of the list.
  // sum_over adds g(i) per block, then the blocks in order: the same sum
  // for any thread count.
  template <class F>
  void for_each_node(const std::vector<int>& nodes, F&& f);
  template <class G>
  double sum_over(const std::vector<int>& nodes, G&& g);
  std::vector<double> partial_;
  // A node list as runs of consecutive node numbers [first, end), cut at
  // the same block boundaries as for_each_node's: the hot passes over the
  // free nodes (velocities, positions) then run over flat arrays the
  // compiler vectorises, in the list's order, block by block as before.
  struct NodeRuns {
    std::vector<size_t> block_start;  // per block, its first run; one more entry at the end
    std::vector<std::pair<size_t, size_t>> runs;
  };
  static NodeRuns runs_of(const std::vector<int>& nodes);
  // run(b, first, end) for each run [first, end) of block b, for every
  // block, on the pool when there are several.
  template <class R>
  void for_each_run(const NodeRuns& runs, R&& run);
  NodeRuns free_runs_;
  std::vector<double> ke_partial_;

  const Domain& dom_;
  Partition part_;
  const Model& m_;
  double dt_;
  double dt_last_ = 0.0, dt_cap_ = 0.0, horizon_ = -1.0, h_taken_ = 0.0;
  bool last_of_horizon_ = false;
  long shrunk_steps_ = 0;
  double step_limit_ = 1e300;
  int limit_kind_ = 0;
  long limit_element_ = -1;
  void choose_step();
  // v_{n+1/2} = v_{n−1/2} + h·a_n: h = (Δt_{n−1/2} + Δt_{n+1/2})/2, Δt/2 on the first step.
  double velocity_step() const { return n_ == 0 ? 0.5 * dt_ : 0.5 * (dt_last_ + dt_); }
  double t_ = 0.0;
  long n_ = 0;
  UserLoad* user_load_ = nullptr;
  // Nodal state, one array per quantity. x_ and v_ are mutable because
  // x() and v() place the bodies' interior nodes, which no pass reads.
  mutable std::vector<Vec3> x_, v_;
  mutable bool interior_placed_ = true;
  std::vector<Vec3> inv_mass_free_;  // per free node: 1/m on free DOFs, 0 on fixed ones
  std::vector<Vec3> f_int_, f_ext_, f_ext_prev_, f_con_, f_con_prev_, x_prev_, v_prev_;
  std::vector<double> part_internal_step_, part_hourglass_step_;  // this step's, per part
  std::vector<double> mass_, contact_mass_;
  std::vector<int> body_of_;  // rigid body index per node, -1 if none
  std::vector<int> active_;   // nodes of the per-node passes, ascending
  std::vector<int> free_;     // nodes not in a rigid body, ascending
  // The nodes each kind of force can reach (zeroed and its work summed there
  // only): element and discrete nodes, the user load's, the contacts'.
  std::vector<int> int_nodes_, ext_nodes_, con_nodes_;
  RigidBodies bodies_;
  std::unique_ptr<ThreadPool> pool_;  // null: one thread
  // Mobility for stage 6: group per node (the node, or N + its body), and per group.
  std::vector<int> group_;
  std::vector<double> group_inv_mass_;
  std::vector<Vec3> group_free_;
  std::vector<NodalForce> implicit_forces_;
  std::vector<Vec3> group_force_, group_moment_;   // scratch, zero outside implicit_loads()
  std::vector<int> touched_groups_;
  std::vector<char> group_touched_;                // scratch: 1 for the groups in touched_groups_
  // Element state, one struct per element type (elements/).
  Hex8State hex8_;
  Axi4State axi4_;
  BarState bars_;
  std::vector<std::unique_ptr<PenaltyContact>> contacts_;
  // Per cross section, where its forces are: hex8 and axi4 force slots, and
  // bar ends (element index, 0 for n1 or 1 for n2).
  struct SectionSlots {
    std::vector<int> hex, axi;
    std::vector<std::pair<int, int>> bar_ends;
  };
  std::vector<SectionSlots> sections_;
  double damping_power_ = 0.0;
  mutable double contact_force_ = 0.0;
  mutable bool contact_force_stale_ = false;
  Energies energies_;
  double energy0_ = 0.0;
  // The run-quality guard (the end of every step, solver.cpp): what is not
  // finite, named by node; a node farther outside the initial bounding box
  // than the box's diagonal (every kBoxCheckEvery steps, agreed by all ranks).
  void check_state() const;
  std::string first_non_finite() const;
  static constexpr long kBoxCheckEvery = 32;
  static constexpr double kMaxContactDepth = 0.2;  // of a contact's element size: deeper stops the run
  Vec3 box_lo_ = Vec3::Zero(), box_hi_ = Vec3::Zero();
  double box_size_ = 0.0;
  // Across ranks (see the top of this file). sharers_[i]: the ranks that
  // hold node i, ascending ({0} for a node no element touches).
  void plan_ranks(const std::vector<char>& global);
  // Stage 1's end: shared nodes' forces summed, element energies, history
  // elements and section forces shared; `error` (an inverted element here)
  // ends the step on every rank.
  void reduce_element_work(ElementWork& w, const std::string& error);
  Vec3 local_section_force(size_t k) const;
  std::vector<std::vector<int>> sharers_;
  struct Exchange {
    std::vector<int> peers;                      // ranks this one shares nodes with
    std::vector<std::vector<int>> nodes;         // per peer: the nodes shared with it, ascending
    std::vector<std::vector<double>> send, recv;
    std::vector<int> shared;                     // nodes held here and elsewhere, ascending
    std::vector<size_t> first;                   // per shared node: its sources [first[k], first[k + 1])
    std::vector<std::pair<int, size_t>> sources; // in rank order: (peer index, offset in recv) or (-1, 0) for this rank's
  } ex_;
  std::vector<double> mass_ke_;  // the mass this rank counts in the kinetic energy (0 where another rank counts the node)
  std::vector<double> scalars_mine_, scalars_all_;
  std::vector<Vec3> section_total_;
};

}  // namespace fe
