// tlm_host component library against physics references (DESIGN.md):
// line delay and Joukowsky, relief characteristic, accumulator law,
// spool-valve node balance, energy account, cavitation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "components/hydraulic/HydraulicTurbulentOrificeQ.hpp"
#include "components/hydraulic/HydraulicVolumeC.hpp"
#include "components/hydraulic/SpoolValveQ.hpp"
#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"

namespace {

// Run a model text, return the results file.
std::string run(const testing_support::TempDir& dir, const std::string& text) {
  std::ofstream(dir.file("m.tlm")) << text;
  tlm::System sys(tlm::read_model(dir.file("m.tlm")));
  sys.run(dir.file("r.h5"), false);
  return dir.file("r.h5");
}

std::vector<double> series(const std::string& file, const std::string& name) { return h5io::read_series(file, name); }

size_t first_change(const std::vector<double>& p, double p0) {
  for (size_t i = 0; i < p.size(); ++i)
    if (std::fabs(p[i] - p0) > 1e-6 * std::fabs(p0) + 1e-9) return i;
  return p.size();
}

}  // namespace

class LineDelay : public ::testing::TestWithParam<int> {};

TEST_P(LineDelay, APressureStepArrivesAfterExactlyNSteps) {
  const int n = GetParam();
  // a = sqrt(β/ρ) = 1000 m/s; L = n·a·Δt gives a delay of exactly n steps.
  const double dt = 1e-5, a = 1000.0;
  testing_support::TempDir dir;
  std::string f = run(dir, "*SIMULATION\ntimestep, 1e-5\nstoptime, " + std::to_string((n + 5) * dt) +
                               "\n*COMPONENT\n"
                               "src, PressureSourceC, p=2e6\n"
                               "in, HydraulicTurbulentOrificeQ, A=1e-4\n"
                               "line, LosslessLineC, L=" + std::to_string(n * a * dt) + ", d=0.01, rho=1000, beta=1e9, p0=1e5\n"
                               "out, HydraulicTurbulentOrificeQ, A=1e-4\n"
                               "vol, HydraulicVolumeC, V=1e-3, p0=1e5, ports=1\n"
                               "*CONNECT\nsrc.P1, in.P1\nin.P2, line.P1\nline.P2, out.P1\nout.P2, vol.P1\n");
  const size_t at_inlet = first_change(series(f, "nodes/line.P1/p"), 1e5);
  const size_t at_outlet = first_change(series(f, "nodes/line.P2/p"), 1e5);
  EXPECT_EQ(at_outlet - at_inlet, static_cast<size_t>(n)) << "a " << n << "-step line";
}

INSTANTIATE_TEST_SUITE_P(Steps, LineDelay, ::testing::Values(1, 2, 3, 7));

TEST(LosslessLine, SuddenClosureRaisesThePressureByJoukowsky) {
  // Reservoir → line (ρ = 870, β = 1.4e9, d = 20 mm, 2 m) → valve that shuts
  // at t = 5 ms. The valve-side pressure must jump by ρ·a·Δv.
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 5.5e-3
*COMPONENT
close, SignalStep, y0=1, y1=0, t_step=5e-3
src, PressureSourceC, p=5e6
in, HydraulicTurbulentOrificeQ, Cd=0.8, A=3e-4
line, LosslessLineC, L=2, d=0.02, rho=870, beta=1.4e9, p0=5e6
valve, VariableOrificeQ, Cd=0.7, area=0:0; 1:2e-5
tank, PressureSourceC, p=1e5
*CONNECT
src.P1, in.P1
in.P2, line.P1
line.P2, valve.P1
valve.P2, tank.P1
close.y, valve.x
)");
  const auto t = series(f, "time");
  const auto p = series(f, "nodes/line.P2/p");
  const auto q = series(f, "components/valve/q");
  size_t k = 0;
  while (t[k] < 5e-3 - 1e-9) ++k;  // the row the closed valve first acts in
  const double q0 = q[k - 1];
  const double rho = 870, a = std::sqrt(1.4e9 / rho), area = M_PI * 0.02 * 0.02 / 4.0;
  const double joukowsky = rho * a * (q0 / area);
  ASSERT_GT(q0, 1e-4) << "the valve must have carried a steady flow";
  EXPECT_NEAR(q[k], 0.0, 1e-12);
  // The reflected wave needs 2L/a = 2.8 ms to come back, so p[k] − p[k−1] is
  // the pure Joukowsky jump; 1 % as the issue states (the flow still changes
  // by ~1e-4 relative over the last step).
  EXPECT_NEAR(p[k] - p[k - 1], joukowsky, 0.01 * joukowsky);
}

