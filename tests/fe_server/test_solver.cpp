// fe_server: deck reader, central-difference solver and the cavity-pressure hook.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <sys/resource.h>
#include <thread>
#include <sstream>

#include "deck_errors.hpp"
#include "loads/cavity_load.hpp"
#include "config/port_table.hpp"
#include "input/deck_reader.hpp"
#include "input/mesher.hpp"
#include "h5io/timeseries.hpp"
#include "impact_decks.hpp"
#include "output/history.hpp"
#include "solver/solver.hpp"

namespace {

// A 2 kg mass on a 2e5 N/m spring to a fixed node, kicked with 0.5 m/s.
const char* kOscillator = R"(*KEYWORD
*NODE
1, 0, 0, 0
2, 0, 0, -0.1, 7
*ELEMENT_MASS
1, 1, 2.0
*BOUNDARY_SPC_NODE
1, 0, 1, 1, 0
*PART
spring
1, 1, 1
*SECTION_DISCRETE
1, 0
*MAT_SPRING_ELASTIC
1, 2.0e5
*ELEMENT_DISCRETE
1, 1, 2, 1
*INITIAL_VELOCITY_NODE
1, 0, 0, 0.5
*CONTROL_TERMINATION
0.01
*END
)";

using fe_test::deck_error;

}  // namespace

TEST(DeckReader, ReadsTheOscillator) {
  fe::DeckWarnings w;
  auto m = fe::parse_deck(kOscillator, "osc.k", &w);
  EXPECT_TRUE(w.messages.empty());
  ASSERT_EQ(m.node_ids.size(), 2u);
  EXPECT_TRUE(m.fixed[1].all());
  EXPECT_FALSE(m.fixed[0][2]);
  ASSERT_EQ(m.discretes.size(), 1u);
  EXPECT_DOUBLE_EQ(m.discretes[0].k, 2.0e5);
  EXPECT_DOUBLE_EQ(m.end_time, 0.01);
}

TEST(DeckReader, FixedWidthCardsReadLikeCommaCards) {
  std::string fixed = "*KEYWORD\n*NODE\n       1             0.0             0.0             0.0\n"
                      "       2             0.0             0.0            -0.1       7\n"
                      "*ELEMENT_MASS\n       1       1             2.0\n";
  auto m = fe::parse_deck(fixed, "fixed.k");
  EXPECT_DOUBLE_EQ(m.x0[1].z(), -0.1);
  EXPECT_TRUE(m.fixed[1].all());
  EXPECT_DOUBLE_EQ(m.mass[0], 2.0);
}

TEST(DeckReader, ErrorsAndWarningsNameTheLine) {
  std::string bad = kOscillator;
  bad.replace(bad.find("1, 1, 2, 1\n"), 11, "1, 1, 7, 1\n");
  EXPECT_NE(deck_error(bad).find("deck.k:17: node 7 is not defined"), std::string::npos) << deck_error(bad);
  // A keyword that is not read is an error unless it provably changes no
  // result (output requests; *CONTROL_ cards of defaults only).
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n*HOURGLASS\n1,4\n")
                .find("deck.k:4: *HOURGLASS is not supported by this fe_server version: per-part hourglass control"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n*DEFINE_BOX\n1,0,1\n").find("deck.k:4: keyword *DEFINE_BOX is not supported"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n*CONTROL_IMPLICIT_GENERAL\n1,1e-3\n")
                .find("deck.k:5: *CONTROL_IMPLICIT_GENERAL is not supported by this fe_server version and field 1 ('1')"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n*CASE_BEGIN_1\n*INITIAL_VELOCITY_NODE\n1,0,0,0\n*CASE_END_1\n")
                .find("deck.k:4: *CASE_BEGIN_1: load cases (*CASE) are not supported"),
            std::string::npos);
  // A shell is an axisymmetric solid only: its part must say so.
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n*ELEMENT_SHELL\n1,1,1,2,3,4\n"
                       "*PART\np\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2e11,0.3\n")
                .find("deck.k:8: part 1 needs a *SECTION_SHELL with ELFORM 15 or 14"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*SECTION_SHELL\n1,2\n0\n").find("deck.k:3: ELFORM 2"), std::string::npos);
  // Clockwise nodes, or a node off the x–y plane, are named.
  const std::string axi_tail = "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2e11,0.3\n";
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0\n4,0,1,0\n*ELEMENT_SHELL\n1,1,1,4,3,2\n" + axi_tail)
                .find("counter-clockwise"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n2,1,0,0\n3,1,1,0.5\n4,0,1,0\n*ELEMENT_SHELL\n1,1,1,2,3,4\n" + axi_tail)
                .find("x-y plane"),
            std::string::npos);
  EXPECT_NE(deck_error("*KEYWORD\n*NODE\n1,0,0,0\n").find("has no mass"), std::string::npos);
  fe::DeckWarnings w;
  std::string unknown = std::string(kOscillator);
  unknown.insert(unknown.find("*END"), "*DATABASE_BNDOUT\n1e-4\n");
  unknown.insert(unknown.find("*END"), "*CONTROL_ACCURACY\n0, 1,\n\n");  // defaults only (INN 1 is LS-DYNA's)
  fe::parse_deck(unknown, "deck.k", &w);
  ASSERT_EQ(w.messages.size(), 2u);
  EXPECT_NE(w.messages[0].find("deck.k:22: warning: *DATABASE_BNDOUT asks for LS-DYNA's output"), std::string::npos)
      << w.messages[0];
  EXPECT_NE(w.messages[1].find("deck.k:24: warning: *CONTROL_ACCURACY is not supported; its cards hold only"),
            std::string::npos)
      << w.messages[1];
}

