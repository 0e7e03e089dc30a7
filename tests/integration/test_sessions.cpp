// fe_server --sessions N (issue 18, item 1): sessions one after another on
// the same port and token, each from the deck's initial state into its own
// results file, a summary line per session; then the server exits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <chrono>
#include <csignal>
#include <unistd.h>
#include <string>
#include <future>
#include <thread>
#include <vector>

#include "h5io/timeseries.hpp"
#include "socketlib/protocol.h"
#include "integration_support.hpp"
#include "../scenes/hammer_two_fmus.hpp"

namespace {

int run_host(const TempDir& dir, int port, const std::string& out) {
  ChildProcess host({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
                     "127.0.0.1:" + std::to_string(port), "--out", dir.file(out), "--quiet", "--set",
                     "simulation.stoptime=0.01"});
  const int rc = host.wait(kHardTimeout);
  EXPECT_EQ(rc, 0) << host.output();
  return rc;
}

}  // namespace

TEST(Sessions, TwoHostsInTurnGetTwoIdenticalSessionsFromOneServer) {
  TempDir dir;
  Server server(dir, {"--sessions", "2", "--out", dir.file("fe_{session}.h5")});
  ASSERT_GT(server.port, 0) << server.child->output();
  run_host(dir, server.port, "host_1.h5");
  run_host(dir, server.port, "host_2.h5");  // same port: the server is still listening
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
  const std::string log = server.child->output();
  EXPECT_NE(log.find("session 1: session ended by the host"), std::string::npos) << log;
  EXPECT_NE(log.find("session 2: session ended by the host"), std::string::npos) << log;
  // Each session from the deck's initial state: the same host inputs give
  // the same FE results, bit for bit.
  const auto x1 = h5io::read_series(dir.file("fe_1.h5"), "ports/cavity.x");
  const auto x2 = h5io::read_series(dir.file("fe_2.h5"), "ports/cavity.x");
  ASSERT_GT(x1.size(), 100u);
  EXPECT_EQ(x1, x2);
  double largest = 0.0;
  for (double v : x1) largest = std::max(largest, std::fabs(v));
  EXPECT_GT(largest, 0.0) << "the piston moved";
  // After its last session the server has closed its port.
  EXPECT_FALSE(std::filesystem::exists(dir.file("fe_3.h5")));
}

TEST(Sessions, WithoutAPatternTheSessionNumberGoesBeforeTheExtension) {
  TempDir dir;
  Server server(dir, {"--sessions", "2"});  // --out fe.h5 from the helper
  ASSERT_GT(server.port, 0) << server.child->output();
  run_host(dir, server.port, "h1.h5");
  run_host(dir, server.port, "h2.h5");
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
  EXPECT_TRUE(std::filesystem::exists(dir.file("fe_1.h5")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("fe_2.h5")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("fe.h5")));
}

// A session that fails (its host killed mid-run: link lost) is reported and
// the next host is served; the exit code is that failure's (6).
TEST(Sessions, AFailedSessionIsReportedAndTheNextOneServed) {
  TempDir dir;
  Server server(dir, {"--sessions", "2", "--step-timeout", "2", "--out", dir.file("fe_{session}.h5")});
  ASSERT_GT(server.port, 0) << server.child->output();
  {
    ChildProcess doomed({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
                         "127.0.0.1:" + std::to_string(server.port), "--out", dir.file("doomed.h5"), "--quiet", "--set",
                         "simulation.stoptime=100"});
    // Let it run into the session, then kill it without a word to the server.
    for (int i = 0; i < 1000 && server.child->output().find("session accepted") == std::string::npos; ++i) usleep(10000);
    ASSERT_NE(server.child->output().find("session accepted"), std::string::npos) << server.child->output();
    usleep(100000);
    ::kill(doomed.pid(), SIGKILL);
    doomed.wait(kHardTimeout);
  }
  run_host(dir, server.port, "host_2.h5");
  EXPECT_EQ(server.child->wait(kHardTimeout), 6) << server.child->output();
  const std::string log = server.child->output();
  EXPECT_NE(log.find("session 1: link lost"), std::string::npos) << log;
  EXPECT_NE(log.find("session 2: session ended by the host"), std::string::npos) << log;
  EXPECT_GT(h5io::read_series(dir.file("fe_2.h5"), "ports/cavity.x").size(), 100u);
}