TEST(ReliefValve, SettlesOnItsCrackingPressurePlusOverride) {
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 0.05
*COMPONENT
pump, FlowSourceQ, q=1e-3
vol, HydraulicVolumeC, V=2e-4, p0=1e5, ports=2
relief, ReliefValveQ, p_crack=1e7, K=5e-9, tau=1e-3
tank, PressureSourceC, p=1e5
*CONNECT
pump.P1, vol.P1
vol.P2, relief.P1
relief.P2, tank.P1
)");
  const auto p = series(f, "nodes/vol.P2/p");
  // Steady state: all the pump flow through the valve, q = K·(Δp − p_crack).
  const double expected = 1e5 + 1e7 + 1e-3 / 5e-9;
  EXPECT_NEAR(p.back(), expected, 1e-3 * expected);
}

TEST(GasAccumulator, FollowsThePolytropicLawAndConservesOil) {
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-5
stoptime, 0.2
*COMPONENT
pump, FlowSourceQ, q=1e-3
acc, GasAccumulatorC, V0=1e-3, p0=2e6, n=1.4, p_init=2e6
*CONNECT
pump.P1, acc.P1
)");
  const auto V = series(f, "components/acc/V_oil");
  const auto p = series(f, "nodes/acc.P1/p");
  const auto t = series(f, "time");
  // Oil in = pump flow × time, integrated exactly; the flow of a step
  // enters the oil volume at the start of the next, so one step is pending.
  EXPECT_NEAR(V.back(), 1e-3 * (t.back() - 1e-5), 1e-15);
  // Gas: p = p0·(V0/(V0 − V_oil))^n; the port pressure is taken half a
  // step ahead, so it leads by p'·q·Δt/2 ≈ 1e-4 relative.
  const double law = 2e6 * std::pow(1e-3 / (1e-3 - V.back()), 1.4);
  EXPECT_NEAR(p.back(), law, 1e-3 * law);
}

TEST(SpoolValve, EdgesOnOneNodeAreSolvedTogether) {
  testing_support::TempDir dir;
  // Half open to both edges at x = 4 mm (underlapped here on purpose).
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 2e-3
*COMPONENT
xv, SignalStep, y0=0.004, y1=0.004
P, PressureSourceC, p=1.5e7
A, HydraulicVolumeC, V=5e-5, p0=5e6, ports=1
T, PressureSourceC, p=4e5
valve, SpoolValveQ, Cd=0.7, area_PA=0:0; 0.008:2e-5, area_AT=0:2e-5; 0.008:0
*CONNECT
P.P1, valve.P
valve.A, A.P1
valve.T, T.P1
xv.y, valve.x
)");
  const auto qPA = series(f, "components/valve/q_PA"), qAT = series(f, "components/valve/q_AT");
  const auto pA = series(f, "nodes/A.P1/p");
  const double K = 0.7 * 1e-5 * std::sqrt(2.0 / 870.0);
  const size_t i = qPA.size() - 1;
  // Each edge obeys the orifice law at the solved p_A (source and tank have Zc = 0).
  EXPECT_NEAR(qPA[i], K * std::sqrt(1.5e7 - pA[i]), 1e-6 * qPA[i]);
  EXPECT_NEAR(qAT[i], K * std::sqrt(pA[i] - 4e5), 1e-6 * qAT[i]);
  // Equal edges in steady state: the flows balance and p_A sits midway.
  EXPECT_NEAR(qPA[i], qAT[i], 1e-3 * qPA[i]);
  EXPECT_NEAR(pA[i], 0.5 * (1.5e7 + 4e5), 1e-3 * 1.5e7);
}