TEST(Solver, SpringMassFollowsTheAnalyticSolution) {
  auto m = fe::parse_deck(kOscillator, "osc.k");
  const double omega = std::sqrt(2.0e5 / 2.0), v0 = 0.5;
  const double dt = 0.05 / omega;
  fe::Solver s(m, dt);
  const int steps = static_cast<int>(2.0 * 2.0 * M_PI / omega / dt);  // two periods
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    s.step();
    const double exact = v0 / omega * std::sin(omega * s.time());
    worst = std::max(worst, std::fabs(s.x()[0].z() - exact));
  }
  // Central difference has a relative frequency error of (ω·Δt)²/24, so after
  // ω·t = 4π radians the phase error is 4π·(ω·Δt)²/24 ≈ 1.3e-3 rad; allow twice that
  // of the amplitude v0/ω.
  const double phase_bound = 4.0 * M_PI * (omega * dt) * (omega * dt) / 24.0;
  EXPECT_LT(worst, 2.0 * phase_bound * v0 / omega);
  // A conservative system: the energy balance closes to round-off-level, bounded
  // by the O((ω·Δt)²) oscillation of the discrete energy around its mean.
  EXPECT_LT(std::fabs(s.energies().balance_error), (omega * dt) * (omega * dt) * 0.5 * 2.0 * v0 * v0);
}

// *BOUNDARY_PRESCRIBED_MOTION_NODE on a *DEFINE_CURVE: a massless node
// (the far end of a feed spring) is driven 10 mm along y over 20 ms (a ramp,
// then held); a 5 kg mass hangs on it by a spring, with or without a damper
// (ζ ≈ 1.06). The node follows the curve to round-off at every step; with the
// damper the mass settles where the spring is unstretched, 10 mm on; the
// prescribed motion's work (the reaction it takes, booked with the loads)
// closes the energy account.
TEST(PrescribedMotion, ANodeFollowsItsCurveAndItsWorkClosesTheEnergyAccount) {
  auto run = [](double c, double* settled, double* balance, double* work) {
    std::ostringstream d;
    d << "*KEYWORD\n*NODE\n1, 0, 0, 0\n2, 0, -0.1, 0\n*ELEMENT_MASS\n1, 2, 5.0\n*BOUNDARY_SPC_NODE\n"
         "1, 0, 1, 0, 1\n2, 0, 1, 0, 1\n*PART\nspring\n1, 1, 1\n*PART\ndamper\n2, 1, 2\n*SECTION_DISCRETE\n1, 0\n"
         "*MAT_SPRING_ELASTIC\n1, 1.0e5\n*MAT_DAMPER_VISCOUS\n2, "
      << c << "\n*ELEMENT_DISCRETE\n1, 1, 2, 1\n2, 2, 2, 1\n"
              "*DEFINE_CURVE\n$ lcid, sidr, sfa, sfo\n7, 0, 1.0, 0.01\n0.0, 0.0\n0.02, 1.0\n1.0, 1.0\n"
              "*BOUNDARY_PRESCRIBED_MOTION_NODE\n$ nid, dof, vad, lcid\n1, 2, 2, 7\n*END\n";
    fe::Model m = fe::parse_deck(d.str(), "feed.k");
    EXPECT_EQ(m.prescribed.size(), 1u);
    fe::Solver s(m, 1e-5);
    double worst = 0.0;
    while (s.time() < 0.1) {
      s.step();
      const double u = s.x()[0].y() - m.x0[0].y();
      worst = std::max(worst, std::fabs(u - 0.01 * std::min(1.0, s.time() / 0.02)));
    }
    EXPECT_LT(worst, 1e-15) << "m: the driven node is on its curve";
    *settled = s.x()[1].y() - m.x0[1].y();
    *balance = s.energies().balance_error;
    *work = s.energies().external_work;
  };
  double settled = 0, balance = 0, work = 0;
  run(0.0, &settled, &balance, &work);
  // Spring only: the error is the discrete energy's O((ω·Δt)²) wobble
  // (ω·Δt = 1.4e-3): 1e-5 of the work bounds it (measured 5e-7).
  EXPECT_GT(work, 1.0);
  EXPECT_LT(std::fabs(balance), 1e-5 * work) << "J of " << work << " J";
  run(1.5e3, &settled, &balance, &work);
  // The slow overdamped mode (100 1/s) leaves 3e-4 of the 7.5 mm lag c·v/k
  // 80 ms after the ramp: 2e-5 m.
  EXPECT_NEAR(settled, 0.01, 2e-5) << "the mass settles 10 mm on";
  // With the damper: its dissipation is booked at first order in Δt (its
  // force from v_{n−1/2}); measured 0.14 % at Δt = 10 us, 0.014 % at 1 us.
  EXPECT_LT(std::fabs(balance), 5e-3 * work) << "J of " << work << " J";
}