// Between sessions the port stays open to anyone: a silent stranger who
// connects after the first session does not keep the second host out; with
// --sessions 0 a signal while waiting for the next host ends the server
// cleanly (exit 128 + N), and so does no host within --accept-timeout (4).
TEST(Sessions, AStrangerBetweenSessionsIsNoObstacleAndASignalOrNoHostEndsTheServer) {
  TempDir dir;
  {
    Server server(dir, {"--sessions", "0", "--out", dir.file("fe_{session}.h5")});
    ASSERT_GT(server.port, 0) << server.child->output();
    run_host(dir, server.port, "h1.h5");
    sl_socket stranger = SL_SOCKET_INIT;
    ASSERT_EQ(sl_connect("127.0.0.1", server.port, sl_now_ms() + 5000, &stranger), SL_OK);  // and says nothing
    run_host(dir, server.port, "h2.h5");
    sl_close(&stranger);
    for (int i = 0; i < 1000 && server.child->output().find("session 3: listening") == std::string::npos; ++i)
      usleep(10000);
    ::kill(server.child->pid(), SIGTERM);
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_EQ(server.child->wait(kHardTimeout), 128 + SIGTERM) << server.child->output();
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
    EXPECT_GT(h5io::read_series(dir.file("fe_2.h5"), "ports/cavity.x").size(), 100u) << "the second host was served";
  }
  TempDir quiet;
  Server lonely(quiet, {"--sessions", "0", "--accept-timeout", "0.5"});
  EXPECT_EQ(lonely.child->wait(kHardTimeout), 4) << lonely.child->output();
}

// One fmi2DoStep may span several coupling steps (FMPy picks 2^k times the
// default step): n exchanges with the input held. Stepped by 1×, 16× and
// 128× the coupling step with the same constant input, the FMU's outputs at
// their common times are the same bits: the server does the same FE steps
// from the same inputs whatever the importer's communication step.
TEST(Sessions, AnFmuSteppedBy1x16xOr128xTheCouplingStepGivesTheSameStatesAtCommonTimes) {
  TempDir dir;
  Server server(dir, {"--sessions", "3", "--out", dir.file("fe_{session}.h5")});
  ASSERT_GT(server.port, 0) << server.child->output();
  auto archive = std::make_shared<tlm::FmuArchive>(PCS_ONE_DOF_FMU);
  const config::PortTable t = config::read_port_table(archive->dir() + "/resources/ports.cfg");
  constexpr int kSteps = 512;  // coupling steps: four 128× steps
  auto run = [&](int n) {
    std::vector<std::vector<double>> at_128;  // every output, at every 128th coupling step
    auto instance = connected_fmu(archive, "piston", server.port);
    tlm::FmuInstance& fmu = *instance;
    const unsigned p = fmu.vr("cavity.p");
    std::vector<unsigned> outs;
    for (const auto& v : archive->description().variables)
      if (v.causality == "output") outs.push_back(v.value_reference);
    for (int k = 0; k < kSteps; k += n) {
      fmu.set_real(p, 1.02e7);  // held constant: a step in pressure above the preload's
      fmu.do_step(k * t.dt, n * t.dt);
      if ((k + n) % 128 == 0) {
        at_128.emplace_back();
        for (unsigned vr : outs) at_128.back().push_back(fmu.get_real(vr));
      }
    }
    fmu.terminate();
    return at_128;
  };
  const auto one = run(1), sixteen = run(16), big = run(128);
  ASSERT_EQ(one.size(), 4u);
  EXPECT_EQ(one, sixteen);
  EXPECT_EQ(one, big);
  EXPECT_NE(one.front(), one.back()) << "the face moved: the comparison means something";
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
}

