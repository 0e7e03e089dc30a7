// Stiffness-proportional (Rayleigh) damping, *DAMPING_PART_STIFFNESS with
// COEF = −β: the damping force is β·K·v, so every mode of angular frequency
// ω decays at ζ = β·ω/2 of critical, and its energy as exp(−β·ω²·t). The
// closed form is checked on a free bar's first axial mode with each element
// kind that applies it (axisymmetric quad, hexahedron, tetrahedron); the
// stable step it lowers on a heavily damped bar; the reader's refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "block_decks.hpp"
#include "deck_errors.hpp"
#include "elements/element_blocks.hpp"
#include "input/deck_reader.hpp"
#include "solver/mass_scaling.hpp"
#include "solver/solver.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kE = 2.1e11, kRho = 7850.0;

// A solid steel rod along y, radius R, length L, as ny axisymmetric quads
// (one radial cell), moving in its first free-free axial mode
// v_y = v0·cos(π·y/L) (the nodes' values, which is the lumped chain's mode
// shape but for the Poisson coupling to the radius).
std::string axi_rod(int ny, double L, double R, double v0, const std::string& extra) {
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*PART\nrod\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1," << kRho << "," << kE << ",0.3\n*NODE\n";
  for (int j = 0; j <= ny; ++j) d << 2 * j + 1 << ",0," << L * j / ny << ",0\n" << 2 * j + 2 << "," << R << "," << L * j / ny << ",0\n";
  d << "*ELEMENT_SHELL\n";
  for (int j = 0; j < ny; ++j) d << j + 1 << ",1," << 2 * j + 1 << "," << 2 * j + 2 << "," << 2 * j + 4 << "," << 2 * j + 3 << "\n";
  d << "*INITIAL_VELOCITY_NODE\n";
  for (int j = 0; j <= ny; ++j)
    for (int k : {1, 2}) d << 2 * j + k << ",0," << v0 * std::cos(kPi * j / ny) << ",0\n";
  return d.str() + extra;
}

// The same rod as a column of 1×1×nz cubes (hexahedra or six tetrahedra
// each) of side h along z.
std::string solid_rod(int nz, double h, bool tets, double v0, const std::string& extra) {
  std::ostringstream d;
  d.precision(17);
  d << fe_test::block_deck(1, 1, nz, h, tets, kE, 0.3).deck << "*INITIAL_VELOCITY_NODE\n";
  for (int k = 0; k <= nz; ++k)
    for (int c = 1; c <= 4; ++c) d << 4 * k + c << ",0,0," << v0 * std::cos(kPi * k / nz) << "\n";
  return d.str() + extra;
}

struct Decay {
  double omega = 0.0;  // measured from the end's velocity, rad/s
  double rate = 0.0;   // −d ln(E)/dt of the mechanical energy, 1/s
  double balance = 0.0, energy0 = 0.0;
};

// Runs `periods` first-mode periods (of the angular frequency omega_guess);
// the end node is `end`, its axial velocity component `axis`. The energy's
// slope is fitted from the second period on (the higher modes the initial
// shape excites a little decay many times faster), over whole half periods
// (the energy of a damped mode ripples at 2ω).
Decay run_decay(const std::string& deck, size_t end, int axis, double omega_guess, int periods) {
  fe::Model m = fe::parse_deck(deck, "rod.k");
  const double dt = m.dt_scale * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  std::vector<double> t, lnE, crossings;
  double v_last = 0.0;
  const double t_end = periods * 2.0 * kPi / omega_guess;
  Decay d;
  while (s.time() < t_end) {
    s.step();
    const double E = s.energies().kinetic + s.energies().internal;
    if (d.energy0 == 0.0) d.energy0 = E;
    t.push_back(s.time()), lnE.push_back(std::log(E));
    const double v = s.v()[end][axis];
    if (t.size() > 1 && (v > 0.0) != (v_last > 0.0)) crossings.push_back(s.time() - dt * v / (v - v_last));
    v_last = v;
  }
  // Half periods between the second crossing and the last but one.
  d.omega = kPi * static_cast<double>(crossings.size() - 3) / (crossings[crossings.size() - 2] - crossings[1]);
  const double half = kPi / d.omega, t0 = 2.0 * kPi / d.omega;
  const double t1 = t0 + half * std::floor((t.back() - t0) / half);
  double n = 0, st = 0, sy = 0, stt = 0, sty = 0;
  for (size_t k = 0; k < t.size(); ++k)
    if (t[k] >= t0 && t[k] < t1) n += 1, st += t[k], sy += lnE[k], stt += t[k] * t[k], sty += t[k] * lnE[k];
  d.rate = -(n * sty - st * sy) / (n * stt - st * st);
  d.balance = s.energies().balance_error;
  return d;
}

}  // namespace

