// Rigid bodies as six-DOF bodies (solver/rigid_body.hpp): conservation laws
// of a free tumbling body, an off-centre impact against rigid-body impact
// theory, constraints, *PART_INERTIA, and the cost being that of the live
// nodes only.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

namespace {

using fe::Vec3;

// A nodal rigid body of eight point masses at the corners of a box, the
// masses unequal so that its inertia tensor has products of inertia, moving
// with v_c and spinning with ω (node velocities v_c + ω × r).
struct Tumbler {
  std::string deck;
  Vec3 com, v, omega;
};

Tumbler tumbler(const Vec3& v, const Vec3& omega) {
  const double masses[8] = {1.0, 2.0, 1.5, 0.5, 3.0, 1.0, 2.5, 0.7};
  Vec3 x[8];
  for (int i = 0; i < 8; ++i) x[i] = Vec3(i & 1 ? 0.3 : 0.0, i & 2 ? 0.2 : 0.0, i & 4 ? 0.1 : 0.0) + Vec3(1.0, -2.0, 0.5);
  Vec3 com = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < 8; ++i) {
    com += masses[i] * x[i];
    m += masses[i];
  }
  com /= m;
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*NODE\n";
  for (int i = 0; i < 8; ++i) d << i + 1 << "," << x[i].x() << "," << x[i].y() << "," << x[i].z() << "\n";
  d << "*ELEMENT_MASS\n";
  for (int i = 0; i < 8; ++i) d << i + 1 << "," << i + 1 << "," << masses[i] << "\n";
  d << "*INITIAL_VELOCITY_NODE\n";
  for (int i = 0; i < 8; ++i) {
    const Vec3 vi = v + omega.cross(x[i] - com);
    d << i + 1 << "," << vi.x() << "," << vi.y() << "," << vi.z() << "\n";
  }
  d << "*SET_NODE_LIST\n1\n1,2,3,4,5,6,7,8\n*CONSTRAINED_NODAL_RIGID_BODY\n1,0,1\n";
  return {d.str(), com, v, omega};
}

// Angular momentum about the body's centre from the nodes' own state.
Vec3 nodal_angular_momentum(const fe::Model& m, const fe::Solver& s, const Vec3& com, const Vec3& v_com) {
  Vec3 L = Vec3::Zero();
  for (size_t i = 0; i < m.x0.size(); ++i) L += m.mass[i] * (s.x()[i] - com).cross(s.v()[i] - v_com);
  return L;
}

}  // namespace

// A free asymmetric body tumbling (spin with a component about each principal
// axis) and translating, no loads, for 20 turns: its momentum and angular
// momentum do not change (no force or moment acts: exactly, up to the
// round-off of adding zero), it stays rigid, and its kinetic energy stays
// within the 1 % energy bound.
TEST(RigidBody, AFreeTumblingBodyConservesMomentumAngularMomentumAndEnergy) {
  const Vec3 v0(0.3, -0.2, 1.0), w0(20.0, -35.0, 50.0);
  const Tumbler t = tumbler(v0, w0);
  fe::Model m = fe::parse_deck(t.deck, "tumbler.k");
  const double dt = 1e-4;  // |ω|·Δt = 0.0065
  fe::Solver s(m, dt);
  const auto& b = s.bodies()[0];
  ASSERT_TRUE(b.rotates);
  EXPECT_LT((b.com0 - t.com).norm(), 1e-14);
  EXPECT_LT((b.omega - w0).norm(), 1e-12 * w0.norm()) << "ω from the nodes' velocities";
  const Vec3 L0 = b.L, v_start = b.v;
  // v_c from the nodes' momentum, where their ω × r parts (~10 m/s) cancel to round-off.
  EXPECT_LT((v_start - v0).norm(), 1e-13 * w0.norm());
  const double ke0 = 0.5 * b.mass * v0.squaredNorm() + 0.5 * w0.dot(b.inertia0 * w0);
  const double d01 = (m.x0[0] - m.x0[7]).norm();
  const int steps = static_cast<int>(20 * 2 * M_PI / (w0.norm() * dt));
  double worst_energy = 0.0;
  for (int n = 0; n < steps; ++n) {
    s.step();
    worst_energy = std::max(worst_energy, std::fabs(s.energies().balance_error));
  }
  EXPECT_EQ(b.v, v_start) << "no force: the velocity is the initial one, bit for bit";
  EXPECT_LT((b.L - L0).norm(), 1e-13 * L0.norm()) << "no moment: L is conserved";
  // x_c += Δt·v_c each step: a round-off of a few ulp of |x_c| per step.
  EXPECT_LT((b.com - (t.com + s.time() * v_start)).norm(), steps * 4e-16 * t.com.norm());
  // The nodes' own angular momentum: their chord velocities differ from
  // ω × r by O((ω·Δt)²) = 4e-5 of it.
  const Vec3 Ln = nodal_angular_momentum(m, s, b.com, b.v);
  EXPECT_LT((Ln - L0).norm(), 1e-4 * L0.norm());
  EXPECT_NEAR((s.x()[0] - s.x()[7]).norm(), d01, 1e-12) << "the body stays rigid";
  EXPECT_LT(worst_energy, 0.01 * ke0);
  // And the rotation really happened: node 1 is not where pure translation puts it.
  EXPECT_GT((s.x()[0] - (m.x0[0] + s.time() * v0)).norm(), 0.01);
}

