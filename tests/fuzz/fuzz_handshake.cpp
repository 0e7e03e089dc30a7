// Fuzz target: fe_server's side of the session handshake. The input is what
// a client sends; it is written into one end of a socket pair, and the
// server's handshake state machine (CouplingServer::handshake_step, the same
// code accept_clients runs) examines and answers it frame by frame until it
// binds, refuses or waits for more.
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "coupling/coupling_server.hpp"

namespace {
const char* kTable =
    "$FMU_SETTINGS\nmodel, fuzz\ntimestep, 1.0e-5\nmode, pressure\nsubcycles, 1\ntimeout, 1\n"
    "$FMU_HOPSAN_PORTS\n1, cavity, Hydraulic\n$FMU_HOPSAN_SEND\n1, pressure, 1.0\n"
    "$FMU_HOPSAN_RECEIVE\n1, flow, 1.0\n";

fe::CouplingServer& server() {
  static fe::CouplingServer s = [] {
    fe::ServerOptions opt;
    opt.quiet = true;
    opt.token = "fuzz-token";
    return fe::CouplingServer(opt, {config::parse_port_table(kTable, "fuzz.cfg")});
  }();
  return s;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 65536) return 0;  // more than a socket pair buffers
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) return 0;
  sl_socket client = {fds[0], 0};
  fe::CouplingServer::Pending p;
  p.conn = {fds[1], 0};
  p.deadline = sl_now_ms() + 1000;
  p.peer = "fuzz";
  if (size) sl_send_all(&client, data, size, sl_now_ms() + 1000);
  for (int frames = 0; frames < 8; ++frames) {
    std::string why;
    const auto progress = server().handshake_step(p, why);
    if (progress != fe::CouplingServer::HandshakeProgress::Waiting || p.pause_until > 0) break;
  }
  sl_close(&p.conn);
  sl_close(&client);
  return 0;
}
