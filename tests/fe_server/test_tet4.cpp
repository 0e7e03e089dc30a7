// The four-node tetrahedron (ELFORM 10, element_tet4.hpp): patch test,
// exact volumes and masses, rigid motion, its stable step against the
// eigenvalues of its own assembled stiffness, the bar impact in tetrahedra
// against hexahedra and 1D theory, the reader's forms and refusals, and the
// outer faces a contact finds on a tetrahedral mesh.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "block_decks.hpp"
#include "config/keyword_reader.hpp"
#include "deck_errors.hpp"
#include "elements/element_tet4.hpp"
#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

namespace {

constexpr double kRho = fe_test::kBlockRho;
using fe_test::Block;
using fe_test::block_deck;

fe::Mat83 slots(const std::vector<fe::Vec3>& a, const fe::SolidElement& e) {
  fe::Mat83 out;
  for (int k = 0; k < 8; ++k) out.row(k) = a[static_cast<size_t>(e.n[k])].transpose();
  return out;
}

using fe_test::deck_error;

}  // namespace

// A linear velocity field v = G·x gives every tetrahedron L = G exactly
// (linear shape functions), however distorted; the volumes fill the block
// exactly and the lumped masses add up to ρ·V (the degenerate one-point
// hexahedron this replaces put 3/4 of it there: 8·det J at the centre).
TEST(Tet4, PatchTestVolumesAndMassesAreExact) {
  const Block blk = block_deck(2, 2, 2, 0.5, true, 1e9, 0.3, 0.15);
  fe::Model m = fe::parse_deck(blk.deck, "block.k");
  ASSERT_EQ(m.solids.size(), 48u);
  Eigen::Matrix3d G;
  G << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, 0.0, 7e-4, 1.5e-3;
  double total = 0.0;
  for (const auto& e : m.solids) {
    ASSERT_TRUE(e.tet4) << "element " << e.id;
    Eigen::Matrix<double, 4, 3> b;
    double V = 0.0;
    ASSERT_TRUE(fe::tet4_gradients(slots(m.x0, e), b, V));
    Eigen::Matrix<double, 4, 3> v;
    for (int a = 0; a < 4; ++a) v.row(a) = (G * m.x0[static_cast<size_t>(e.n[fe::kTet4Corners[a]])]).transpose();
    EXPECT_LT((v.transpose() * b - G).norm(), 1e-14 * G.norm()) << "element " << e.id;
    total += V;
  }
  EXPECT_NEAR(total, 1.0, 1e-14) << "tetrahedra fill the block exactly";
  double mass = 0.0;
  for (double mi : m.mass) mass += mi;
  EXPECT_NEAR(mass, kRho * 1.0, 1e-12 * kRho);
  // Run the field: every element carries the same stress (constant strain
  // rate everywhere), so the interior nodes feel no net force.
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = G * m.x0[i];
  fe::Solver s(m, 1e-9);
  s.step();
  for (size_t e = 1; e < m.solids.size(); ++e)
    EXPECT_LT((s.stress(e) - s.stress(0)).norm(), 1e-9 * s.stress(0).norm()) << "element " << m.solids[e].id;
  EXPECT_GT(s.stress(0).norm(), 0.0);
}

TEST(Tet4, RigidMotionMakesNoStrain) {
  const Block blk = block_deck(2, 2, 2, 0.5, true, 1e6, 0.3, 0.15);
  fe::Model m = fe::parse_deck(blk.deck, "block.k");
  const double dt = 0.5 * fe::Solver::stable_dt(m).dt;
  const Eigen::Vector3d t(0.3, -0.2, 0.1), omega(0, 0, 0.05 / (200 * dt)), c(0.5, 0.5, 0.5);
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = t + omega.cross(m.x0[i] - c);
  fe::Solver s(m, dt);
  for (int k = 0; k < 200; ++k) s.step();
  double worst = 0.0;
  for (size_t e = 0; e < m.solids.size(); ++e) worst = std::max(worst, s.stress(e).cwiseAbs().maxCoeff());
  // As the hexahedron's (test_elements.cpp): σ ~ E·(ω·Δt)²·steps from moving
  // the nodes on straight lines while the body turns.
  EXPECT_LT(worst, 1e6 * std::pow(omega.z() * dt, 2) * 200);
  EXPECT_EQ(s.energies().hourglass, 0.0) << "a tetrahedron has no hourglass modes";
}

