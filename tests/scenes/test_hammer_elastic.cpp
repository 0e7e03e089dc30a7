// The elastic hammer on its test rig (issue 14's main job,
// scenes/hammer_elastic): piston, tool, housing and anvil as elastic
// axisymmetric bodies in fe_server, the rig preloaded by dynamic
// relaxation, TLM coupling every 10 us, positions relative to the housing in
// the host; against the monolithic reference over the start-up (the
// piston's first rise, the valve's first switch, the first impact), and the
// first blow's stress pulse in the tool against 1D wave theory.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"
#include "stress_pulse.hpp"

using testing_support::ChildProcess;
using testing_support::TempDir;

namespace {

const std::string kBuilt = PCS_BUILD_SCENES_DIR "/hammer_elastic";
constexpr double kStop = 0.0675;  // the first impact comes at ~66.5 ms
constexpr double kE = 2.1e11, kRho = 7850.0, kRt = 0.0325, kRp = 0.0305, kLp = 0.64;

struct Traces {
  std::vector<double> t, lift, v, spool;
  std::vector<double> te, sigma, v_cut;  // the tool's gauge section
  std::string server_log;
  double fe_bytes = 0.0;  // FE history rows written
};

// First contact onset of the piston on the tool after 10 ms (the piston
// starts resting on it): the lift falls through 0.2 mm on the way down.
double impact_time(const Traces& r, double* v_impact) {
  for (size_t i = 1; i < r.t.size(); ++i)
    if (r.t[i] > 0.01 && r.lift[i - 1] >= 2e-4 && r.lift[i] < 2e-4) {
      if (v_impact) *v_impact = -r.v[i - 1];
      return r.t[i];
    }
  return -1.0;
}

// y(t) by linear interpolation in a time series.
double at(const std::vector<double>& ts, const std::vector<double>& ys, double t) {
  const size_t k = static_cast<size_t>(std::lower_bound(ts.begin(), ts.end(), t) - ts.begin());
  if (k == 0) return ys.front();
  if (k >= ts.size()) return ys.back();
  return ys[k - 1] + (ys[k] - ys[k - 1]) * (t - ts[k - 1]) / (ts[k] - ts[k - 1]);
}

// First time the spool passes mid-stroke (4 mm) towards WORK.
double switch_time(const Traces& r) {
  for (size_t i = 1; i < r.t.size(); ++i)
    if (r.spool[i - 1] < 4e-3 && r.spool[i] >= 4e-3)
      return r.t[i - 1] + (4e-3 - r.spool[i - 1]) / (r.spool[i] - r.spool[i - 1]) * (r.t[i] - r.t[i - 1]);
  return -1.0;
}

class HammerElastic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
#ifdef PCS_SANITIZED
    return;  // minutes of co-simulation under the sanitizers; the parts are unit-tested there
#endif
    TempDir dir;
    ChildProcess server({PCS_FE_SERVER_EXE, "--model", kBuilt + "/deck.k", "--ports",
                         PCS_SCENES_DIR "/hammer_elastic/ports.cfg", "--listen", "127.0.0.1:0", "--port-file",
                         dir.file("port"), "--out", dir.file("fe.h5"), "--accept-timeout", "20", "--threads", "1"});
    const int port = testing_support::read_port_file(dir.file("port"), 10.0);
    ASSERT_GT(port, 0) << server.output();
    ChildProcess host({PCS_TLM_HOST_EXE, PCS_SCENES_DIR "/hammer_elastic/model.tlm", "--fmu", kBuilt + "/hammer_elastic.fmu",
                       "--server", "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"), "--quiet",
                       "--set", "simulation.stoptime=" + std::to_string(kStop), "--set", "simulation.timestep=1e-5",
                       "--set", "simulation.log_every=1"});
    const int rc = host.wait(250.0);
    ASSERT_TRUE(rc == 0 || rc == 4) << host.output();  // 4: the report finds no settled blows in 67 ms
    ASSERT_EQ(server.wait(30.0), 0) << server.output();
    cosim_ = new Traces;
    Traces& c = *cosim_;
    c.server_log = server.output();
    c.t = h5io::read_series(dir.file("host.h5"), "time");
    c.lift = h5io::read_series(dir.file("host.h5"), "components/mech/x");
    c.v = h5io::read_series(dir.file("host.h5"), "components/mech/v");
    c.spool = h5io::read_series(dir.file("host.h5"), "components/smech/x");
    c.te = h5io::read_series(dir.file("fe.h5"), "time_elements");
    c.sigma = h5io::read_series(dir.file("fe.h5"), "sections/111/fy");
    for (double& s : c.sigma) s /= M_PI * kRt * kRt;
    c.v_cut = h5io::read_series(dir.file("fe.h5"), "sections/111/vy");
    for (const auto& [name, rows] : h5io::list_series(dir.file("fe.h5"))) c.fe_bytes += 8.0 * static_cast<double>(rows);

    tlm::ModelSpec spec = tlm::read_model(PCS_SCENES_DIR "/hammer_monolithic/model.tlm");
    spec.apply_override("simulation.stoptime=" + std::to_string(kStop));
    spec.report.clear();
    tlm::System mono(std::move(spec));
    mono.run(dir.file("mono.h5"), false);
    ref_ = new Traces;
    ref_->t = h5io::read_series(dir.file("mono.h5"), "time");
    ref_->lift = h5io::read_series(dir.file("mono.h5"), "components/piston/x");
    ref_->v = h5io::read_series(dir.file("mono.h5"), "components/piston/v");
    ref_->spool = h5io::read_series(dir.file("mono.h5"), "components/spool/x");
  }
  static void TearDownTestSuite() {
    delete cosim_;
    delete ref_;
    cosim_ = ref_ = nullptr;
  }
  void SetUp() override {
#ifdef PCS_SANITIZED
    GTEST_SKIP() << "minutes of co-simulation under the sanitizers; runs in the normal build";
#endif
    ASSERT_TRUE(cosim_ && ref_) << "the co-simulation did not run";
  }
  static Traces *cosim_, *ref_;
};
Traces* HammerElastic::cosim_ = nullptr;
Traces* HammerElastic::ref_ = nullptr;

}  // namespace

