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

// Every session needs a token, on loopback too (every local user can reach a
// loopback port, and a cluster node has many), of 16 to 255 printable ASCII
// characters wherever it comes from; the key checked is the key used, so a
// NUL cannot make a 31-byte token the empty key. Serving without a token is
// an explicit, loopback-only --insecure-no-token that warns. (Servers here
// bind 0.0.0.0 but nothing connects from outside loopback: the ones that
// start give up after their 0.5 s accept deadline, exit 4.)
TEST(Token, EverySessionNeedsAPrintableTokenOfSixteenCharacters) {
  TempDir dir;
  testing_support::ScopedEnv no_env_token("PCS_TOKEN", nullptr);
  testing_support::ScopedEnv no_env_file("PCS_TOKEN_FILE", nullptr);
  auto server = [&](const std::string& listen, std::vector<std::string> extra) {
    std::vector<std::string> argv = {PCS_FE_SERVER_EXE, "--model", kScene + "/piston.k", "--ports",
                                     kScene + "/ports.cfg", "--listen", listen, "--accept-timeout", "0.5",
                                     "--port-file", dir.file("port"), "--out", dir.file("fe.h5")};
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto child = std::make_unique<ChildProcess>(argv);
    const int rc = child->wait(kHardTimeout);
    return std::make_pair(rc, child->output());
  };
  struct Case {
    const char* name;
    std::string listen;
    std::vector<std::string> extra;
    int rc;
    std::string says;
  };
  const std::string nul_token = std::string(1, '\0') + "0123456789abcdef0123456789abcd";
  const std::vector<Case> cases = {
      {"none on loopback", "127.0.0.1:0", {}, 2, "a session needs a token of at least 16 characters, on loopback too"},
      {"none off loopback", "0.0.0.0:0", {}, 2, "a session needs a token of at least 16 characters"},
      {"short", "127.0.0.1:0", {"--token-file", dir.private_file("short", "8chars!!")}, 2,
       "the token has 8 characters, at least 16 are required"},
      {"NUL first", "127.0.0.1:0", {"--token-file", dir.private_file("nul", nul_token)}, 2,
       "the token holds byte 0x00 at position 1"},
      {"not ASCII", "127.0.0.1:0", {"--token-file", dir.private_file("utf8", "p\xc3\xa4ssword-0123456789")}, 2,
       "the token holds byte 0xc3 at position 2"},
      {"control byte", "127.0.0.1:0", {"--token-file", dir.private_file("ctl", "0123456789\x01" "abcdef0123")}, 2,
       "byte 0x01 at position 11"},
      {"no token off loopback", "0.0.0.0:0", {"--insecure-no-token"}, 2, "--insecure-no-token is for loopback only"},
      // A name is not an address: one that merely starts with "127." may resolve anywhere.
      {"a name, not loopback", "127.0.0.1.example:0", {"--insecure-no-token"}, 2, "is for loopback only"},
      {"both", "127.0.0.1:0", {"--insecure-no-token", "--token-file", dir.private_file("good", "0123456789abcdef0123")},
       2, "contradict each other"},
      {"no token, loopback, explicit", "127.0.0.1:0", {"--insecure-no-token"}, 4,
       "WARNING: --insecure-no-token: any local user can connect"},
      {"good, off loopback", "0.0.0.0:0", {"--token-file", dir.file("good")}, 4, "no host connected"},
  };
  for (const Case& c : cases) {
    const auto [rc, out] = server(c.listen, c.extra);
    EXPECT_EQ(rc, c.rc) << c.name << "\n" << out;
    EXPECT_NE(out.find(c.says), std::string::npos) << c.name << "\n" << out;
  }
  {  // the environment is held to the same rule
    testing_support::ScopedEnv short_env("PCS_TOKEN", "short");
    const auto [rc, out] = server("127.0.0.1:0", {});
    EXPECT_EQ(rc, 2) << out;
    EXPECT_NE(out.find("$PCS_TOKEN: the token has 5 characters"), std::string::npos) << out;
  }
  // The host's side too: a token file it cannot use is refused before it connects.
  ChildProcess host({PCS_TLM_HOST_EXE, kScene + "/model.tlm", "--token-file", dir.file("nul")});
  EXPECT_EQ(host.wait(kHardTimeout), 2) << host.output();
  EXPECT_NE(host.output().find("byte 0x00 at position 1"), std::string::npos) << host.output();
}

// An empty token, or one whose first byte is NUL (it once keyed the HMAC
// with ""), never authenticates against a server that has a token.
TEST(Token, AnEmptyOrNulTokenNeverAuthenticates) {
  TempDir dir;
  Server server(dir, {"--handshake-timeout", "2"});
  ASSERT_GT(server.port, 0) << server.child->output();
  pcs_fmu::CouplingClient empty(scene_table());
  try {
    empty.connect("127.0.0.1", server.port, "", 5.0);
    ADD_FAILURE() << "an empty token must be refused";
  } catch (const pcs_fmu::LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("wrong or missing token"), std::string::npos) << e.what();
  }
  pcs_fmu::CouplingClient nul(scene_table());
  try {
    nul.connect("127.0.0.1", server.port, std::string(1, '\0') + "0123456789abcdef0123456789abcd", 5.0);
    ADD_FAILURE() << "a token with a NUL must be refused";
  } catch (const pcs_fmu::LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("byte 0x00 at position 1"), std::string::npos) << e.what();
  }
  // By hand, as a stranger that keys its proof with the empty key.
  sl_socket s = SL_SOCKET_INIT;
  ASSERT_EQ(sl_connect("127.0.0.1", server.port, sl_now_ms() + 5000, &s), SL_OK);
  EXPECT_EQ(testing_support::raw_client_handshake(s, scene_table(), "", PCS_PROTOCOL_VERSION, false)
                .rfind("ABORT: wrong or missing token", 0),
            0u);
  sl_close(&s);
  expect_real_host_served(server);
}

