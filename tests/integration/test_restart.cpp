// Checkpoint and restart (issue 18, item 3): a run stopped by a signal, or
// killed outright after a periodic checkpoint (a lost node), continues from
// its checkpoints and writes exactly the results an uninterrupted run
// writes: every series of both sides' files compared bit for bit. There is
// no tolerance: the restart restores every value the next step reads, and
// the arithmetic after it is the same arithmetic in the same order.
// Checkpoints of another step, deck, port table or model are refused with
// what differs.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "../fe_server/impact_decks.hpp"
#include "../scenes/hammer_two_fmus.hpp"
#include "config/checkpoint.hpp"
#include "h5io/timeseries.hpp"
#include "integration_support.hpp"
#include "output/checkpoint.hpp"

namespace {

namespace fs = std::filesystem;

constexpr double kRunTimeout = 120.0;  // no wait is longer (the sanitizer build is slow)

// Every series of `a` is in `b` with the same rows, bit for bit.
void expect_identical_files(const std::string& a, const std::string& b) {
  const auto series = h5io::list_series(a);
  ASSERT_GT(series.size(), 3u) << a;
  size_t differing = 0;
  for (const auto& [name, rows] : series) {
    const std::vector<double> x = h5io::read_series(a, name), y = h5io::read_series(b, name);
    if (x.size() != y.size() || (!x.empty() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) != 0)) {
      if (++differing <= 5) {
        size_t at = 0;
        while (at < std::min(x.size(), y.size()) && std::memcmp(&x[at], &y[at], sizeof(double)) == 0) ++at;
        ADD_FAILURE() << name << ": " << x.size() << " rows against " << y.size() << ", first difference at row " << at;
      }
    }
  }
  EXPECT_EQ(differing, 0u) << a << " against " << b << ", " << series.size() << " series";
}

