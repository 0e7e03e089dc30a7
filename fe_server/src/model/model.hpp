// The structural model as read from a keyword deck: nodal arrays per
// quantity, discrete springs/dampers, nodal rigid bodies, segment sets and the
// co-simulation loading sets. SI units throughout.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "config/keyword_reader.hpp"
#include "fatigue/damage.hpp"

namespace fe {

using Vec3 = Eigen::Vector3d;

struct DiscreteElement {
  int id = 0;
  int n1 = 0, n2 = 0;     // node indices (not ids)
  double k = 0.0;         // spring stiffness, N/m (0: none)
  double c = 0.0;         // damping, N·s/m (0: none)
  double offset = 0.0;    // initial offset, m: positive gives tension at t = 0
  double length0 = 0.0;   // initial length, m
  config::SourceLocation where;
};

// Nodes that move together as one body with six DOFs (solver/rigid_body.hpp):
// a *MAT_RIGID part's nodes, or a *CONSTRAINED_NODAL_RIGID_BODY's node set.
struct RigidBody {
  int id = 0;
  std::vector<int> nodes;  // node indices
  double mass = 0.0;
  // *PART_INERTIA: mass, centre of mass, inertia tensor about it (global
  // axes) and initial velocities given in the deck instead of summed from the
  // nodes.
  bool inertia_given = false;
  Vec3 com = Vec3::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  Vec3 v0 = Vec3::Zero(), omega0 = Vec3::Zero();
  // Constrained global DOFs (*MAT_RIGID CMO = 1, CON1 and CON2); a
  // translational SPC on any of the body's nodes also fixes that translation.
  Eigen::Matrix<bool, 3, 1> fixed_translation{false, false, false};
  Eigen::Matrix<bool, 3, 1> fixed_rotation{false, false, false};
  config::SourceLocation where;
};

struct Segment {
  int n[4] = {0, 0, 0, 0};  // node indices; n[3] == n[2] for a triangle
  // A 2-node line segment of an axisymmetric boundary has n[2] = n[3] = -1;
  // its outward normal points to the right of n[0] → n[1] in the x–y plane
  // (the body lies on its left, as for a counter-clockwise element).
  bool line() const { return n[2] < 0; }
  // Distinct corners: 2 for a line, 3 for a triangle, 4 for a quad.
  int corners() const { return line() ? 2 : n[3] == n[2] ? 3 : 4; }
};

struct Material {
  int id = 0;
  double rho = 0.0, E = 0.0, nu = 0.0;
  bool rigid = false;
  // *MAT_RIGID CMO = 1: CON1 and CON2 as fixed global translations and rotations.
  Eigen::Matrix<bool, 3, 1> rigid_fixed_translation{false, false, false};
  Eigen::Matrix<bool, 3, 1> rigid_fixed_rotation{false, false, false};
  // J2 plasticity (*MAT_PLASTIC_KINEMATIC, 003; *MAT_PIECEWISE_LINEAR_
  // PLASTICITY, 024), radial return in the solids: initial yield stress
  // SIGY, plastic modulus H = E·ETAN/(E − ETAN), BETA the isotropic share of
  // the hardening (0 kinematic, 1 isotropic; 024 is isotropic), or 024's
  // yield stress against effective plastic strain (LCSS or EPS/ES, the last
  // segment's slope beyond its end).
  bool plastic = false;
  double yield = 0.0, plastic_modulus = 0.0, beta = 1.0;
  std::vector<double> hardening_strain, hardening_stress;  // empty: SIGY and H
  // The yield stress at effective plastic strain ep and its slope there.
  double yield_stress(double ep, double* slope) const;
  // Derived: Lamé constants and the dilatational wave speed.
  double lambda() const { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
  double mu() const { return E / (2.0 * (1.0 + nu)); }
  double wave_speed() const { return std::sqrt((lambda() + 2.0 * mu()) / rho); }
  config::SourceLocation where;
};

struct Part {
  int id = 0;
  std::string title;
  int section = 0, material = 0;
  double bar_area = 0.0;  // m², for 1D bar (truss) sections
  // *DAMPING_PART_STIFFNESS with COEF < 0: Rayleigh stiffness-proportional
  // damping C = β·K, β = |COEF| in s. The elements add the damping stress
  // β·C:D (C the elastic tangent, D the strain rate) to the stress their
  // forces carry, not to the stress they store; a mode of angular frequency
  // ω is damped at ζ = β·ω/2 of critical. 0: none.
  double stiffness_damping = 0.0;
  config::SourceLocation where;
};

// A solid: an eight-node hexahedron (a wedge as a degenerate one, repeated
// nodes), or a four-node tetrahedron (tet4, ELFORM 10: element_tet4.hpp)
// in the slots n1 n2 n3 n3 n4 n4 n4 n4.
struct SolidElement {
  int id = 0, part = 0;
  int n[8] = {0, 0, 0, 0, 0, 0, 0, 0};  // node indices
  double mass_scale = 1.0;  // density factor from selective mass scaling
  bool tet4 = false;
};

// Four-node axisymmetric solid (element_axi4.hpp): *ELEMENT_SHELL of a part
// whose *SECTION_SHELL has ELFORM 14 or 15; nodes in the x–y plane, x = r.
struct AxiElement {
  int id = 0, part = 0;
  int n[4] = {0, 0, 0, 0};  // node indices, counter-clockwise in (r, y)
  double mass_scale = 1.0;  // density factor from selective mass scaling
};

// Two-node 1D bar (truss): axial force only, area from its section.
struct BarElement {
  int id = 0, part = 0;
  int n1 = 0, n2 = 0;
  double mass_scale = 1.0;  // density factor from selective mass scaling
};

// *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE between two segment sets, or
// between the nodes of a node set (SSTYP 4) and a segment set: one-sided,
// e.g. the end node of a 1D bar against a solid's face.
struct ContactDef {
  int slave_set = 0, master_set = 0;  // segment set ids (slave: a node set id when slave_nodes)
  bool slave_nodes = false;           // SSTYP 4: the slave side is a node set
  // *CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE: the sets are segment sets of
  // 2-node line segments (the boundaries of the parts of two part sets,
  // built by the reader), checked in the x–y plane.
  bool planar = false;
  // *CONTACT_AUTOMATIC_SINGLE_SURFACE: one surface (the outer faces of the
  // solids of its parts, a segment set the reader builds: master_set) in
  // contact with itself: every node against every face but those of its own
  // elements. part_ids holds the parts (empty: all).
  bool single_surface = false;
  std::vector<int> part_ids;
  // Coulomb friction as LS-DYNA's: μ = FD + (FS − FD)·exp(−DC·|v_t|) of the
  // sliding speed v_t, the friction force at most VC·A (the touched
  // segment's area) when VC > 0 (contact.hpp).
  double fs = 0.0, fd = 0.0, dc = 0.0, vc = 0.0;
  double damping = 0.2;               // VDC as a fraction of critical
  double stiffness_factor = 1.0;      // SFS
  config::SourceLocation where;
};

// *CONTACT_TIED_SURFACE_TO_SURFACE (or _NODES_TO_SURFACE: the slave side a
// node set): each slave node lying on a master segment at t = 0 moves with
// it from then on, as a constraint: its mass and force go to the segment's
// nodes by its position's weights, and it takes their weighted velocity
// (LS-DYNA's constraint-based tie; solver.hpp).
struct TieDef {
  int slave_set = 0, master_set = 0;  // segment sets (slave: a node set when slave_nodes)
  bool slave_nodes = false;
  config::SourceLocation where;
};

// A co-simulation port acting on a segment set (*USER_LOADING_SET); "along
// the axis" below is Model::symmetry_axis (z in 3D, y in 2D axisymmetric decks).
struct LoadingSet {
  int port_id = 0;
  int segment_set = 0;  // PRESSS: a segment set; FORCE: a node set
  bool force = false;   // FORCE: a mechanical port's force along the axis on a node set
  // BODY (force is then true too): SID is a part set; the port's force acts
  // on its nodes in proportion to their masses (a body force: gravity,
  // friction, a cushion on an elastic body without hourglassing its
  // surface) and reports the parts' centre-of-mass motion.
  bool body = false;
  std::vector<int> body_nodes;  // node indices of the part set's elements (BODY)
  // Cavity bounds along the axis, moving with the reference node (e.g. on
  // the housing; -1: fixed). A segment is loaded by the fraction of it inside.
  double z_min = -1e300, z_max = 1e300;
  int reference_node = -1;
  double ramp = 0.0;  // m: width over which a face normal to the axis enters the cavity (0: a step)
  config::SourceLocation where;
};

// *USER_LOADING_SQUEEZE_FILM (fe_server's own member of the user-load
// family; loads/squeeze_film.hpp): the oil film between a face on the node
// set NSID1 and one on NSID2, gap h = H0 + DIR·(u1 − u2) along the axis (u:
// the sets' mass-weighted mean displacements), annulus RO/RI, viscosity MU,
// coefficient held below HMIN.
struct SqueezeFilmDef {
  int set1 = 0, set2 = 0;
  double direction = 1.0, h0 = 0.0, r_out = 0.0, r_in = 0.0, viscosity = 0.0, h_min = 5e-6;
  config::SourceLocation where;
};

// *DATABASE_CROSS_SECTION_SET: the force through a cut, the sum of the
// internal forces that the elements of the sets (those on one side of the
// cut) exert on the cut's nodes, as LS-DYNA's SECFORC output defines it.
struct CrossSection {
  int id = 0;
  std::vector<int> nodes;               // node indices of the cut, ascending
  std::vector<int> solids, axis, bars;  // element indices (deformable parts only)
  config::SourceLocation where;
};

// *DEFINE_CURVE: a load curve, piecewise linear between its points,
// constant beyond its ends (LS-DYNA extrapolates the end slopes only for
// some keywords; a held end value is what a prescribed motion expects).
// value(t) = SFO·y((t − OFFA)/SFA) + OFFO, as LS-DYNA scales and offsets.
struct Curve {
  int id = 0;
  int sidr = 0;  // 0: the transient only, 1: dynamic relaxation only, 2: both
  std::vector<double> a, o;  // abscissae (ascending), ordinates
  double sfa = 1.0, sfo = 1.0, offa = 0.0, offo = 0.0;
  config::SourceLocation where;
  double value(double t) const;
};

// *BOUNDARY_PRESCRIBED_MOTION_NODE / _SET: a translational DOF of nodes
// follows a curve (VAD 0 velocity, 1 acceleration, 2 displacement) scaled by
// SF, between BIRTH and DEATH. The solver imposes it on the velocity of each
// step and books the force that takes as work of the loads.
struct PrescribedMotion {
  std::vector<int> nodes;  // node indices (empty for a rigid part's)
  int rigid_part = 0;      // *BOUNDARY_PRESCRIBED_MOTION_RIGID: the part whose rigid body translates
  int dof = 0;             // 0 x, 1 y, 2 z
  int vad = 2;
  int curve_id = 0;  // in Model::curves
  double sf = 1.0, birth = 0.0, death = 1e28;
  config::SourceLocation where;
};

// *LOAD_BODY_X/Y/Z: a base acceleration a(t) = SF·curve(t) along an axis;
// every node feels the inertia force −m·a (gravity along −y: *LOAD_BODY_Y
// with +9.81); with *LOAD_BODY_PARTS only the nodes of those parts' elements.
// LCIDDR: the curve during dynamic relaxation (0: LCID, if that curve acts
// there, SIDR ≥ 1).
struct BodyLoad {
  int dof = 2;
  bool all_nodes = true;   // false: *LOAD_BODY_PARTS, `nodes` only
  std::vector<int> nodes;  // node indices of the parts' elements (*LOAD_BODY_PARTS)
  int curve_id = 0, curve_dr_id = 0;
  double sf = 1.0;
  config::SourceLocation where;
};

// *LOAD_SEGMENT / *LOAD_SEGMENT_SET: a pressure p(t) = SF·curve(t − AT)
// (nothing before AT) on segments, positive pushing against the segment's
// normal (the right-hand rule of N1..N4, LS-DYNA's convention: a positive
// pressure on a face numbered counter-clockwise seen from outside pushes
// into the body), following the surface as it moves. A 2-node segment of an
// axisymmetric deck loads its ring.
struct SegmentPressure {
  std::vector<Segment> segments;
  int curve_id = 0;
  double sf = 1.0, at = 0.0;
  config::SourceLocation where;
};

// *LOAD_NODE_POINT / *LOAD_NODE_SET: a force SF·curve(t) along a global
// translation (DOF 1–3) on each of the nodes.
struct NodalLoad {
  std::vector<int> nodes;  // node indices
  int dof = 0;             // 0 x, 1 y, 2 z
  int curve_id = 0;
  double sf = 1.0;
  config::SourceLocation where;
};

// *DAMPING_GLOBAL / *DAMPING_PART_MASS: mass-proportional damping, a force
// −D(t)·m·v on every deformable node (of the part), D = SF·curve(t) (or
// *DAMPING_GLOBAL's constant VALDMP), per direction times STX, STY, STZ.
// *PCS_FATIGUE_PART (a card of our own, docs/fatigue.md): the fatigue of
// every element of a part, counted while the run goes (output/fatigue.hpp):
// an equivalent stress per element, times a notch factor, rainflow-counted
// (ASTM E1049-85) and summed on an S-N curve with a mean-stress correction
// (Palmgren-Miner). Stresses in the deck's units.
struct FatigueDef {
  int part = 0;
  fatigue::SnCurve curve;
  fatigue::MeanStress mean = fatigue::MeanStress::None;
  double su = 0.0;     // ultimate strength (Goodman, Gerber)
  // 0: signed von Mises (the sign of the hydrostatic stress: a compressive
  // pulse counts as compression); 1: the principal stress of largest
  // magnitude, with its sign.
  int stress = 0;
  double kf = 1.0;    // notch factor on the element's stress (1: the mesh's stress as it is)
  double gate = 0.0;  // reversals smaller than this are not counted
  // s: sample every round(DT / FE step) steps (0: every FE step). Each
  // sample costs about 5 ns per element (bench/RESULTS.md); DT ≤ T/50 keeps
  // the peak of a vibration of period T within 0.2 %.
  double dt = 0.0;
  config::SourceLocation where;
};

struct MassDamping {
  bool all_nodes = true;
  std::vector<int> nodes;  // node indices (*DAMPING_PART_MASS)
  int curve_id = 0;        // 0: the constant `value`
  double value = 0.0, sf = 1.0;
  Vec3 scale = Vec3::Ones();
  config::SourceLocation where;
};

// *CONTROL_DYNAMIC_RELAXATION: before the transient, the model settles
// under the loads whose curves act in that phase (SIDR 1 or 2), its
// velocities scaled by DRFCTR every step, until, at a check every NRCYCK
// steps, the kinetic energy is below DRTOL of its peak and the largest
// out-of-balance force on a part below DRTOL of the largest support force
// (or DRTERM passes). The
// transient then starts at t = 0 from that state, every node at rest. Runs
// when a curve has SIDR ≥ 1 or IDRFLG = 1, as in LS-DYNA.
struct DynamicRelaxation {
  int nrcyck = 250;
  double drtol = 1e-3, drfctr = 0.995, drterm = 1e28;
  bool idrflg = false;
  config::SourceLocation where;
};

struct Model {
  std::string title;
  std::string source;
  // Written on the results' root group: every check the user waived
  // (--accept-energy-error, --allow-coarse-coupling) and every substitution
  // --approximate allowed, so a result says how far it can be trusted.
  std::map<std::string, std::string> run_attributes;
  // The axis of the bodies of revolution: z (2) in 3D decks, y (1) in a 2D
  // axisymmetric deck (LS-DYNA's convention). Cavity bounds, mechanical port
  // forces and their displacements are along it.
  int symmetry_axis = 2;
  // Per node, indexed 0..N-1; node_ids maps back to the deck's ids.
  std::vector<int> node_ids;
  std::map<int, int> node_index;
  std::vector<Vec3> x0;          // initial coordinates
  std::vector<Vec3> v0;          // initial velocities
  std::vector<double> mass;      // lumped nodal mass
  std::vector<Eigen::Matrix<bool, 3, 1>> fixed;  // translational SPCs
  std::vector<DiscreteElement> discretes;
  std::map<int, Material> materials;
  std::map<int, Part> parts;
  std::vector<SolidElement> solids;
  std::vector<BarElement> bars;
  std::vector<AxiElement> axis;     // axisymmetric solids
  std::vector<ContactDef> contacts;
  std::vector<TieDef> ties;
  std::map<int, std::vector<int>> part_sets;
  std::vector<int> history_solids;  // element indices into solids
  std::vector<int> history_bars;    // element indices into bars (*DATABASE_HISTORY_BEAM)
  std::vector<int> history_axis;    // element indices into axis (*DATABASE_HISTORY_SHELL)
  std::vector<CrossSection> cross_sections;
  double snapshot_interval = 0.0;  // *DATABASE_BINARY_D3PLOT DT (0: no field output)
  // History intervals, s (0: not given, the default of output/history.hpp):
  // energies, contact and ports (*DATABASE_GLSTAT, *DATABASE_RCFORC), history
  // nodes (*DATABASE_NODOUT), history elements and sections (*DATABASE_ELOUT,
  // *DATABASE_SECFORC).
  double history_dt_global = 0.0, history_dt_nodes = 0.0, history_dt_elements = 0.0;
  // LS-DYNA's ASCII files asked for (glstat, matsum, rcforc, nodout, elout:
  // their *DATABASE_ card) and their DT, s (output/ascii_output.hpp).
  std::map<std::string, double> ascii_dt;
  double dt2ms = 0.0;              // *CONTROL_TIMESTEP DT2MS (< 0: mass scaling to |DT2MS|)
  double hourglass_q = 0.1;        // *CONTROL_HOURGLASS QH
  double bulk_q1 = 1.5, bulk_q2 = 0.06;  // *CONTROL_BULK_VISCOSITY (quadratic, linear)
  std::vector<RigidBody> rigid_bodies;
  std::map<int, std::vector<Segment>> segment_sets;
  std::map<int, std::vector<int>> node_sets;
  std::vector<LoadingSet> loading_sets;
  std::vector<SqueezeFilmDef> squeeze_films;
  std::vector<int> history_nodes;  // node indices
  std::map<int, Curve> curves;
  std::vector<PrescribedMotion> prescribed;
  std::vector<BodyLoad> body_loads;
  std::vector<SegmentPressure> segment_pressures;
  std::vector<MassDamping> mass_damping;
  std::vector<FatigueDef> fatigue;
  std::vector<NodalLoad> nodal_loads;
  DynamicRelaxation relaxation;
  bool relaxes() const;  // a dynamic relaxation phase runs before the transient
  double end_time = 0.0;           // *CONTROL_TERMINATION (0: not given)
  double dt_scale = 0.9;           // *CONTROL_TIMESTEP TSSFAC

  int index_of(int node_id, const config::SourceLocation& where) const;
  double total_mass() const;
};

// Area vector of a segment (|A| = area, direction = normal by node order);
// for a 2D line the ring it sweeps about the y axis, 2π·r̄·L.
Vec3 segment_area_vector(const Segment& s, const std::vector<Vec3>& x);

// How a segment's area is shared by its corners (Σ w = 1), for its load and
// for its flow alike: equal shares on a 3D segment; on a 2D line the ring's
// consistent shares ∫N_a·r ds/∫r ds = (2r_a + r_b)/(3(r_a + r_b)), so a face
// normal to the axis loads its outer node more than the one on the axis.
void segment_corner_weights(const Segment& s, const std::vector<Vec3>& x, double w[4]);

}  // namespace fe
