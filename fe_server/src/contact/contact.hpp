// Penalty contact between two segment sets (*CONTACT_AUTOMATIC_SURFACE_TO_
// SURFACE), symmetric: the nodes of each surface are checked against the
// segments of the other. With a node set on the slave side (SSTYP 4) it is
// one-sided: those nodes against the master's segments.
//
// A node behind a segment (gap g = (x − x_c)·n < 0, n the segment's outward
// normal, its projection inside the segment) is pushed out with
//   F = k·(−g) + c·(−ġ),   only while F > 0 (contact never pulls),
// and the reaction goes to the segment's nodes by the projection's
// barycentric weights. Penalty contact keeps a pressed node shallow, so of
// the faces a node is shallow behind, the deepest is the one pressed (at an
// edge struck along the axis the node is also level with the side face); a
// face it is deep behind while on or shallow behind another is the far side
// of a convex corner, not a contact (two parts touching at t = 0: a tool's
// top node level with a piston's edge is not 6 mm inside the piston).
// Stiffness from the masses and the time step, as in
// LS-DYNA's SOFT = 1: k = SFS·0.1·m_eff/Δt², capped at 0.2·m_eff/Δt². The
// cap matters: a contact node already vibrates with its elements at up to
// ω·Δt = 2·TSSFAC = 1.8; adding the penalty (both passes: ω_c·Δt ≤ 0.63)
// keeps sqrt(1.8² + 0.4) = 1.91 below central difference's limit of 2, so
// a 100× stiffer SFS cannot make the energy grow.
// Damping c = VDC·2·sqrt(k·m_eff).
// Friction (Coulomb, as LS-DYNA's): each node in contact carries a
// tangential force f_t that the relative sliding loads elastically with the
// same k, f_t ← f_t − k·v_t·Δt (v_t the node's velocity relative to the
// segment's foot, in the segment's plane; f_t first turned into the current
// plane), and that is capped at μ·F_n with μ = FD + (FS − FD)·exp(−DC·|v_t|)
// and, when VC > 0, at VC·A (A the touched segment's area): below the cap
// the node sticks, at it it slides and the friction dissipates (in the
// contact energy, which is the work the contact forces take). A node that
// leaves contact lets its f_t go.
// Candidate segments are searched every `search_interval` steps.
#pragma once

#include <array>
#include <vector>

#include "config/checkpoint.hpp"
#include "model/model.hpp"

namespace fe {

// Projects `point` onto segment `seg` at positions x: true if it lies within
// `window` in front of or behind it (gap g along the outward unit normal n)
// and its foot falls inside the segment, with the foot's weights w over the
// corners (barycentric on the quad's two triangles; a line's two ends).
// A line's foot may lie up to past[k] of its length beyond end k (its
// weights then clamped to that end; *t, if given, the foot's unclamped
// position along the line): see PenaltyContact::Side::past.
bool project_onto_segment(const Segment& seg, const Vec3& point, const std::vector<Vec3>& x, double window, double& g,
                          Vec3& n, double w[4], const std::array<double, 2>& past = {1e-6, 1e-6},
                          double* t = nullptr);
// A segment's length scale: the side of its area, or a line's length.
double segment_size(const Segment& s, const std::vector<Vec3>& x);

class PenaltyContact {
 public:
  PenaltyContact(const Model& model, const ContactDef& def, double dt, const std::vector<double>& nodal_mass);
  // Add contact forces for positions x and velocities v; returns the number of active contacts.
  int apply(const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f, long step);
  // Largest penetration of the last apply(), m.
  double max_penetration() const { return max_penetration_; }
  // The deepest pressed node of the last apply() and its segment's nodes
  // (model indices; -1 when nothing touched).
  int deepest_node() const { return deepest_node_; }
  // The most a node of the contact's surfaces moved per step at the last
  // search, and which (model index): beyond half an element a node can
  // cross the touch window in one step, unseen.
  double fastest_step() const { return fastest_step_; }
  int fastest_node() const { return fastest_node_; }
  const std::array<int, 4>& deepest_segment() const { return deepest_segment_; }
  // The last apply()'s resultant force on each side's nodes (slave: the
  // slave set's, master: the master set's; equal and opposite) and the mass
  // of that side's nodes in contact (LS-DYNA's rcforc).
  const Vec3& slave_force() const { return slave_force_; }
  const Vec3& master_force() const { return master_force_; }
  double slave_mass() const { return slave_mass_; }
  double master_mass() const { return master_mass_; }
  double element_size() const { return size_; }
  // Throws std::runtime_error naming the deepest node if, at positions x, a
  // node is already behind a segment of the other surface (beyond round-off).
  void refuse_initial_penetration(const Model& model, const ContactDef& def, const std::vector<Vec3>& x);
  // The search's candidate lists and the last penetration (checkpoints).
  void state(config::StateIO& io);

