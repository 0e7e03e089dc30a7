// Signals (issue 17, items 2 and 4): SIGINT and SIGTERM stop either side
// cleanly (results flushed and closed, the peer told through ABORT, exit
// 128 + signal); after kill -9 the results file still opens with its rows up
// to the last periodic flush, and the killed host's FMU folder is removed
// by the next host.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "h5io/timeseries.hpp"
#include "integration_support.hpp"

namespace {

// True if the file opens as an ordinary HDF5 file: its writer closed it.
// (A file whose writer was killed is still marked as being written.)
bool closed_cleanly(const std::string& path) {
  hid_t f = -1;
  H5E_BEGIN_TRY { f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
  H5E_END_TRY;
  if (f < 0) return false;
  H5Fclose(f);
  return true;
}

// Rows whose time is finite and increasing: a consistent series.
void expect_consistent_rows(const std::string& path, size_t at_least) {
  const std::vector<double> t = h5io::read_series(path, "time");
  EXPECT_GE(t.size(), at_least) << path;
  for (size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1])) {
      ADD_FAILURE() << path << ": time not increasing at row " << i;
      break;
    }
}

// A killed writer's file opens as a user opens it: with h5py's SWMR reader
// (Debian's python3-h5py) with at least `rows` rows, and plainly once
// `h5clear -s` (hdf5-tools) cleared its being-written mark (on a copy).
void expect_opens_as_users_do(const std::string& path, size_t rows) {
  ChildProcess h5py({"/usr/bin/python3", "-c",
                     "import sys, h5py\n"
                     "with h5py.File(sys.argv[1], 'r', swmr=True) as f: print('rows', f['time'].shape[0])\n",
                     path});
  EXPECT_EQ(h5py.wait(kHardTimeout), 0) << h5py.output();
  const size_t at = h5py.output().find("rows ");
  ASSERT_NE(at, std::string::npos) << h5py.output();
  EXPECT_GE(std::stoul(h5py.output().substr(at + 5)), rows) << h5py.output();
  const std::string copy = path + ".cleared";
  std::filesystem::copy_file(path, copy, std::filesystem::copy_options::overwrite_existing);
  ChildProcess clear({"/usr/bin/h5clear", "-s", copy});
  EXPECT_EQ(clear.wait(kHardTimeout), 0) << clear.output();
  EXPECT_TRUE(closed_cleanly(copy)) << "opens plainly after h5clear -s";
  std::filesystem::remove(copy);
}

size_t fmu_folders(const std::string& dir) {
  size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().filename().string().rfind("tlm_host_fmu_", 0) == 0) ++n;
  return n;
}

// A long co-simulation of the one-DOF scene, the host's FMU unpacked under
// `tmp` (TMPDIR), so a test can see what it leaves there.
std::unique_ptr<ChildProcess> start_host(const TempDir& dir, int port, const std::string& tmp) {
  setenv("TMPDIR", tmp.c_str(), 1);  // inherited by the child only: each test is its own process
  auto host = std::make_unique<ChildProcess>(std::vector<std::string>{
      PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
      "127.0.0.1:" + std::to_string(port), "--out", dir.file("host.h5"), "--quiet", "--set", "simulation.stoptime=100",
      "--set", "piston.verbose=0"});
  unsetenv("TMPDIR");
  return host;
}

// Runs until both sides have written a few thousand rows.
void let_it_run() { std::this_thread::sleep_for(std::chrono::milliseconds(1500)); }

// After a clean stop of either side: both files closed and whole, no FMU folder left.
void expect_both_files_closed_and_no_folder(const TempDir& dir, const Server& server) {
  EXPECT_TRUE(closed_cleanly(server.out));
  EXPECT_TRUE(closed_cleanly(dir.file("host.h5")));
  expect_consistent_rows(server.out, 1000);
  expect_consistent_rows(dir.file("host.h5"), 1000);
  EXPECT_EQ(fmu_folders(dir.path()), 0u) << "the host removed its FMU folder";
}

}  // namespace

// SIGINT (Ctrl-C) and SIGHUP stop the server at once, the host told why.
TEST(Signals, SigintOrSighupStopsTheServerCleanlyAndTellsTheHost) {
  for (const int sig : {SIGINT, SIGHUP}) {
    const std::string name = sig == SIGINT ? "SIGINT" : "SIGHUP";
    SCOPED_TRACE(name);
    TempDir dir;
    Server server(dir);
    ASSERT_GT(server.port, 0) << server.child->output();
    auto host = start_host(dir, server.port, dir.path());
    let_it_run();
    kill(server.child->pid(), sig);
    EXPECT_EQ(server.child->wait(kHardTimeout), 128 + sig) << server.child->output();
    EXPECT_NE(server.child->output().find("stopped by " + name + " "), std::string::npos) << server.child->output();
    EXPECT_EQ(host->wait(kHardTimeout), 4) << host->output();
    EXPECT_NE(host->output().find("fe_server stopped by " + name), std::string::npos)
        << "the host is told why through ABORT:\n" << host->output();
    expect_both_files_closed_and_no_folder(dir, server);
  }
}

