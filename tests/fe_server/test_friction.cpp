// Coulomb friction in the penalty contact (contact.hpp): a block sliding on
// a fixed plate under gravity comes to rest as the closed forms of a
// sliding mass say, for a constant μ, a speed-dependent one (DC) and the
// viscous limit VC·A; the kinetic energy it loses is the contact's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "config/keyword_reader.hpp"
#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

namespace {

// A 10 mm steel cube (nodes 11-18) resting on a fixed 40 × 40 × 5 mm plate
// (nodes 1-8), its bottom face at the plate's top (z = 0), moving at v0
// along x; gravity g along −z (100 g: the slide takes milliseconds); the
// contact's card 2 as given.
std::string sliding_block(double v0, double g, const std::string& card2) {
  std::ostringstream d;
  d << "*KEYWORD\n*NODE\n"
       "1,-0.02,-0.02,-0.005\n2,0.02,-0.02,-0.005\n3,0.02,0.02,-0.005\n4,-0.02,0.02,-0.005\n"
       "5,-0.02,-0.02,0\n6,0.02,-0.02,0\n7,0.02,0.02,0\n8,-0.02,0.02,0\n"
       "11,-0.005,-0.005,0\n12,0.005,-0.005,0\n13,0.005,0.005,0\n14,-0.005,0.005,0\n"
       "15,-0.005,-0.005,0.01\n16,0.005,-0.005,0.01\n17,0.005,0.005,0.01\n18,-0.005,0.005,0.01\n"
       "*PART\nplate\n1,1,1\n*PART\nblock\n2,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2e11,0.3\n"
       "*ELEMENT_SOLID\n1,1,1,2,3,4,5,6,7,8\n2,2,11,12,13,14,15,16,17,18\n"
       "*SET_NODE_LIST\n1\n1,2,3,4,5,6,7,8\n*BOUNDARY_SPC_SET\n1,0,1,1,1\n"
       "*SET_NODE_LIST\n2\n11,12,13,14,15,16,17,18\n*INITIAL_VELOCITY\n2\n"
    << v0 << ",0,0\n"
    << "*SET_SEGMENT\n1\n11,14,13,12\n*SET_SEGMENT\n2\n5,6,7,8\n"
       "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n1,2,0,0\n"
    << card2 << "\n*DEFINE_CURVE\n9\n0," << g << "\n1," << g << "\n*LOAD_BODY_Z\n9\n*END\n";
  return d.str();
}

struct Slide {
  double stop_time = -1.0, distance = 0.0, ke0 = 0.0, contact = 0.0, balance = 0.0, v_after = 0.0;
};

// Runs to t_end; the stop is the first step whose velocity is not positive.
Slide slide(const std::string& deck, double t_end) {
  const fe::Model m = fe::parse_deck(deck, "slide.k");
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  const size_t a = static_cast<size_t>(m.node_index.at(15));  // a top corner of the block
  Slide r;
  double x_start = m.x0[a].x();
  while (s.time() < t_end) {
    s.step();
    if (s.step_count() == 1) r.ke0 = s.energies().kinetic;
    const double v = s.v()[a].x();
    if (r.stop_time < 0.0 && v <= 0.0) r.stop_time = s.time();
  }
  r.distance = s.x()[a].x() - x_start;
  r.contact = s.energies().contact;
  r.balance = s.energies().balance_error;
  r.v_after = s.v()[a].x();
  return r;
}

}  // namespace