// The stable step is 2/ω_max of the element on its lumped masses. ω_max is
// taken here from the stiffness the kernel itself applies (K column j =
// −f/Δt for a unit velocity of DOF j, from zero stress, no viscosity), not
// from the closed form the step function uses: the two must agree.
TEST(Tet4, TheStableStepIsTheElementsOwnHighestFrequency) {
  const double E = 200e9, nu = 0.3, lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const Eigen::Vector3d corners[4] = {{0, 0, 0}, {1.1e-3, 0.1e-3, 0}, {0.3e-3, 0.9e-3, 0.1e-3}, {0.2e-3, 0.3e-3, 1.2e-3}};
  fe::Mat83 x;
  const int map[8] = {0, 1, 2, 2, 3, 3, 3, 3};
  for (int k = 0; k < 8; ++k) x.row(k) = corners[map[k]].transpose();
  const double dt = 1e-9;
  Eigen::Matrix<double, 12, 12> K;
  double V = 0.0;
  for (int j = 0; j < 12; ++j) {
    fe::SolidBatch B{};
    for (int l = 0; l < fe::SolidBatch::W; ++l) {
      for (int s = 0; s < 8; ++s)
        for (int i = 0; i < 3; ++i) B.x[s][i][l] = x(s, i), B.v[s][i][l] = 0.0;
      B.v[fe::kTet4Corners[j / 3]][j % 3][l] = 1.0;
      B.lambda[l] = lambda, B.two_mu[l] = 2 * mu, B.rho[l] = kRho, B.c[l] = 1.0, B.spl[l] = 1.0;
      B.plastic[l] = nullptr;
      for (int c = 0; c < 6; ++c) B.sig[c][l] = 0.0;
    }
    fe::tet4_kernel(B, dt, 0.0, 0.0);
    V = B.volume[0];
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) K(3 * a + i, j) = -B.f[fe::kTet4Corners[a]][i][0] / dt;
  }
  EXPECT_LT((K - K.transpose()).norm(), 1e-9 * K.norm()) << "the kernel's stiffness is symmetric";
  const double w2 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>>(K / (kRho * V / 4.0)).eigenvalues().maxCoeff();
  EXPECT_NEAR(fe::tet4_stable_step(x, lambda, mu, kRho, 0.0), 2.0 / std::sqrt(w2), 1e-9 * 2.0 / std::sqrt(w2));
  // Below the smallest altitude over the wave speed, as the header says.
  EXPECT_LT(fe::tet4_stable_step(x, lambda, mu, kRho, 0.0),
            fe::tet4_characteristic_length(x) / std::sqrt((lambda + 2 * mu) / kRho));
}

