// Rainflow counting, S-N curves, mean-stress corrections and Miner damage
// (issue 35), against ASTM E1049-85's worked example, hand counts and closed
// forms. Counts are multiples of 0.5 and ranges differences of the inputs:
// they are compared exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "fatigue/damage.hpp"
#include "fatigue/rainflow.hpp"

using fatigue::Cycle;

namespace {

// Total count per range.
std::map<double, double> by_range(const std::vector<Cycle>& cycles) {
  std::map<double, double> m;
  for (const auto& c : cycles) m[c.range] += c.count;
  return m;
}

std::vector<std::tuple<double, double, double>> sorted(const std::vector<Cycle>& cycles) {
  std::vector<std::tuple<double, double, double>> v;
  for (const auto& c : cycles) v.emplace_back(c.range, c.mean, c.count);
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

// ASTM E1049-85, 5.4.4 and its Fig. 6 / Table X: the history -2 1 -3 5 -1
// 3 -4 4 -2 gives ranges 9 (0.5), 8 (1.0), 6 (0.5), 4 (1.5), 3 (0.5).
TEST(Rainflow, TheAstmWorkedExampleGivesItsTable) {
  const auto cycles = fatigue::rainflow({-2, 1, -3, 5, -1, 3, -4, 4, -2});
  const std::map<double, double> want = {{3, 0.5}, {4, 1.5}, {6, 0.5}, {8, 1.0}, {9, 0.5}};
  EXPECT_EQ(by_range(cycles), want);
  // The full cycle of range 4 is the one from -1 to 3 (mean 1).
  bool full = false;
  for (const auto& c : cycles) full = full || (c.range == 4 && c.count == 1.0 && c.mean == 1.0);
  EXPECT_TRUE(full);
}

// Constant amplitude from a valley: every range of 200 counts, as halves,
// to one cycle per two reversals; the ends' ranges of 100 are half cycles
// about +50 and -50 (hand count).
TEST(Rainflow, ConstantAmplitudeCountsItsCyclesAndTheEndsAsHalves) {
  const auto cycles = fatigue::rainflow({0, 100, -100, 100, -100, 100, -100, 0});
  const auto m = by_range(cycles);
  EXPECT_EQ(m.at(200), 2.5);
  EXPECT_EQ(m.at(100), 1.0);
  int halves_of_100 = 0;
  for (const auto& c : cycles)
    if (c.range == 100) halves_of_100 += (c.count == 0.5 && (c.mean == 50 || c.mean == -50));
  EXPECT_EQ(halves_of_100, 2);
}

// An inner cycle on the way down (hand count): 0 10 4 6 0 gives the full
// cycle 4-6 (range 2, mean 5) and the outer range 10 as two halves.
TEST(Rainflow, AnInnerCycleIsCountedWholeAndTheOuterRangeAsHalves) {
  const auto cycles = fatigue::rainflow({0, 10, 4, 6, 0});
  ASSERT_EQ(cycles.size(), 3u);
  EXPECT_EQ(sorted(cycles), (std::vector<std::tuple<double, double, double>>{{2, 5, 1.0}, {10, 5, 0.5}, {10, 5, 0.5}}));
}

// Samples between turning points and a dip smaller than the gate: only the
// turning points count, and the gate removes the small cycle (hand count:
// 10 -> 9.5 -> 10.2 is a cycle of range 0.5 without the gate).
TEST(Rainflow, OnlyTurningPointsCountAndTheGateRemovesSmallReversals) {
  const std::vector<double> h = {0, 5, 10, 9.75, 9.5, 10.2, 5, 0};
  EXPECT_EQ(by_range(fatigue::rainflow(h)), (std::map<double, double>{{0.5, 1.0}, {10.2, 1.0}}));
  EXPECT_EQ(by_range(fatigue::rainflow(h, 1.0)), (std::map<double, double>{{10.2, 1.0}}));
}

// The streaming counter gives the cycles the four-point rule gives on the
// whole history at once, on long random histories, with and without a gate;
// and it holds a few reversals, not the history.
TEST(Rainflow, StreamingCountsEqualWholeHistoryCountsAndHoldFewReversals) {
  std::mt19937_64 rng(20261203);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (double gate : {0.0, 0.3}) {
    std::vector<double> h;
    double x = 0.0;
    for (int i = 0; i < 200000; ++i) {
      x = 0.98 * x + noise(rng);  // a bounded random process, with a blow-like sine on top
      h.push_back(x + 5.0 * std::sin(0.01 * i));
    }
    EXPECT_EQ(sorted(fatigue::rainflow(h, gate)), sorted(fatigue::rainflow_whole(h, gate))) << "gate " << gate;
    fatigue::RainflowCounter counter(gate);
    size_t most = 0;
    double cycles = 0;
    for (double v : h) {
      counter.add(v, [&](const Cycle& c) { cycles += c.count; });
      most = std::max(most, counter.held());
    }
    EXPECT_GT(cycles, 1000.0);
    EXPECT_LT(most, 64u) << "reversals held at once over 200000 samples";
  }
}

// Constant amplitude against the S-N curve: k cycles of amplitude Sa_ref do
// k / N_ref of damage; half the amplitude does 2^-m of it per cycle; below
// the endurance limit nothing, or with Haibach's slope 2m - 1 the closed form.
TEST(Damage, ConstantAmplitudeLoadingDoesCyclesOverNFromTheCurve) {
  const fatigue::SnCurve sn{300.0, 1e5, 5.0, 100.0, false};
  std::vector<double> h = {-300};
  for (int k = 0; k < 1000; ++k) h.insert(h.end(), {300, -300});
  fatigue::Damage d{sn};
  for (const auto& c : fatigue::rainflow(h)) d.add(c);
  EXPECT_DOUBLE_EQ(d.cycles, 1000.0);
  EXPECT_NEAR(d.damage, 1000.0 / 1e5, 1e-15);
  EXPECT_DOUBLE_EQ(sn.cycles_to_failure(150.0), 1e5 * 32.0);
  EXPECT_TRUE(std::isinf(sn.cycles_to_failure(80.0))) << "below the endurance limit";
  fatigue::SnCurve haibach = sn;
  haibach.haibach = true;
  const double n_knee = 1e5 * std::pow(3.0, 5.0);
  EXPECT_DOUBLE_EQ(haibach.cycles_to_failure(80.0), n_knee * std::pow(100.0 / 80.0, 9.0));
  EXPECT_DOUBLE_EQ(haibach.cycles_to_failure(200.0), sn.cycles_to_failure(200.0)) << "above the knee: Basquin";
  EXPECT_FALSE(sn.check().size()) << sn.check();
  const fatigue::SnCurve negative_slope{300.0, 1e5, -5.0, 0.0, false};
  EXPECT_NE(negative_slope.check(), "");
}

// The mean-stress corrections against their closed forms (Sa 100, Sm 200,
// Su 800): Goodman 100/(1 - 1/4), Gerber 100/(1 - 1/16), SWT sqrt(300 * 100);
// no credit for compression; a mean at Su fails at once.
TEST(Damage, MeanStressCorrectionsFollowTheirClosedForms) {
  using fatigue::MeanStress;
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, 200, MeanStress::Goodman, 800), 100.0 / 0.75);
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, 200, MeanStress::Gerber, 800), 100.0 / (1.0 - 1.0 / 16.0));
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, 200, MeanStress::Swt, 800), std::sqrt(300.0 * 100.0));
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, 200, MeanStress::None, 800), 100.0);
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, -200, MeanStress::Goodman, 800), 100.0);
  EXPECT_DOUBLE_EQ(fatigue::equivalent_amplitude(100, -200, MeanStress::Swt, 800), 0.0) << "Smax -100: no tension";
  EXPECT_TRUE(std::isinf(fatigue::equivalent_amplitude(100, 800, MeanStress::Goodman, 800)));
  EXPECT_THROW(fatigue::mean_stress_from_name("morrow"), std::invalid_argument);
  // And in the damage: a tensile mean makes the same cycles do more.
  const fatigue::SnCurve sn{300.0, 1e5, 5.0, 0.0, false};
  fatigue::Damage plain{sn}, goodman{sn, MeanStress::Goodman, 800.0};
  const Cycle c{200.0, 200.0, 1.0};
  plain.add(c);
  goodman.add(c);
  EXPECT_NEAR(goodman.damage / plain.damage, std::pow(1.0 / 0.75, 5.0), 1e-12);
}
