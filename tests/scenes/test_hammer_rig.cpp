// The hammer reworked against the rig (scenes/hammer_rig): the acceptance
// figures of the validated-hammer work on the monolithic model, in its four
// running conditions. The bands are the rig's: the thesis' Table 2 flows
// (Andersson 2018) give the ratios 0.825 / 0.847 / 0.738; the accepted bands
// around them are the issue's, as are ±10 % per flow, ±1 % on the operating
// pressure and 15–30 Hz. Each run is the scene's own 1.2 s (15 or more blows after
// the report's 0.3 s settle), so the figures are what the scene reports.
#include <algorithm>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "calibration.hpp"
#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"
#include "stress_pulse.hpp"

namespace {

struct Case {
  std::string name;
  std::string p_crack;  // the relief setting the scene calibrated for this case (conditions.csv)
  std::string area;     // m²
  double p_set_abs;     // the operating pressure, absolute (gauge + 1.013 bar)
  double q_measured;    // l/min, thesis Table 2
};

// The rig's measured flows, thesis Table 2 (the committed
// scenes/hammer_monolithic/thesis_table2.csv: "c11, 80" rows), by case.
std::map<std::string, double> table2_flows() {
  std::ifstream in(PCS_SCENES_DIR "/hammer_monolithic/thesis_table2.csv");
  std::map<std::string, double> flows;
  for (std::string line; std::getline(in, line);)
    if (line.size() > 1 && line[0] == 'c' && std::isdigit(static_cast<unsigned char>(line[1])))
      flows[line.substr(1, line.find(',') - 1)] = std::stod(line.substr(line.find(',') + 1));
  return flows;
}

// The scene's conditions (scenes/hammer_rig/conditions.csv: case, bar, mm,
// relief.p_crack, restrictor.A) with the rig's measured flows.
std::vector<Case> read_cases() {
  const std::map<std::string, double> measured = table2_flows();
  std::ifstream in(PCS_SCENES_DIR "/hammer_rig/conditions.csv");
  std::vector<Case> cases;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line.rfind("case", 0) == 0) continue;
    std::stringstream row(line);
    std::string name, bar, mm, p_crack, area;
    std::getline(row, name, ','), std::getline(row, bar, ','), std::getline(row, mm, ','),
        std::getline(row, p_crack, ','), std::getline(row, area, ',');
    cases.push_back({name, p_crack, area, (std::stod(bar) + 1.013) * 1e5, measured.at(name)});
  }
  return cases;
}

tlm::PercussionFigures run_case(const Case& c, const std::string& h5) {
  return tlm::run_percussion(tlm::read_model(PCS_SCENES_DIR "/hammer_rig/model.tlm"),
                             {"relief.p_crack=" + c.p_crack, "restrictor.A=" + c.area}, h5);
}

// Mean of a logged series over [t0, t1].
double mean_over(const std::string& h5, const std::string& series, double t0, double t1) {
  const std::vector<double> t = h5io::read_series(h5, "time"), y = h5io::read_series(h5, series);
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < t.size(); ++i)
    if (t[i] >= t0 && t[i] <= t1) sum += y[i], ++n;
  return n ? sum / n : 0.0;
}

// The rig's three flow ratios (cases 11, 12, 21, 22 in q) in the issue's
// bands around the measured 0.825 / 0.847 / 0.738.
void expect_ratios_in_their_bands(const double q[4]) {
  const double d150 = q[1] / q[0], d100 = q[3] / q[2], p60 = q[2] / q[0];
  std::printf("ratios: %.3f at 150 bar, %.3f at 100 bar, 100/150 bar %.3f\n", d150, d100, p60);
  EXPECT_GE(d150, 0.80);
  EXPECT_LE(d150, 0.86);
  EXPECT_GE(d100, 0.82);
  EXPECT_LE(d100, 0.88);
  EXPECT_GE(p60, 0.71);
  EXPECT_LE(p60, 0.79);
}

}  // namespace