// VAD 0 (velocity) with BIRTH and DEATH, on a node set: the nodes move at
// the curve's velocity only between the two times, and are free after (a
// free mass keeps its velocity).
TEST(PrescribedMotion, AVelocityBetweenBirthAndDeathThenTheNodeIsFree) {
  const char* deck = R"(*KEYWORD
*NODE
1, 0, 0, 0
*ELEMENT_MASS
1, 1, 2.0
*SET_NODE_LIST
4
1
*DEFINE_CURVE
3
0.0, 2.0
1.0, 2.0
*BOUNDARY_PRESCRIBED_MOTION_SET
$ nsid, dof, vad, lcid, sf, vid, death, birth
4, 3, 0, 3, 1.5, 0, 0.002, 0.001
*END
)";
  fe::Model m = fe::parse_deck(deck, "vel.k");
  fe::Solver s(m, 1e-5);
  while (s.time() < 0.0009) s.step();
  EXPECT_EQ(s.v()[0].z(), 0.0) << "not before BIRTH";
  while (s.time() < 0.0015) s.step();
  EXPECT_EQ(s.v()[0].z(), 3.0) << "SF × the curve";
  while (s.time() < 0.003) s.step();
  EXPECT_EQ(s.v()[0].z(), 3.0) << "after DEATH the free mass keeps its velocity";
}