// A point mass strikes a free rigid plate off its centre, along the normal,
// through penalty contact without damping (an elastic impact). Rigid-body
// impact theory: the plate's effective mass at the contact point is
// 1/m_eff = 1/M + d²/I, the impulse J = 2·m·m_eff/(m + m_eff)·v0, and the plate
// leaves with V = J/M and ω = d·J/I about the axis normal to d and the
// normal. The 1 % tolerance covers the contact's finite duration (the plate
// turns by ~1e-4 rad while in contact) and the penalty's stored energy.
TEST(RigidBody, APlateHitOffCentreGetsTheRightRotation) {
  const double M = 4.0, m = 0.1, v0 = 1.0, d = 0.05, a = 0.1;
  std::ostringstream k;
  k << "*KEYWORD\n*NODE\n1," << -a << "," << -a << ",0\n2," << a << "," << -a << ",0\n3," << a << "," << a
    << ",0\n4," << -a << "," << a << ",0\n5," << d << ",0,0.002\n"
    << "*ELEMENT_MASS\n1,1,1\n2,2,1\n3,3,1\n4,4,1\n5,5," << m << "\n"
    << "*INITIAL_VELOCITY_NODE\n5,0,0," << -v0 << "\n"
    << "*SET_NODE_LIST\n1\n1,2,3,4\n*SET_NODE_LIST\n2\n5\n*CONSTRAINED_NODAL_RIGID_BODY\n1,0,1\n"
    << "*SET_SEGMENT\n1\n1,2,3,4\n"
    << "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2,1,4,0\n0,0,0,0,0\n";
  fe::Model model = fe::parse_deck(k.str(), "hit.k");
  fe::Solver s(model, 1e-6);
  for (int n = 0; n < 20000; ++n) s.step();  // 20 ms: approach (2 ms), contact, separation
  const auto& b = s.bodies()[0];
  const double I = 4.0 * a * a;  // I_yy of four 1 kg corners at x = ±a
  const double m_eff = 1.0 / (1.0 / M + d * d / I);
  const double J = 2.0 * m * m_eff / (m + m_eff) * v0;
  ASSERT_GT(std::fabs(b.v.z()), 0.0) << "the plate was hit";
  EXPECT_NEAR(b.v.z(), -J / M, 0.01 * J / M);
  EXPECT_NEAR(b.omega.y(), d * J / I, 0.01 * d * J / I);
  EXPECT_NEAR(b.omega.x(), 0.0, 1e-9);
  EXPECT_NEAR(b.omega.z(), 0.0, 1e-9);
  // Momentum of the whole (plate and point mass) is conserved by the contact
  // to round-off: its forces are equal and opposite.
  const double p = M * b.v.z() + m * s.v()[4].z();
  EXPECT_NEAR(p, -m * v0, 1e-9 * m * v0);
}

