// Fatigue counted during the FE run (*PCS_FATIGUE_PART, issue 35): a free-free
// bar ringing in its first axial mode loads each element with a known
// sinusoid, σ_a(y) = ρ·c·V·sin(πy/L); the damage each element counts
// equals the closed form from that amplitude and the number of periods.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "axi_decks.hpp"
#include "h5io/timeseries.hpp"
#include "input/deck_reader.hpp"
#include "output/fatigue.hpp"
#include "output/history.hpp"
#include "solver/solver.hpp"

namespace {

constexpr double kL = 0.2, kR = 0.01, kV = 1.0;
constexpr int kNr = 2, kNy = 40;

// The bar with ν = 0 (no radial inertia: the 1D wave), every node moving
// at V·cos(πy/L): the first free-free mode at its zero of displacement.
// Without the linear bulk viscosity (Q2 = 0): its 0.06 damps this mode by
// about 0.24 % of critical (Q2·πh/2L), 14 % of the amplitude in 10 periods,
// which the closed form does not have.
std::string ringing_bar(const std::string& fatigue_cards, double snapshot_dt = 0.0) {
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n" << axi_test::block(1, 1, 0.0, kR, kNr, 0.0, kL, kNy)
    << "*PART\nbar\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*CONTROL_BULK_VISCOSITY\n1.5,0\n"
    << "*INITIAL_VELOCITY_NODE\n";
  for (int j = 0; j <= kNy; ++j)
    for (int i = 0; i <= kNr; ++i) d << 1 + j * (kNr + 1) + i << ",0," << kV * std::cos(M_PI * j / kNy) << ",0\n";
  if (snapshot_dt > 0.0) d << "*DATABASE_BINARY_D3PLOT\n" << snapshot_dt << "\n";
  d << fatigue_cards;
  return d.str();
}

}  // namespace

TEST(FatigueFe, EachElementOfARingingBarCountsTheDamageOfItsSinusoid) {
  // S-N: 40 MPa at 1e6 cycles, m = 5, no endurance limit, no mean correction.
  fe::Model m = fe::parse_deck(ringing_bar("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n0,1,0\n"), "ring.k");
  ASSERT_EQ(m.fatigue.size(), 1u);
  const double c = std::sqrt(2.1e11 / 7850.0), period = 2.0 * kL / c, k = 10.0;
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  fe::FatigueTracker t(m, dt);
  ASSERT_FALSE(t.empty());
  while (s.time() < k * period) {
    s.step();
    t.sample(s);
  }
  const std::vector<double> damage = t.damage_field();
  ASSERT_EQ(damage.size(), m.axis.size());
  // Closed form: from 0, the stress goes to ∓A and swings k times: 2k − 1
  // half cycles of range 2A, and the first and last quarter swings, half
  // cycles of range A (amplitude A/2): D = (k − ½)/N(A) + 1/N(A/2).
  // Tolerance 3 %: the element's constant strain averages the mode over its
  // length (−0.03 %), the FE mode's frequency and amplitude (< 0.2 %),
  // sampled every FE step (~90 a period: −0.06 % at a peak); damage goes
  // with the amplitude to the 5th power.
  const fatigue::SnCurve sn{40e6, 1e6, 5.0, 0.0, false};
  const double h = kL / kNy, shape = std::sin(M_PI * h / (2.0 * kL)) / (M_PI * h / (2.0 * kL));
  int checked = 0;
  for (size_t e = 0; e < m.axis.size(); ++e) {
    double yc = 0.0;
    for (int n = 0; n < 4; ++n) yc += m.x0[static_cast<size_t>(m.axis[e].n[n])].y() / 4.0;
    const double a = 7850.0 * c * kV * std::sin(M_PI * yc / kL) * shape;
    if (a < 0.5 * 7850.0 * c * kV) continue;  // the middle of the bar: the ends' small stresses say little
    const double want = (k - 0.5) / sn.cycles_to_failure(a) + 1.0 / sn.cycles_to_failure(0.5 * a);
    EXPECT_NEAR(damage[e], want, 0.03 * want) << "element " << m.axis[e].id << " at y = " << yc;
    ++checked;
  }
  EXPECT_GT(checked, 20);
  EXPECT_NE(t.report(s.time()).find("part 1 element"), std::string::npos) << t.report(s.time());
}