TEST(PrescribedMotion, BadCardsAreRefusedWithTheirLine) {
  const std::string base = "*KEYWORD\n*NODE\n1,0,0,0\n*ELEMENT_MASS\n1,1,1.0\n*DEFINE_CURVE\n3\n0,0\n1,1\n";
  auto error = [](const std::string& text) {
    try {
      fe::parse_deck(text, "m.k");
    } catch (const config::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error(base + "*BOUNDARY_PRESCRIBED_MOTION_NODE\n1,2,2,9\n").find("m.k:11: LCID 9 is not defined"),
            std::string::npos);
  EXPECT_NE(error(base + "*BOUNDARY_PRESCRIBED_MOTION_NODE\n1,5,2,3\n").find("m.k:11: DOF 5"), std::string::npos);
  EXPECT_NE(error(base + "*BOUNDARY_PRESCRIBED_MOTION_NODE\n1,2,4,3\n").find("VAD 4"), std::string::npos);
  EXPECT_NE(error("*KEYWORD\n*DEFINE_CURVE\n3\n0,0\n1,1\n0.5,2\n").find("m.k:6: the curve's abscissae must increase"),
            std::string::npos);
  EXPECT_NE(error(base + "*BOUNDARY_SPC_NODE\n1,0,0,1,0\n*BOUNDARY_PRESCRIBED_MOTION_NODE\n1,2,2,3\n").find("fixed by an SPC"),
            std::string::npos);
}

// The preload (*CONTROL_DYNAMIC_RELAXATION): a steel column of ten 1D bars
// (with 1 kg at each end) stands on a support spring under gravity
// (*LOAD_BODY_Z, both phases) and is pressed down by a feed spring whose far
// end a prescribed motion drives 10 mm down: on a ramp during the
// relaxation (curve SIDR 1), held there in the transient (SIDR 0). After the
// relaxation the support carries the feed plus the weight (statics), the
// residual is a small fraction of the feed, and the transient starts at rest
// and stays there.
TEST(DynamicRelaxation, APreloadedColumnSettlesToItsStaticStateAndTheTransientStartsAtRest) {
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*NODE\n";
  for (int i = 0; i <= 10; ++i) d << i + 1 << ",0,0," << 0.01 * i << "\n";
  d << "100,0,0,-0.05\n200,0,0,0.15\n";
  d << "*ELEMENT_MASS\n1,1,1.0\n2,11,1.0\n";
  d << "*PART\ncolumn\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*ELEMENT_BEAM\n";
  for (int i = 1; i <= 10; ++i) d << i << ",1," << i << "," << i + 1 << "\n";
  d << "*PART\nsupport\n2,2,2\n*PART\nfeed\n3,2,3\n*SECTION_DISCRETE\n2,0\n"
       "*MAT_SPRING_ELASTIC\n2,1.0e7\n*MAT_SPRING_ELASTIC\n3,1.0e5\n"
       "*ELEMENT_DISCRETE\n901,2,100,1\n902,3,11,200\n";
  d << "*SET_NODE_LIST\n1\n";
  for (int i = 1; i <= 11; ++i) d << i << (i % 8 == 0 ? "\n" : ",");
  d << "\n*BOUNDARY_SPC_SET\n1,0,1,1,0\n*BOUNDARY_SPC_NODE\n100,0,1,1,1\n200,0,1,1,0\n";
  d << "*DEFINE_CURVE\n1,2\n0,9.81\n1,9.81\n"            // gravity, both phases
       "*DEFINE_CURVE\n2,1\n0,0\n0.005,-0.01\n1,-0.01\n"  // the feed's ramp, relaxation only
       "*DEFINE_CURVE\n3,0\n0,-0.01\n1,-0.01\n"            // held in the transient
       "*LOAD_BODY_Z\n1\n"
       "*BOUNDARY_PRESCRIBED_MOTION_NODE\n200,3,2,2\n200,3,2,3\n"
       "*CONTROL_DYNAMIC_RELAXATION\n$ nrcyck, drtol, drfctr\n250,1e-8,0.995\n";
  fe::Model m = fe::parse_deck(d.str(), "column.k");
  ASSERT_TRUE(m.relaxes());
  fe::Solver s(m, 1e-6);
  const fe::Solver::RelaxationReport r = s.relax();
  ASSERT_TRUE(r.ran);
  EXPECT_TRUE(r.converged) << r.steps << " steps, kinetic " << r.kinetic << " of " << r.peak;
  s.begin_transient();
  EXPECT_EQ(s.time(), 0.0);
  const auto& x = s.x();
  auto u = [&](int id) { return x[static_cast<size_t>(m.index_of(id, {}))].z() - m.x0[static_cast<size_t>(m.index_of(id, {}))].z(); };
  EXPECT_NEAR(u(200), -0.01, 1e-15) << "the feed's far end where its curve put it";
  const double feed = 1e5 * (u(11) - u(200));          // the feed spring's compression × k
  const double support = -1e7 * u(1);                  // the support spring's compression × k
  const double weight = m.total_mass() * 9.81;         // the column's 2.0785 kg
  std::printf("preload: feed %.3f N, weight %.4f N, support %.3f N; residual %.3g N (%s), %.3g %% of %.1f N; "
              "%ld steps\n", feed, weight, support, r.resultant, r.worst.c_str(), 100 * r.resultant / r.load, r.load,
              r.steps);
  EXPECT_GT(feed, 900.0);
  // Statics: the support carries the feed and the weight. DRTOL 1e-4 leaves
  // a velocity of 1 % of the peak in the slowest mode, an out-of-balance of
  // the same order of a small force: 0.1 % of the feed bounds both.
  EXPECT_NEAR(support, feed + weight, 1e-3 * feed);
  EXPECT_LT(r.resultant, 1e-3 * feed);
  EXPECT_NEAR(r.load, feed + weight, 1e-2 * feed) << "the largest support force: the support spring's anchor";
  // The transient starts at rest and stays (the same loads, now from curves 1 and 3).
  const double top = u(11);
  double vmax = 0.0;
  while (s.time() < 2e-3) {
    s.step();
    for (const auto& v : s.v()) vmax = std::max(vmax, v.norm());
  }
  EXPECT_LT(vmax, 1e-4) << "m/s";
  EXPECT_NEAR(u(11), top, 1e-7);
}

// *LOAD_BODY_Y with *LOAD_BODY_PARTS: gravity on the parts of the set only.
// Two free steel bars side by side: the one in the set falls at g (every
// node, so it stays unstressed), the other stays where it is.
TEST(BodyLoad, GravityActsOnTheSetsPartsOnly) {
  const std::string deck = "*KEYWORD\n*NODE\n1,0,0,0\n2,0,0.1,0\n3,0.05,0,0\n4,0.05,0.1,0\n"
                           "*PART\nfalls\n1,1,1\n*PART\nstays\n2,1,1\n*SECTION_BEAM\n1,3\n1e-4\n"
                           "*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*ELEMENT_BEAM\n1,1,1,2\n2,2,3,4\n"
                           "*SET_PART_LIST\n5\n1\n*LOAD_BODY_PARTS\n5\n*DEFINE_CURVE\n1\n0,9.81\n1,9.81\n"
                           "*LOAD_BODY_Y\n1\n";
  fe::Model m = fe::parse_deck(deck, "g.k");
  const double dt = 1e-6;
  fe::Solver s(m, dt);
  for (int k = 0; k < 1000; ++k) s.step();
  // Central differences: v_{n+1/2} = −g·(t_n + Δt/2) exactly for a constant
  // force; the falling bar's own force, from its length, carries the
  // round-off of the positions' difference (ε ~ 1e-16): 1.3e-12 m/s after
  // 1000 steps, bounded here by 1e-11 (1e-9 of the velocity).
  for (int i : {0, 1}) EXPECT_NEAR(s.v()[static_cast<size_t>(i)].y(), -9.81 * (s.time() - 0.5 * dt), 1e-11) << "node " << i + 1;
  for (int i : {2, 3}) EXPECT_EQ(s.v()[static_cast<size_t>(i)].y(), 0.0) << "node " << i + 1;
  EXPECT_LT(std::fabs(s.bar_stress(0)), 1e-3) << "Pa: a uniform body force stresses nothing";
}

TEST(DynamicRelaxation, InitialVelocitiesCannotBeCombinedWithIt) {
  try {
    fe::parse_deck("*KEYWORD\n*NODE\n1,0,0,0\n*ELEMENT_MASS\n1,1,1.0\n*INITIAL_VELOCITY_NODE\n1,0,0,1\n"
                   "*CONTROL_DYNAMIC_RELAXATION\n250,0,0,0,0,0,0,1\n",
                   "dr.k");
    FAIL() << "must refuse";
  } catch (const config::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dr.k:8: dynamic relaxation ends with every node at rest"), std::string::npos)
        << e.what();
  }
}

TEST(Solver, RefusesATimeStepAboveTheStableLimitAndNamesTheElement) {
  auto m = fe::parse_deck(kOscillator, "osc.k");
  const double critical = 2.0 / std::sqrt(2.0e5 / 2.0);
  EXPECT_NEAR(fe::Solver::stable_dt(m).dt, critical, 1e-15);
  try {
    fe::Solver s(m, critical);  // above TSSFAC × critical
    FAIL() << "an unstable step must be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("discrete element 1 (osc.k:17"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(fe::Solver(m, 0.9 * critical));
}

TEST(CavityPressureLoad, LoadAndFlowUseTheSameAreaSoPowerBalances) {
  // A 0.2 m × 0.1 m rigid plate pushed by a cavity on its +z side.
  const char* plate = R"(*KEYWORD
*NODE
1, 0, 0, 0
2, 0.2, 0, 0
3, 0.2, 0.1, 0
4, 0, 0.1, 0
*ELEMENT_MASS
1, 1, 1.0
*SET_NODE_LIST
1
1, 2, 3, 4
*CONSTRAINED_NODAL_RIGID_BODY
1, 0, 1
*SET_SEGMENT
1
1, 2, 3, 4
*USER_LOADING_SET
1, PRESSS, 1
*INITIAL_VELOCITY_NODE
1, 0, 0, 0.3
2, 0, 0, 0.3
3, 0, 0, 0.3
4, 0, 0, 0.3
)";
  auto m = fe::parse_deck(plate, "plate.k");
  auto t = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-4\n$FMU_HOPSAN_PORTS\n1, cav, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n",
      "p.cfg");
  fe::CavityPressureLoad load(m, t);
  const int slot = load.slot_of_port(1);
  ASSERT_EQ(slot, 0);
  load.set_pressure(slot, 2.0e6);
  std::vector<fe::Vec3> f(m.x0.size(), fe::Vec3::Zero());
  load.apply(0.0, m.x0, m.v0, f);
  fe::Vec3 total = fe::Vec3::Zero();
  for (const auto& fi : f) total += fi;
  EXPECT_NEAR(total.z(), -2.0e6 * 0.02, 1e-6);  // pushes against the normal (+z)
  EXPECT_NEAR(load.area(slot), 0.02, 1e-15);
  const double q = load.flow(slot, m.v0);
  EXPECT_NEAR(q, 0.02 * 0.3, 1e-15);  // moving into the cavity displaces A·v
  // Hydraulic power p·q equals the power the pressure takes from the structure.
  double structural = 0.0;
  for (size_t i = 0; i < f.size(); ++i) structural -= f[i].dot(m.v0[i]);
  EXPECT_NEAR(2.0e6 * q, structural, 1e-9);
}

TEST(CavityPressureLoad, ASegmentSlidingPastTheCavityEdgeIsLoadedByItsWettedFraction) {
  // A lateral strip (normal +x) 10 mm long in z, sliding up through a cavity
  // whose upper edge is at z = 0.
  const char* strip = R"(*KEYWORD
*NODE
1, 0, 0, -0.01
2, 0, 0.01, -0.01
3, 0, 0.01, 0
4, 0, 0, 0
*ELEMENT_MASS
1, 1, 1.0
2, 2, 1.0
3, 3, 1.0
4, 4, 1.0
*SET_SEGMENT
1
1, 2, 3, 4
*USER_LOADING_SET
$ sid, ltype, port, zmin, zmax
1, PRESSS, 1, -1.0, 0.0
)";
  auto m = fe::parse_deck(strip, "strip.k");
  auto t = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-4\n$FMU_HOPSAN_PORTS\n1, cav, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n",
      "p.cfg");
  fe::CavityPressureLoad load(m, t);
  load.set_pressure(0, 1e6);
  const double full = 1e6 * 1e-4;  // p·A, A = 10 mm × 10 mm
  std::vector<fe::Vec3> v(4, fe::Vec3(0.2, 0, 0.5));  // moving out of the surface and up
  double previous = full;
  for (double dz : {0.0, 0.0025, 0.005, 0.0075, 0.01, 0.012}) {
    std::vector<fe::Vec3> x = m.x0;
    for (auto& p : x) p.z() += dz;
    std::vector<fe::Vec3> f(4, fe::Vec3::Zero());
    load.apply(0.0, x, v, f);
    double fx = 0.0, power = 0.0;
    for (size_t i = 0; i < 4; ++i) {
      fx += f[i].x();
      power -= f[i].dot(v[i]);
    }
    const double wetted = std::clamp(1.0 - dz / 0.01, 0.0, 1.0);
    EXPECT_NEAR(-fx, full * wetted, 1e-9 * full) << "dz = " << dz;
    EXPECT_LE(-fx, previous + 1e-12) << "the load falls monotonically as the strip leaves";
    previous = -fx;
    // Flow from the same wetted areas: p·q equals the power on the structure.
    EXPECT_NEAR(1e6 * load.flow(0, v), power, 1e-9 * full);
  }
}