TEST(HammerRig, FlowFollowsTheRestrictorAndThePressureAsOnTheRig) {
  const std::vector<Case> cases = read_cases();
  ASSERT_EQ(cases.size(), 4u) << "conditions.csv must hold the four cases 11, 12, 21, 22 in order";
  double q[4];
  for (int i = 0; i < 4; ++i) {
    testing_support::TempDir dir;
    const tlm::PercussionFigures f = run_case(cases[i], dir.file("r.h5"));
    q[i] = f.q_in * 6e4;
    SCOPED_TRACE("case " + cases[i].name);
    // The figure is the flow into the hammer: over the same whole cycles it
    // equals what enters the supply hose at the pump (the hose's and the
    // node's storage return to their level each cycle: measured within
    // 0.05 %). The return restrictor's flow read as the inlet's would be
    // 5 % low (the leakage and the pilot's drain bypass it).
    ASSERT_GE(f.impact_times.size(), 2u);
    const double supplied = mean_over(dir.file("r.h5"), "components/fit_s/q", f.impact_times.front(),
                                      f.impact_times.back());
    EXPECT_NEAR(f.q_in / supplied, 1.0, 0.01) << f.q_in << " against " << supplied << " m³/s";
    EXPECT_NEAR(q[i] / cases[i].q_measured, 1.0, 0.10) << q[i] << " l/min";
    EXPECT_NEAR(f.p_in / cases[i].p_set_abs, 1.0, 0.01) << f.p_in << " Pa";
    EXPECT_GE(f.frequency, 15.0);
    EXPECT_LE(f.frequency, 30.0);
    EXPECT_GE(f.blows, 15);  // whole cycles after the settle time that the figures average
  }
  expect_ratios_in_their_bands(q);
}

// The same bands with the lumped piston rebounding from the tool as the
// elastic one does in the co-simulation: its fastest rise in the millisecond
// after each impact is 3.09-3.14 m/s in all four conditions of the main job,
// where the lumped contact's e = 0.9 gives 5.7 m/s at 150 bar. That rebound
// is what set the co-simulated 150 bar ratio apart from this model's (0.863
// against 0.849 before the valve's reversal was timed to the impact): the
// piston, braked by cavity A at supply pressure until the spool opened A->T,
// lost time the restrictor does not set. e = 0.55 gives the elastic rebound
// at 150 bar (at 100 bar 2.5 m/s, where the co-simulation's stays 3.1), and
// with it this model gave 0.864 on the old valve timing, the co-simulation's
// figure then (scenes/hammer_rig/README.md). Bounds: the bands; the
// rebound at 150 bar within 10 % of the co-simulation's 3.1 m/s, so that the
// case is the co-simulation's.
TEST(HammerRig, TheBandsHoldWhenTheLumpedPistonReboundsAsTheElasticOneDoes) {
  const std::vector<Case> cases = read_cases();
  ASSERT_EQ(cases.size(), 4u);
  double q[4];
  for (int i = 0; i < 4; ++i) {
    SCOPED_TRACE("case " + cases[i].name);
    testing_support::TempDir dir;
    const tlm::PercussionFigures f =
        tlm::run_percussion(tlm::read_model(PCS_SCENES_DIR "/hammer_rig/model.tlm"),
                            {"relief.p_crack=" + cases[i].p_crack, "restrictor.A=" + cases[i].area,
                             "piston.e_contact=0.55"},
                            dir.file("r.h5"));
    q[i] = f.q_in * 6e4;
    // The rebound: the piston's fastest rise in the millisecond after each
    // impact (the contact force's onset, coming down) after the settle time.
    const std::vector<double> t = h5io::read_series(dir.file("r.h5"), "time"),
                              v = h5io::read_series(dir.file("r.h5"), "components/piston/v"),
                              F = h5io::read_series(dir.file("r.h5"), "components/piston/F_contact");
    double sum = 0.0;
    int n = 0;
    for (size_t k = 1; k < t.size(); ++k)
      if (t[k] > 0.3 && F[k - 1] == 0.0 && F[k] != 0.0 && v[k - 1] < -1.0) {
        double rise = 0.0;
        for (size_t j = k; j < t.size() && t[j] < t[k] + 1e-3; ++j) rise = std::max(rise, v[j]);
        sum += rise, ++n;
      }
    ASSERT_GT(n, 10);
    std::printf("case %s: rebound %.2f m/s over %d blows, %.1f l/min, %.2f Hz\n", cases[i].name.c_str(), sum / n, n, q[i],
                f.frequency);
    if (i < 2) EXPECT_NEAR(sum / n, 3.1, 0.31);
    EXPECT_NEAR(q[i] / cases[i].q_measured, 1.0, 0.10) << q[i] << " l/min";
    EXPECT_GE(f.frequency, 15.0);
    EXPECT_LE(f.frequency, 30.0);
  }
  expect_ratios_in_their_bands(q);
}