// The field snapshot files hold the same datasets with the same values.
herr_t collect(hid_t, const char* name, const H5O_info_t* info, void* out) {
  if (info->type == H5O_TYPE_DATASET) static_cast<std::vector<std::string>*>(out)->push_back(name);
  return 0;
}
std::vector<double> read_all(hid_t f, const std::string& name) {
  hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  hid_t space = H5Dget_space(d);
  std::vector<double> v(static_cast<size_t>(H5Sget_simple_extent_npoints(space)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(space);
  H5Dclose(d);
  return v;
}
void expect_identical_field_files(const std::string& a, const std::string& b) {
  hid_t fa = H5Fopen(a.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), fb = H5Fopen(b.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(fa, 0) << a;
  ASSERT_GE(fb, 0) << b;
  std::vector<std::string> na, nb;
  H5Ovisit2(fa, H5_INDEX_NAME, H5_ITER_INC, collect, &na, H5O_INFO_BASIC);
  H5Ovisit2(fb, H5_INDEX_NAME, H5_ITER_INC, collect, &nb, H5O_INFO_BASIC);
  EXPECT_EQ(na, nb);
  EXPECT_GT(na.size(), 15u * 8u) << "15 snapshots and the mesh";
  size_t differing = 0;
  for (const auto& n : na)
    if (std::find(nb.begin(), nb.end(), n) != nb.end() && read_all(fa, n) != read_all(fb, n)) ++differing;
  EXPECT_EQ(differing, 0u);
  H5Fclose(fa);
  H5Fclose(fb);
}

// Every file in `dir`, byte for byte (its name to its contents).
std::map<std::string, std::string> files_of(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    std::ifstream f(e.path(), std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    out[e.path().filename().string()] = s.str();
  }
  return out;
}

// Every file in `before` is still there with the same bytes (a server's
// port file, its rendezvous with the host and no result, may be rewritten).
void expect_untouched(const std::map<std::string, std::string>& before, const std::string& dir) {
  const auto now = files_of(dir);
  for (const auto& [name, bytes] : before) {
    if (name.size() > 5 && name.compare(name.size() - 5, 5, ".port") == 0) continue;
    const auto it = now.find(name);
    if (it == now.end()) ADD_FAILURE() << name << " is gone";
    else EXPECT_TRUE(it->second == bytes) << name << " changed (" << bytes.size() << " -> " << it->second.size() << " bytes)";
  }
}

// Rows of the running host's results file that are already on disk (it
// flushes at least once a second; read as an SWMR reader).
size_t rows_on_disk(const std::string& path) {
  try {
    for (const auto& [name, rows] : h5io::list_series(path))
      if (name == "time") return rows;
  } catch (const std::exception&) {
    // not created yet
  }
  return 0;
}

// Waits until the host has written more than `rows` rows: it is mid-run,
// whatever the machine's load (a fixed sleep could land before its first
// step or after its last).
void wait_for_rows(const std::string& path, size_t rows, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (rows_on_disk(path) <= rows && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

void wait_for_file(const std::string& path, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!fs::exists(path) && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

// ---------------------------------------------------------------- standalone

// The coaxial bar impact with a plastic tool (yield 100 MPa below the
// 162 MPa pulse, kinematic hardening: back stresses), contact, and node and
// solid histories: every kind of state a step carries; field snapshots if
// asked for.
std::string plastic_impact_deck(double end_time, bool snapshots) {
  std::string d = fe_test::bar_impact_deck(0.1, 0.2, 0.01, 0.005, 8.0, fe_test::kE);
  const std::string tool_part = "*PART\ntool\n2,1,2\n";
  const size_t at = d.find(tool_part);
  if (at == std::string::npos) return "";
  d.replace(at, tool_part.size(), "*PART\ntool\n2,1,3\n");
  std::ostringstream s;
  s << d << "*MAT_PLASTIC_KINEMATIC\n3,7850,2.1e11,0.3,1.0e8,2.0e9,0.0\n"
    << "*DATABASE_HISTORY_NODE\n1,100001\n*DATABASE_HISTORY_SOLID\n1,2\n*CONTROL_TERMINATION\n" << end_time << "\n";
  if (snapshots) {  // and LS-DYNA's ASCII files (comma cards: no 10-column limit)
    s << "*DATABASE_BINARY_D3PLOT\n" << end_time / 15 << "\n";
    for (const char* kw : {"GLSTAT", "MATSUM", "RCFORC", "NODOUT", "ELOUT"})
      s << "*DATABASE_" << kw << "\n" << end_time / 40 << ",\n";
  }
  return s.str();
}

struct Standalone {
  TempDir dir;
  std::string deck = dir.file("impact.k");
  Standalone(double end_time, bool snapshots) { std::ofstream(deck) << plastic_impact_deck(end_time, snapshots); }
  std::vector<std::string> args(const std::string& out, std::vector<std::string> extra) const {
    std::vector<std::string> a{PCS_FE_SERVER_EXE, "--model", deck, "--out", dir.file(out)};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
};

// ---------------------------------------------------------------- co-simulation

const std::string kHammer = PCS_SCENES_DIR "/hammer";
const std::string kHammerBuilt = PCS_BUILD_SCENES_DIR "/hammer";
// s of hammer time: the piston lifts, the valve switches. About 2.5 s of
// wall time here: the results file's first flush (after 1 s) is mid-run.
constexpr double kStop = 0.04;

struct CoSim {
  std::unique_ptr<ChildProcess> server, host;
};

// fe_server and tlm_host on loopback; files `tag`_fe.h5 and `tag`_host.h5 in dir.
CoSim start(const TempDir& dir, const std::string& tag, const std::vector<std::string>& server_extra,
            const std::vector<std::string>& host_extra, const std::string& deck = kHammerBuilt + "/deck.k",
            const std::string& ports = kHammer + "/ports.cfg", const std::string& model = kHammer + "/model.tlm") {
  CoSim c;
  const std::string port_file = dir.file(tag + ".port");
  fs::remove(port_file);
  std::vector<std::string> s{PCS_FE_SERVER_EXE, "--model", deck, "--ports", ports, "--listen", "127.0.0.1:0",
                             "--port-file", port_file, "--out", dir.file(tag + "_fe.h5"), "--accept-timeout", "30"};
  s.insert(s.end(), server_extra.begin(), server_extra.end());
  c.server = std::make_unique<ChildProcess>(s);
  const int port = testing_support::read_port_file(port_file, 30.0);
  EXPECT_GT(port, 0) << c.server->output();
  std::vector<std::string> h{PCS_TLM_HOST_EXE, model, "--fmu", kHammerBuilt + "/hammer.fmu", "--server",
                             "127.0.0.1:" + std::to_string(port), "--out", dir.file(tag + "_host.h5"), "--set",
                             "simulation.stoptime=" + std::to_string(kStop)};
  h.insert(h.end(), host_extra.begin(), host_extra.end());
  c.host = std::make_unique<ChildProcess>(h);
  return c;
}

// Exit 4 of a completed host run is its report's complaint that 30 ms hold
// no settled blows (the run itself completed); any other failure is not.
void expect_completed(CoSim& c) {
  const int rc = c.host->wait(kRunTimeout);
  EXPECT_TRUE(rc == 0 || (rc == 4 && c.host->output().find("tlm_host: report: ") != std::string::npos))
      << c.host->output();
  EXPECT_EQ(c.server->wait(kRunTimeout), 0) << c.server->output();
}

// The uninterrupted run; returns its rows.
size_t reference(const TempDir& dir) {
  CoSim c = start(dir, "ref", {}, {});
  expect_completed(c);
  return rows_on_disk(dir.file("ref_host.h5"));
}

}  // namespace

// Without field snapshots: those are not written in SWMR mode, and a kill
// in the middle of one leaves their file unreadable (fe_server says so).
TEST(Restart, AStandaloneRunKilledMinus9ContinuesFromItsLastCheckpointBitForBit) {
  Standalone s(0.0015, false);
  ChildProcess full(s.args("full.h5", {"--quiet"}));
  ASSERT_EQ(full.wait(kRunTimeout), 0) << full.output();

  // Checkpoints every 0.12 s of wall time; killed without warning after the first.
  const std::string ckpt = s.dir.file("part.ckpt");
  ChildProcess doomed(s.args("part.h5", {"--checkpoint", ckpt, "--checkpoint-every", "0.002"}));
  wait_for_file(ckpt, 60.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ::kill(doomed.pid(), SIGKILL);
  ASSERT_EQ(doomed.wait(kRunTimeout), -1000 - SIGKILL)
      << "the run must still be going when it is killed (make the deck longer):\n" << doomed.output();
  ASSERT_TRUE(fs::exists(ckpt)) << doomed.output();

  ChildProcess resumed(s.args("part.h5", {"--restart", ckpt}));
  ASSERT_EQ(resumed.wait(kRunTimeout), 0) << resumed.output();
  EXPECT_NE(resumed.output().find("restarted from"), std::string::npos) << resumed.output();
  expect_identical_files(s.dir.file("full.h5"), s.dir.file("part.h5"));
}

TEST(Restart, AStandaloneRunStoppedBySigtermWritesItsCheckpointAndContinuesBitForBit) {
  Standalone s(0.003, true);  // about 2.7 s: the results' first flush (after 1 s) comes mid-run
  // Each run in its own folder: the ASCII files (glstat, ...) go next to the results.
  fs::create_directories(s.dir.file("full"));
  fs::create_directories(s.dir.file("part"));
  ChildProcess full(s.args("full/fe.h5", {"--quiet"}));
  ASSERT_EQ(full.wait(kRunTimeout), 0) << full.output();
  const std::string ckpt = s.dir.file("part.ckpt");
  ChildProcess stopped(s.args("part/fe.h5", {"--checkpoint", ckpt}));
  wait_for_rows(s.dir.file("part/fe.h5"), 0, kRunTimeout);  // stepping, whatever the machine's load
  ::kill(stopped.pid(), SIGTERM);
  ASSERT_EQ(stopped.wait(kRunTimeout), 128 + SIGTERM) << stopped.output();
  EXPECT_NE(stopped.output().find("checkpoint in " + ckpt), std::string::npos) << stopped.output();
  ChildProcess resumed(s.args("part/fe.h5", {"--restart", ckpt, "--threads", "2"}));  // any thread count: same bits
  ASSERT_EQ(resumed.wait(kRunTimeout), 0) << resumed.output();
  expect_identical_files(s.dir.file("full/fe.h5"), s.dir.file("part/fe.h5"));
  // The field snapshots continue too: the same snapshots, the same index.
  expect_identical_field_files(s.dir.file("full/fe_fields.h5"), s.dir.file("part/fe_fields.h5"));
  auto text = [](const std::string& path, bool skip_clock = false) {
    std::ifstream in(path);
    std::string t;
    for (std::string l; std::getline(in, l);)  // the wall clock's lines differ from run to run
      if (!skip_clock || (l.find("time per zone cycle") == std::string::npos && l.find(" date ") == std::string::npos))
        t += l + "\n";
    return t;
  };
  EXPECT_EQ(text(s.dir.file("full/fe_fields.xdmf")), text(s.dir.file("part/fe_fields.xdmf")));
  // And LS-DYNA's ASCII files: the same blocks, none twice.
  for (const char* name : {"glstat", "matsum", "rcforc", "nodout", "elout"}) {
    const std::string a = text(s.dir.file(std::string("full/") + name), true);
    EXPECT_GT(a.size(), 1000u) << name;
    EXPECT_EQ(a, text(s.dir.file(std::string("part/") + name), true)) << name;
  }
}

// The case: the host stopped at about half time by SIGTERM, both
// sides restarted from their checkpoints.
TEST(Restart, ACoSimulationStoppedByTheHostsSigtermContinuesBitForBitOnBothSides) {
  TempDir dir;
  const size_t rows = reference(dir);
  CoSim c = start(dir, "run", {}, {"--checkpoint", dir.file("host.ckpt")});
  wait_for_rows(dir.file("run_host.h5"), 0, kRunTimeout);
  ASSERT_LT(rows_on_disk(dir.file("run_host.h5")), rows) << "the run must still be going";
  ::kill(c.host->pid(), SIGTERM);
  ASSERT_EQ(c.host->wait(kRunTimeout), 128 + SIGTERM) << "stopped mid-run:\n" << c.host->output();
  EXPECT_EQ(c.server->wait(kRunTimeout), 10) << c.server->output();  // ended after a checkpoint
  ASSERT_TRUE(fs::exists(dir.file("run_fe.ckpt"))) << c.server->output();

  {  // A restarted server killed -9 while it waits for its host (a batch job
     // killed at its wall time before the host came) leaves its results as
     // they were, readable: it continues them only once the host resumed.
     // (It once left a file that opened neither as an SWMR reader nor plainly.)
    const auto before = files_of(dir.path());
    const size_t rows = rows_on_disk(dir.file("run_fe.h5"));
    ChildProcess waiting({PCS_FE_SERVER_EXE, "--model", kHammerBuilt + "/deck.k", "--ports", kHammer + "/ports.cfg",
                          "--listen", "127.0.0.1:0", "--port-file", dir.file("waiting.port"), "--out",
                          dir.file("run_fe.h5"), "--restart", dir.file("run_fe.ckpt"), "--accept-timeout", "30"});
    ASSERT_GT(testing_support::read_port_file(dir.file("waiting.port"), 30.0), 0) << waiting.output();
    // Killed once it says it waits (everything before the host is done).
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (waiting.output().find("listening on") == std::string::npos && std::chrono::steady_clock::now() < end)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_NE(waiting.output().find("listening on"), std::string::npos) << waiting.output();
    ::kill(waiting.pid(), SIGKILL);
    EXPECT_EQ(waiting.wait(kRunTimeout), -1000 - SIGKILL);
    expect_untouched(before, dir.path());
    EXPECT_EQ(rows_on_disk(dir.file("run_fe.h5")), rows) << "it opens with its rows";
    // Any rows at all: how many depends on when the SIGTERM came (99 under
    // ASan on a loaded machine); the bytes are checked by expect_untouched.
    EXPECT_GT(rows, 0u);
  }
  // And the restart that follows still continues bit for bit.
  CoSim r = start(dir, "run", {"--restart", dir.file("run_fe.ckpt")}, {"--restart", dir.file("host.ckpt")});
  expect_completed(r);
  EXPECT_NE(r.server->output().find("restarted from"), std::string::npos) << r.server->output();
  expect_identical_files(dir.file("ref_host.h5"), dir.file("run_host.h5"));
  expect_identical_files(dir.file("ref_fe.h5"), dir.file("run_fe.h5"));
}

// A cluster's wall-time limit: SIGTERM reaches fe_server only; it asks the
// host for the checkpoint of both sides.
TEST(Restart, ACoSimulationWhoseServerGotSigtermContinuesBitForBitOnBothSides) {
  TempDir dir;
  const size_t rows = reference(dir);
  CoSim c = start(dir, "run", {}, {});
  wait_for_rows(dir.file("run_host.h5"), 0, kRunTimeout);
  ASSERT_LT(rows_on_disk(dir.file("run_host.h5")), rows) << "the run must still be going";
  ::kill(c.server->pid(), SIGTERM);
  ASSERT_EQ(c.host->wait(kRunTimeout), 10) << "stopped mid-run:\n" << c.host->output();
  EXPECT_EQ(c.server->wait(kRunTimeout), 128 + SIGTERM) << c.server->output();
  // Without --checkpoint the host's checkpoint goes next to its results.
  CoSim r = start(dir, "run", {"--restart", dir.file("run_fe.ckpt")}, {"--restart", dir.file("run_host.ckpt")});
  expect_completed(r);
  expect_identical_files(dir.file("ref_host.h5"), dir.file("run_host.h5"));
  expect_identical_files(dir.file("ref_fe.h5"), dir.file("run_fe.h5"));
}

// Two FMUs in one session (piston and valve, stepped concurrently): the
// host asks both at once, fe_server checkpoints when both have asked, both
// resume. SIGTERM to the server, so both FMUs also see STOPPING.
TEST(Restart, TwoFmusOnOneSessionCheckpointAndResumeTogetherBitForBit) {
  TempDir dir;
  const std::string model = dir.file("model.tlm");
  std::ofstream(model) << hammer_model_with_two_fmus(kHammer, kHammerBuilt);
  auto run = [&](const std::string& tag, std::vector<std::string> server_extra, std::vector<std::string> host_extra) {
    CoSim c;
    const std::string port_file = dir.file(tag + ".port");
    fs::remove(port_file);
    std::vector<std::string> s{PCS_FE_SERVER_EXE, "--model", kHammerBuilt + "/deck.k", "--ports",
                               kHammer + "/two_fmus/piston.cfg", "--ports", kHammer + "/two_fmus/valve.cfg", "--listen",
                               "127.0.0.1:0", "--port-file", port_file, "--out", dir.file(tag + "_fe.h5"),
                               "--accept-timeout", "30"};
    s.insert(s.end(), server_extra.begin(), server_extra.end());
    c.server = std::make_unique<ChildProcess>(s);
    const int port = testing_support::read_port_file(port_file, 30.0);
    EXPECT_GT(port, 0) << c.server->output();
    std::vector<std::string> h{PCS_TLM_HOST_EXE, model, "--server", "127.0.0.1:" + std::to_string(port), "--out",
                               dir.file(tag + "_host.h5"), "--set", "simulation.stoptime=0.1", "--set",
                               "simulation.timestep=1e-5", "--set", "simulation.log_every=1"};
    h.insert(h.end(), host_extra.begin(), host_extra.end());
    c.host = std::make_unique<ChildProcess>(h);
    return c;
  };
  CoSim ref = run("ref", {}, {});
  expect_completed(ref);
  const size_t rows = rows_on_disk(dir.file("ref_host.h5"));
  CoSim c = run("run", {}, {});
  wait_for_rows(dir.file("run_host.h5"), 0, kRunTimeout);
  ASSERT_LT(rows_on_disk(dir.file("run_host.h5")), rows) << "the run must still be going";
  ::kill(c.server->pid(), SIGTERM);
  ASSERT_EQ(c.host->wait(kRunTimeout), 10) << c.host->output();
  EXPECT_EQ(c.server->wait(kRunTimeout), 128 + SIGTERM) << c.server->output();
  CoSim r = run("run", {"--restart", dir.file("run_fe.ckpt")}, {"--restart", dir.file("run_host.ckpt")});
  expect_completed(r);
  expect_identical_files(dir.file("ref_host.h5"), dir.file("run_host.h5"));
  expect_identical_files(dir.file("ref_fe.h5"), dir.file("run_fe.h5"));
}

// A lost node: both processes killed outright (kill -9) after the host's
// periodic checkpoints (--checkpoint-every) have begun. The pair of files of
// one step restarts the run, bit for bit: the host's checkpoint and
// fe_server's of its step (its newest, or FILE.prev when the kill came
// between the two sides' writes). Both results files were left marked as
// being written; the restart continues them.
TEST(Restart, ACoSimulationKilledMinus9ContinuesFromItsLastPeriodicCheckpointsBitForBit) {
  TempDir dir;
  const size_t rows = reference(dir);
  const std::string host_ckpt = dir.file("run_host.ckpt");
  CoSim c = start(dir, "run", {}, {"--checkpoint", host_ckpt, "--checkpoint-every", "0.002"});  // every 0.12 s
  wait_for_file(host_ckpt, kRunTimeout);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_LT(rows_on_disk(dir.file("run_host.h5")), rows) << "the run must still be going";
  ::kill(c.host->pid(), SIGKILL);
  ::kill(c.server->pid(), SIGKILL);
  c.host->wait(kRunTimeout);
  c.server->wait(kRunTimeout);
  // The steps the two sides' files hold (their identity records).
  config::StateReader host(host_ckpt);
  host.expect("kind", std::string("tlm_host"), "program");
  host.expect("model digest", config::file_sha256(kHammer + "/model.tlm"), "model");
  std::string logged;
  host.text("logged series", logged);  // which series: another test checks it is compared
  uint64_t fs = 0;
  host.value("timestep", fs);
  long step = 0;
  host.value("step", step);
  const fe::CheckpointIdentity id{config::file_sha256(kHammerBuilt + "/deck.k"),
                                  config::read_port_table(kHammer + "/ports.cfg").hash(), 0};
  std::string fe_ckpt = dir.file("run_fe.ckpt");
  if (fe::checkpoint_step(fe_ckpt, id) != step) fe_ckpt += ".prev";
  ASSERT_EQ(fe::checkpoint_step(fe_ckpt, id), step) << "fe_server's checkpoint of the host's step";
  CoSim r = start(dir, "run", {"--restart", fe_ckpt}, {"--restart", host_ckpt});
  expect_completed(r);
  expect_identical_files(dir.file("ref_host.h5"), dir.file("run_host.h5"));
  expect_identical_files(dir.file("ref_fe.h5"), dir.file("run_fe.h5"));
}

TEST(Restart, CheckpointsOfAnotherStepDeckPortTableOrModelAreRefusedSayingWhat) {
  TempDir dir;
  // Checkpoints of both sides at step k1: a long run stopped once it is going.
  CoSim a = start(dir, "a", {}, {"--checkpoint", dir.file("a_host.ckpt"), "--set", "simulation.stoptime=1"});
  wait_for_rows(dir.file("a_host.h5"), 0, kRunTimeout);
  ::kill(a.host->pid(), SIGTERM);
  ASSERT_EQ(a.host->wait(kRunTimeout), 128 + SIGTERM) << a.host->output();
  ASSERT_EQ(a.server->wait(kRunTimeout), 10) << a.server->output();
  // The server's checkpoint at k1 + 100: resumed at k1 by an importer that
  // steps on and asks for one (the FMU's own checkpoint functions).
  fs::copy_file(dir.file("a_fe.h5"), dir.file("b_fe.h5"));
  ChildProcess server({PCS_FE_SERVER_EXE, "--model", kHammerBuilt + "/deck.k", "--ports", kHammer + "/ports.cfg",
                       "--listen", "127.0.0.1:0", "--port-file", dir.file("b.port"), "--out", dir.file("b_fe.h5"),
                       "--restart", dir.file("a_fe.ckpt"), "--checkpoint", dir.file("b_fe.ckpt"), "--accept-timeout",
                       "30"});
  const int port = testing_support::read_port_file(dir.file("b.port"), 30.0);
  ASSERT_GT(port, 0) << server.output();
  const std::string stopped = a.host->output();  // "stopped by SIGTERM after step K; checkpoint in ..."
  const size_t at = stopped.find("after step ");
  ASSERT_NE(at, std::string::npos) << stopped;
  const long k1 = std::stol(stopped.substr(at + 11));
  {
    auto archive = std::make_shared<tlm::FmuArchive>(kHammerBuilt + "/hammer.fmu");
    const config::PortTable t = config::read_port_table(archive->dir() + "/resources/ports.cfg");
    auto instance = connected_fmu(archive, "fe", port, k1);
    tlm::FmuInstance& fmu = *instance;
    EXPECT_EQ(fmu.checkpoint(), dir.file("b_fe.ckpt"));  // at k1 again: becomes b_fe.ckpt.prev below
    for (long k = k1; k < k1 + 100; ++k) fmu.do_step(static_cast<double>(k) * t.dt, t.dt);  // the inputs' start values
    EXPECT_EQ(fmu.checkpoint(), dir.file("b_fe.ckpt"));
    fmu.terminate();
  }
  ASSERT_EQ(server.wait(kRunTimeout), 10) << server.output();

  {  // the server at k1 + 100, the host at k1 (as a node lost between the two sides' writes leaves them):
     // both told, and told that fe_server's previous checkpoint is of the host's step
    fs::copy_file(dir.file("a_host.h5"), dir.file("b_host.h5"));
    // A refused restart touches no file: both sides check everything (the
    // other side's step included) before they continue any (they once cut
    // both results files to their checkpoints' rows, then refused).
    const auto before = files_of(dir.path());
    CoSim c = start(dir, "b", {"--restart", dir.file("b_fe.ckpt")}, {"--restart", dir.file("a_host.ckpt")});
    EXPECT_NE(c.host->wait(kRunTimeout), 0);
    EXPECT_EQ(c.server->wait(kRunTimeout), 3) << c.server->output();
    expect_untouched(before, dir.path());
    EXPECT_NE(c.server->output().find(dir.file("b_fe.h5") + " left as it was"), std::string::npos) << c.server->output();
    const std::string why = "the host resumes after step " + std::to_string(k1) +
                            ", this fe_server's checkpoint is after step " + std::to_string(k1 + 100) +
                            ": both sides must restart from checkpoints of the same step";
    EXPECT_NE(c.server->output().find(why), std::string::npos) << c.server->output();
    EXPECT_NE(c.host->output().find(why), std::string::npos) << "the host is told:\n" << c.host->output();
    EXPECT_NE(c.server->output().find(dir.file("b_fe.ckpt.prev") + " is fe_server's checkpoint of step " +
                                      std::to_string(k1) + ": restart fe_server with --restart " + dir.file("b_fe.ckpt.prev")),
              std::string::npos)
        << c.server->output();
  }

  {  // another deck: the same mesh, one comment more
    std::ofstream(dir.file("deck.k")) << std::ifstream(kHammerBuilt + "/deck.k").rdbuf() << "$ changed\n";
    for (const char* mesh : {"piston_mesh.k", "spool_mesh.k", "tool_rock.k"}) fs::copy_file(kHammerBuilt + "/" + mesh, dir.file(mesh));
    ChildProcess s({PCS_FE_SERVER_EXE, "--model", dir.file("deck.k"), "--ports", kHammer + "/ports.cfg", "--out",
                    dir.file("x.h5"), "--restart", dir.file("b_fe.ckpt"), "--accept-timeout", "5"});
    EXPECT_EQ(s.wait(kRunTimeout), 3) << s.output();
    EXPECT_NE(s.output().find("the deck's contents (SHA-256)"), std::string::npos) << s.output();
  }
  {  // another port table
    ChildProcess s({PCS_FE_SERVER_EXE, "--model", kHammerBuilt + "/deck.k", "--ports", kHammer + "/ports_tlm.cfg",
                    "--out", dir.file("b_fe.h5"), "--restart", dir.file("b_fe.ckpt"), "--accept-timeout", "5"});
    EXPECT_EQ(s.wait(kRunTimeout), 3) << s.output();
    EXPECT_NE(s.output().find("the port tables' hash"), std::string::npos) << s.output();
  }
  {  // another model on the host's side
    std::ofstream(dir.file("model.tlm")) << std::ifstream(kHammer + "/model.tlm").rdbuf() << "$ changed\n";
    ChildProcess h({PCS_TLM_HOST_EXE, dir.file("model.tlm"), "--fmu", kHammerBuilt + "/hammer.fmu", "--server",
                    "127.0.0.1:1", "--out", dir.file("a_host.h5"), "--restart", dir.file("a_host.ckpt")});
    EXPECT_EQ(h.wait(kRunTimeout), 3) << h.output();
    EXPECT_NE(h.output().find("the model file's contents (SHA-256)"), std::string::npos) << h.output();
  }
  {  // the same model writing other series (--log): the results file would
     // keep the dropped series cut at the checkpoint while the rest grow
    ChildProcess h({PCS_TLM_HOST_EXE, kHammer + "/model.tlm", "--fmu", kHammerBuilt + "/hammer.fmu", "--server",
                    "127.0.0.1:1", "--out", dir.file("a_host.h5"), "--restart", dir.file("a_host.ckpt"), "--log",
                    "components/mech"});
    EXPECT_EQ(h.wait(kRunTimeout), 3) << h.output();
    EXPECT_NE(h.output().find("the series written (*LOG, --log; SHA-256)"), std::string::npos) << h.output();
  }
  {  // a damaged file
    std::fstream f(dir.file("a_host.ckpt"), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(100);
    f.put('\x55');
    f.close();
    ChildProcess h({PCS_TLM_HOST_EXE, kHammer + "/model.tlm", "--fmu", kHammerBuilt + "/hammer.fmu", "--server",
                    "127.0.0.1:1", "--out", dir.file("a_host.h5"), "--restart", dir.file("a_host.ckpt")});
    EXPECT_EQ(h.wait(kRunTimeout), 3) << h.output();
    EXPECT_NE(h.output().find("is damaged"), std::string::npos) << h.output();
  }
}

// An importer that does not know STOPPING (it steps on, never asks for the
// checkpoint): the server serves it through the grace, then stops as it
// would have without one, telling it why. One that never even asks whether
// the server stops (FMPy, fmusim, Hopsan) is warned through its logger at
// the step the request came, once, instead of stepping on in silence.
TEST(Restart, AnImporterThatNeverCheckpointsGetsTheOldStopWhenTheGraceEnds) {
  for (const bool asks : {true, false}) {
    SCOPED_TRACE(asks ? "an importer that asks" : "an importer that never asks");
    TempDir dir;
    ChildProcess server({PCS_FE_SERVER_EXE, "--model", PCS_SCENES_DIR "/one_dof/piston.k", "--ports",
                         PCS_SCENES_DIR "/one_dof/ports.cfg", "--listen", "127.0.0.1:0", "--port-file",
                         dir.file("port"), "--out", dir.file("fe.h5"), "--accept-timeout", "20", "--stop-grace", "1"});
    const int port = testing_support::read_port_file(dir.file("port"), 20.0);
    ASSERT_GT(port, 0) << server.output();
    auto archive = std::make_shared<tlm::FmuArchive>(PCS_ONE_DOF_FMU);
    const config::PortTable t = config::read_port_table(archive->dir() + "/resources/ports.cfg");
    auto instance = connected_fmu(archive, "piston", port);
    tlm::FmuInstance& fmu = *instance;
    const unsigned p = fmu.vr("cavity.p");
    std::chrono::steady_clock::time_point signalled{}, failed{};
    bool asked = false;
    std::string error;
    testing::internal::CaptureStderr();  // the importer's logger writes there
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    for (long k = 0; error.empty() && std::chrono::steady_clock::now() < give_up; ++k) {
      if (k == 200) {
        ::kill(server.pid(), SIGTERM);
        signalled = std::chrono::steady_clock::now();
      }
      try {
        fmu.set_real(p, 1.0e7);
        fmu.do_step(static_cast<double>(k) * t.dt, t.dt);
        if (asks) asked = asked || fmu.stop_requested();
      } catch (const std::exception& e) {
        error = e.what();
        failed = std::chrono::steady_clock::now();
      }
    }
    const std::string logged = testing::internal::GetCapturedStderr();
    if (asks) EXPECT_TRUE(asked) << "the server asked for a checkpoint";
    EXPECT_NE(error.find("did not checkpoint within"), std::string::npos) << error;
    EXPECT_GE(std::chrono::duration<double>(failed - signalled).count(), 0.9) << "served through the 1 s grace";
    EXPECT_EQ(server.wait(kRunTimeout), 128 + SIGTERM) << server.output();
    const std::string warning = "asks for a checkpoint of both sides, which this importer cannot take";
    const size_t first = logged.find(warning);
    if (asks) {
      EXPECT_EQ(first, std::string::npos) << "an importer that asks is not warned:\n" << logged;
    } else {
      EXPECT_NE(first, std::string::npos) << logged;
      EXPECT_EQ(logged.find(warning, first + 1), std::string::npos) << "once:\n" << logged;
    }
  }
}