TEST(EnergyBalance, AnErrorAboveTheBoundWarnsAndOneHundredTimesAboveFails) {
  // Bound: 1 % of the largest energy the run held (here 1000 J → 10 J).
  bool exceeded = false, failed = false;
  fe::History::judge_energy(9.0, 1000.0, &exceeded, &failed);
  EXPECT_FALSE(exceeded);
  EXPECT_FALSE(failed);
  fe::History::judge_energy(-11.0, 1000.0, &exceeded, &failed);
  EXPECT_TRUE(exceeded);
  EXPECT_FALSE(failed);
  fe::History::judge_energy(1001.0, 1000.0, &exceeded, &failed);  // 100.1 × the bound
  EXPECT_TRUE(exceeded);
  EXPECT_TRUE(failed);
  fe::History::judge_energy(1e17, 1000.0, &exceeded, &failed);  // the issue's case: exit 0 before
  EXPECT_TRUE(failed);
}

// The balance's scale is the most energy the model held, the springs'
// stored energy included: the one-DOF piston run on its own (no cavity
// pressure to balance the spring's 10 kN preload) swings on a spring that
// holds ½·k·0.01² = 50 J while its kinetic energy never passes 10 J. With the
// springs left out of the scale its balance error counted 155 % of 9.5 J and
// ended the run as a failure (exit 8).
TEST(EnergyBalance, TheScaleCountsTheEnergyStoredInSprings) {
  fe::Model m = fe::read_deck(PCS_SCENES_DIR "/one_dof/piston.k");
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  const std::string out = ::testing::TempDir() + "/spring_scale.h5";
  bool exceeded = false, failed = false;
  std::string summary;
  {
    fe::History h(out, m, nullptr, s.dt(), s.dt());
    for (int k = 0; k < 2000; ++k) {
      s.step();
      h.record(s, {}, {});
    }
    summary = h.energy_summary(s, &exceeded, &failed);
  }
  std::remove(out.c_str());
  EXPECT_NE(summary.find("of 50."), std::string::npos) << summary;
  EXPECT_FALSE(failed) << summary;
}

