// fe_server's solver across MPI ranks against the same solver on one rank,
// in one process per rank: every rank runs the model twice, once alone
// (Domain::serial()) and once with the others (Domain::world()), and rank 0
// compares the gathered states. CTest runs this binary under mpirun with 1,
// 2 and 3 ranks (oversubscribed on a 2-core machine); alone it runs as one
// rank and the comparisons still hold.
//
// Tolerance: the runs differ only in the order of the sums at shared nodes
// (a rank's partial force plus the others', against one sum in element
// order): a few units of round-off (2.2e-16 relative) per shared node and
// step. The explicit scheme carries such a perturbation with the waves
// without amplifying it (it is stable), so after N steps it is at most
// ~N·1e-16 of the state's scale; 1e-10 leaves a factor of ~1000 over the
// 200–800 steps here (measured: below 1e-12). A wrong exchange (a missing
// or doubled contribution at one node) is a difference of order 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../fe_server/axi_decks.hpp"
#include "../fe_server/block_decks.hpp"
#include "../fe_server/impact_decks.hpp"
#include "config/port_table.hpp"
#include "input/deck_reader.hpp"
#include "input/mesher.hpp"
#include "loads/cavity_load.hpp"
#include "parallel/domain.hpp"
#include "solver/solver.hpp"

namespace {

const fe::Domain& world() { return fe::Domain::world(); }

struct State {
  std::vector<fe::Vec3> x, v;
  std::vector<Eigen::Matrix<double, 6, 1>> stress;
  std::vector<double> plastic;
  fe::Energies e;
  double contact_force = 0.0, peak_contact_force = 0.0;
};

// Runs `steps` steps; `each(solver, k)` before step k (loads).
template <class Each>
State run(const fe::Model& m, double dt, const fe::Domain& d, int steps, Each each, const fe::Partition* part = nullptr,
          fe::UserLoad* load = nullptr) {
  fe::Solver s(m, dt, d, part);
  if (load) s.set_user_load(load);
  double st_peak = 0.0;
  for (int k = 0; k < steps; ++k) {
    each(s, k);
    s.step();
    st_peak = std::max(st_peak, s.contact_force());
  }
  State st;
  s.gather_fields(st.x, st.v, st.stress, st.plastic, m.solids.empty() && !m.axis.empty());
  st.e = s.energies();
  st.contact_force = s.contact_force();
  st.peak_contact_force = st_peak;
  return st;
}

State run(const fe::Model& m, double dt, const fe::Domain& d, int steps, const fe::Partition* part = nullptr) {
  return run(m, dt, d, steps, [](fe::Solver&, int) {}, part);
}

double largest(const std::vector<fe::Vec3>& a) {
  double m = 0.0;
  for (const auto& x : a) m = std::max(m, x.cwiseAbs().maxCoeff());
  return m;
}

constexpr double kTol = 1e-10;  // of each quantity's scale: see the top of this file

// Energies on every rank; the gathered state on rank 0.
void expect_same(const State& one, const State& many, const fe::Model& m, const std::string& what) {
  const double scale = std::max(one.e.scale, 1e-30);
  EXPECT_NEAR(many.e.kinetic, one.e.kinetic, kTol * scale) << what;
  EXPECT_NEAR(many.e.internal, one.e.internal, kTol * scale) << what;
  EXPECT_NEAR(many.e.hourglass, one.e.hourglass, kTol * scale) << what;
  EXPECT_NEAR(many.e.contact, one.e.contact, kTol * scale) << what;
  EXPECT_NEAR(many.e.external_work, one.e.external_work, kTol * scale) << what;
  EXPECT_NEAR(many.e.balance_error, one.e.balance_error, kTol * scale) << what;
  EXPECT_NEAR(many.contact_force, one.contact_force, kTol * std::max(one.peak_contact_force, 1.0)) << what;
  EXPECT_NEAR(many.peak_contact_force, one.peak_contact_force, kTol * std::max(one.peak_contact_force, 1.0)) << what;
  if (world().rank() != 0) return;
  ASSERT_EQ(many.x.size(), one.x.size());
  std::vector<fe::Vec3> u(one.x.size());
  for (size_t i = 0; i < u.size(); ++i) u[i] = one.x[i] - m.x0[i];
  const double du = largest(u), dv = largest(one.v);
  ASSERT_GT(du, 0.0) << what << ": nothing moved";
  double worst_x = 0, worst_v = 0, worst_s = 0, ds = 0;
  for (size_t i = 0; i < u.size(); ++i) {
    worst_x = std::max(worst_x, (many.x[i] - one.x[i]).cwiseAbs().maxCoeff() / du);
    worst_v = std::max(worst_v, (many.v[i] - one.v[i]).cwiseAbs().maxCoeff() / dv);
  }
  for (const auto& s : one.stress) ds = std::max(ds, s.cwiseAbs().maxCoeff());
  for (size_t e = 0; e < one.stress.size(); ++e)
    worst_s = std::max(worst_s, (many.stress[e] - one.stress[e]).cwiseAbs().maxCoeff() / std::max(ds, 1e-30));
  EXPECT_LT(worst_x, kTol) << what << ": positions";
  EXPECT_LT(worst_v, kTol) << what << ": velocities";
  EXPECT_LT(worst_s, kTol) << what << ": stresses";
  std::printf("%s on %d ranks: largest differences from one rank, of their scale: x %.2g, v %.2g, stress %.2g, "
              "balance %.2g J\n",
              what.c_str(), world().size(), worst_x, worst_v, worst_s, many.e.balance_error - one.e.balance_error);
}

// Elements dealt out one by one (k mod P): every element's neighbours are
// on other ranks, so every face is cut, the contact faces and the cavity's
// segments included. The worst case for the exchange.
fe::Partition dealt(const fe::Model& m) {
  fe::Partition p;
  p.rank = world().rank(), p.ranks = world().size();
  if (p.ranks == 1) return p;
  p.solid.assign(m.solids.size(), -1), p.axi.assign(m.axis.size(), -1), p.bar.assign(m.bars.size(), -1);
  auto rigid = [&](int part) { return m.materials.at(m.parts.at(part).material).rigid; };
  int k = 0;
  for (size_t e = 0; e < m.solids.size(); ++e)
    if (!rigid(m.solids[e].part)) p.solid[e] = k++ % p.ranks;
  for (size_t e = 0; e < m.axis.size(); ++e)
    if (!rigid(m.axis[e].part)) p.axi[e] = k++ % p.ranks;
  p.method = "dealt";
  return p;
}

}  // namespace