// ζ = 1 % at the rod's first mode (β from its measured undamped ω), run
// for 12 periods. Tolerance 0.5 % on the decay rate: central differences
// shift a mode's decay by O((ω·Δt)²) (ω·Δt ≈ 0.04 here: 0.2 %), and the
// fit over whole half periods leaves O(ζ/periods) of the ripple; measured
// 0.06–0.08 % for the three kinds.
TEST(StiffnessDamping, AFreeRodsFirstModeDecaysAtBetaOmegaOverTwo) {
  const double omega = kPi * std::sqrt(kE / kRho) / 0.5;  // the slender rod's, to size the run
  auto card = [](double b) {
    std::ostringstream c;
    c.precision(17);
    c << "*DAMPING_PART_STIFFNESS\n$ pid, coef\n1," << -b << "\n";
    return c.str();
  };
  struct Kind {
    const char* name;
    std::string (*deck)(const std::string& card);
    size_t end;  // the node at the far end, and its axial direction
    int axis;
  };
  const Kind kinds[] = {
      {"axisymmetric", [](const std::string& c) { return axi_rod(50, 0.5, 0.01, 1.0, c); }, 2 * 50, 1},
      {"hexahedra", [](const std::string& c) { return solid_rod(50, 0.01, false, 1.0, c); }, 4 * 50, 2},
      {"tetrahedra", [](const std::string& c) { return solid_rod(50, 0.01, true, 1.0, c); }, 4 * 50, 2},
  };
  for (const Kind& k : kinds) {
    const Decay undamped = run_decay(k.deck(""), k.end, k.axis, omega, 12);
    const double b = 2.0 * 0.01 / undamped.omega;
    const Decay d = run_decay(k.deck(card(b)), k.end, k.axis, omega, 12);
    const double want = b * d.omega * d.omega;
    // The undamped rod loses 1.2–1.8 % of that rate to the bulk viscosity's
    // linear term (Q2 on its compressions), which acts on the damped rod too.
    EXPECT_NEAR(d.rate - undamped.rate, want, 0.005 * want) << k.name << ": measured " << d.rate << " 1/s, β·ω² " << want;
    EXPECT_LT(std::fabs(undamped.rate), 0.03 * want) << k.name << ": the undamped rod nearly keeps its energy";
    EXPECT_NEAR(d.omega, undamped.omega, 1e-3 * undamped.omega) << k.name << ": ζ = 1 % moves ω by ζ²/2";
    // The damping's work is booked (Energies::damping): the account closes
    // to central differences' O(ζ·ω·Δt) of the energy.
    EXPECT_LT(std::fabs(d.balance), 0.005 * d.energy0) << k.name << ": balance " << d.balance << " J of " << d.energy0;
  }
}

// Heavy damping (β·ω_max/2 ≈ 1 at the elements' highest mode) lowers the
// stable step to (2/ω)·(√(1 + ζ²) − ζ): the rod then runs at the step the
// solver takes and loses energy; at the undamped step it would grow
// without bound.
TEST(StiffnessDamping, HeavyDampingLowersTheStableStepAndTheRunStaysBounded) {
  const std::string plain = axi_rod(20, 0.2, 0.01, 1.0, "");
  const fe::Model m0 = fe::parse_deck(plain, "rod.k");
  const double dt0 = fe::Solver::stable_dt(m0).dt;
  const double omega_max = 2.0 * (std::sqrt(1.0 + m0.bulk_q2 * m0.bulk_q2) - m0.bulk_q2) / dt0;
  const double beta = 2.0 / omega_max;  // ζ = 1 at the element's highest mode
  std::ostringstream c;
  c.precision(17);
  c << "*DAMPING_PART_STIFFNESS\n1," << -beta << "\n";
  fe::Model m = fe::parse_deck(axi_rod(20, 0.2, 0.01, 1.0, c.str()), "rod.k");
  const double dt = fe::Solver::stable_dt(m).dt;
  EXPECT_NEAR(dt, fe::damped_stable_step(omega_max, m.bulk_q2, beta), 1e-9 * dt);
  EXPECT_LT(dt, 0.5 * dt0) << "ζ ≈ 1.06 (with Q2) allows 0.39/0.94 of the undamped step";
  fe::Solver s(m, m.dt_scale * dt);
  double E0 = 0.0;
  for (int k = 0; k < 5000; ++k) {
    s.step();
    const double E = s.energies().kinetic + s.energies().internal;
    if (k == 0) E0 = E;
    ASSERT_TRUE(std::isfinite(E) && E <= E0 * (1.0 + 1e-9)) << "step " << k << ": " << E << " J of " << E0;
  }
}