// A bar of 4 mm × 4 mm × 100 mm at 5 m/s whose end face is held from t = 0
// (ν = 0: the 1D bar exactly): a compression wave of ρ·c·v0 (c = √(E/ρ))
// runs up the bar and back: at height z it lasts 2(L − z)/c (the release
// from the free end arrives at (2L − z)/c), here at the layer of cells
// 1-2 mm above the held end. Tetrahedra and
// hexahedra of the same 1 mm grid against theory and each other: 2 % (the
// grid's dispersion rounds the fronts; the plateau is the median over the
// pulse and the length its width at half the plateau).
TEST(Tet4, ABarStoppedAtOneEndCarriesTheOneDimensionalPulse) {
  const double E = 200e9, v0 = 5.0, L = 0.1, h = 1e-3, c = std::sqrt(E / kRho);
  struct Pulse {
    double plateau = 0.0, length = 0.0, balance = 0.0, ke0 = 0.0;
  };
  auto run = [&](bool tets, double nu = 0.0) {
    std::string deck = block_deck(4, 4, 100, h, tets, E, nu).deck;
    deck += "*SET_NODE_GENERATE\n1\n1,25\n*BOUNDARY_SPC_SET\n1,0,0,0,1\n"
            "*SET_NODE_GENERATE\n2\n26,999999\n*INITIAL_VELOCITY\n2\n0,0,-5.0\n*END\n";
    const fe::Model m = fe::parse_deck(deck, "bar.k");
    const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
    fe::Solver s(m, dt);
    std::vector<size_t> gauge;  // the elements of the cell layer at z = 1-2 mm
    for (size_t e = 0; e < m.solids.size(); ++e) {
      double z = 0.0;
      for (int k = 0; k < 8; ++k) z += m.x0[static_cast<size_t>(m.solids[e].n[k])].z() * fe::solid_mass_share(m.solids[e], k);
      if (z > h && z < 2 * h) gauge.push_back(e);
    }
    std::vector<double> sig;
    Pulse p;
    while (s.time() < 2.5 * L / c) {
      s.step();
      if (s.step_count() == 1) p.ke0 = s.energies().kinetic;
      double sz = 0.0;
      for (size_t e : gauge) sz += s.stress(e)(2) / static_cast<double>(gauge.size());
      sig.push_back(sz);
      p.balance = std::max(p.balance, std::fabs(s.energies().balance_error));
    }
    std::vector<double> comp;
    for (double v : sig)
      if (v < -1e6) comp.push_back(v);
    std::sort(comp.begin(), comp.end());
    p.plateau = comp.empty() ? 0.0 : comp[comp.size() / 2];
    for (double v : sig)
      if (v < 0.5 * p.plateau) p.length += dt;
    return p;
  };
  const Pulse tet = run(true), hex = run(false);
  // At ν = 0.3 the 4 mm bar is still thin against the pulse (its lateral
  // inertia shows in the front only): the same bounds, the elements' own
  // stiffness (the tetrahedron is the stiffer one) now in play.
  const Pulse tet3 = run(true, 0.3), hex3 = run(false, 0.3);
  const double theory = -kRho * c * v0, duration = 2 * (L - 1.5 * h) / c;
  std::printf("plateau %.4g (tet) %.4g (hex), at nu 0.3 %.4g (tet) %.4g (hex), theory %.4g Pa; length %.4g (tet) "
              "%.4g (hex), at nu 0.3 %.4g (tet) %.4g (hex), theory %.4g s\n",
              tet.plateau, hex.plateau, tet3.plateau, hex3.plateau, theory, tet.length, hex.length, tet3.length,
              hex3.length, duration);
  for (const Pulse* p : {&tet, &hex, &tet3, &hex3}) {
    EXPECT_NEAR(p->plateau, theory, 0.02 * std::fabs(theory));
    EXPECT_NEAR(p->length, duration, 0.02 * duration);
  }
  EXPECT_NEAR(tet.plateau, hex.plateau, 0.02 * std::fabs(theory));
  EXPECT_NEAR(tet3.plateau, hex3.plateau, 0.02 * std::fabs(theory));
  // The energy account closes (the held end does no work).
  EXPECT_LT(tet.balance, 1e-3 * tet.ke0);
}

