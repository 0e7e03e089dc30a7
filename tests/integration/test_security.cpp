// Tokens (issue 17, item 3): never on a command line, never on the wire, a
// private file or the environment, both sides prove they know it, and off
// loopback a short token is refused.
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "coupling_client.hpp"
#include "h5io/timeseries.hpp"
#include "integration_support.hpp"
#include "socketlib/protocol.h"
#include "test_peer.hpp"

namespace {

// A TCP relay on loopback between one client and the server that keeps a
// copy of every byte in both directions: a capture of the wire.
class WireTap {
 public:
  explicit WireTap(int server_port) : server_port_(server_port) {
    if (sl_listen("127.0.0.1", 0, &listener_) != SL_OK) throw std::runtime_error("WireTap: cannot listen");
    port = sl_local_port(&listener_);
    thread_ = std::thread([this] { relay(); });
  }
  ~WireTap() {
    if (thread_.joinable()) thread_.join();
    sl_close(&listener_);
  }
  std::string captured() {
    if (thread_.joinable()) thread_.join();
    return bytes_;
  }
  int port = 0;

 private:
  void relay() {
    const int64_t deadline = sl_now_ms() + 30000;  // hard bound on the whole relay
    sl_socket a = SL_SOCKET_INIT, b = SL_SOCKET_INIT;
    if (sl_accept(&listener_, deadline, &a) != SL_OK) return;
    if (sl_connect("127.0.0.1", server_port_, deadline, &b) != SL_OK) {
      sl_close(&a);
      return;
    }
    char buf[65536];
    for (bool open = true; open && sl_now_ms() < deadline;) {
      pollfd p[2] = {{a.fd, POLLIN, 0}, {b.fd, POLLIN, 0}};
      if (poll(p, 2, 200) <= 0) continue;
      for (int i = 0; i < 2 && open; ++i) {
        if (!(p[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
        sl_socket& from = i == 0 ? a : b;
        sl_socket& to = i == 0 ? b : a;
        const ssize_t n = ::recv(from.fd, buf, sizeof buf, 0);
        if (n <= 0) {
          open = false;
          break;
        }
        bytes_.append(buf, static_cast<size_t>(n));
        if (sl_send_all(&to, buf, static_cast<size_t>(n), deadline) != SL_OK) open = false;
      }
    }
    sl_close(&a);
    sl_close(&b);
  }
  int server_port_;
  sl_socket listener_ = SL_SOCKET_INIT;
  std::thread thread_;
  std::string bytes_;
};

std::string read_whole(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

TEST(Token, NeverTakenFromTheCommandLine) {
  TempDir dir;
  ChildProcess fe({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg", "--token",
                   "correct-horse"});
  EXPECT_EQ(fe.wait(kHardTimeout), 2) << fe.output();
  EXPECT_NE(fe.output().find("--token-file"), std::string::npos) << fe.output();
  ChildProcess host({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--token", "correct-horse"});
  EXPECT_EQ(host.wait(kHardTimeout), 2) << host.output();
  EXPECT_NE(host.output().find("visible to every local user"), std::string::npos) << host.output();
  ChildProcess set({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--set", "piston.token=correct-horse"});
  EXPECT_EQ(set.wait(kHardTimeout), 2) << set.output();
}

TEST(Token, FileMustBePrivateToItsOwner) {
  TempDir dir;
  const std::string path = dir.private_file("token", "correct-horse");
  std::filesystem::permissions(path, std::filesystem::perms::group_read, std::filesystem::perm_options::add);
  ChildProcess fe({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                   "--token-file", path});
  EXPECT_EQ(fe.wait(kHardTimeout), 2) << fe.output();
  EXPECT_NE(fe.output().find("mode 0640"), std::string::npos) << fe.output();
  EXPECT_NE(fe.output().find("chmod 600"), std::string::npos) << fe.output();
  ChildProcess missing({PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports", kScene + "/ports.cfg",
                        "--token-file", dir.file("nope")});
  EXPECT_EQ(missing.wait(kHardTimeout), 2) << missing.output();
  EXPECT_NE(missing.output().find(dir.file("nope")), std::string::npos) << missing.output();
}

// Binding all interfaces needs a token of 16 characters or more. (The
// servers here bind 0.0.0.0 but nothing connects to them from outside
// loopback: the last one gives up after its 0.5 s accept deadline.)
TEST(Token, OffLoopbackAShortOrEmptyTokenIsRefused) {
  TempDir dir;
  const std::vector<std::string> base = {PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports",
                                         kScene + "/ports.cfg", "--listen", "0.0.0.0:0", "--accept-timeout", "0.5",
                                         "--port-file", dir.file("port"), "--out", dir.file("fe.h5")};
  ChildProcess none(base);
  EXPECT_EQ(none.wait(kHardTimeout), 2) << none.output();
  EXPECT_NE(none.output().find("off loopback: a token of at least 16 characters is required (none given)"),
            std::string::npos)
      << none.output();
  auto with = base;
  with.insert(with.end(), {"--token-file", dir.private_file("short", "8chars!!")});
  ChildProcess shortish(with);
  EXPECT_EQ(shortish.wait(kHardTimeout), 2) << shortish.output();
  EXPECT_NE(shortish.output().find("got 8"), std::string::npos) << shortish.output();
  // A name is not an address: one that merely starts with "127." may resolve anywhere.
  auto named = base;
  named[6] = "127.0.0.1.example:0";
  ChildProcess by_name(named);
  EXPECT_EQ(by_name.wait(kHardTimeout), 2) << by_name.output();
  EXPECT_NE(by_name.output().find("off loopback"), std::string::npos) << by_name.output();
  auto good = base;
  good.insert(good.end(), {"--token-file", dir.private_file("good", "0123456789abcdef0123")});
  ChildProcess fine(good);
  EXPECT_EQ(fine.wait(kHardTimeout), 4) << "a long token starts the server; no host comes\n" << fine.output();
}

// A whole session through a relay that records the wire: the session runs,
// and the token is neither in the capture nor in the server's command line.
TEST(Token, NeverCrossesTheWireNorAppearsInTheProcessTable) {
  TempDir dir;
  const std::string token = "correct-horse-battery-staple-17";
  const std::string token_file = dir.private_file("token", token);
  Server server(dir, {"--token-file", token_file});
  ASSERT_GT(server.port, 0) << server.child->output();
  const std::string cmdline = read_whole("/proc/" + std::to_string(server.child->pid()) + "/cmdline");
  EXPECT_NE(cmdline.find("--token-file"), std::string::npos) << "the cmdline was read";
  EXPECT_EQ(cmdline.find(token), std::string::npos);
  WireTap tap(server.port);
  ChildProcess host({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--fmu", PCS_ONE_DOF_FMU, "--server",
                     "127.0.0.1:" + std::to_string(tap.port), "--token-file", token_file, "--out", dir.file("host.h5"),
                     "--quiet", "--set", "simulation.stoptime=0.002", "--set", "piston.verbose=0"});
  EXPECT_EQ(host.wait(kHardTimeout), 0) << host.output();
  EXPECT_EQ(server.child->wait(kHardTimeout), 0) << server.child->output();
  const std::string wire = tap.captured();
  EXPECT_GT(wire.size(), 1000u) << "the relay carried the session";
  EXPECT_EQ(wire.find(token), std::string::npos) << "the token crossed the wire";
  EXPECT_EQ(wire.find(token.substr(0, 8)), std::string::npos) << "part of the token crossed the wire";
}

// The host checks the server's proof before it proves anything itself: a
// server that does not know the token learns nothing and is refused.
TEST(Token, TheHostRefusesAServerThatCannotProveTheToken) {
  config::PortTable t = scene_table();
  testing_support::TestPeer impostor(t, testing_support::TestPeer::Behaviour::Echo, "not-the-token");
  pcs_fmu::CouplingClient client(t);
  try {
    client.connect("127.0.0.1", impostor.port(), "the-real-token", 5.0);
    FAIL() << "a server without the token must be refused";
  } catch (const pcs_fmu::LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("could not prove it knows our token"), std::string::npos) << e.what();
  }
  impostor.join();
  EXPECT_EQ(impostor.error(), "client aborted the handshake") << "the host sent no proof of its own";
}