// A host that comes while another session runs is told at once that the
// server is busy (ABORT SL_EBUSY), says so, and retries until its deadline:
// it is served when the first session ends. Before, it sat in the listen
// backlog in silence, and with a shorter deadline than the first run timed
// out with "no answer" and no hint why.
TEST(Sessions, AHostWhileAnotherSessionRunsIsToldTheServerIsBusyAndServedAfter) {
  TempDir dir;
  Server server(dir, {"--sessions", "2", "--out", dir.file("fe_{session}.h5")});
  ASSERT_GT(server.port, 0) << server.child->output();
  const std::string at = "127.0.0.1:" + std::to_string(server.port);
  ChildProcess first({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server", at, "--out",
                      dir.file("h1.h5"), "--quiet", "--set", "simulation.stoptime=0.4"});  // about 3 s of wall
  for (int i = 0; i < 1000 && server.child->output().find("session accepted") == std::string::npos; ++i) usleep(10000);
  ASSERT_NE(server.child->output().find("session accepted"), std::string::npos) << server.child->output();
  ChildProcess second({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server", at, "--out",
                       dir.file("h2.h5"), "--quiet", "--set", "simulation.stoptime=0.01"});
  EXPECT_EQ(second.wait(kHardTimeout), 0) << second.output();
  EXPECT_EQ(first.wait(kHardTimeout), 0) << first.output();
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
  EXPECT_NE(second.output().find("is busy: running another session"), std::string::npos) << second.output();
  EXPECT_NE(server.child->output().find("turned away: busy"), std::string::npos) << server.child->output();
  EXPECT_NE(server.child->output().find("session 2: session ended by the host after 1000 coupling steps"),
            std::string::npos)
      << server.child->output();
}

namespace {

// fe_server on the hammer scene split into its piston's and valve's FMUs,
// with a short step time-out (the deadlock is told at 0.8 of it).
struct SplitSession {
  TempDir dir;
  const std::string hammer = PCS_SCENES_DIR "/hammer", built = PCS_BUILD_SCENES_DIR "/hammer";
  config::PortTable piston = config::read_port_table(hammer + "/two_fmus/piston.cfg");
  config::PortTable valve = config::read_port_table(hammer + "/two_fmus/valve.cfg");
  ChildProcess server{{PCS_FE_SERVER_EXE, "--model", built + "/deck.k", "--ports", hammer + "/two_fmus/piston.cfg",
                       "--ports", hammer + "/two_fmus/valve.cfg", "--listen", "127.0.0.1:0", "--port-file",
                       dir.file("port"), "--out", dir.file("fe.h5"), "--step-timeout", "2", "--accept-timeout", "20"}};
  int port = testing_support::read_port_file(dir.file("port"), kHardTimeout);
  // The two FMUs' clients, each with its own deadline of 10 s.
  pcs_fmu::CouplingClient a{piston}, b{valve};
  void connect() {
    a.connect("127.0.0.1", port, testing_support::session_token(), 10.0);
    b.connect("127.0.0.1", port, testing_support::session_token(), 10.0);
  }
  // Each FMU's inputs: a wave of 50 bar into every chamber (its impedance a
  // chamber's, 1e11 Pa s/m^3) and no force.
  std::vector<double> inputs(const config::PortTable& t, double wave) const {
    std::vector<double> v;
    for (const auto& var : t.to_fe) v.push_back(var.name().find(".Zc") != std::string::npos ? 1e11
                                                : var.name().find(".c") != std::string::npos ? wave : 0.0);
    return v;
  }
};

}  // namespace

// The thesis' split (piston and valve as two FMUs of one session) under an
// importer that steps one FMU before it has set the other's inputs: the
// first FMU's step waits for a result that needs the second's inputs of the
// same step, which the importer sends only after. Before, both sides timed
// out with "no RESULT at step 0 ... SL_ETIMEDOUT" and no hint; now the
// server tells the waiting FMU why, before its own deadline, and what to
// change.
TEST(Sessions, TwoFmusSteppedOneAfterTheOtherAreToldWhyTheyDeadlockBeforeTheirDeadline) {
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  std::vector<double> in(s.piston.to_fe.size(), 0.0), out;
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  try {
    s.a.step(0, 0.0, s.piston.dt, in, out);  // the sequential master: the valve's step would come after
  } catch (const pcs_fmu::LinkError& e) {
    why = e.what();
  }
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(why.find("steps its FMUs one after another"), std::string::npos) << why;
  EXPECT_NE(why.find("FMU '" + s.valve.model_name + "' sent no STEP 0"), std::string::npos) << why;
  EXPECT_NE(why.find("Use one FMU for the whole model"), std::string::npos) << why;
  EXPECT_LT(waited, 5.0) << "told at 0.8 of the server's 2 s step time-out, long before the FMU's own 10 s";
  EXPECT_EQ(s.server.wait(kHardTimeout), 6) << s.server.output();
  EXPECT_NE(s.server.output().find("steps its FMUs one after another"), std::string::npos) << s.server.output();
}

