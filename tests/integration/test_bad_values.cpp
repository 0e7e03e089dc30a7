// Bad values (issue 17, item 5): every number is range-checked where it is
// read and refused with its location (file:line, or the option), with the
// documented exit code, before anything runs.
#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "h5io/timeseries.hpp"
#include "process.hpp"

using testing_support::ChildProcess;
using testing_support::TempDir;

namespace {

const std::string kScene = PCS_SCENES_DIR "/one_dof";

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Outcome {
  int code;
  std::string output;
};

Outcome run(const std::vector<std::string>& argv) {
  ChildProcess p(argv);
  const int code = p.wait(30.0);
  return {code, p.output()};
}

void expect_refused(const Outcome& o, int code, const std::vector<std::string>& words) {
  EXPECT_EQ(o.code, code) << o.output;
  for (const auto& w : words) EXPECT_NE(o.output.find(w), std::string::npos) << "missing '" << w << "' in\n" << o.output;
}

}  // namespace

TEST(BadValues, SimulationSettingsGivenBySetAreCheckedLikeTheModelFile) {
  TempDir dir;
  for (const auto& [set, why] : std::vector<std::pair<std::string, std::string>>{
           {"simulation.log_every=0", "log_every must be from 1 to 1e9"},  // was SIGFPE
           {"simulation.log_every=5000000000", "log_every must be from 1 to 1e9"},
           {"simulation.timestep=-1e-5", "timestep"},                       // was exit 0 after 0 steps
           {"simulation.stoptime=inf", "expected a finite number"},          // was exit 0 after 0 steps
           {"simulation.stoptime=1e9", "is not a run that ends"}}) {
    Outcome o = run({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--set", set, "--out",
                     dir.file("h.h5"), "--quiet"});
    expect_refused(o, 3, {"--set " + set + ": ", why});
    EXPECT_EQ(o.output.find("--set " + set + ":0"), std::string::npos) << "an option has no line number";
  }
}

TEST(BadValues, ServerTimeoutsOutsideTheirRangeAreRefusedNamingTheOption) {
  TempDir dir;
  for (const char* t : {"nan", "inf", "-1", "1e30"}) {  // every deadline was already past
    Outcome o = run({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                     "--accept-timeout", t, "--out", dir.file("f.h5")});
    expect_refused(o, 2, {"--accept-timeout: expected a number from 0.001 to 1e+06, got '" + std::string(t) + "'"});
  }
  Outcome o = run({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                   "--step-timeout", "0", "--out", dir.file("f.h5")});
  expect_refused(o, 2, {"--step-timeout"});
}

TEST(BadValues, APortTableTimeoutOfInfinityOr1e30IsRefusedAtItsLine) {
  TempDir dir;
  const std::string table = read(kScene + "/ports.cfg");
  int line = 0;
  {
    std::istringstream in(table);
    std::string l;
    for (int n = 1; std::getline(in, l); ++n)
      if (l.rfind("timeout", 0) == 0) line = n;
  }
  ASSERT_GT(line, 0);
  for (const char* t : {"inf", "1e30"}) {
    std::ofstream(dir.file("p.cfg")) << std::regex_replace(table, std::regex("timeout,[^\n]*"), "timeout, " + std::string(t));
    Outcome o = run({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", dir.file("p.cfg"), "--out",
                     dir.file("f.h5")});
    expect_refused(o, 3, {dir.file("p.cfg") + ":" + std::to_string(line) + ":", "timeout"});
  }
}

TEST(BadValues, NaNInADeckIsRefusedAtItsLineNotFoundLaterAsAnUnstableState) {
  TempDir dir;
  const std::string deck = read(kScene + "/piston.k");
  const std::string bad = std::regex_replace(deck, std::regex("\n5, 0.0, 0.0, 0.1\n"), "\n5, 0.0, 0.0, nan\n");
  ASSERT_NE(bad, deck);
  std::ofstream(dir.file("nan.k")) << bad;
  Outcome o = run({PCS_FE_SERVER_EXE, "--model", dir.file("nan.k"), "--ports", kScene + "/ports.cfg", "--out",
                   dir.file("f.h5")});
  expect_refused(o, 3, {"nan.k:", "field 4 of *INITIAL_VELOCITY_NODE: 'nan' is not a finite number"});
}

TEST(BadValues, APortCountMustBeAWholeNumber) {
  TempDir dir;
  for (const char* n : {"2.5", "5.8e9"}) {  // 2.5 became 2; 5.8e9 was undefined behaviour
    std::ofstream(dir.file("m.tlm")) << "*SIMULATION\ntimestep, 1e-5\nstoptime, 1e-3\n*COMPONENT\n"
                                        "vol, HydraulicVolumeC, V=1e-4, ports="
                                     << n << "\n";
    Outcome o = run({PCS_TLM_HOST_EXE, dir.file("m.tlm"), "--out", dir.file("h.h5"), "--quiet"});
    expect_refused(o, 3, {dir.file("m.tlm") + ":5:", "ports must be a whole number from 1 to 64"});
  }
}