 private:
  struct Side {
    std::vector<Segment> segments;
    std::vector<int> nodes;  // unique nodes of the other surface, checked against `segments`
    // Per node i, nearby segments cand[start[i] .. start[i+1]) (flat, reused:
    // no allocation once the lists have reached their size).
    std::vector<int> start, cand;
    // Per segment, at the last search: the squared distance from its corner
    // 0 within which a node can touch it (its diameter, with room for the
    // deformation until the next search, plus the depth limit). A node
    // farther away is skipped without the segment's normal.
    std::vector<double> reach2;
    std::vector<Vec3> centre;  // scratch of the search
    long next_search = 0;      // the step of the next search (search_interval(), adaptive)
    // Per segment (lines, 2D): how far beyond each end, as a fraction of its
    // length, a node's foot still counts: 5 % where the line meets the next
    // line of its surface, round-off at a free end. A node pressed onto a
    // vertex of a surface can project past the ends of both lines there (a
    // wedge g·angle wide on a face that deformation kinks; a node exactly
    // at the corner where two bodies of one radius meet, after round-off),
    // and a contact that lets go there and catches again a step later is
    // not conservative: on the axisymmetric bar impact with SFACT 0.3 it
    // pumped 20 % of the impact energy into the faces' hourglass modes.
    // Where the next line turns by more than 10° (a corner of the body), a
    // node past the end counts only while it is no farther in front of that
    // next line than it is pressed into this one: a node beside the body is
    // not on it (test Axi4Mixed.ANodeBesideACornerIsNotOnTheFacePastIt).
    std::vector<std::array<double, 2>> past;
    std::vector<std::array<int, 2>> corner;  // the next line at a corner, per end; -1: none
    std::vector<Vec3> friction;  // per node (of `nodes`): its tangential force, 0 out of contact
  };
  struct Contact {
    double g = 0.0;  // gap along n, negative behind the segment
    Vec3 n;          // the segment's outward unit normal
    double w[4];     // the projection's weights over the segment's corners
  };
  // Does `node` project inside `seg` within |g| ≤ window of it (in front or behind)?
  bool project(const Side& s, size_t j, size_t node, const std::vector<Vec3>& x, double window, Contact& c) const;
  // Is node i in contact, and with which segment (c, seg)? Of the faces it
  // is shallow behind (≤ kCornerDepth segment sizes) the deepest; else, if it
  // is deep behind faces and on or in front of none, the least deep; else
  // (behind none, or deep behind one face at a convex corner while on
  // another) not in contact.
  bool touching(const Side& s, size_t i, const std::vector<Vec3>& x, double window, bool reach_check, Contact& c,
                size_t& seg) const;
  // Penalty contact keeps penetrations to a few hundredths of a segment
  // (k = 0.1·m/Δt²); a tenth separates them from a corner's geometry.
  static constexpr double kCornerDepth = 0.1;
  void search(Side& s, const std::vector<Vec3>& x);
  // Steps until the next search: a pair left out is at least 3 sizes apart
  // and may touch from 1.75 sizes, so the two may close 1.25 sizes, at twice
  // the fastest of the side's nodes: every search_interval_ steps at most,
  // every step at impact speeds (a striker at 1000 m/s on a 5 mm mesh moved
  // 2.6 elements between two searches and was never seen).
  long steps_to_next_search(const Side& s, const std::vector<Vec3>& v) const;
  // Side 0's nodes are the slave set's (or the slave node set), side 1's the master's.
  int side_forces(Side& s, bool slave_nodes, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f);
  const std::vector<double>& mass_;
  double dt_, sfs_, damping_, size_ = 0.0, max_penetration_ = 0.0;
  double fs_ = 0.0, fd_ = 0.0, dc_ = 0.0, vc_ = 0.0;  // friction (ContactDef)
  int deepest_node_ = -1;
  mutable double fastest_step_ = 0.0;
  mutable int fastest_node_ = -1;
  std::array<int, 4> deepest_segment_{-1, -1, -1, -1};
  std::vector<Side> sides_;
  // Single surface: per segment, the nodes of the element it is a face of
  // (a node is never in contact with its own elements' faces).
  bool single_ = false;
  std::vector<std::array<int, 8>> owner_;
  Vec3 slave_force_ = Vec3::Zero(), master_force_ = Vec3::Zero();
  double slave_mass_ = 0.0, master_mass_ = 0.0;
  int search_interval_ = 20;
};

}  // namespace fe