// Selective mass scaling of a damped part adds the mass that gives the
// step asked for, no more: the heavier element's highest mode is damped
// less (ζ = Q2 + β·ω/2 falls with ω), which the square of the steps' ratio
// does not know (it added 2.7 % to the rig's housing where 1.3 % suffice).
TEST(StiffnessDamping, MassScalingOfADampedPartReachesTheStepExactly) {
  for (const double beta : {0.0, 1e-7, 1e-6}) {
    std::ostringstream c;
    c.precision(17);
    c << "*DAMPING_PART_STIFFNESS\n1," << -beta << "\n";
    fe::Model m = fe::parse_deck(axi_rod(20, 0.2, 0.01, 1.0, c.str()), "rod.k");
    const double target = 3.0 * m.dt_scale * fe::Solver::stable_dt(m).dt;
    const fe::MassScalingReport r = fe::apply_mass_scaling(m, target);
    EXPECT_EQ(r.elements_scaled, 20) << "β " << beta;
    EXPECT_NEAR(m.dt_scale * fe::Solver::stable_dt(m).dt, target, 1e-9 * target) << "β " << beta;
  }
}

TEST(StiffnessDamping, TheReaderTakesBetaAndRefusesWhatItWouldGetWrong) {
  const std::string rod = axi_rod(4, 0.04, 0.01, 0.0, "");
  {
    const fe::Model m = fe::parse_deck(rod + "*DAMPING_PART_STIFFNESS\n1,-2.5e-7\n", "d.k");
    EXPECT_DOUBLE_EQ(m.parts.at(1).stiffness_damping, 2.5e-7);
  }
  {
    const fe::Model m = fe::parse_deck(rod + "*SET_PART_LIST\n3\n1\n*DAMPING_PART_STIFFNESS_SET\n3,-1e-7\n", "d.k");
    EXPECT_DOUBLE_EQ(m.parts.at(1).stiffness_damping, 1e-7);
  }
  const int line = 1 + static_cast<int>(std::count(rod.begin(), rod.end(), '\n')) + 1;  // the card's
  const std::string at = "d.k:" + std::to_string(line) + ": ";
  const std::string pos = fe_test::deck_error(rod + "*DAMPING_PART_STIFFNESS\n1,0.1\n", "d.k");
  EXPECT_NE(pos.find(at + "COEF 0.1 > 0 asks for LS-DYNA's proprietary"), std::string::npos) << pos;
  EXPECT_NE(pos.find("COEF = -beta"), std::string::npos) << pos;
  EXPECT_NE(fe_test::deck_error(rod + "*DAMPING_PART_STIFFNESS\n2,-1e-7\n", "d.k").find(at + "PID 2 is not a *PART"),
            std::string::npos);
  EXPECT_NE(fe_test::deck_error(rod + "*DAMPING_PART_STIFFNESS_SET\n9,-1e-7\n", "d.k").find(at + "part set 9 is not defined"),
            std::string::npos);
  std::string rigid = rod;
  rigid.replace(rigid.find("*MAT_ELASTIC"), 12, "*MAT_RIGID");
  EXPECT_NE(fe_test::deck_error(rigid + "*DAMPING_PART_STIFFNESS\n1,-1e-7\n", "d.k").find("part 1 is rigid"),
            std::string::npos);
  const std::string bar =
      "*KEYWORD\n*NODE\n1,0,0,0\n2,0,0,1.0\n*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n*MAT_ELASTIC\n1,7850,2.1e11,0\n"
      "*ELEMENT_BEAM\n1,1,1,2\n*DAMPING_PART_STIFFNESS\n1,-1e-7\n";
  EXPECT_NE(fe_test::deck_error(bar, "d.k").find("part 1 holds bar elements"), std::string::npos);
  EXPECT_NE(fe_test::deck_error(rod + "*DAMPING_PART_STIFFNESS\n1,-1e-7\n1,-2e-7\n", "d.k").find("given stiffness damping twice"),
            std::string::npos);
  const std::string spring = rod + "*PART\nspring\n2,2,2\n*SECTION_DISCRETE\n2,0\n*MAT_SPRING_ELASTIC\n2,1e6\n"
                                   "*ELEMENT_DISCRETE\n90,2,1,3\n*DAMPING_PART_STIFFNESS\n2,-1e-7\n";
  const std::string none = fe_test::deck_error(spring, "d.k");
  EXPECT_NE(none.find("part 2 has no solid or axisymmetric elements"), std::string::npos) << none;
  // The same spring part given mass damping: an error at its line, where the
  // reader looked its material up among the solids' and threw map::at.
  const std::string mass = fe_test::deck_error(rod + "*PART\nspring\n2,2,2\n*SECTION_DISCRETE\n2,0\n*MAT_SPRING_ELASTIC\n2,1e6\n"
                                               "*ELEMENT_DISCRETE\n90,2,1,3\n*DEFINE_CURVE\n5\n0,1\n1,1\n*DAMPING_PART_MASS\n2,5\n", "d.k");
  EXPECT_NE(mass.find("part 2 is a spring or damper part"), std::string::npos) << mass;
  const std::string range = fe_test::deck_error(rod + "*DAMPING_FREQUENCY_RANGE\n0.01,100,3000,0\n", "d.k");
  EXPECT_NE(range.find("frequency-independent damping is LS-DYNA's own formulation"), std::string::npos) << range;
}