// The report refuses an inlet flow read away from the inlet pressure's node:
// the scene's first version named the return restrictor (5–7 % low, exit 0).
TEST(HammerRig, AnInletFlowAwayFromTheInletNodeIsRefusedAtItsLine) {
  std::ifstream in(PCS_SCENES_DIR "/hammer_rig/model.tlm");
  std::stringstream text;
  text << in.rdbuf();
  std::string model = text.str();
  const std::string right = "inlet_q,  components/fit_P/q";
  ASSERT_NE(model.find(right), std::string::npos);
  EXPECT_NO_THROW({
    tlm::ModelSpec ok = tlm::read_model(PCS_SCENES_DIR "/hammer_rig/model.tlm");
    tlm::report_settings(ok);
  });
  model.replace(model.find(right), right.size(), "inlet_q,  components/restrictor/q");
  testing_support::TempDir dir;
  std::ofstream(dir.file("model.tlm")) << model;
  tlm::ModelSpec spec = tlm::read_model(dir.file("model.tlm"));
  try {
    tlm::report_settings(spec);
    ADD_FAILURE() << "the return restrictor's flow was taken as the inlet flow";
  } catch (const config::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("model.tlm:"), std::string::npos) << what;  // file:line
    EXPECT_NE(what.find("not the flow at the inlet node supply_hose.P2"), std::string::npos) << what;
  }
}

// The reworked hammer co-simulated (deck.k, model_elastic.tlm, ports.cfg of
// scenes/hammer_rig) over its first three blows, case 11, against the
// monolithic model of the same circuit: the start-up follows it, the blows'
// stress pulses are what 1D wave theory gives, selective mass scaling stays
// under 1 % per part and the FE's energy account holds. One test: the
// co-simulation (about a minute) runs once. The whole acceptance table over
// 20 and more blows per condition is the main job's (scripts/run.sh).
namespace {

// Times [s] and velocities [m/s, down positive] of the piston's impacts: the
// lift falling through 0.2 mm after 10 ms (the piston starts on the tool).
void impacts(const std::vector<double>& t, const std::vector<double>& x, const std::vector<double>& v,
             std::vector<double>& times, std::vector<double>& speeds) {
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] > 0.01 && x[i - 1] >= 2e-4 && x[i] < 2e-4) times.push_back(t[i]), speeds.push_back(-v[i - 1]);
}

}  // namespace