TEST(Sessions, TwoFmusWhoseInputsAreSetBeforeEitherStepsRunOneAfterTheOther) {
  // The sequential importer's order: both FMUs' inputs set (INPUTS), then
  // the piston's FMU stepped, then the valve's. The piston's FMU steps by
  // two coupling steps at once, the valve's by one: its second step's RESULT
  // came while its inputs were being set again (the same values), and waits
  // for its step.
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  pcs_fmu::CouplingClient &a = s.a, &b = s.b;
  ASSERT_TRUE(a.split_session() && b.split_session());
  const std::vector<double> in_a = s.inputs(s.piston, 50e5), in_b = s.inputs(s.valve, 50e5);
  std::vector<double> out_a, out_b0, out_b1;
  const double dt = s.piston.dt;
  a.send_inputs(0, 0.0, dt, in_a);
  b.send_inputs(0, 0.0, dt, in_b);
  a.step(0, 0.0, dt, in_a, out_a);  // runs at once: the valve's inputs are in
  a.step(1, dt, dt, in_a, out_a);   // the valve's inputs held, as an FMU holds them over a longer step
  b.step(0, 0.0, dt, in_b, out_b0);  // its RESULT is waiting
  b.send_inputs(1, dt, dt, in_b);  // the same values: step 1 ran with them
  b.step(1, dt, dt, in_b, out_b1);
  ASSERT_EQ(out_b1.size(), s.valve.to_host.size());
  a.bye();
  b.bye();
  EXPECT_EQ(s.server.wait(kHardTimeout), 0) << s.server.output();
  EXPECT_NE(s.server.output().find("after 2 coupling steps"), std::string::npos) << s.server.output();
}