// SIGTERM (a batch system's wall-time limit) asks the host for a checkpoint
// of both sides first: the host takes it at its next step and ends (exit
// 10), the server then stops (143); both files closed, both checkpoints
// there. (That a restart from them continues bit for bit: test_restart.)
TEST(Signals, SigtermToTheServerEndsTheRunWithACheckpointOfBothSides) {
  TempDir dir;
  Server server(dir);
  ASSERT_GT(server.port, 0) << server.child->output();
  auto host = start_host(dir, server.port, dir.path());
  let_it_run();
  kill(server.child->pid(), SIGTERM);
  EXPECT_EQ(server.child->wait(kHardTimeout), 128 + SIGTERM) << server.child->output();
  EXPECT_NE(server.child->output().find("stopped by SIGTERM: the host ended the session after the checkpoint"),
            std::string::npos)
      << server.child->output();
  EXPECT_EQ(host->wait(kHardTimeout), 10) << host->output();
  EXPECT_NE(host->output().find("fe_server is stopping"), std::string::npos) << host->output();
  EXPECT_TRUE(std::filesystem::exists(dir.file("fe.ckpt"))) << server.child->output();
  EXPECT_TRUE(std::filesystem::exists(dir.file("host.ckpt"))) << host->output();
  expect_both_files_closed_and_no_folder(dir, server);
}

TEST(Signals, SigintOrSigtermStopsTheHostCleanlyAndTellsTheServer) {
  for (const int sig : {SIGINT, SIGTERM}) {
    SCOPED_TRACE(sig == SIGINT ? "SIGINT" : "SIGTERM");
    TempDir dir;
    Server server(dir);
    ASSERT_GT(server.port, 0) << server.child->output();
    auto host = start_host(dir, server.port, dir.path());
    let_it_run();
    EXPECT_EQ(fmu_folders(dir.path()), 1u) << "the running host's FMU folder";
    kill(host->pid(), sig);
    EXPECT_EQ(host->wait(kHardTimeout), 128 + sig) << host->output();
    EXPECT_NE(host->output().find(std::string("stopped by ") + (sig == SIGINT ? "SIGINT" : "SIGTERM")),
              std::string::npos)
        << host->output();
    EXPECT_EQ(server.child->wait(kHardTimeout), 7) << server.child->output();
    EXPECT_NE(server.child->output().find("host aborted"), std::string::npos) << server.child->output();
    expect_both_files_closed_and_no_folder(dir, server);
  }
}

// kill -9 runs no clean-up at all: what survives is what was flushed. The
// writers flush at least once a second, so after 2.5 s of running each file
// holds at least the first second's rows.
TEST(Signals, AfterKillMinus9BothFilesOpenWithTheirFlushedRows) {
  TempDir dir;
  Server server(dir);
  ASSERT_GT(server.port, 0) << server.child->output();
  auto host = start_host(dir, server.port, dir.path());
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  kill(server.child->pid(), SIGKILL);
  kill(host->pid(), SIGKILL);
  EXPECT_EQ(server.child->wait(kHardTimeout), -1000 - SIGKILL);
  EXPECT_EQ(host->wait(kHardTimeout), -1000 - SIGKILL);
  EXPECT_FALSE(closed_cleanly(server.out)) << "a killed writer cannot close its file";
  expect_consistent_rows(server.out, 1000);
  expect_consistent_rows(dir.file("host.h5"), 1000);
  expect_opens_as_users_do(server.out, 1000);
  expect_opens_as_users_do(dir.file("host.h5"), 1000);
  // The killed host left its FMU folder; the next host removes it.
  EXPECT_EQ(fmu_folders(dir.path()), 1u);
  TempDir next_dir;
  Server next_server(next_dir);
  ASSERT_GT(next_server.port, 0) << next_server.child->output();
  setenv("TMPDIR", dir.path().c_str(), 1);
  ChildProcess next({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
                     "127.0.0.1:" + std::to_string(next_server.port), "--out", next_dir.file("host.h5"), "--quiet",
                     "--set", "simulation.stoptime=0.001", "--set", "piston.verbose=0"});
  unsetenv("TMPDIR");
  EXPECT_EQ(next.wait(kHardTimeout), 0) << next.output();
  EXPECT_EQ(fmu_folders(dir.path()), 0u) << next.output();
}

