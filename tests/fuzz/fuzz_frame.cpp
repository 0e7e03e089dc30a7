// Fuzz target: the wire protocol's frame reader and payload decoders.
// The input is written into a socket pair and read back as frames, so the
// real receive path (header checks, length limits, truncation) is exercised.
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "socketlib/protocol.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 65536) return 0;
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, fds) != 0) return 0;
  sl_socket w = {fds[0], 0}, r = {fds[1], 0};
  if (size) sl_send_all(&w, data, size, sl_now_ms() + 1000);
  sl_close(&w);
  std::vector<uint8_t> buf(4096);
  for (int frames = 0; frames < 64; ++frames) {
    pcs_header h{};
    int rc = pcs_recv_frame(&r, &h, buf.data(), static_cast<uint32_t>(buf.size()), sl_now_ms() + 1000);
    if (rc != SL_OK && rc != SL_EVERSION) break;
    pcs_hello hello;
    pcs_hello_ack ack;
    pcs_abort ab;
    pcs_challenge ch;
    pcs_auth au;
    double values[32], t, dt;
    uint32_t count;
    pcs_decode_hello(buf.data(), h.payload_size, &hello);
    pcs_decode_hello_ack(buf.data(), h.payload_size, &ack);
    pcs_decode_abort(buf.data(), h.payload_size, &ab);
    pcs_decode_challenge(buf.data(), h.payload_size, &ch);
    pcs_decode_auth(buf.data(), h.payload_size, &au);
    pcs_decode_values(buf.data(), h.payload_size, &t, &dt, values, 32, &count);
    (void)pcs_msg_name(h.type);
  }
  sl_close(&r);
  return 0;
}
