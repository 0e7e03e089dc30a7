// Shared by the integration tests: a real fe_server process for the one-DOF
// scene on an ephemeral loopback port, under a hard time-out.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "config/port_table.hpp"
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

}  // namespace