TEST_F(HammerElastic, StartUpFollowsTheMonolithicReferenceToTheFirstImpact) {
  const Traces &c = *cosim_, &r = *ref_;
  double v_c = 0, v_r = 0;
  const double t_c = impact_time(c, &v_c), t_r = impact_time(r, &v_r);
  ASSERT_GT(t_r, 0.0) << "the reference piston must strike within " << kStop << " s";
  ASSERT_GT(t_c, 0.0) << "the co-simulated piston must strike within " << kStop << " s";
  // Until the first impact both pistons are driven by the same hydraulics;
  // what differs: the host steps at 10 us here (1 us in the reference), the
  // FE piston's mass is its mesh's (14.36 kg, 0.3 % below 14.4), it is elastic
  // (its centre of mass moves, ~1 um of static squeeze), and the tool is an
  // elastic body on the rig where the reference lumps it, and the housing
  // moves (the host reads positions relative to it). Bounds: the lift within
  // 1 % of the stroke (measured 142 um of 61.6 mm), the valve's switch within
  // 100 us (ten host steps; the spool takes 1.3 ms to switch; measured 32 us
  // early), the impact within 0.2 ms (measured on the same 10 us row) and its
  // velocity within 1 % (a 0.3 % lighter piston under the same forces
  // strikes 0.15 % faster; measured +0.17 %).
  double worst = 0.0, stroke = 0.0;
  for (size_t i = 0; i < c.t.size(); ++i) {
    if (c.t[i] > std::min(t_c, t_r) - 1e-3) break;
    const double lr = at(r.t, r.lift, c.t[i]);
    worst = std::max(worst, std::fabs(c.lift[i] - lr));
    stroke = std::max(stroke, lr);
  }
  std::printf("elastic hammer: worst lift difference %.1f um of %.1f mm; switch %+.1f us; impact %+.1f us at %.3f m/s "
              "(reference %.3f)\n",
              1e6 * worst, 1e3 * stroke, 1e6 * (switch_time(c) - switch_time(r)), 1e6 * (t_c - t_r), v_c, v_r);
  EXPECT_GT(stroke, 0.05) << "the piston must have risen";
  EXPECT_LT(worst, 0.01 * stroke);
  ASSERT_GT(switch_time(r), 0.0);
  EXPECT_NEAR(switch_time(c), switch_time(r), 100e-6);
  EXPECT_NEAR(t_c, t_r, 0.2e-3);
  EXPECT_NEAR(v_c, v_r, 0.01 * v_r);
}