// Constrained DOFs: *MAT_RIGID CMO = 1 with CON1 = 4 (x, y) and CON2 = 7 (all
// rotations): the same off-centre hit only pushes the body along z, with the
// whole mass (J = 2·m·M/(m + M)·v0).
TEST(RigidBody, ConstrainedRotationsAndTranslationsAreHeld) {
  const double v0 = 1.0, m = 0.1, a = 0.1, d = 0.05;
  std::ostringstream k;
  k << "*KEYWORD\n*NODE\n1," << -a << "," << -a << ",0\n2," << a << "," << -a << ",0\n3," << a << "," << a
    << ",0\n4," << -a << "," << a << ",0\n5," << d << ",0,0.002\n6," << -a << "," << -a << ",-0.01\n"
    << "7," << a << "," << -a << ",-0.01\n8," << a << "," << a << ",-0.01\n9," << -a << "," << a << ",-0.01\n"
    << "*PART\nplate\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_RIGID\n1,7850,2.1e11,0.3\n1.0,4,7\n"
    << "*ELEMENT_SOLID\n1,1,6,7,8,9,1,2,3,4\n"
    << "*ELEMENT_MASS\n5,5," << m << "\n*INITIAL_VELOCITY_NODE\n5,0.2,0," << -v0 << "\n"
    << "*SET_NODE_LIST\n2\n5\n*SET_SEGMENT\n1\n1,2,3,4\n"
    << "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2,1,4,0\n0,0,0,0,0\n";
  fe::Model model = fe::parse_deck(k.str(), "held.k");
  ASSERT_EQ(model.rigid_bodies.size(), 1u);
  const double M = model.rigid_bodies[0].mass;
  fe::Solver s(model, 1e-6);
  for (int n = 0; n < 20000; ++n) s.step();
  const auto& b = s.bodies()[0];
  EXPECT_FALSE(b.rotates);
  EXPECT_EQ(b.omega, Vec3::Zero());
  EXPECT_EQ(b.v.x(), 0.0);
  EXPECT_EQ(b.v.y(), 0.0);
  const double J = 2.0 * m * M / (m + M) * v0;
  EXPECT_NEAR(b.v.z(), -J / M, 0.01 * J / M);
}

// *PART_INERTIA: the deck's mass, centre, tensor (with products of inertia)
// and initial velocities replace the mesh's; a body spun about a non-principal
// axis has L = I·ω.
TEST(RigidBody, PartInertiaGivesMassTensorAndInitialVelocities) {
  const std::string deck =
      "*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n"
      "*PART_INERTIA\nblock\n1,1,1\n0.5,0.5,0.5,12.0,0,0\n2.0,0.1,0.0,3.0,0.2,4.0\n1.0,0,0,0,5.0,0\n"
      "*SECTION_SOLID\n1,1\n*MAT_RIGID\n1,1000,2.1e11,0.3\n*ELEMENT_SOLID\n1,1,1,2,3,4,5,6,7,8\n";
  fe::Model m = fe::parse_deck(deck, "inertia.k");
  ASSERT_EQ(m.rigid_bodies.size(), 1u);
  EXPECT_DOUBLE_EQ(m.rigid_bodies[0].mass, 12.0);
  fe::Solver s(m, 1e-5);
  const auto& b = s.bodies()[0];
  Eigen::Matrix3d I;
  I << 2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0;
  EXPECT_LT((b.inertia0 - I).norm(), 1e-15);
  EXPECT_EQ(b.v, Vec3(1.0, 0, 0));
  EXPECT_EQ(b.omega, Vec3(0, 5.0, 0));
  EXPECT_LT((b.L - I * Vec3(0, 5.0, 0)).norm(), 1e-14) << "L = I·ω has x and z parts from the products";
  // Node 1 starts with v_c + ω × (x − x_c).
  const Vec3 v1 = Vec3(1, 0, 0) + Vec3(0, 5.0, 0).cross(Vec3(-0.5, -0.5, -0.5));
  EXPECT_LT((s.v()[0] - v1).norm(), 1e-14);
  EXPECT_THROW(fe::parse_deck("*KEYWORD\n*NODE\n1,0,0,0\n*PART_INERTIA\nb\n1,1,1\n0,0,0,1,1,0\n1,0,0,1,0,1\n0,0,0,0,0,0\n",
                              "ircs.k"),
               std::exception)
      << "IRCS = 1 (local axes) is refused, not misread";
}