TEST(HammerRig, CoSimulatedFirstBlowsFollowTheMonolithicModelAndOneDimensionalWaveTheory) {
#ifdef PCS_SANITIZED
  GTEST_SKIP() << "a minute of co-simulation in the normal build; under the sanitizers its parts are unit-tested";
#endif
  const std::vector<Case> cases = read_cases();
  ASSERT_FALSE(cases.empty());
  const Case& c11 = cases.front();
  constexpr double kStop = 0.19;  // impacts at about 88, 140 and 183 ms, the third pulse whole by 0.19 s
  const std::string built = PCS_BUILD_SCENES_DIR "/hammer_rig";
  testing_support::TempDir dir;
  testing_support::ChildProcess server({PCS_FE_SERVER_EXE, "--model", built + "/deck.k", "--ports",
                                        PCS_SCENES_DIR "/hammer_rig/ports.cfg", "--listen", "127.0.0.1:0", "--port-file",
                                        dir.file("port"), "--out", dir.file("fe.h5"), "--accept-timeout", "30",
                                        "--threads", "1"});
  const int port = testing_support::read_port_file(dir.file("port"), 20.0);
  ASSERT_GT(port, 0) << server.output();
  testing_support::ChildProcess host(
      {PCS_TLM_HOST_EXE, PCS_SCENES_DIR "/hammer_rig/model_elastic.tlm", "--fmu", built + "/hammer_rig.fmu", "--server",
       "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"), "--quiet", "--set",
       "simulation.stoptime=" + std::to_string(kStop), "--set", "simulation.timestep=1e-5", "--set",
       "simulation.log_every=1", "--set", "relief.p_crack=" + c11.p_crack, "--set", "restrictor.A=" + c11.area});
  const int rc = host.wait(280.0);
  ASSERT_TRUE(rc == 0 || rc == 4) << host.output();  // 4: no settled blows in 0.19 s for the report
  ASSERT_EQ(server.wait(30.0), 0) << server.output();
  const std::string log = server.output();

  // Selective mass scaling: fe_server lists "part P: added M kg to T kg (S %)".
  int scaled_parts = 0;
  for (size_t at = log.find(": added "); at != std::string::npos; at = log.find(": added ", at + 1)) {
    const size_t open = log.find('(', at);
    const double percent = std::stod(log.substr(open + 1));
    EXPECT_LT(percent, 1.0) << log.substr(at, 60);
    ++scaled_parts;
  }
  EXPECT_GE(scaled_parts, 1) << "the deck asks for mass scaling (DT2MS < 0): fe_server must report it\n" << log;
  EXPECT_NE(log.find("dynamic relaxation converged"), std::string::npos) << log;
  EXPECT_NE(log.find("bound 1 %"), std::string::npos) << log;
  EXPECT_EQ(log.find("exceeds its bound"), std::string::npos) << log;

  // The main job's output per simulated second and condition (issue 39's
  // bound: 50 MB): fe.h5's rows at the deck's rates, and the host's series
  // (model_elastic.tlm's *LOG and the report's) at the main job's 20 us
  // rows (this test writes them every 10 us). 40 MB for these two leaves 10
  // for the reference, which the main job writes at 6. Rows, not file
  // sizes: HDF5 keeps each series' last chunk (4096 rows) whole, a fixed
  // few MB that a run of 0.19 s would count 8 times over.
  double fe_rows = 0.0;
  for (const auto& [name, rows] : h5io::list_series(dir.file("fe.h5"))) fe_rows += 8.0 * static_cast<double>(rows);
  const double host_series = static_cast<double>(h5io::list_series(dir.file("host.h5")).size());
  const double per_second = fe_rows / kStop + host_series * 8.0 / 20e-6;
  std::printf("output per simulated second: fe.h5 %.1f MB, host.h5 %.1f MB (%g series at 20 us)\n", fe_rows / kStop / 1e6,
              host_series * 8.0 / 20e-6 / 1e6, host_series);
  EXPECT_LT(per_second, 40e6);
  EXPECT_LT(host_series, 40.0) << "model_elastic.tlm's *LOG keeps the host's results to what the main job reads";

  std::vector<double> tc, vc, tr, vr;
  impacts(h5io::read_series(dir.file("host.h5"), "time"), h5io::read_series(dir.file("host.h5"), "components/mech/x"),
          h5io::read_series(dir.file("host.h5"), "components/mech/v"), tc, vc);
  tlm::ModelSpec spec = tlm::read_model(PCS_SCENES_DIR "/hammer_rig/model.tlm");
  for (const std::string& o : {"simulation.stoptime=" + std::to_string(kStop), "relief.p_crack=" + c11.p_crack,
                               "restrictor.A=" + c11.area})
    spec.apply_override(o);
  spec.report.clear();
  tlm::System mono(std::move(spec));
  mono.run(dir.file("mono.h5"), false);
  impacts(h5io::read_series(dir.file("mono.h5"), "time"), h5io::read_series(dir.file("mono.h5"), "components/piston/x"),
          h5io::read_series(dir.file("mono.h5"), "components/piston/v"), tr, vr);
  ASSERT_GE(tr.size(), 3u) << "the monolithic piston must strike three times in " << kStop << " s";
  ASSERT_GE(tc.size(), 3u) << "the co-simulated piston must strike three times in " << kStop << " s";
  // The same hydraulics drive both pistons; what differs: the host's 10 us
  // step (1 us in the monolithic model), the elastic bodies, and the housing,
  // which moves on the rig (1.5 mm over a cycle) where the monolithic model
  // holds it. Bounds: the first impact within 0.5 ms (measured +0.1 ms), each
  // cycle's period within 5 % (measured +2.3 % and +2.0 %: the housing's
  // recoil), each impact velocity within 2 % (measured −0.4, +0.2, −0.4 %).
  for (size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("impact " + std::to_string(k + 1));
    std::printf("impact %zu: %.2f ms at %.3f m/s (monolithic %.2f ms at %.3f m/s)\n", k + 1, 1e3 * tc[k], vc[k],
                1e3 * tr[k], vr[k]);
    EXPECT_NEAR(vc[k], vr[k], 0.02 * vr[k]);
    if (k == 0) EXPECT_NEAR(tc[0], tr[0], 0.5e-3);
    else EXPECT_NEAR(tc[k] - tc[k - 1], tr[k] - tr[k - 1], 0.05 * (tr[k] - tr[k - 1]));
  }

  // Each blow's primary pulse in the tool (gauge 200 mm below its top,
  // section 111): the down-going stress σ_d = (σ + ρ·c0·v)/2 against the 1D
  // impedance estimate σ = −v0·ρ·c0·A_p/(A_p + A_t) for the striking stem
  // (r 30.5 mm) on the tool (r 33.5 mm), lasting 2·L/c0 (L = 283.4 mm); W =
  // (A_t·c0/E)·∫σ_d² against ½mv² (m = 6.0 kg). The bounds: plateau
  // within 5 %, length within 10 %, W at most 101 % of ½mv². W's lower bound:
  // the stem and the tool differ by 17 % in impedance, so 1 − (0.17/1.83)² =
  // 99 % of the energy crosses at first contact and the steps return part of
  // it later: 90 % (measured 95–97 %; plateaus 2.0–2.6 % under the estimate,
  // lengths within 0.3 %).
  constexpr double kE = 2.1e11, kRho = 7850.0, kAp = M_PI * 0.0305 * 0.0305, kAt = M_PI * 0.0335 * 0.0335;
  const double c0 = std::sqrt(kE / kRho);
  const std::vector<double> te = h5io::read_series(dir.file("fe.h5"), "time_elements"),
                            fy = h5io::read_series(dir.file("fe.h5"), "sections/111/fy"),
                            vy = h5io::read_series(dir.file("fe.h5"), "sections/111/vy");
  for (size_t k = 0; k < 3; ++k) {
    SCOPED_TRACE("blow " + std::to_string(k + 1));
    const double level = -vc[k] * kRho * c0 * kAp / (kAp + kAt), length = 2.0 * 0.28337 / c0;
    std::vector<double> t, sd;
    for (size_t i = 0; i < te.size(); ++i)
      if (te[i] > tc[k] - 20e-6 && te[i] < tc[k] + 0.6e-3) t.push_back(te[i]), sd.push_back(0.5 * (fy[i] / kAt + kRho * c0 * vy[i]));
    const testing_support::StressPulse pulse = testing_support::primary_stress_pulse(t, sd, level, 30e-6, 10, kAt, c0, kE);
    ASSERT_TRUE(pulse.whole) << "the pulse must end within the record";
    ASSERT_GT(pulse.plateau_samples, 5);
    const double measured = pulse.length, W = pulse.energy;
    const double plateau = pulse.plateau, kinetic = 0.5 * 6.0 * vc[k] * vc[k];
    std::printf("blow %zu at %.3f m/s: plateau %.1f MPa (1D %.1f), length %.1f us (2L/c0 %.1f), W %.1f J of %.1f J\n",
                k + 1, vc[k], plateau / 1e6, level / 1e6, 1e6 * measured, 1e6 * length, W, kinetic);
    EXPECT_NEAR(plateau, level, 0.05 * std::fabs(level));
    EXPECT_NEAR(measured, length, 0.10 * length);
    EXPECT_LE(W, 1.01 * kinetic);
    EXPECT_GE(W, 0.90 * kinetic);
  }

  // The deck's structural damping (*DAMPING_PART_STIFFNESS, deck.k): over
  // the cycle between the second and third impacts the viscous hourglass
  // control takes under 5 % of the blow's ½mv² (issue 34's bound; measured
  // 4.3 %, and 13.0 % with the deck's damping block taken out), and in the
  // 4 ms before the third impact the piston's gauge rings at under 1 MPa rms
  // (0.14 MPa; 2.30 MPa without the damping).
  const std::vector<double> tg = h5io::read_series(dir.file("fe.h5"), "time"),
                            hg = h5io::read_series(dir.file("fe.h5"), "energy/hourglass");
  auto at = [&](double t) { return hg[static_cast<size_t>(std::lower_bound(tg.begin(), tg.end(), t) - tg.begin())]; };
  const double cycle = at(tc[2]) - at(tc[1]), kinetic = 0.5 * 6.0 * vc[1] * vc[1];
  const std::vector<double> fp = h5io::read_series(dir.file("fe.h5"), "sections/101/fy");
  double n = 0.0, sum = 0.0, sum2 = 0.0;
  for (size_t i = 0; i < te.size(); ++i)
    if (te[i] > tc[2] - 4.5e-3 && te[i] < tc[2] - 0.5e-3) {
      const double s = fp[i] / kAp;
      n += 1.0, sum += s, sum2 += s * s;
    }
  const double ring = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  std::printf("hourglass %.1f J over the second cycle (%.1f %% of %.0f J); piston ringing %.2f MPa rms\n", cycle,
              100.0 * cycle / kinetic, kinetic, ring / 1e6);
  EXPECT_LT(cycle, 0.05 * kinetic);
  EXPECT_LT(ring, 1e6);
}