// The hex8 bar impact (contact, the wave through both bars) as METIS cuts it.
TEST(Ranks, TheBarImpactMatchesOneRank) {
  const fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE), "impact.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const State one = run(m, dt, fe::Domain::serial(), 400), many = run(m, dt, world(), 400);
  EXPECT_GT(one.e.internal, 0.0) << "the bars were loaded";
  expect_same(one, many, m, "hex8 bar impact");
}

// Tetrahedra over hexahedra in one block (tests/fe_server/block_decks.hpp),
// stretched and sheared, as METIS cuts it and dealt out element by element
// (every tetrahedron's neighbours on other ranks).
TEST(Ranks, TetrahedraAndHexahedraMatchOneRank) {
  fe::Model m = fe::parse_deck(fe_test::block_deck(8, 8, 8, 1e-3, true, 2e11, 0.3, 0.1, "10", 3).deck, "block.k");
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(0.3 * m.x0[i].y(), 0.0, 50.0 * m.x0[i].z());
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const State one = run(m, dt, fe::Domain::serial(), 300), many = run(m, dt, world(), 300);
  EXPECT_GT(one.e.internal, 0.0);
  expect_same(one, many, m, "tet4 and hex8 block");
  const fe::Partition p = dealt(m);
  expect_same(one, run(m, dt, world(), 300, &p), m, "tet4 and hex8 block, dealt");
}

// The axisymmetric bar impact (2D contact), as METIS cuts it.
TEST(Ranks, TheAxisymmetricBarImpactMatchesOneRank) {
  const fe::Model m = fe::parse_deck(axi_test::bar_impact_deck(0.1, 0.02, 0.3, 0.02, 0.0025, 8.0, 0.3, 0.0), "axi.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const State one = run(m, dt, fe::Domain::serial(), 800), many = run(m, dt, world(), 800);
  EXPECT_GT(one.e.internal, 0.0);
  expect_same(one, many, m, "axisymmetric bar impact");
}

// Every face cut: the contact's two faces lie on every rank's elements, and
// the piston is a rigid body whose force is summed from nodes whose
// element forces come from several ranks.
TEST(Ranks, AContactCutByThePartitionAndARigidStrikerMatchOneRank) {
  std::string deck = fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE);
  const std::string piston = "*PART\npiston\n1,1,1\n";
  deck.replace(deck.find(piston), piston.size(), "*PART\npiston\n1,1,3\n*MAT_RIGID\n3,7850,2.1e11,0.3\n");
  const fe::Model m = fe::parse_deck(deck, "rigid_striker.k");
  ASSERT_EQ(m.rigid_bodies.size(), 1u);
  const fe::Partition p = dealt(m);
  if (world().size() > 1) {  // the tool's contact face (set 2) has corners of elements on every rank
    std::vector<char> on(static_cast<size_t>(world().size()), 0);
    std::vector<char> face(m.x0.size(), 0);
    for (const auto& seg : m.segment_sets.at(2))
      for (int k = 0; k < seg.corners(); ++k) face[static_cast<size_t>(seg.n[k])] = 1;
    for (size_t e = 0; e < m.solids.size(); ++e)
      for (int k : m.solids[e].n)
        if (face[static_cast<size_t>(k)] && p.solid[e] >= 0) on[static_cast<size_t>(p.solid[e])] = 1;
    for (int r = 0; r < world().size(); ++r) EXPECT_TRUE(on[static_cast<size_t>(r)]) << "rank " << r << " has no contact element";
  }
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const State one = run(m, dt, fe::Domain::serial(), 400), many = run(m, dt, world(), 400, &p);
  EXPECT_GT(one.peak_contact_force, 0.0) << "the striker hit";
  expect_same(one, many, m, "rigid striker, contact cut");
}