// The cost of a rigid body is that of its live nodes: a finely meshed rigid
// block touched on one face by one node puts only that face's nodes into
// the per-node passes.
TEST(RigidBody, OnlyTheLiveNodesOfABodyArePassedOverEachStep) {
  std::ostringstream d;
  const int n = 10;  // 11³ = 1331 nodes
  d << "*KEYWORD\n*NODE\n";
  auto id = [&](int i, int j, int k) { return 1 + i + (n + 1) * (j + (n + 1) * k); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) d << id(i, j, k) << "," << 0.01 * i << "," << 0.01 * j << "," << 0.01 * k << "\n";
  d << "5000,0.05,0.05,0.101\n*ELEMENT_MASS\n1,5000,0.01\n*INITIAL_VELOCITY_NODE\n5000,0,0,-1\n";
  d << "*PART\nblock\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_RIGID\n1,7850,2.1e11,0.3\n*ELEMENT_SOLID\n";
  int e = 1;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        d << e++ << ",1," << id(i, j, k) << "," << id(i + 1, j, k) << "," << id(i + 1, j + 1, k) << ","
          << id(i, j + 1, k) << "," << id(i, j, k + 1) << "," << id(i + 1, j, k + 1) << "," << id(i + 1, j + 1, k + 1)
          << "," << id(i, j + 1, k + 1) << "\n";
  d << "*SET_SEGMENT\n1\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      d << id(i, j, n) << "," << id(i + 1, j, n) << "," << id(i + 1, j + 1, n) << "," << id(i, j + 1, n) << "\n";
  d << "*SET_NODE_LIST\n2\n5000\n*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2,1,4,0\n";
  fe::Model m = fe::parse_deck(d.str(), "block.k");
  fe::Solver s(m, 1e-7);
  EXPECT_EQ(s.active_nodes(), 1u + 121u) << "the striker and the block's top face";
  EXPECT_EQ(s.bodies()[0].interior.size(), 1331u - 121u);
  for (int k = 0; k < 20000; ++k) s.step();  // the striker hits and rebounds
  EXPECT_LT(s.bodies()[0].v.z(), 0.0) << "the block was pushed";
  // x() places the interior nodes: the bottom corner moved with the body.
  EXPECT_NEAR(s.x()[0].z(), s.bodies()[0].com.z() - s.bodies()[0].com0.z(), 1e-12);
}

// A user load that does not say which nodes it loads may load any node, an
// interior node of a rigid body included: the solver then keeps every node
// live, and the body feels the force.
TEST(RigidBody, AnUndeclaredUserLoadOnAnInteriorNodeMovesTheBody) {
  struct Push : fe::UserLoad {
    void apply(double, const std::vector<Vec3>&, const std::vector<Vec3>&, std::vector<Vec3>& f) override {
      f[0] += Vec3(0, 0, 10.0);
    }
    void state(config::StateIO&) override {}  // a constant force: nothing carried between steps
  } push;
  const std::string deck =
      "*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n5,0,0,1\n6,1,0,1\n7,1,1,1\n8,0,1,1\n"
      "*PART\nblock\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_RIGID\n1,1000,2.1e11,0.3\n1.0,0,7\n"
      "*ELEMENT_SOLID\n1,1,1,2,3,4,5,6,7,8\n";
  fe::Model m = fe::parse_deck(deck, "push.k");
  fe::Solver s(m, 1e-4);
  EXPECT_EQ(s.active_nodes(), 0u) << "nothing reads or loads the block";
  s.set_user_load(&push);
  EXPECT_EQ(s.active_nodes(), 8u);
  for (int k = 0; k < 100; ++k) s.step();
  // 10 N on 1000 kg: v_{n+1/2} after 100 steps is a·(Δt/2 + 99·Δt).
  EXPECT_NEAR(s.bodies()[0].v.z(), 10.0 / 1000.0 * 99.5e-4, 1e-15);
}