TEST_F(HammerElastic, FirstBlowIsAPlateauAtTheImpedanceLevelLastingTwoPistonTransits) {
  const Traces& c = *cosim_;
  double v0 = 0;
  const double t0 = impact_time(c, &v0);
  ASSERT_GT(t0, 0.0);
  // The down-going stress at the gauge, 200 mm below the tool's top:
  // σ_d = (σ + ρ·c0·v)/2 (1D wave relations), from the section's force and
  // mean velocity.
  const double c0 = std::sqrt(kE / kRho);
  std::vector<double> t, sd;
  for (size_t i = 0; i < c.te.size(); ++i)
    if (c.te[i] > t0 - 20e-6) t.push_back(c.te[i]), sd.push_back(0.5 * (c.sigma[i] + kRho * c0 * c.v_cut[i]));
  ASSERT_GT(t.size(), 10u);
  ASSERT_GT(t.back(), t0 + 5e-4 - 2e-4) << "the run must hold the whole pulse";
  // 1D impedance estimate (one steel): the striking stem (Ø61) on the tool
  // (Ø65), σ = −v0·ρ·c0·A_p/(A_p + A_t), for 2·L_piston/c0 (the piston's own
  // steps send small partial reflections, ~6 % of the level each).
  const double Ap = M_PI * kRp * kRp, At = M_PI * kRt * kRt;
  const double level = -v0 * kRho * c0 * Ap / (Ap + At), length = 2.0 * kLp / c0;
  // Half-level crossings give the pulse's length; its plateau is the mean
  // over the middle half.
  // W = (A·c0/E)·∫σ_d² over the pulse against the blow's kinetic energy ½mv²
  // (m: the mesh's 14.36 kg): the stem and the tool differ by 6 % in
  // impedance, so 1 − 0.063² of the energy goes into the tool at the first
  // contact; the collar and rear steps return part of it later. Bound: 95–101 %
  // (measured at 5.2 m/s: plateau +1.3 %, length −0.2 %, W 97.7 %).
  const testing_support::StressPulse pulse = testing_support::primary_stress_pulse(t, sd, level, 50e-6, 20, At, c0, kE);
  ASSERT_TRUE(pulse.whole) << "the pulse must end within the run";
  ASSERT_GT(pulse.plateau_samples, 10);
  const double measured_length = pulse.length, plateau = pulse.plateau, W = pulse.energy;
  const double kinetic = 0.5 * 14.36 * v0 * v0;
  std::printf("first blow at %.3f m/s: plateau %.1f MPa (1D %.1f), length %.1f us (2L/c0 %.1f), W %.1f J of %.1f J\n", v0,
              plateau / 1e6, level / 1e6, measured_length * 1e6, length * 1e6, W, kinetic);
  // Issue 14's bounds: the plateau within 5 % of the 1D estimate, the length within 10 %.
  EXPECT_NEAR(plateau, level, 0.05 * std::fabs(level));
  EXPECT_NEAR(measured_length, length, 0.10 * length);
  EXPECT_GT(W, 0.95 * kinetic);
  EXPECT_LT(W, 1.01 * kinetic);
}

TEST_F(HammerElastic, TheFeHistoriesStayWithinFiftyMegabytesPerSimulatedSecond) {
  // Issue 13's bound for the hammer main job: the deck's rates (energies,
  // ports and nodes every 20 us, the two gauge sections every 2 us) against
  // 0.5 GB per simulated second when every FE step was written. Rows, not
  // the file's size (HDF5 keeps each series' last chunk whole).
  std::printf("FE history rows: %.1f MB per simulated second\n", cosim_->fe_bytes / kStop / 1e6);
  EXPECT_GT(cosim_->fe_bytes, 0.0);
  EXPECT_LT(cosim_->fe_bytes / kStop, 50e6);
}

TEST_F(HammerElastic, ThePreloadReachesTheRigsStaticState) {
  // fe_server's report of the dynamic relaxation: "... residual: the largest
  // out-of-balance force on one part R N (...), P % of the largest support
  // force L N". Converged means below DRTOL = 1e-3 of L; L is what the tool
  // and anvil carry to the foundation: the 10 kN feed and the weights
  // (housing 142, piston 14.4, tool 15.6, anvil 24.7, bracket 30 kg: 2.2 kN),
  // within 5 % (the piston and the feed spring's end are the only free
  // choices of where it splits).
  const std::string& log = cosim_->server_log;
  const size_t at = log.find("dynamic relaxation converged after");
  ASSERT_NE(at, std::string::npos) << log;
  const std::string line = log.substr(at, log.find('\n', at) - at);
  double percent = -1.0, support = -1.0;
  const size_t p = line.find("N (");
  ASSERT_NE(p, std::string::npos) << line;
  ASSERT_EQ(std::sscanf(line.c_str() + line.find("), ", p) + 3, "%lf %% of the largest support force %lf N", &percent,
                        &support),
            2)
      << line;
  std::printf("preload: %s\n", line.c_str());
  EXPECT_LT(percent, 0.1) << line;
  EXPECT_NEAR(support, 10e3 + 226.7 * 9.81, 0.05 * (10e3 + 226.7 * 9.81)) << line;
}

TEST_F(HammerElastic, TheEnergyAccountHoldsAndNothingHourglasses) {
  // fe_server's closing line states the balance against its 1 % bound and
  // warns, per part, of hourglassing (more than 10 % of the internal work
  // put into the part). Piston (1), tool (2) and anvil (4), whose stresses
  // the report reads, must not hourglass. The housing (5) does, slightly:
  // 11.2 % of its 7.3 J over the start-up, under the stop ring's and the
  // small cavity faces' line loads on its one-element-wide rings (a 10 mm
  // axial mesh measured the same); bounded here at 15 % until its mesh is
  // refined where those loads act.
  const std::string& log = cosim_->server_log;
  EXPECT_NE(log.find("bound 1 %"), std::string::npos) << log;
  EXPECT_EQ(log.find("exceeds its bound"), std::string::npos) << log;
  for (int part : {1, 2, 4}) EXPECT_EQ(log.find("part " + std::to_string(part) + ": hourglass"), std::string::npos) << log;
  if (const size_t at = log.find("part 5: hourglass energy"); at != std::string::npos) {
    double joules = 0.0, percent = 100.0;
    ASSERT_EQ(std::sscanf(log.c_str() + at, "part 5: hourglass energy %lf J is %lf %%", &joules, &percent), 2);
    EXPECT_LT(percent, 15.0) << log.substr(at, 200);
  }
}