// Histories at the rates the deck asks for (*DATABASE_GLSTAT, NODOUT, ELOUT
// DT): each stream's rows are exactly the every-step rows at its times, and
// a DT at or below the FE step writes every step.
TEST(History, DecimatedHistoriesHoldTheEveryStepValuesAtTheirTimes) {
  std::string deck = fe_test::bar_impact_deck(0.05, 0.1, 0.01, 0.005, 8.0, fe_test::kE);
  deck += "*DATABASE_HISTORY_SOLID\n1,2\n*DATABASE_HISTORY_NODE\n1,100001\n";
  fe::Model every = fe::parse_deck(deck + "*DATABASE_ELOUT\n1e-12\n*DATABASE_NODOUT\n1e-12\n*DATABASE_GLSTAT\n1e-12\n",
                                   "every.k");
  const double dt = 0.9 * fe::Solver::stable_dt(every).dt;
  std::ostringstream rates;
  // Comma cards: the values are longer than a 10-column field.
  rates << "*DATABASE_GLSTAT\n" << 5 * dt << ",\n*DATABASE_NODOUT\n" << 3 * dt << ",\n*DATABASE_ELOUT\n" << 7 * dt << ",\n";
  fe::Model sparse = fe::parse_deck(deck + rates.str(), "sparse.k");
  const std::string dir = ::testing::TempDir();
  const int steps = 400;
  for (auto [model, file] : {std::pair<fe::Model*, std::string>{&every, dir + "/every.h5"}, {&sparse, dir + "/sparse.h5"}}) {
    fe::Solver s(*model, dt);
    fe::History h(file, *model, nullptr, dt, 1.0);
    for (int k = 0; k < steps; ++k) {
      s.step();
      h.record(s, {}, {});
    }
  }
  struct Check {
    const char *time, *series;
    int every;
  };
  for (const Check& c : {Check{"time", "energy/kinetic", 5}, Check{"time_nodes", "nodes/100001/vz", 3},
                         Check{"time_elements", "solids/2/szz", 7}}) {
    const auto t_all = h5io::read_series(dir + "/every.h5", c.time), v_all = h5io::read_series(dir + "/every.h5", c.series);
    const auto t = h5io::read_series(dir + "/sparse.h5", c.time), v = h5io::read_series(dir + "/sparse.h5", c.series);
    ASSERT_EQ(t_all.size(), static_cast<size_t>(steps)) << c.time;
    ASSERT_EQ(t.size(), static_cast<size_t>(steps / c.every)) << c.time;
    for (size_t r = 0; r < t.size(); ++r) {
      const size_t i = (r + 1) * static_cast<size_t>(c.every) - 1;  // row r is FE step (r+1)·every
      ASSERT_EQ(t[r], t_all[i]) << c.series << " row " << r;
      ASSERT_EQ(v[r], v_all[i]) << c.series << " row " << r;
    }
    double largest = 0.0;
    for (double x : v) largest = std::max(largest, std::fabs(x));
    EXPECT_GT(largest, 0.0) << c.series << ": the compared values are not all zero";
  }
  // Each part's hourglass energy (part_energy/hourglass/<id>) sums to the
  // model's, row by row, and the impact puts some in each part.
  const auto all = h5io::read_series(dir + "/every.h5", "energy/hourglass");
  const auto p1 = h5io::read_series(dir + "/every.h5", "part_energy/hourglass/1");
  const auto p2 = h5io::read_series(dir + "/every.h5", "part_energy/hourglass/2");
  ASSERT_EQ(p1.size(), all.size());
  for (size_t r = 0; r < all.size(); ++r) ASSERT_NEAR(p1[r] + p2[r], all[r], 1e-12 * std::fabs(all.back())) << "row " << r;
  EXPECT_GT(p1.back(), 0.0);
  EXPECT_GT(p2.back(), 0.0);
  std::remove((dir + "/every.h5").c_str());
  std::remove((dir + "/sparse.h5").c_str());
}

