// Coupling overhead per exchange, as ratios taken in one run:
//   (a) plain TCP ping-pong of the same payload sizes (blocking send/recv, TCP_NODELAY)
//   (b) socketlib frames with deadlines (pcs_send_frame / pcs_recv_frame)
//   (c) a full coupling step: fmi2DoStep through the FMU against a live fe_server
//       (one-DOF scene: one FE step of a rigid body per exchange)
// Usage: bench_coupling [steps]   (fe_server and the FMU paths are compiled in)
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bench_args.hpp"
#include "config/port_table.hpp"
#include "fmu_importer.hpp"
#include "process.hpp"
#include "socketlib/protocol.h"

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// STEP carries 1 value and RESULT 2 in the one-DOF scene: the same byte counts here.
const size_t kRequest = PCS_HEADER_SIZE + 28, kReply = PCS_HEADER_SIZE + 36;

void recv_exact(int fd, uint8_t* p, size_t n) {
  while (n) {
    ssize_t r = recv(fd, p, n, 0);
    if (r <= 0) std::exit(1);
    p += r;
    n -= static_cast<size_t>(r);
  }
}

// Plain blocking calls: the floor the framed link is compared with.
void make_blocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) & ~O_NONBLOCK); }

double plain_tcp(int steps) {
  sl_socket l = SL_SOCKET_INIT;
  sl_listen("127.0.0.1", 0, &l);
  int port = sl_local_port(&l);
  std::thread echo([&] {
    sl_socket c = SL_SOCKET_INIT;
    sl_accept(&l, sl_now_ms() + 10000, &c);
    make_blocking(c.fd);
    uint8_t buf[256];
    for (int k = 0; k < steps; ++k) {
      recv_exact(c.fd, buf, kRequest);
      send(c.fd, buf, kReply, 0);
    }
    sl_close(&c);
  });
  sl_socket c = SL_SOCKET_INIT;
  sl_connect("127.0.0.1", port, sl_now_ms() + 10000, &c);
  int fd = c.fd;
  make_blocking(fd);
  uint8_t buf[256] = {};
  auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) {
    send(fd, buf, kRequest, 0);
    recv_exact(fd, buf, kReply);
  }
  double s = seconds_since(t0);
  echo.join();
  sl_close(&c);
  sl_close(&l);
  return s / steps;
}

double framed(int steps) {
  sl_socket l = SL_SOCKET_INIT;
  sl_listen("127.0.0.1", 0, &l);
  int port = sl_local_port(&l);
  std::thread echo([&] {
    sl_socket c = SL_SOCKET_INIT;
    sl_accept(&l, sl_now_ms() + 10000, &c);
    uint8_t buf[256];
    pcs_header h{};
    double v[2] = {1, 2};
    for (int k = 0; k < steps; ++k) {
      pcs_recv_frame(&c, &h, buf, sizeof buf, sl_now_ms() + 10000);
      int n = pcs_encode_values(0, 0, v, 2, buf, sizeof buf);
      pcs_send_frame(&c, PCS_MSG_RESULT, h.step, buf, static_cast<uint32_t>(n), sl_now_ms() + 10000);
    }
    sl_close(&c);
  });
  sl_socket c = SL_SOCKET_INIT;
  sl_connect("127.0.0.1", port, sl_now_ms() + 10000, &c);
  uint8_t buf[256];
  double v[1] = {1}, out[2];
  pcs_header h{};
  auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) {
    int n = pcs_encode_values(0, 0, v, 1, buf, sizeof buf);
    pcs_send_frame(&c, PCS_MSG_STEP, static_cast<uint64_t>(k), buf, static_cast<uint32_t>(n), sl_now_ms() + 10000);
    pcs_recv_frame(&c, &h, buf, sizeof buf, sl_now_ms() + 10000);
    double t = 0, dt = 0;
    uint32_t count = 0;
    pcs_decode_values(buf, h.payload_size, &t, &dt, out, 2, &count);
  }
  double s = seconds_since(t0);
  echo.join();
  sl_close(&c);
  sl_close(&l);
  return s / steps;
}

double fmu_step(int steps) {
  testing_support::TempDir dir;
  const std::string scene = PCS_SCENES_DIR "/one_dof";
  testing_support::ChildProcess server({PCS_FE_SERVER_EXE, "--model", scene + "/piston.k", "--ports",
                                        scene + "/ports.cfg", "--port-file", dir.file("port"), "--out",
                                        dir.file("fe.h5"), "--quiet"});
  int port = testing_support::read_port_file(dir.file("port"), 10.0);
  auto archive = std::make_shared<tlm::FmuArchive>(PCS_ONE_DOF_FMU);
  double dt = archive->description().default_step;
  double per_step = 0;
  {
    tlm::FmuInstance fmu(archive, "bench", false);
    fmu.set_string(fmu.vr("server.host"), "127.0.0.1");
    fmu.set_integer(fmu.vr("server.port"), port);
    fmu.setup_experiment(0, 0);
    fmu.enter_initialization();
    fmu.exit_initialization();
    unsigned p = fmu.vr("cavity.p"), q = fmu.vr("cavity.q");
    auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) {
      fmu.set_real(p, 1e7);
      fmu.do_step(k * dt, dt);
      (void)fmu.get_real(q);
    }
    per_step = seconds_since(t0) / steps;
    fmu.terminate();
  }
  server.wait(30);
  return per_step;
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage = "usage: bench_coupling [ROUND_TRIPS]   loopback exchanges per kind (default 20000)";
  bench::help_or_nothing(argc, argv, usage);
  const int steps = bench::count_arg(argc, argv, 1, 20000, "ROUND_TRIPS", usage);
  double a = plain_tcp(steps), b = framed(steps), c = fmu_step(steps);
  std::printf("coupling exchange on loopback, %d round trips each, one run:\n", steps);
  std::printf("  plain TCP ping-pong (blocking)   %8.2f us   1.00\n", a * 1e6);
  std::printf("  socketlib frames with deadlines  %8.2f us   %.2f\n", b * 1e6, b / a);
  std::printf("  fmi2DoStep against fe_server     %8.2f us   %.2f\n", c * 1e6, c / a);
  std::printf("csv:coupling,tcp,%.3f,1\ncsv:coupling,socketlib,%.3f,%.4f\ncsv:coupling,fmi2DoStep,%.3f,%.4f\n", a * 1e6,
              b * 1e6, b / a, c * 1e6, c / a);
  return 0;
}
