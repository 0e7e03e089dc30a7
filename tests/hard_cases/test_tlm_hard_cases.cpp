// Hard cases for tlm_host (issue 6): a valve slamming shut and cavitation
// in the hammer's cavity A end in bounded, physical results, never NaN.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "components/hydraulic/HydraulicVolumeC.hpp"
#include "h5io/timeseries.hpp"
#include "model.hpp"
#include "process.hpp"

namespace {

void expect_finite(const std::string& file, const std::string& name) {
  for (double v : h5io::read_series(file, name)) ASSERT_TRUE(std::isfinite(v)) << name;
}

}  // namespace

// A valve carrying about 10 m/s in a Ø20 mm line slams shut in one step.
// Upstream the pressure jumps by Joukowsky's ρ·a·Δv ≈ 10 MPa, twice the 50 bar
// supply, so the downstream side would fall below zero absolute: its
// chamber must hold at the vapour pressure instead, and the upstream line,
// lossless, must ring without growing.
TEST(HardCase, AValveSlammingShutRisesByJoukowskyAndCavitatesDownstreamWithoutGrowth) {
  testing_support::TempDir dir;
  std::ofstream(dir.file("m.tlm")) << R"(*SIMULATION
timestep, 1e-6
stoptime, 0.03
*COMPONENT
close, SignalStep, y0=1, y1=0, t_step=0.01
src,   PressureSourceC, p=5e6
in,    HydraulicTurbulentOrificeQ, Cd=0.8, A=3e-4
line,  LosslessLineC, L=2, d=0.02, rho=870, beta=1.4e9, p0=5e6
valve, VariableOrificeQ, Cd=0.7, area=0:0; 1:6e-5
body,  HydraulicVolumeC, V=1e-5, beta=1.4e9, p0=5e6, p_vap=5e3, ports=2
out,   HydraulicTurbulentOrificeQ, Cd=0.8, A=3e-4
line2, LosslessLineC, L=2, d=0.02, rho=870, beta=1.4e9, p0=5e6
drain, HydraulicTurbulentOrificeQ, Cd=0.8, A=3e-4
tank,  PressureSourceC, p=1e5
*CONNECT
src.P1, in.P1
in.P2, line.P1
line.P2, valve.P1
valve.P2, body.P1
body.P2, out.P1
out.P2, line2.P1
line2.P2, drain.P1
drain.P2, tank.P1
close.y, valve.x
)";
  tlm::System sys(tlm::read_model(dir.file("m.tlm")));
  sys.run(dir.file("r.h5"), false);
  const std::string f = dir.file("r.h5");
  for (const char* n : {"nodes/line.P2/p", "nodes/body.P1/p", "components/valve/q", "components/body/p_mean"})
    expect_finite(f, n);
  const auto t = h5io::read_series(f, "time");
  const auto p = h5io::read_series(f, "nodes/line.P2/p");
  const auto q = h5io::read_series(f, "components/valve/q");
  const auto pb = h5io::read_series(f, "components/body/p_mean");
  size_t k = 0;  // the row the closed valve first acts in
  while (t[k] < 0.01 - 2e-6 || std::fabs(q[k]) > 1e-12) ++k;
  const double rho = 870, a = std::sqrt(1.4e9 / rho), area = M_PI * 0.02 * 0.02 / 4.0;
  const double jump = rho * a * q[k - 1] / area;
  ASSERT_GT(jump, 5e6) << "the case needs a Joukowsky rise above the supply pressure";
  // The first jump: Joukowsky within 1 % (as the line test; the flow still
  // changes by ~1e-4 relative over the last step).
  EXPECT_NEAR(p[k] - p[k - 1], jump, 0.01 * jump);
  // Lossless ringing: no later peak above the first one (+0.5 % for the
  // source orifice's transmitted share of the wave).
  double first_peak = 0.0, later_peak = 0.0;
  const double round_trip = 2.0 * 2.0 / a;
  for (size_t i = k; i < t.size(); ++i) {
    double& peak = t[i] < t[k] + round_trip ? first_peak : later_peak;
    peak = std::max(peak, p[i]);
  }
  EXPECT_LE(later_peak, 1.005 * first_peak);
  // Downstream: held at the vapour pressure, never below it.
  for (double v : pb) ASSERT_GE(v, 5e3 - 1e-6);
  auto* body = dynamic_cast<tlm::HydraulicVolumeC*>(sys.find("body"));
  ASSERT_NE(body, nullptr);
  EXPECT_GE(body->cavitation_events(), 1);
}