// Threads change nothing: the bar impact (hex8 blocks, contact, node passes
// in blocks) and an elastic cylinder under a time-varying cavity pressure
// (the user-load hook as in a co-simulation) give bit-identical positions,
// velocities, stresses and energies on 1, 2 and 3 threads. The decks are
// large enough for several element blocks and node blocks, so the threads
// really share the work.
TEST(Threads, OneTwoAndThreeThreadsGiveBitIdenticalResults) {
  struct State {
    std::vector<fe::Vec3> x, v;
    std::vector<double> szz;
    double ke = 0, internal = 0, balance = 0;
  };
  auto run = [](const fe::Model& m, int threads, fe::CavityPressureLoad* load, int steps) {
    fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
    s.set_threads(threads);
    EXPECT_EQ(s.threads(), threads);
    if (load) s.set_user_load(load);
    for (int k = 0; k < steps; ++k) {
      if (load) load->set_pressure(0, 1e7 * std::sin(0.05 * k));
      s.step();
    }
    State st{s.x(), s.v(), {}, s.energies().kinetic, s.energies().internal, s.energies().balance_error};
    for (size_t e = 0; e < m.solids.size(); ++e) st.szz.push_back(s.stress(e)(2));
    return st;
  };
  fe::Model impact = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE), "impact.k");
  ASSERT_GT(impact.solids.size(), 3 * fe::hex8_block_size(impact.solids.size()));
  ASSERT_GT(impact.x0.size(), 2 * fe::Solver::kNodeBlock);
  fe::RevolutionMeshOptions o;
  o.element_size = 0.003;
  const fe::RevolutionMesh mesh = fe::mesh_revolution({{0.1, 0.02, 0.0}}, o);
  fe::Model plug = fe::parse_deck("*KEYWORD\n" + mesh.keyword_text +
                                      "*PART\np\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n"
                                      "*USER_LOADING_SET\n1,PRESSS,1\n",
                                  "plug.k");
  const auto table = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-5\n$FMU_HOPSAN_PORTS\n1, cav, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n",
      "p.cfg");
  for (int threads : {2, 3}) {
    const State a = run(impact, 1, nullptr, 150), b = run(impact, threads, nullptr, 150);
    EXPECT_TRUE(a.x == b.x && a.v == b.v && a.szz == b.szz) << threads << " threads, impact";
    EXPECT_EQ(a.ke, b.ke);
    EXPECT_EQ(a.internal, b.internal);
    EXPECT_EQ(a.balance, b.balance);
    EXPECT_GT(a.internal, 0.0) << "the bars were loaded";
    fe::CavityPressureLoad la(plug, table), lb(plug, table);
    const State c = run(plug, 1, &la, 150), d = run(plug, threads, &lb, 150);
    EXPECT_TRUE(c.x == d.x && c.v == d.v && c.szz == d.szz) << threads << " threads, cavity";
    EXPECT_EQ(c.balance, d.balance);
    EXPECT_GT(c.internal, 0.0) << "the plug was loaded";
  }
}