// No offline guessing: a stranger who connects knows the table hash (the
// FMU's GUID is public) and picks its nonce. Had the server proved first (it
// did: a 3-character token fell in 0.09 s of offline guesses), its CHALLENGE
// would carry HMAC(token, ...) to check guesses against. Now everything a
// stranger receives is the same whatever the server's token: a CHALLENGE of
// the random nonce alone, then the same ABORT. Two servers with different
// tokens, the same stranger against each.
TEST(Token, AStrangerReceivesNothingThatDependsOnTheToken) {
  TempDir a_dir, b_dir;
  Server a(a_dir, {"--token-file", a_dir.private_file("token", "first-token-0123456789")});
  Server b(b_dir, {"--token-file", b_dir.private_file("token", "other-token-9876543210")});
  ASSERT_GT(a.port, 0);
  ASSERT_GT(b.port, 0);
  auto stranger = [](int port) {
    sl_socket s = SL_SOCKET_INIT;
    EXPECT_EQ(sl_connect("127.0.0.1", port, sl_now_ms() + 5000, &s), SL_OK);
    const config::PortTable t = scene_table();
    pcs_hello hello{PCS_PROTOCOL_VERSION, t.hash(), t.dt, static_cast<uint32_t>(t.subcycles), {}};
    uint8_t buf[2048];
    int n = pcs_encode_hello(&hello, buf, sizeof buf);
    EXPECT_EQ(pcs_send_frame(&s, PCS_MSG_HELLO, 0, buf, static_cast<uint32_t>(n), sl_now_ms() + 2000), SL_OK);
    std::vector<std::string> received;  // type and payload (the nonce left out) of every frame
    pcs_header h{};
    EXPECT_EQ(pcs_recv_frame(&s, &h, buf, sizeof buf, sl_now_ms() + 5000), SL_OK);
    EXPECT_EQ(h.type, PCS_MSG_CHALLENGE);
    EXPECT_EQ(h.payload_size, PCS_NONCE_SIZE) << "a CHALLENGE carries the server's nonce and nothing else";
    received.push_back(std::string(pcs_msg_name(h.type)) + " of " + std::to_string(h.payload_size) + " bytes");
    pcs_auth guess{};  // any proof: a guess
    n = pcs_encode_auth(&guess, buf, sizeof buf);
    EXPECT_EQ(pcs_send_frame(&s, PCS_MSG_AUTH, 0, buf, static_cast<uint32_t>(n), sl_now_ms() + 2000), SL_OK);
    while (pcs_recv_frame(&s, &h, buf, sizeof buf, sl_now_ms() + 5000) == SL_OK)
      received.push_back(std::string(pcs_msg_name(h.type)) + ": " +
                         std::string(reinterpret_cast<const char*>(buf), h.payload_size));
    sl_close(&s);
    return received;
  };
  const auto from_a = stranger(a.port), from_b = stranger(b.port);
  EXPECT_EQ(from_a, from_b) << "what a stranger receives must not depend on the token";
  ASSERT_EQ(from_a.size(), 2u) << "a CHALLENGE, then the ABORT";
  EXPECT_EQ(from_a[1].rfind("ABORT", 0), 0u) << from_a[1];
}

// The FMU never gives its token back: fmi2GetString(server.token) is empty
// (fmusim's --log-fmi-calls, a GUI's parameter table would show it).
TEST(Token, NotReadableThroughTheFmiApi) {
  auto archive = std::make_shared<tlm::FmuArchive>(PCS_ONE_DOF_FMU);
  tlm::FmuInstance fmu(archive, "reader", false);
  fmu.setup_experiment(0.0, 0.0);
  fmu.enter_initialization();
  fmu.set_string(fmu.vr("server.token"), "write-only-token-0123456789");
  EXPECT_EQ(fmu.get_string(fmu.vr("server.token")), "");
  fmu.set_string(fmu.vr("server.host"), "127.0.0.1");
  EXPECT_EQ(fmu.get_string(fmu.vr("server.host")), "127.0.0.1") << "other strings still read back";
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

// The host checks the server's proof in HELLO_ACK: an impostor that takes
// any AUTH but does not know the token is refused before any step.
TEST(Token, TheHostRefusesAServerThatCannotProveTheToken) {
  config::PortTable t = scene_table();
  testing_support::TestPeer impostor(t, testing_support::TestPeer::Behaviour::AcceptAnyProof,
                                     "not-the-token-0123456789");
  pcs_fmu::CouplingClient client(t);
  try {
    client.connect("127.0.0.1", impostor.port(), "the-real-token-0123456789", 5.0);
    FAIL() << "a server without the token must be refused";
  } catch (const pcs_fmu::LinkError& e) {
    EXPECT_NE(std::string(e.what()).find("could not prove it knows our token"), std::string::npos) << e.what();
  }
  impostor.join();
}