// The hammer with its P→A valve edge halved: at the end of the work stroke
// the piston draws cavity A open faster than the throttled edge fills it.
// Cavity A must cavitate at the vapour pressure, never below, and the
// hammer must keep cycling after it.
TEST(HardCase, CavitationInCavityAIsHeldAtVapourPressureAndTheHammerKeepsCycling) {
  testing_support::TempDir dir;
  std::ifstream in(std::string(PCS_SCENES_DIR) + "/hammer_monolithic/model.tlm");
  std::stringstream text;
  text << in.rdbuf();
  std::string model = text.str();
  const std::string full = "0.008:3.14e-4, area_AT";
  ASSERT_NE(model.find(full), std::string::npos) << "the reference model's P→A edge moved; update this test";
  model.replace(model.find(full), full.size(), "0.008:1.57e-4, area_AT");
  std::ofstream(dir.file("m.tlm")) << model;
  tlm::ModelSpec spec = tlm::read_model(dir.file("m.tlm"));
  spec.stop_time = 0.15;
  tlm::System sys(spec);
  sys.run(dir.file("r.h5"), false);
  const std::string f = dir.file("r.h5");
  const auto pA = h5io::read_series(f, "components/cavA/p_mean");
  const auto v = h5io::read_series(f, "components/piston/v");
  for (double p : pA) ASSERT_GE(p, 5e3 - 1e-6);
  for (double x : v) ASSERT_TRUE(std::isfinite(x));
  auto* cavA = dynamic_cast<tlm::HydraulicVolumeC*>(sys.find("cavA"));
  ASSERT_NE(cavA, nullptr);
  EXPECT_GE(cavA->cavitation_events(), 1);
  // Still a hammer: the piston reverses (blow, return) several times after
  // the first cavitation.
  size_t first = 0;
  while (first < pA.size() && pA[first] > 5e3 + 1.0) ++first;
  ASSERT_LT(first, pA.size());
  int reversals = 0;
  for (size_t i = first + 1; i < v.size(); ++i) reversals += (v[i] > 0.0) != (v[i - 1] > 0.0);
  EXPECT_GE(reversals, 4);
}