// The pool's threads wait passively: a solver with 4 threads, idle between
// steps for 0.3 s (as it is while fe_server waits for the host), uses
// almost no CPU: 0.0–0.1 ms measured. A spinning pool burns its cores
// (0.6 s measured with the wait turned into a loop, on 2 cores); the bound,
// 30 ms, leaves room for a loaded machine's scheduling.
TEST(Threads, IdleWorkersDoNotSpin) {
  fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.15, 0.01, 0.0025, 8.0, fe_test::kE), "impact.k");
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  s.set_threads(4);
  s.step();  // the workers have run once
  auto cpu = [] {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  };
  const double before = cpu();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double used = cpu() - before;
  EXPECT_LT(used, 0.03);
  std::printf("idle pool: %.1f ms of CPU in 300 ms\n", 1e3 * used);
}

// The element stream's rows carry the time of the state their stresses come
// from: a bar stretched by a heavy end moving at a constant v has
// σ(t) = E·v·t/L, so each row must hold σ(time_elements) (a row labelled
// one step late is off by E·v·Δt/L, 1/100 of the stress after 100 steps).
TEST(History, ElementRowsCarryTheTimeOfTheirStresses) {
  const double E = 2.1e11, L = 0.1, v = 0.01, dt = 1e-7;
  std::ostringstream d;
  d << "*KEYWORD\n*NODE\n1,0,0,0,7\n2,0,0," << L << "\n*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n*MAT_ELASTIC\n1,7850,"
    << E << ",0.3\n*ELEMENT_BEAM\n1,1,1,2\n*ELEMENT_MASS\n1,2,1e9\n*INITIAL_VELOCITY_NODE\n2,0,0," << v
    << "\n*DATABASE_HISTORY_BEAM\n1\n*DATABASE_ELOUT\n1e-12\n*END\n";
  fe::Model m = fe::parse_deck(d.str(), "stretch.k");
  const std::string file = ::testing::TempDir() + "/stretch.h5";
  {
    fe::Solver s(m, dt);
    fe::History h(file, m, nullptr, dt, 1.0);
    for (int k = 0; k < 300; ++k) {
      s.step();
      h.record(s, {}, {});
    }
  }
  const auto t = h5io::read_series(file, "time_elements"), sigma = h5io::read_series(file, "bars/1/axial_stress");
  ASSERT_EQ(t.size(), 300u);
  EXPECT_EQ(t[0], 0.0) << "the first step's stresses are those of x_0";
  for (size_t r = 100; r < t.size(); r += 50)
    EXPECT_NEAR(sigma[r], E * v * t[r] / L, 1e-6 * E * v * t[r] / L) << "row " << r;  // the 1e9 kg end slows by 1e-9
  std::remove(file.c_str());
}