// A user can watch a running job's file: it opens while it is written and
// grows from one look to the next.
TEST(Signals, ARunningJobsFileCanBeWatchedLive) {
  TempDir dir;
  Server server(dir);
  ASSERT_GT(server.port, 0) << server.child->output();
  auto host = start_host(dir, server.port, dir.path());
  let_it_run();
  const size_t first = h5io::read_series(server.out, "time").size();
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const size_t second = h5io::read_series(server.out, "time").size();
  EXPECT_GT(first, 0u);
  EXPECT_GT(second, first) << "the file grows while it is watched";
  kill(host->pid(), SIGTERM);
  EXPECT_EQ(host->wait(kHardTimeout), 128 + SIGTERM) << host->output();
  EXPECT_EQ(server.child->wait(kHardTimeout), 7) << server.child->output();
}

// A server waiting for its host (here for up to 10 s) is in a blocking wait:
// each stop signal still ends it at once (socketlib's waits look at the stop
// flag every 200 ms) with 128 + N and the reason. 2 s: ten of those slices.
TEST(Signals, EachStopSignalEndsAServerWaitingForItsHost) {
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
    SCOPED_TRACE(sig);
    TempDir dir;
    Server server(dir);
    ASSERT_GT(server.port, 0) << server.child->output();
    kill(server.child->pid(), sig);
    EXPECT_EQ(server.child->wait(2.0), 128 + sig) << server.child->output();
    EXPECT_NE(server.child->output().find("while waiting for the host"), std::string::npos) << server.child->output();
  }
}

// A dynamic relaxation is a loop of its own before the run (before the host
// is served): a stop signal ends it too, within 64 steps (milliseconds
// here, also under the sanitizers), with 128 + N and how far it got. The
// deck: a 2D steel block of 2000 quads on its base under gravity, relaxed
// with almost no damping (DRFCTR 0.999999) and DRTOL 1e-9: minutes of
// relaxation if nothing stopped it.
TEST(Signals, AStopSignalEndsADynamicRelaxation) {
  TempDir dir;
  std::ostringstream d;
  const int nr = 20, ny = 100;
  d << "*KEYWORD\n*NODE\n";
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nr; ++i) d << 1 + j * (nr + 1) + i << "," << 0.001 * i << "," << 0.001 * j << ",0\n";
  d << "*ELEMENT_SHELL\n";
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nr; ++i) {
      const int n = 1 + j * (nr + 1) + i;
      d << 1 + j * nr + i << ",1," << n << "," << n + 1 << "," << n + nr + 2 << "," << n + nr + 1 << "\n";
    }
  d << "*PART\nblock\n1,1,1\n*SECTION_SHELL\n1,15\n0\n*MAT_ELASTIC\n1,7850,2.1e11,0.3\n*SET_NODE_LIST\n1\n";
  for (int i = 0; i <= nr; ++i) d << i + 1 << (i % 8 == 7 || i == nr ? "\n" : ",");
  d << "*BOUNDARY_SPC_SET\n1,0,1,1,1\n*DEFINE_CURVE\n1,2\n0,9.81\n1,9.81\n*LOAD_BODY_Y\n1\n"
       "*CONTROL_DYNAMIC_RELAXATION\n250,1e-9,0.999999\n*CONTROL_TERMINATION\n1e-3\n";
  std::ofstream(dir.file("block.k")) << d.str();
  ChildProcess server({PCS_FE_SERVER_EXE, "--model", dir.file("block.k"), "--out", dir.file("fe.h5"), "--threads", "1"});
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(server.pid(), SIGTERM);
  // 2 s: the signal is looked at every 64 steps (ms), the rest is start-up.
  EXPECT_EQ(server.wait(2.0), 128 + SIGTERM) << server.output();
  EXPECT_NE(server.output().find("stopped by SIGTERM during the dynamic relaxation, after "), std::string::npos)
      << server.output();
}

// How soon a host whose FMU waits must be gone after the signal that ends
// the wait: socketlib's 200 ms slice, plus the host's teardown (closing the
// results, freeing the FMU), a few ms here and more under the sanitizers.
#ifdef PCS_SANITIZED
constexpr double kWaitStopBound = 1.5;
#else
constexpr double kWaitStopBound = 0.5;
#endif