// A tiny chamber (0.01 cm³) under the one-DOF piston: ω·T = 1.7 at the
// 10 µs coupling step, beyond what a held pressure can follow (the
// added-mass-like case of partitioned coupling). fe_server prints before the
// run the smallest stable chamber (0.028 cm³, above this one). Its port
// table with the line `1, impedance` sends the host's Zc, so fe_server
// refuses the port at coupling step 0, before any FE step, with ω·T and the
// fixes (exit 3), and the host stops at step 0 with its message. Waived
// (--allow-coarse-coupling), the loop diverges and the host's port guard
// stops it naming node and step. (The one-DOF scene's own table stays
// without the line: the protocol tests' peers are written for its layout.)
TEST(HardCase, ATinyChamberMakingTheFluidStiffAgainstThePistonIsRefusedBeforeItsFirstStep) {
  const std::string scene = PCS_SCENES_DIR "/one_dof";
  for (const bool waived : {false, true}) {
    SCOPED_TRACE(waived ? "--allow-coarse-coupling" : "default");
    testing_support::TempDir dir;
    std::ifstream in(scene + "/ports.cfg");
    std::stringstream text;
    text << in.rdbuf();
    std::string table = text.str();
    const std::string send = "1,         pressure, 1.0\n";
    ASSERT_NE(table.find(send), std::string::npos) << "the one-DOF port table's pressure line moved";
    table.replace(table.find(send), send.size(), send + "1,         impedance\n");
    std::ofstream(dir.file("ports.cfg")) << table;
    testing_support::ChildProcess gen({PCS_FMUGEN_EXE, dir.file("ports.cfg"), "-o", dir.file("zc.fmu")});
    ASSERT_EQ(gen.wait(30.0), 0) << gen.output();
    std::vector<std::string> server_args{PCS_FE_SERVER_EXE, "--model", scene + "/piston.k", "--ports",
                                         dir.file("ports.cfg"), "--listen", "127.0.0.1:0", "--port-file",
                                         dir.file("port"), "--out", dir.file("fe.h5"), "--accept-timeout", "20"};
    if (waived) server_args.push_back("--allow-coarse-coupling");
    testing_support::ChildProcess server(server_args);
    const int port = testing_support::read_port_file(dir.file("port"), 10.0);
    ASSERT_GT(port, 0) << server.output();
    testing_support::ChildProcess host({PCS_TLM_HOST_EXE, scene + "/model.tlm", "--fmu", dir.file("zc.fmu"), "--server",
                                        "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"), "--quiet",
                                        "--set", "chamber.V=1e-8", "--set", "simulation.stoptime=0.02"});
    EXPECT_NE(host.wait(60.0), 0);
    const int server_rc = server.wait(30.0);
    const std::string fe = server.output(), h = host.output();
    EXPECT_NE(fe.find("needs a chamber of at least 0.028 cm³"), std::string::npos) << fe;
    if (!waived) {
      EXPECT_EQ(server_rc, 3) << fe;
      for (const std::string& out : {fe, h}) {
        EXPECT_NE(out.find("at coupling step 0: pressure-coupled port cavity is beyond the stability limit of "
                           "pressure coupling"),
                  std::string::npos)
            << out;
        EXPECT_NE(out.find("ω·T = 1.67 at the coupling step 1e-05 s, above 1"), std::string::npos) << out;
        EXPECT_NE(out.find("lower the coupling step to at most 5.98e-06 s"), std::string::npos) << out;
      }
      EXPECT_NE(h.find("at step 0 (t = 0 s)"), std::string::npos) << h;
      EXPECT_EQ(h5io::read_series(dir.file("host.h5"), "time").size(), 1u) << "the start's row only: no step ran";
      continue;
    }
    // Waived: the host's run-quality guard stops it at the FMU's port, whose
    // pressure swings far below −1 bar absolute (−133 bar by the first
    // steps), naming node and step; fe_server is told and ends.
    EXPECT_NE(h.find("the pressure at the FMU's port node chamber.P2 is "), std::string::npos) << h;
    EXPECT_NE(h.find("at step "), std::string::npos) << h;
    EXPECT_NE(fe.find("host aborted at step "), std::string::npos) << fe;
    // What was written is kept, and it is finite.
    const auto x = h5io::read_series(dir.file("host.h5"), "time");
    EXPECT_GE(x.size(), 2u);  // the start and the steps before the stop
    for (double v : h5io::read_series(dir.file("host.h5"), "nodes/chamber.P2/p")) ASSERT_TRUE(std::isfinite(v));
  }
}

// The same tiny chamber under TLM coupling (issue 16): the FE side solves
// its port implicitly, so the loop itself stays bounded at ω·T = 1.7 where
// pressure coupling diverges (the case above). Bounded is not right: the
// frequency is off by about 30 % and the port's pressure swings to −133 bar
// absolute. fe_server refuses the port at step 0 (Stops.*); waived there,
// the host's port guard stops it at its first step with the node's name.
TEST(HardCase, ATinyChamberUnderTlmCouplingIsRefusedOrStoppedAtItsPort) {
  testing_support::TempDir dir;
  const std::string scene = PCS_SCENES_DIR "/one_dof";
  testing_support::ChildProcess server({PCS_FE_SERVER_EXE, "--model", scene + "/piston.k", "--ports",
                                        PCS_SCENES_DIR "/one_dof_tlm/ports.cfg", "--listen", "127.0.0.1:0",
                                        "--port-file", dir.file("port"), "--out", dir.file("fe.h5"),
                                        "--accept-timeout", "20", "--allow-coarse-coupling"});
  const int port = testing_support::read_port_file(dir.file("port"), 10.0);
  ASSERT_GT(port, 0) << server.output();
  testing_support::ChildProcess host({PCS_TLM_HOST_EXE, scene + "/model.tlm", "--fmu", PCS_ONE_DOF_TLM_FMU,
                                      "--server", "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"),
                                      "--quiet", "--set", "chamber.V=1e-8", "--set", "orifice.A=1e-12", "--set",
                                      "simulation.stoptime=0.04"});
  EXPECT_EQ(host.wait(60.0), 4) << host.output();
  EXPECT_EQ(server.wait(30.0), 7) << server.output();  // the host aborted
  EXPECT_NE(host.output().find("the pressure at the FMU's port node chamber.P2 is -133"), std::string::npos)
      << host.output();
  for (double v : h5io::read_series(dir.file("host.h5"), "nodes/chamber.P2/p")) EXPECT_GE(v, -11e5) << "no row beyond the bound";
}