TEST(Sessions, InputsChangedAfterAnotherFmuSteppedWithThemAreRefusedWithTheReason) {
  // fe_server ran step 0 with the valve's inputs as set when the piston's FMU
  // stepped; the importer then sets other values for the valve's step 0.
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  pcs_fmu::CouplingClient &a = s.a, &b = s.b;
  std::vector<double> out;
  const double dt = s.piston.dt;
  b.send_inputs(0, 0.0, dt, s.inputs(s.valve, 50e5));
  a.step(0, 0.0, dt, s.inputs(s.piston, 50e5), out);
  std::string why;
  try {
    b.send_inputs(0, 0.0, dt, s.inputs(s.valve, 60e5));
  } catch (const pcs_fmu::LinkError& e) {
    why = e.what();
  }
  EXPECT_NE(why.find("FMU 'hammer_valve''s inputs for step 0 changed after fe_server had run that step"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("must set the inputs of them all before it steps the first"), std::string::npos) << why;
  EXPECT_EQ(s.server.wait(kHardTimeout), 6) << s.server.output();
}

TEST(Sessions, AStepWhoseValuesDifferFromTheInputsAStepRanWithIsRefused) {
  // The same, found at the valve's STEP (an importer that set its inputs
  // by a path that did not tell the FMU, or a faulty FMU).
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  pcs_fmu::CouplingClient &a = s.a, &b = s.b;
  std::vector<double> out;
  const double dt = s.piston.dt;
  b.send_inputs(0, 0.0, dt, s.inputs(s.valve, 50e5));
  a.step(0, 0.0, dt, s.inputs(s.piston, 50e5), out);
  std::string why;
  try {
    b.step(0, 0.0, dt, s.inputs(s.valve, 60e5), out);
    b.step(1, dt, dt, s.inputs(s.valve, 60e5), out);  // the refusal comes at the server's next read
  } catch (const pcs_fmu::LinkError& e) {
    why = e.what();
  }
  EXPECT_NE(why.find("inputs for step 0 changed after fe_server had run that step"), std::string::npos) << why;
  EXPECT_EQ(s.server.wait(kHardTimeout), 6) << s.server.output();
}

TEST(Sessions, AHostSettingAndSteppingEachFmuInTurnIsToldWhyAndExits) {
  // tlm_host --peers one-by-one: the order of Hopsan's sequential solver.
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  std::ofstream(s.dir.file("model.tlm")) << hammer_model_with_two_fmus(s.hammer, s.built);
  ChildProcess host({PCS_TLM_HOST_EXE, s.dir.file("model.tlm"), "--server", "127.0.0.1:" + std::to_string(s.port),
                     "--out", s.dir.file("host.h5"), "--quiet", "--peers", "one-by-one", "--set",
                     "simulation.timestep=1e-5", "--set", "simulation.stoptime=0.01"});
  EXPECT_EQ(host.wait(kHardTimeout), 4) << host.output();
  EXPECT_NE(host.output().find("one that sets and steps each FMU in turn (Hopsan's sequential solver) deadlocks here"),
            std::string::npos)
      << host.output();
  EXPECT_EQ(s.server.wait(kHardTimeout), 6) << s.server.output();
}

TEST(Sessions, InputsSetOnAnotherThreadThanTheStepWaitForTheirFmusOwnStep) {
  // A parallel importer: the valve's thread sets its inputs in two calls
  // while the piston's FMU steps from the main thread. The first call's
  // INPUTS must not be taken for final (they came from another thread than
  // the piston's STEP): fe_server waits for the valve's own STEP, and the
  // second call's values are the ones stepped with. Taken for final, the
  // step would have run with half the inputs and the second call refused.
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  pcs_fmu::CouplingClient &a = s.a, &b = s.b;
  const double dt = s.piston.dt;
  std::vector<double> first = s.inputs(s.valve, 0.0), second = s.inputs(s.valve, 50e5), out_a, out_b;
  std::promise<void> first_set;
  std::string why;
  std::thread valve([&] {
    try {
      b.send_inputs(0, 0.0, dt, first);
      first_set.set_value();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the piston's STEP is in by now
      b.send_inputs(0, 0.0, dt, second);
      b.step(0, 0.0, dt, second, out_b);
    } catch (const pcs_fmu::LinkError& e) {
      why = e.what();
    }
  });
  first_set.get_future().wait();
  try {
    a.step(0, 0.0, dt, s.inputs(s.piston, 50e5), out_a);
  } catch (const pcs_fmu::LinkError& e) {
    why += e.what();
  }
  valve.join();
  EXPECT_EQ(why, "");
  a.bye();
  b.bye();
  EXPECT_EQ(s.server.wait(kHardTimeout), 0) << s.server.output();
}

TEST(Sessions, AStopSignalWhileASplitRoundWaitsEndsTheServerAndTellsTheFmuThatWaits) {
  // The round's own wait (several FMUs' sockets at once): the piston's FMU
  // has stepped, the valve's never will. SIGINT there stops fe_server at
  // once (130), its history closed, and the waiting FMU is told why.
  SplitSession s;
  ASSERT_GT(s.port, 0) << s.server.output();
  s.connect();
  std::string why;
  std::thread piston([&] {
    std::vector<double> out;
    try {
      s.a.step(0, 0.0, s.piston.dt, s.inputs(s.piston, 50e5), out);
    } catch (const pcs_fmu::LinkError& e) {
      why = e.what();
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // inside the round's wait (0.8 of 2 s)
  kill(s.server.pid(), SIGINT);
  piston.join();
  EXPECT_EQ(s.server.wait(kHardTimeout), 128 + SIGINT) << s.server.output();
  EXPECT_NE(why.find("fe_server stopped by SIGINT"), std::string::npos) << why;
  EXPECT_NE(s.server.output().find("kept in"), std::string::npos) << s.server.output();
}