// A cavity's segment set cut by the partition, in both coupling modes: a
// prescribed pressure, and TLM (p = c + Zc·q with the flow q of all the
// cavity's segments, solved with the step's velocities: the global flow).
TEST(Ranks, ACavityCutByThePartitionMatchesOneRankInBothModes) {
  fe::RevolutionMeshOptions o;
  o.element_size = 0.003;
  const fe::RevolutionMesh mesh = fe::mesh_revolution({{0.1, 0.02, 0.0}}, o);
  const fe::Model m = fe::parse_deck("*KEYWORD\n" + mesh.keyword_text +
                                         "*PART\np\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n"
                                         "*USER_LOADING_SET\n1,PRESSS,1\n",
                                     "plug.k");
  const fe::Partition p = dealt(m);
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  for (const bool tlm : {false, true}) {
    const auto table = config::parse_port_table(
        std::string("$FMU_SETTINGS\nmodel, p\ntimestep, 1e-5\nmode, ") + (tlm ? "tlm" : "pressure") +
            "\n$FMU_HOPSAN_PORTS\n1, cav, Hydraulic\n$FMU_HOPSAN_SEND\n" + (tlm ? "1, c\n1, Zc\n" : "1, p\n") +
            "$FMU_HOPSAN_RECEIVE\n1, q\n",
        "p.cfg");
    fe::CavityPressureLoad a(m, table), b(m, table);
    auto loads = [&](fe::CavityPressureLoad& l) {
      return [&l, tlm](fe::Solver&, int k) {
        if (tlm)
          l.set_wave(0, 1e7 * std::sin(0.05 * k), 2e9);
        else
          l.set_pressure(0, 1e7 * std::sin(0.05 * k));
      };
    };
    const State one = run(m, dt, fe::Domain::serial(), 300, loads(a), nullptr, &a);
    const State many = run(m, dt, world(), 300, loads(b), &p, &b);
    EXPECT_GT(one.e.external_work, 0.0) << "the cavity did work";
    expect_same(one, many, m, tlm ? "cavity, TLM" : "cavity, pressure");
  }
}

// Loads on every node (gravity on all parts, global mass damping) make
// every node global: each rank integrates all of them; still the one-rank
// result.
TEST(Ranks, LoadsOnEveryNodeMatchOneRank) {
  const fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE) +
                                         "*DEFINE_CURVE\n7\n0,9810\n1,9810\n*LOAD_BODY_Z\n7\n"
                                         "*DAMPING_GLOBAL\n0, 50.0\n",
                                     "gravity.k");
  ASSERT_FALSE(m.body_loads.empty());
  ASSERT_FALSE(m.mass_damping.empty());
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const State one = run(m, dt, fe::Domain::serial(), 300), many = run(m, dt, world(), 300);
  EXPECT_NE(one.e.external_work, 0.0) << "gravity and damping did work";
  expect_same(one, many, m, "gravity and mass damping");
}

// An element that inverts on one rank ends the step on every rank with its
// message and the rank named, instead of leaving the others waiting.
TEST(Ranks, AnElementThatInvertsOnOneRankStopsEveryRank) {
  fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE), "impact.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  // One face of a tool element driven through the opposite face at 30 km/s
  // (~8 mm per step through 2.5 mm; at 1 km/s the stiffness stops the face
  // within 0.2 mm): it inverts in its first steps.
  const auto& el = m.solids[5].n;
  fe::Vec3 across = fe::Vec3::Zero();
  for (int a = 0; a < 4; ++a) across += 0.25 * (m.x0[static_cast<size_t>(el[a + 4])] - m.x0[static_cast<size_t>(el[a])]);
  for (int a = 0; a < 4; ++a) m.v0[static_cast<size_t>(el[a])] = 3e4 * across.normalized();
  fe::Solver s(m, dt, world());
  std::string message;
  try {
    for (int k = 0; k < 200; ++k) s.step();
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("inverted"), std::string::npos) << message;
  if (world().rank() == 0) std::printf("every rank stopped with: %s\n", message.c_str());
  if (world().parallel()) {
    EXPECT_NE(message.find("(on rank "), std::string::npos) << message;
  }
}

int main(int argc, char** argv) {
  fe::Domain::init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  fe::Domain::finalize();
  return rc;
}