// Constant μ = 0.3: the block decelerates at μ·g, stops after v0/(μg) having
// slid v0²/(2μg), and stays (static friction holds it). 3 %: the contact
// settles from the block's first step onto the plate (the normal force
// rings about m·g, damped by VDC), and the stop is read at the first step
// whose velocity is not positive; the distance from the top corner (the
// block rocks by microns).
TEST(Friction, ABlockSlidesToRestAsMuGSays) {
  const double v0 = 1.0, g = 981.0, mu = 0.3;
  const Slide r = slide(sliding_block(v0, g, "0.3,0.3,0,0,20"), 1.5 * v0 / (mu * g));
  std::printf("mu 0.3: stopped at %.4g s (closed form %.4g), slid %.4g m (%.4g); contact took %.4g of %.4g J\n",
              r.stop_time, v0 / (mu * g), r.distance, v0 * v0 / (2 * mu * g), r.contact, r.ke0);
  EXPECT_NEAR(r.stop_time, v0 / (mu * g), 0.03 * v0 / (mu * g));
  EXPECT_NEAR(r.distance, v0 * v0 / (2 * mu * g), 0.03 * v0 * v0 / (2 * mu * g));
  EXPECT_LT(std::fabs(r.v_after), 0.01 * v0) << "it stays at rest";
  // The energy lost is the contact's (friction's work; gravity does none on
  // a horizontal slide), and the account closes.
  EXPECT_NEAR(r.contact, r.ke0, 0.05 * r.ke0);
  EXPECT_LT(std::fabs(r.balance), 0.01 * r.ke0);
}

// μ = FD + (FS − FD)·exp(−DC·v): FS 0.6, FD 0.2, DC 20 s/m. The stopping
// distance is ∫v dv/(μ(v)·g) from v0 to 0 (a sliding mass), here by
// Simpson's rule on 2000 intervals.
TEST(Friction, ASpeedDependentCoefficientFollowsItsDecay) {
  const double v0 = 1.0, g = 981.0, fs = 0.6, fd = 0.2, dc = 20.0;
  auto mu = [&](double v) { return fd + (fs - fd) * std::exp(-dc * v); };
  double distance = 0.0, time = 0.0;
  const int n = 2000;
  for (int k = 0; k <= n; ++k) {
    const double v = v0 * k / n, w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    distance += w * v / (mu(v) * g);
    time += w / (mu(v) * g);
  }
  distance *= v0 / n / 3.0;
  time *= v0 / n / 3.0;
  const Slide r = slide(sliding_block(v0, g, "0.6,0.2,20,0,20"), 1.5 * time);
  std::printf("DC: stopped at %.4g s (closed form %.4g), slid %.4g m (%.4g)\n", r.stop_time, time, r.distance, distance);
  EXPECT_NEAR(r.stop_time, time, 0.03 * time);
  EXPECT_NEAR(r.distance, distance, 0.03 * distance);
  // Against the constant FD and FS it must lie between.
  EXPECT_LT(r.distance, v0 * v0 / (2 * fd * g));
  EXPECT_GT(r.distance, v0 * v0 / (2 * fs * g));
}

// VC caps the friction force at VC·A per node, A the area of the segment
// it touches: here the plate's whole top face (one segment, 40 × 40 mm),
// so at VC = 50 Pa the four bottom nodes of the block slide against
// 4·VC·A = 0.32 N, below μ·m·g: the block stops after m·v0/(4·VC·A).
TEST(Friction, TheViscousLimitCapsTheForce) {
  const double v0 = 1.0, g = 981.0, m = 7850.0 * 1e-6, A = 0.04 * 0.04, vc = 50.0;
  const double force = 4.0 * vc * A;  // each of the block's four bottom nodes at its cap
  ASSERT_LT(force, 0.3 * m * g);
  const double t = v0 * m / force;
  const Slide r = slide(sliding_block(v0, g, "0.3,0.3,0," + std::to_string(vc) + ",20"), 1.5 * t);
  std::printf("VC: stopped at %.4g s (closed form %.4g)\n", r.stop_time, t);
  EXPECT_NEAR(r.stop_time, t, 0.03 * t);
}

TEST(Friction, NegativeCoefficientsAreRefusedAtTheirLine) {
  const std::string deck = sliding_block(1.0, 9.81, "-0.3");
  const std::string line = std::to_string(std::count(deck.begin(), deck.begin() + static_cast<long>(deck.find("-0.3")), '\n') + 1);
  try {
    fe::parse_deck(deck, "slide.k");
    FAIL() << "accepted";
  } catch (const config::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("slide.k:" + line + ": FS, FD, DC and VC must not be negative"), std::string::npos)
        << e.what();
  }
}
