// Shared by the integration tests: a real fe_server process for the one-DOF
// scene on an ephemeral loopback port, under a hard time-out.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "coupling_client.hpp"
#include "fmu_importer.hpp"
#include "h5io/timeseries.hpp"
#include "test_peer.hpp"
#include "process.hpp"

namespace {

using testing_support::ChildProcess;
using testing_support::TempDir;

inline const std::string kScene = PCS_SCENES_DIR "/one_dof";
constexpr double kHardTimeout = 20.0;  // no test waits longer for a child

class Server {
 public:
  explicit Server(const TempDir& dir, std::vector<std::string> extra = {}) : out(dir.file("fe.h5")) {
    std::vector<std::string> argv = {PCS_FE_SERVER_EXE, "--model",     kScene + "/piston.k", "--ports",
                                     kScene + "/ports.cfg", "--listen", "127.0.0.1:0",      "--port-file",
                                     dir.file("port"),      "--out",    out,                "--accept-timeout",
                                     "10"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    child = std::make_unique<ChildProcess>(argv);
    port = testing_support::read_port_file(dir.file("port"), 10.0);
  }
  std::unique_ptr<ChildProcess> child;
  std::string out;
  int port = -1;
};

inline config::PortTable scene_table() { return config::read_port_table(kScene + "/ports.cfg"); }

// An instance of `archive` through the host's importer, initialized and
// connected to fe_server at 127.0.0.1:port; with resume_step ≥ 0 it resumes
// a restarted session after that many coupling steps.
inline std::unique_ptr<tlm::FmuInstance> connected_fmu(const std::shared_ptr<tlm::FmuArchive>& archive,
                                                       const std::string& name, int port, long resume_step = -1) {
  auto fmu = std::make_unique<tlm::FmuInstance>(archive, name, false);
  fmu->set_string(fmu->vr("server.host"), "127.0.0.1");
  fmu->set_integer(fmu->vr("server.port"), port);
  fmu->setup_experiment(0.0, 0.0);
  fmu->enter_initialization();
  if (resume_step >= 0) fmu->resume(static_cast<unsigned long long>(resume_step));
  fmu->exit_initialization();
  return fmu;
}

// After strangers were refused the server still serves the real host: a
// short session, a clean end, and each refusal logged with the peer's address.
inline void expect_real_host_served(Server& server, const std::string& token = testing_support::session_token()) {
  config::PortTable t = scene_table();
  pcs_fmu::CouplingClient client(t);
  client.connect("127.0.0.1", server.port, token, 10.0);
  std::vector<double> in = {1.0e7}, out;
  for (uint64_t k = 0; k < 3; ++k) client.step(k, static_cast<double>(k) * t.dt, t.dt, in, out);
  client.bye();
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
  EXPECT_EQ(h5io::read_series(server.out, "time").size(), 3u);
  EXPECT_NE(server.child->output().find("fe_server: refused 127.0.0.1:"), std::string::npos) << server.child->output();
}

}  // namespace