// The reader: four nodes or LS-DYNA's eight with N4 repeated are one
// element; tetrahedra in an ELFORM 1 part are refused (a degenerate
// hexahedron) unless *CONTROL_SOLID ESORT 1 sorts them, as LS-DYNA does;
// a flat or inverted tetrahedron names its node order.
TEST(Tet4, TheReaderReadsBothFormsAndSaysWhatItWillNot) {
  const std::string nodes = "*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n"
                            "*PART\np\n1,1,1\n*MAT_ELASTIC\n1,7850,2e11,0.3\n";
  const fe::Model four = fe::parse_deck(nodes + "*SECTION_SOLID\n1,10\n*ELEMENT_SOLID\n1,1,1,2,3,4\n", "a.k");
  const fe::Model eight = fe::parse_deck(nodes + "*SECTION_SOLID\n1,10\n*ELEMENT_SOLID\n1,1,1,2,3,4,4,4,4,4\n", "b.k");
  ASSERT_TRUE(four.solids[0].tet4 && eight.solids[0].tet4);
  for (int k = 0; k < 8; ++k) EXPECT_EQ(four.solids[0].n[k], eight.solids[0].n[k]);
  for (size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(four.mass[i], 7850.0 / 6.0 / 4.0) << "a quarter of ρV at each corner";
  const std::string in_hex = nodes + "*SECTION_SOLID\n1,1\n*ELEMENT_SOLID\n1,1,1,2,3,4\n";
  EXPECT_NE(deck_error(in_hex).find("the tetrahedra of part 1 (ELFORM 1: degenerate one-point hexahedra"),
            std::string::npos)
      << deck_error(in_hex);
  const fe::Model sorted = fe::parse_deck(in_hex + "*CONTROL_SOLID\n1\n", "c.k");
  EXPECT_TRUE(sorted.solids[0].tet4) << "ESORT 1";
  EXPECT_DOUBLE_EQ(sorted.mass[0], four.mass[0]);
  EXPECT_NE(deck_error(nodes + "*SECTION_SOLID\n1,10\n*ELEMENT_SOLID\n1,1,1,3,2,4\n")
                .find("deck.k:15: solid element 1 is inverted or degenerate (volume -0.1666"),
            std::string::npos);
  EXPECT_NE(deck_error(nodes + "*SECTION_SOLID\n1,10\n*ELEMENT_SOLID\n1,1,1,3,2,4\n").find("N1-N2-N3 counter-clockwise"),
            std::string::npos);
  EXPECT_NE(deck_error(nodes + "*NODE\n5,1,1,1\n6,2,2,2\n7,3,1,1\n8,4,1,1\n*SECTION_SOLID\n1,10\n*ELEMENT_SOLID\n"
                       "1,1,1,2,3,4,5,6,7,8\n")
                .find("has 8 distinct nodes, but part 1 is ELFORM 10"),
            std::string::npos);
  EXPECT_NE(deck_error(nodes + "*SECTION_SOLID\n1,13\n*ELEMENT_SOLID\n1,1,1,2,3,4\n").find("ELFORM 13 would run as ELFORM 10"),
            std::string::npos);
  // A pyramid as a degenerate hexahedron loses a quarter of its mass too:
  // refused, not run.
  EXPECT_NE(deck_error(nodes + "*NODE\n5,1,1,0\n*SECTION_SOLID\n1,1\n*ELEMENT_SOLID\n1,1,1,2,5,3,4,4,4,4\n")
                .find("solid element 1 is a pyramid"),
            std::string::npos);
}

// A single-surface contact on a tetrahedral block finds its outer faces
// only: two triangles per cell face on the surface. A shared triangle is
// the same face whichever corner its two elements repeat in their slots.
TEST(Tet4, AContactFindsTheOuterTrianglesOnly) {
  const Block blk = block_deck(2, 2, 2, 0.5, true, 1e9, 0.3);
  const fe::Model m = fe::parse_deck(blk.deck + "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n0,0,2\n*END\n", "block.k");
  ASSERT_EQ(m.contacts.size(), 1u);
  const auto& faces = m.segment_sets.at(m.contacts[0].master_set);
  EXPECT_EQ(faces.size(), 6u * 4u * 2u);
  double area = 0.0;
  for (const auto& f : faces) {
    EXPECT_EQ(f.corners(), 3);
    // Outward: the face's area vector points away from the block's centre.
    const fe::Vec3 centre = (m.x0[static_cast<size_t>(f.n[0])] + m.x0[static_cast<size_t>(f.n[1])] +
                             m.x0[static_cast<size_t>(f.n[2])]) / 3.0 - fe::Vec3(0.5, 0.5, 0.5);
    EXPECT_GT(fe::segment_area_vector(f, m.x0).dot(centre), 0.0);
    area += fe::segment_area_vector(f, m.x0).norm();
  }
  EXPECT_NEAR(area, 6.0, 1e-12);
}

// Threads change nothing with tetrahedra either, in a block of hexahedra
// (the lower 7 layers of 15×15 cells) under tetrahedra: the element loop's
// first block (1720 elements) holds both kinds, and the 1575 hexahedra end
// inside a batch of 8 lanes (batches stay of one kind); 1, 2 and 3 threads
// give the same bits.
TEST(Tet4, HexahedraAndTetrahedraInOneBlockGiveTheSameBitsOnAnyThreadCount) {
  fe::Model m = fe::parse_deck(block_deck(15, 15, 16, 1e-3, true, 2e11, 0.3, 0.1, "10", 7).deck, "mixed.k");
  size_t tets = 0;
  for (const auto& e : m.solids) tets += e.tet4;
  ASSERT_EQ(tets, 9u * 225u * 6u);
  ASSERT_EQ(m.solids.size() - tets, 7u * 225u);
  ASSERT_NE((m.solids.size() - tets) % fe::hex8_block_size(m.solids.size()), 0u) << "a block holds both kinds";
  ASSERT_NE((m.solids.size() - tets) % fe::kHex8Lanes, 0u) << "and a batch would";
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(0.3 * m.x0[i].y(), 0.0, 50.0 * m.x0[i].z());
  auto run = [&](int threads) {
    fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
    s.set_threads(threads);
    for (int k = 0; k < 60; ++k) s.step();
    std::vector<double> szz;
    for (size_t e = 0; e < m.solids.size(); ++e) szz.push_back(s.stress(e)(2));
    return std::make_tuple(s.x(), s.v(), szz, s.energies().internal);
  };
  const auto one = run(1);
  EXPECT_GT(std::get<3>(one), 0.0);
  for (int threads : {2, 3}) EXPECT_TRUE(run(threads) == one) << threads << " threads";
  // And each kind went through its own kernel: on the undistorted block a
  // linear velocity field v = G·x gives every element the same stress after
  // one step, and the internal work is V·½σ:D·Δt over the block's exact
  // volume (a hexahedron taken for the tetrahedron of its slots 0, 1, 2, 4
  // would count a sixth of its volume).
  fe::Model flat = fe::parse_deck(block_deck(15, 15, 16, 1e-3, true, 2e11, 0.3, 0.0, "10", 7).deck, "flat.k");
  Eigen::Matrix3d G;
  G << 1e-3, 2e-4, -3e-4, 5e-4, -2e-3, 1e-4, 0.0, 7e-4, 1.5e-3;
  for (size_t i = 0; i < flat.x0.size(); ++i) flat.v0[i] = G * flat.x0[i];
  const double dt = 1e-9;
  fe::Solver s(flat, dt);
  s.step();
  const Eigen::Matrix<double, 6, 1> sigma = s.stress(0);
  for (size_t e = 1; e < flat.solids.size(); ++e)
    ASSERT_LT((s.stress(e) - sigma).norm(), 1e-9 * sigma.norm()) << "element " << flat.solids[e].id;
  const Eigen::Matrix3d D = 0.5 * (G + G.transpose());
  const double work = 15e-3 * 15e-3 * 16e-3 * 0.5 *
                      (sigma(0) * D(0, 0) + sigma(1) * D(1, 1) + sigma(2) * D(2, 2) +
                       2.0 * (sigma(3) * D(0, 1) + sigma(4) * D(1, 2) + sigma(5) * D(2, 0))) * dt;
  EXPECT_NEAR(s.energies().internal, work, 1e-10 * std::fabs(work)) << "round-off only";
}