// A host whose FMU is blocked in a wait of the link stops on SIGINT or
// SIGTERM: the FMU's own copy of socketlib watches the host's stop flag
// (pcs_fmu_set_stop_flag), so each wait returns within its 200 ms slice;
// the host then exits 128 + N and removes its FMU folder. Three waits: the
// connection refused and retried (no server yet), a handshake the peer never
// answers, and a step the peer only answers with heartbeats (each restarts
// the receive deadline: without the flag that wait never ended).
TEST(Signals, EachStopSignalEndsAHostWhoseFmuIsWaiting) {
  using Behaviour = testing_support::TestPeer::Behaviour;
  struct Wait {
    const char* name;
    int signo;
    bool with_peer;
    Behaviour behaviour;
  };
  const std::vector<Wait> waits = {{"connection refused, retried", SIGTERM, false, Behaviour::Echo},
                                   {"a handshake never answered", SIGINT, true, Behaviour::SilentAfterHello},
                                   {"a step answered by heartbeats only", SIGTERM, true, Behaviour::EndlessHeartbeats},
                                   {"a step answered by heartbeats only", SIGINT, true, Behaviour::EndlessHeartbeats},
                                   // the FMU's pause before it asks a busy server again (1 s; the signal at 0.8 s)
                                   {"a server busy with another session", SIGTERM, true, Behaviour::Busy}};
  const config::PortTable table = scene_table();  // the peer holds it by reference
  for (const Wait& w : waits) {
    SCOPED_TRACE(w.name);
    TempDir dir;
    std::unique_ptr<testing_support::TestPeer> peer;
    int port = 0;
    if (w.with_peer) {
      peer = std::make_unique<testing_support::TestPeer>(table, w.behaviour);
      port = peer->port();
    } else {  // a port nobody listens on: bound, then closed
      sl_socket s = SL_SOCKET_INIT;
      ASSERT_EQ(sl_listen("127.0.0.1", 0, &s), SL_OK);
      port = sl_local_port(&s);
      sl_close(&s);
    }
    auto host = start_host(dir, port, dir.path());
    std::this_thread::sleep_for(std::chrono::milliseconds(800));  // well inside the wait
    const auto sent = std::chrono::steady_clock::now();
    kill(host->pid(), w.signo);
    const int rc = host->wait(kHardTimeout);
    const double latency = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    EXPECT_EQ(rc, 128 + w.signo) << host->output();
    EXPECT_LT(latency, kWaitStopBound) << host->output();
    std::printf("%s, signal %d: stopped %.0f ms after it\n", w.name, w.signo, 1000.0 * latency);
    EXPECT_EQ(fmu_folders(dir.path()), 0u) << "the FMU folder is removed";
    if (peer) peer->join();
  }
}

// With --checkpoint the first SIGTERM asks for a checkpoint of both sides,
// which needs the link: the step in flight is not cut (the waits run on).
// A peer that never answers cannot give one, so the user sends a second
// signal: that one ends the FMU's wait, and the host still cleans up (its
// FMU folder removed, exit 128 + N) rather than dying where it stands.
TEST(Signals, WithCheckpointsASecondSignalEndsAWaitTheFirstLetRun) {
  const config::PortTable table = scene_table();
  testing_support::TestPeer peer(table, testing_support::TestPeer::Behaviour::EndlessHeartbeats);
  TempDir dir;
  setenv("TMPDIR", dir.path().c_str(), 1);
  ChildProcess host({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
                     "127.0.0.1:" + std::to_string(peer.port()), "--out", dir.file("host.h5"), "--quiet",
                     "--checkpoint", dir.file("host.ckpt"), "--set", "simulation.stoptime=100", "--set",
                     "piston.verbose=0"});
  unsetenv("TMPDIR");
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  kill(host.pid(), SIGTERM);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  int status = 0;
  ASSERT_EQ(::waitpid(host.pid(), &status, WNOHANG), 0) << "the first signal lets the step run on\n" << host.output();
  const auto sent = std::chrono::steady_clock::now();
  kill(host.pid(), SIGTERM);
  EXPECT_EQ(host.wait(kHardTimeout), 128 + SIGTERM) << host.output();
  const double latency = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  EXPECT_LT(latency, kWaitStopBound) << host.output();
  std::printf("the second signal stopped it %.0f ms after it\n", 1000.0 * latency);
  EXPECT_EQ(fmu_folders(dir.path()), 0u) << "the FMU folder is removed";
  peer.join();
}

// kill -9 before the host connects: the results file exists with every
// series declared and 0 rows, and opens (as an SWMR reader: its writer never
// closed it). It was 48 bytes that did not open.
TEST(Signals, AServerKilledMinus9BeforeItsHostCameLeavesAFileThatOpens) {
  TempDir dir;
  Server server(dir);
  ASSERT_GT(server.port, 0) << server.child->output();
  // The port is bound first (a host may connect during a relaxation); the
  // file is made, flushed, and then the server says it is listening.
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.child->output().find("listening on") == std::string::npos && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_NE(server.child->output().find("listening on"), std::string::npos) << server.child->output();
  kill(server.child->pid(), SIGKILL);
  EXPECT_EQ(server.child->wait(kHardTimeout), -1000 - SIGKILL);
  const auto series = h5io::list_series(server.out);
  ASSERT_GT(series.size(), 5u) << "time, the ports and the energies are declared";
  for (const auto& [name, rows] : series) EXPECT_EQ(rows, 0u) << name;
  EXPECT_TRUE(h5io::read_series(server.out, "time").empty());
  expect_opens_as_users_do(server.out, 0);
}