// A notch factor raises the stress before counting: KF 1.2 is 1.2^m the
// damage. The sampling interval DT: one FE step is every step (the same
// bits); two steps sample the bar's 90-steps period 45 times, which moves a
// peak by at most 1 - cos(π/45) = 0.24 %, the damage by 5 times that.
TEST(FatigueFe, ANotchFactorRaisesTheDamageByItsPowerOfTheSlopeAndDtSetsTheSampling) {
  const double fe_dt = 0.9 * fe::Solver::stable_dt(fe::parse_deck(ringing_bar(""), "dt.k")).dt;
  auto run = [](const std::string& card2) {
    fe::Model m = fe::parse_deck(ringing_bar("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n" + card2), "notch.k");
    const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
    fe::Solver s(m, dt);
    fe::FatigueTracker t(m, dt);
    while (s.time() < 2e-4) {
      s.step();
      t.sample(s);
    }
    return t.damage_field()[static_cast<size_t>(kNr * kNy / 2)];
  };
  const double plain = run("0,1,0\n"), notched = run("0,1.2,0\n");
  ASSERT_GT(plain, 0.0);
  EXPECT_NEAR(notched / plain, std::pow(1.2, 5.0), 1e-9 * std::pow(1.2, 5.0));
  std::ostringstream one, two;
  one.precision(17), two.precision(17);
  one << "0,1,0," << fe_dt << "\n";
  two << "0,1,0," << 2.0 * fe_dt << "\n";
  EXPECT_EQ(run(one.str()), plain) << "DT of one FE step samples every step";
  const double sparse = run(two.str());
  EXPECT_NE(sparse, plain);
  EXPECT_NEAR(sparse, plain, 0.02 * plain);
}

