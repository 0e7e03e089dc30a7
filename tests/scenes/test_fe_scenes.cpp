// The FE-only scenes, run by fe_server from their keyword decks (meshes from
// fe_mesh at build time), checked from the HDF5 files a user would read.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "h5io/timeseries.hpp"
#include "process.hpp"

using testing_support::ChildProcess;
using testing_support::TempDir;

namespace {

const std::string kBuilt = PCS_BUILD_SCENES_DIR;

// Mean σ_zz over the gauge layer (every solids/<id>/szz series).
std::vector<double> gauge_stress(const std::string& file, const std::string& deck_dir) {
  // The gauge ids are those fe_mesh listed under *DATABASE_HISTORY_SOLID in the tool mesh.
  std::ifstream mesh(deck_dir + "/tool_mesh.k");
  std::string line;
  std::vector<int> ids;
  bool in = false;
  while (std::getline(mesh, line)) {
    if (line.rfind("*", 0) == 0) {
      in = line.rfind("*DATABASE_HISTORY_SOLID", 0) == 0;
      continue;
    }
    if (!in || line.empty() || line[0] == '$') continue;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) ids.push_back(std::stoi(f));
  }
  std::vector<double> mean;
  for (int id : ids) {
    auto s = h5io::read_series(file, "solids/" + std::to_string(id) + "/szz");
    if (mean.empty()) mean.assign(s.size(), 0.0);
    for (size_t i = 0; i < s.size(); ++i) mean[i] += s[i] / static_cast<double>(ids.size());
  }
  return mean;
}

std::string run_scene(const std::string& scene, const TempDir& dir) {
  const std::string out = dir.file(scene + ".h5");
  ChildProcess fe({PCS_FE_SERVER_EXE, "--model", kBuilt + "/" + scene + "/deck.k", "--out", out, "--quiet"});
  EXPECT_EQ(fe.wait(240.0), 0) << fe.output();
  return out;
}

}  // namespace

TEST(BarImpactScene, MatchesOneDimensionalWaveTheory) {
  TempDir dir;
  const std::string out = run_scene("bar_impact", dir);
  const auto s = gauge_stress(out, kBuilt + "/bar_impact");
  ASSERT_FALSE(s.empty());
  const double E = 2.1e11, rho = 7850, c = std::sqrt(E / rho), v0 = 8.0;
  std::vector<double> comp;
  for (double v : s)
    if (v < -1e6) comp.push_back(v);
  std::sort(comp.begin(), comp.end());
  // Plateau within 1 %: with ν = 0 the bar is exactly 1D (see tests/fe_server for the derivation).
  EXPECT_NEAR(comp[comp.size() / 2], -E * v0 / (2 * c), 0.01 * E * v0 / (2 * c));
  // Energy balance within its stated bound (1 % of the impact energy).
  const auto ke = h5io::read_series(out, "energy/kinetic");
  const auto bal = h5io::read_series(out, "energy/balance_error");
  double worst = 0;
  for (double b : bal) worst = std::max(worst, std::fabs(b));
  EXPECT_LT(worst, 0.01 * ke.front());
  // ParaView's index exists beside the field snapshots.
  EXPECT_TRUE(std::ifstream(dir.file("bar_impact_fields.xdmf")).good());
}

TEST(SteppedPistonScene, FirstPlateauMatchesTheImpedanceStepAndEnergyIsConserved) {
#ifdef PCS_SANITIZED
  // fe_server takes 6.5 min of CPU on this deck under ASan + UBSan (18 s
  // normally); the hex8 paths it runs are those of BarImpactScene, which runs.
  GTEST_SKIP() << "too slow under the sanitizers (6.5 min of CPU); runs in the normal build";
#endif
  TempDir dir;
  const std::string out = run_scene("stepped_piston", dir);
  const auto t = h5io::read_series(out, "time");
  const auto s = gauge_stress(out, kBuilt + "/stepped_piston");
  const auto ke = h5io::read_series(out, "energy/kinetic");
  const auto bal = h5io::read_series(out, "energy/balance_error");
  const double E = 2.1e11, rho = 7850, c0 = std::sqrt(E / rho), v0 = 8.0;
  // 1D: the Ø61 front stem (impedance Z_p) on the Ø65 tool (Z_t) sends
  // σ = ρ·c0·v0·Z_p/(Z_p + Z_t) into the tool until the collar's reflection
  // returns after 2·0.33 m/c0.
  const double ratio = (0.061 * 0.061) / (0.065 * 0.065);  // Z_p/Z_t: same material, area ratio
  const double sigma = rho * c0 * v0 * ratio / (1.0 + ratio);
  size_t arrival = 0;
  while (arrival < s.size() && s[arrival] > -0.1 * sigma) ++arrival;
  ASSERT_LT(arrival, s.size()) << "no pulse reached the gauge";
  double sum = 0;
  int n = 0;
  for (size_t i = arrival; i < s.size() && t[i] < t[arrival] + 2 * 0.33 / c0 - 10e-6; ++i)
    if (t[i] > t[arrival] + 10e-6) sum += s[i], ++n;
  // 8 %: ν = 0.3 makes the Ø65 bar ring (Pochhammer–Chree dispersion) about the
  // 1D plateau, and the mean is over a window of a few ring periods.
  EXPECT_NEAR(-sum / n, sigma, 0.08 * sigma);
  // W = (A·c0/E)∫σ²dt cannot exceed the piston's kinetic energy; the energy balance closes within 1 %.
  const double A = M_PI * 0.0325 * 0.0325;
  double W = 0;
  for (size_t i = 1; i < s.size(); ++i) W += A * c0 / E * s[i] * s[i] * (t[i] - t[i - 1]);
  EXPECT_LT(W, ke.front());
  EXPECT_GT(W, 0.5 * ke.front()) << "most of the energy goes into the pulse";
  double worst = 0;
  for (double b : bal) worst = std::max(worst, std::fabs(b));
  EXPECT_LT(worst, 0.01 * ke.front());
}