// A position relative to the housing, and back: y = u1 − u2 and u1 + u2,
// evaluated in the model's order within the same step (the difference is
// declared before the sum that reads it), so the sum gives back u1 exactly.
TEST(SignalBlocks, SubtractAndAddInTheModelsOrder) {
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-4
stoptime, 2e-3
*COMPONENT
piston, SignalRamp, y0=0, y1=0.08, t0=0, t1=1e-3
housing, SignalStep, y0=0.002, y1=-0.003, t_step=5e-4
rel, SignalSubtract
back, SignalAdd
*CONNECT
piston.y, rel.u1
housing.y, rel.u2
rel.y, back.u1
housing.y, back.u2
)");
  const auto t = series(f, "time"), rel = series(f, "components/rel/y"), back = series(f, "components/back/y");
  ASSERT_EQ(t.size(), rel.size());
  for (size_t i = 0; i < t.size(); ++i) {
    const double ts = t[i];  // a signal at the end of its step
    const double piston = 0.08 * std::min(1.0, ts / 1e-3), housing = ts >= 5e-4 ? -0.003 : 0.002;
    EXPECT_NEAR(rel[i], piston - housing, 1e-15) << "t = " << ts;
    EXPECT_NEAR(back[i], piston, 1e-15) << "t = " << ts;
  }
}

TEST(EnergyAccount, StoredPlusDissipatedIsConservedInAClosedCircuit) {
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-6
stoptime, 0.05
*COMPONENT
a, HydraulicVolumeC, V=1e-4, beta=1e9, p0=2e7, ports=1
b, HydraulicVolumeC, V=3e-4, beta=1e9, p0=1e5, ports=1
o, HydraulicTurbulentOrificeQ, Cd=0.7, A=1e-6
*CONNECT
a.P1, o.P1
o.P2, b.P1
)");
  auto Ea = series(f, "components/a/E_stored"), Eb = series(f, "components/b/E_stored");
  auto loss = series(f, "components/o/E_loss");
  const double initial = Ea.front() + Eb.front();
  const double final_stored = Ea.back() + Eb.back();
  // Equalising 20 MPa with 0.1 MPa in three times the volume stores only
  // about a quarter of the energy again; the orifice must account for the
  // rest. The TLM volumes' wave energy is not exactly V·p²/2β within a
  // transient, hence 1 %.
  const double p_eq = (1e-4 * 2e7 + 3e-4 * 1e5) / 4e-4;
  const double expected_ratio = 4e-4 * p_eq * p_eq / (1e-4 * 2e7 * 2e7 + 3e-4 * 1e5 * 1e5);
  EXPECT_NEAR(final_stored / initial, expected_ratio, 0.01);
  EXPECT_NEAR(final_stored + loss.back(), initial, 0.01 * initial);
}

TEST(Cavitation, PressureNeverGoesBelowVapourAndEventsAreCounted) {
  testing_support::TempDir dir;
  std::ofstream(dir.file("m.tlm")) << R"(*SIMULATION
timestep, 1e-6
stoptime, 0.01
*COMPONENT
drain, FlowSourceQ, q=-1e-4
vol, HydraulicVolumeC, V=1e-4, p0=2e5, p_vap=5e3, ports=1
*CONNECT
drain.P1, vol.P1
)";
  tlm::System sys(tlm::read_model(dir.file("m.tlm")));
  sys.run(dir.file("r.h5"), false);
  auto p = series(dir.file("r.h5"), "components/vol/p_mean");
  for (double v : p) ASSERT_GE(v, 5e3 - 1e-6);
  auto* vol = dynamic_cast<tlm::HydraulicVolumeC*>(sys.find("vol"));
  ASSERT_NE(vol, nullptr);
  EXPECT_EQ(vol->cavitation_events(), 1);
}