// Through the history as fe_server runs it: the field snapshots carry the
// damage (ParaView shows where it would crack), and a checkpoint taken
// mid-run and restored gives the uninterrupted run's damage, bit for bit.
TEST(FatigueFe, TheSnapshotsCarryTheDamageAndACheckpointKeepsTheCounting) {
  fe::Model m = fe::parse_deck(ringing_bar("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n0,1,0\n", 1e-4), "snap.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  const std::string file = ::testing::TempDir() + "/fatigue_fe.h5";
  fe::Solver s(m, dt);
  {
    fe::History h(file, m, nullptr, dt, 1e-5);
    while (s.time() < 3e-4) {
      s.step();
      h.record(s, {}, {});
    }
    EXPECT_NE(h.fatigue_report(s.time()).find("crack initiation after"), std::string::npos);
    h.write_fatigue_table(::testing::TempDir() + "/fatigue_fe.csv", s.time());
  }
  const std::string fields = ::testing::TempDir() + "/fatigue_fe_fields.xdmf";
  std::ifstream x(fields);
  std::stringstream xs;
  xs << x.rdbuf();
  EXPECT_NE(xs.str().find("fatigue_damage"), std::string::npos) << "the XDMF index names the damage field";
  std::ifstream csv(::testing::TempDir() + "/fatigue_fe.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "element,part,x,y,z,cycles,largest_range,damage,time_to_initiation_s");

  // The counters' state through a checkpoint: a tracker restored half-way
  // and run on equals one that ran through.
  fe::Model m2 = fe::parse_deck(ringing_bar("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n0,1,0\n"), "ck.k");
  fe::Solver a(m2, dt), b(m2, dt);
  fe::FatigueTracker ta(m2, dt), tb(m2, dt);
  const std::string ck = ::testing::TempDir() + "/fatigue_fe.ck";
  while (a.time() < 1.5e-4) {
    a.step(), b.step();
    ta.sample(a), tb.sample(b);
  }
  {
    config::StateWriter w;
    tb.state(w);
    w.write(ck);
  }
  fe::FatigueTracker tc(m2, dt);
  {
    config::StateReader r(ck);
    tc.state(r);
    r.finish();
  }
  while (a.time() < 3e-4) {
    a.step();
    ta.sample(a), tc.sample(a);
  }
  EXPECT_EQ(ta.damage_field(), tc.damage_field());
  std::remove(ck.c_str());
  std::remove(file.c_str());
}

// The card's mistakes, each at its line.
TEST(FatigueFe, TheCardsMistakesAreRefusedAtTheirLine) {
  auto refused = [](const std::string& cards, const std::string& want) {
    try {
      fe::parse_deck(ringing_bar(cards), "bad.k");
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << cards;
  };
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n", "two cards per part");
  refused("*PCS_FATIGUE_PART\n9,40e6,1e6,5,0,0,0,0\n0,1,0\n", "PID 9 is not a *PART");
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,-5,0,0,0,0\n0,1,0\n", "the slope m must be positive");
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,1\n0,1,0\n", "needs SU");
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,2,0\n0,1,0\n", "STRESS 2");
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,0\n0,0.5,0\n", "KF must be 1 or more");
  // The hard cases that would end with exit 0 and no or all damage: a curve
  // in MPa in this Pa deck, and a part with no element the tracker counts.
  refused("*PCS_FATIGUE_PART\n1,40,1e6,5,0,0,0,0\n0,1,0\n", "SA_REF 40 is 1.9e-10 of the part's E");
  refused("*PCS_FATIGUE_PART\n1,40e6,1e6,5,0,0,0,1\n1200,1,0\n", "SU 1200 is");
  refused("*PART\nbar\n2,2,1\n*SECTION_BEAM\n2,3\n1e-4\n*NODE\n900001,0,1,0\n900002,0,1.1,0\n"
          "*ELEMENT_BEAM\n900001,2,900001,900002\n*PCS_FATIGUE_PART\n2,40e6,1e6,5,0,0,0,0\n0,1,0\n",
          "part 2 has no axisymmetric elements");
}

// The principal stress of largest magnitude in closed form, against Eigen's
// eigen-solver on random tensors (3D), and the in-plane pair with the hoop
// stress (axisymmetric); round-off is the tolerance.
TEST(FatigueFe, TheLargestPrincipalStressIsTheEigenvalueOfLargestMagnitude) {
  std::srand(7);
  auto rnd = [] { return 2.0 * std::rand() / RAND_MAX - 1.0; };
  for (int k = 0; k < 1000; ++k) {
    Eigen::Matrix<double, 6, 1> s;
    for (int c = 0; c < 6; ++c) s(c) = 1e8 * rnd();
    Eigen::Matrix3d t;
    t << s(0), s(3), s(5), s(3), s(1), s(4), s(5), s(4), s(2);
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(t).eigenvalues();
    double want = ev(0);
    for (int i = 1; i < 3; ++i)
      if (std::fabs(ev(i)) > std::fabs(want)) want = ev(i);
    ASSERT_NEAR(fe::largest_principal(s, false), want, 1e-6 * 1e8) << k;
    Eigen::Matrix<double, 6, 1> a = s;
    a(4) = a(5) = 0.0;  // axisymmetric: rr, yy, θθ, ry
    Eigen::Matrix2d p;
    p << a(0), a(3), a(3), a(1);
    const Eigen::Vector2d e2 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(p).eigenvalues();
    double want_axi = a(2);
    for (int i = 0; i < 2; ++i)
      if (std::fabs(e2(i)) > std::fabs(want_axi)) want_axi = e2(i);
    ASSERT_NEAR(fe::largest_principal(a, true), want_axi, 1e-6 * 1e8) << k;
  }
  Eigen::Matrix<double, 6, 1> uniaxial = Eigen::Matrix<double, 6, 1>::Zero();
  uniaxial(1) = -3e8;
  EXPECT_DOUBLE_EQ(fe::signed_von_mises(uniaxial), -3e8) << "a compressive pulse counts as compression";
}