TEST(BadValues, AServerPortOfZeroAndAnUnwritablePortFileAreRefused) {
  TempDir dir;
  Outcome host = run({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server", "127.0.0.1:0",
                      "--out", dir.file("h.h5"), "--quiet"});
  EXPECT_NE(host.code, 0) << host.output;  // it used the table's port before
  EXPECT_NE(host.output.find("the port must be from 1 to 65535"), std::string::npos) << host.output;
  Outcome server = run({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                        "--port-file", dir.path(), "--out", dir.file("f.h5"), "--accept-timeout", "1"});
  EXPECT_NE(server.code, 0) << server.output;  // it failed silently before
  EXPECT_NE(server.output.find("--port-file: cannot write"), std::string::npos) << server.output;
}

// --threads: 1..1024, else refused naming the option; the session line says
// how many threads the FE uses; without the option a co-simulation on
// loopback leaves one core to tlm_host (docs/fe_server.md, "Threads").
TEST(BadValues, ThreadCountsAreCheckedAndTheDefaultLeavesACoreToTheHostOnLoopback) {
  TempDir dir;
  for (const char* n : {"0", "2000", "two"}) {
    Outcome o = run({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                     "--threads", n, "--out", dir.file("f.h5")});
    expect_refused(o, 2, {"--threads"});
  }
  auto session_line = [&](std::vector<std::string> extra) {
    std::vector<std::string> argv = {PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports",
                                     kScene + "/ports.cfg", "--accept-timeout", "0.5", "--out", dir.file("f.h5")};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return run(argv);  // no host comes: exit 4 after 0.5 s
  };
  Outcome three = session_line({"--threads", "3"});
  EXPECT_EQ(three.code, 4) << three.output;
  EXPECT_NE(three.output.find(", 3 threads)"), std::string::npos) << three.output;
  cpu_set_t set;
  ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  const int expected = std::max(1, CPU_COUNT(&set) - 1);
  Outcome dflt = session_line({});
  const std::string want = ", " + std::to_string(expected) + (expected == 1 ? " thread)" : " threads)");
  EXPECT_NE(dflt.output.find(want), std::string::npos) << "want '" << want << "' in\n" << dflt.output;
}

// No abort, ever: GSL's default handler called abort() on a sweep point
// (piston.c_rock = 1e9, 10^4 times the nominal rock spring, on the
// monolithic hammer: SIGABRT, no step, no time, an empty results file). Its
// handler is off; the failing call became a stop at step 266734 naming the
// spool's root finder. That failure was a late effect: the run-quality
// guard now finds the first node gone NaN (at step 14402) at the next
// results row, step 14409, 252 325 steps (0.25 s of results) earlier. Either way a stop naming step, time and
// cause, with the rows so far kept.
TEST(LibraryErrors, AGslFailureStopsWithStepTimeAndComponentNotAnAbort) {
  TempDir dir;
  const Outcome o = run({PCS_TLM_HOST_EXE, PCS_SCENES_DIR "/hammer_monolithic/model.tlm", "--set",
                         "piston.c_rock=1e9", "--out", dir.file("host.h5"), "--quiet"});
  EXPECT_EQ(o.code, 4) << o.output;
  // (Found at the first row or 16th step after it: at step 14409.)
  for (const char* word : {"at step 144", "(t = ", "node acc_lp.P1 is no longer finite",
                           "results up to the last completed step kept in"})
    EXPECT_NE(o.output.find(word), std::string::npos) << word << "\n" << o.output;
  EXPECT_GT(h5io::read_series(dir.file("host.h5"), "time").size(), 100u) << "the rows before the failure are kept";
}

// The same in a co-simulation (valve.Cd = 1e200 aborted tlm_host there and
// left fe_server with exit 6 and the FMU's folder behind): the host stops
// with its cause, fe_server is told and ends, no folder is left.
TEST(LibraryErrors, AGslFailureInACoSimulationTellsTheServerAndLeavesNoFolder) {
  TempDir dir;
  ChildProcess server({PCS_FE_SERVER_EXE, "--model", PCS_BUILD_SCENES_DIR "/hammer/deck.k", "--ports",
                       PCS_SCENES_DIR "/hammer/ports.cfg", "--listen", "127.0.0.1:0", "--port-file", dir.file("port"),
                       "--out", dir.file("fe.h5"), "--accept-timeout", "30"});
  const int port = testing_support::read_port_file(dir.file("port"), 30.0);
  ASSERT_GT(port, 0) << server.output();
  setenv("TMPDIR", dir.path().c_str(), 1);
  const Outcome host = run({PCS_TLM_HOST_EXE, PCS_SCENES_DIR "/hammer/model.tlm", "--fmu",
                            PCS_BUILD_SCENES_DIR "/hammer/hammer.fmu", "--server", "127.0.0.1:" + std::to_string(port),
                            "--out", dir.file("host.h5"), "--set", "valve.Cd=1e200", "--quiet"});
  unsetenv("TMPDIR");
  EXPECT_EQ(host.code, 4) << host.output;
  EXPECT_NE(host.output.find("in valve (SpoolValveQ): the root finder for p_A failed"), std::string::npos)
      << host.output;
  const int server_rc = server.wait(30.0);
  EXPECT_NE(server_rc, 0) << "the server ends, and not as a completed session\n" << server.output();
  EXPECT_GT(server_rc, 0) << server.output();
  EXPECT_NE(server.output().find("host aborted"), std::string::npos) << server.output();
  for (const auto& e : std::filesystem::directory_iterator(dir.path()))
    EXPECT_NE(e.path().filename().string().rfind("tlm_host_fmu_", 0), 0u) << e.path() << " left behind";
}