TEST(Cavitation, AVolumePulledBelowVapourAndRefilledConservesItsOil) {
  // A closed 100 cm³ volume at 2 bar: 0.9 cm³ are drawn out (far more than
  // the 0.014 cm³ its compressibility gives down to p_vap) and then pushed
  // back, with equal ramps so the two volumes are equal to round-off.
  testing_support::TempDir dir;
  std::ofstream(dir.file("m.tlm")) << R"(*SIMULATION
timestep, 1e-5
stoptime, 0.025
*COMPONENT
stroke, SignalTable, table=0:0; 0.001:-1e-4; 0.009:-1e-4; 0.010:0; 0.011:1e-4; 0.019:1e-4; 0.020:0; 1:0
piston, FlowSourceQ
vol, HydraulicVolumeC, V=1e-4, beta=1.4e9, p0=2e5, p_vap=5e3, ports=1
*CONNECT
stroke.y, piston.q
piston.P1, vol.P1
)";
  tlm::System sys(tlm::read_model(dir.file("m.tlm")));
  sys.run(dir.file("r.h5"), false);
  const double V = 1e-4, beta = 1.4e9, p0 = 2e5, p_vap = 5e3;
  auto p = series(dir.file("r.h5"), "components/vol/p_mean");
  auto vv = series(dir.file("r.h5"), "components/vol/V_void");
  // Drawn volume: 1e-4 m³/s × (8 ms + 2 × ½ ms of ramp) = 9e-7 m³.
  const double drawn = 9e-7, expected_void = drawn - (p0 - p_vap) * V / beta;
  const double max_void = *std::max_element(vv.begin(), vv.end());
  // The ramps are sampled at the step: their sampled volume differs from the
  // exact one by at most q·Δt/2 per ramp end (4 × 5e-10 m³ = 0.2 % here).
  EXPECT_NEAR(max_void, expected_void, 0.003 * expected_void);
  for (double x : p) ASSERT_GE(x, p_vap - 1e-6);
  EXPECT_EQ(vv.back(), 0.0) << "the void is refilled";
  // Oil conserved to 1e-9 of the volume: the pressure returns to p0 within
  // 1e-9·β (a created oil volume ΔV would raise it by ΔV·β/V).
  EXPECT_NEAR(p.back(), p0, 1e-9 * beta) << "oil created: " << (p.back() - p0) * V / beta << " m³";
  auto* vol = dynamic_cast<tlm::HydraulicVolumeC*>(sys.find("vol"));
  ASSERT_NE(vol, nullptr);
  ASSERT_EQ(vol->events().size(), 1u);
  // The void lasts from the moment p_vap is reached until as much oil came
  // back as had been drawn beyond it: symmetric about t = 10 ms.
  const auto& e = vol->events().front();
  EXPECT_NEAR(e.start + 0.5 * e.duration, 0.010, 2e-5) << "start " << e.start << " s, " << e.duration << " s";
  EXPECT_NEAR(e.max_void, max_void, 1e-15);
}

TEST(LaminarLine, SteadyFlowLosesTheHagenPoiseuillePressure) {
  // 1 l/min of oil (ν = 32 mm²/s) through 3 m of Ø4 mm: laminar (Re ≈ 170).
  testing_support::TempDir dir;
  std::string f = run(dir, R"(*SIMULATION
timestep, 1e-5
stoptime, 0.5
*COMPONENT
pump, FlowSourceQ, q=1.6667e-5
line, LaminarLineC, L=3, d=0.004, rho=870, beta=1.4e9, nu=32e-6, p0=1e6
out, LaminarOrificeQ, Kc=1e-10
tank, PressureSourceC, p=1e6
*CONNECT
pump.P1, line.P1
line.P2, out.P1
out.P2, tank.P1
)");
  const auto p1 = series(f, "nodes/line.P1/p"), p2 = series(f, "nodes/line.P2/p");
  const double mu = 32e-6 * 870.0, R = 128.0 * mu * 3.0 / (M_PI * std::pow(0.004, 4));
  const double expected = R * 1.6667e-5;
  // After 0.5 s (≈ 60 wave round trips) the line is in steady flow; the
  // remaining transient decays with the outlet's laminar time constant.
  EXPECT_NEAR(p1.back() - p2.back(), expected, 1e-3 * expected);
}
