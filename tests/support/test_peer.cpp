#include "test_peer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace testing_support {

TestPeer::TestPeer(const config::PortTable& table, Behaviour b, std::string token)
    : table_(table), behaviour_(b), token_(std::move(token)) {
  if (sl_listen("127.0.0.1", 0, &listener_) != SL_OK) throw std::runtime_error("TestPeer: cannot listen");
  port_ = sl_local_port(&listener_);
  thread_ = std::thread([this] { serve(); });
}

TestPeer::~TestPeer() {
  join();
  sl_close(&listener_);
}

void TestPeer::join() {
  if (thread_.joinable()) thread_.join();
}

std::string TestPeer::error() const { return error_; }

void TestPeer::serve() {
  // Every wait here is bounded, so a failing test cannot hang the peer.
  const int64_t deadline = sl_now_ms() + 10000;
  sl_socket c = SL_SOCKET_INIT;
  if (sl_accept(&listener_, deadline, &c) != SL_OK) {
    error_ = "no client";
    return;
  }
  std::vector<uint8_t> buf(PCS_MAX_REASON + 1024);
  pcs_header h{};
  if (pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline) != SL_OK ||
      h.type != PCS_MSG_HELLO) {
    error_ = "no HELLO";
    sl_close(&c);
    return;
  }
  pcs_hello hello{};
  pcs_decode_hello(buf.data(), h.payload_size, &hello);
  if (hello.table_hash != table_.hash() || !pcs_token_equal(hello.token, token_.c_str())) {
    pcs_send_abort(&c, 0, 1, "test peer refuses: port table or token", deadline);
    error_ = "refused";
    sl_close(&c);
    return;
  }
  pcs_hello_ack ack{table_.hash() + (behaviour_ == Behaviour::OtherTable ? 1 : 0), table_.dt,
                    static_cast<uint32_t>(table_.subcycles)};
  int n = pcs_encode_hello_ack(&ack, buf.data(), static_cast<uint32_t>(buf.size()));
  if (behaviour_ == Behaviour::OtherVersion) {
    // A HELLO_ACK in a header of protocol version 99, built by hand.
    std::vector<uint8_t> frame(PCS_HEADER_SIZE + static_cast<size_t>(n));
    pcs_header hh{PCS_MAGIC, 99, PCS_MSG_HELLO_ACK, 0, static_cast<uint32_t>(n)};
    pcs_encode_header(&hh, frame.data());
    std::copy(buf.begin(), buf.begin() + n, frame.begin() + PCS_HEADER_SIZE);
    sl_send_all(&c, frame.data(), frame.size(), deadline);
  } else {
    pcs_send_frame(&c, PCS_MSG_HELLO_ACK, 0, buf.data(), static_cast<uint32_t>(n), deadline);
  }
  std::vector<double> in(table_.to_fe.size()), out(table_.to_host.size());
  for (;;) {
    int rc = pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline);
    if (rc != SL_OK) {
      error_ = sl_err_name(rc);
      break;
    }
    if (h.type != PCS_MSG_STEP) break;  // BYE or ABORT end the session
    double t = 0, dt = 0;
    uint32_t count = 0;
    pcs_decode_values(buf.data(), h.payload_size, &t, &dt, in.data(), static_cast<uint32_t>(in.size()), &count);
    if (behaviour_ == Behaviour::StallOnStep) {
      pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline);  // wait for the client to give up
      break;
    }
    if (behaviour_ == Behaviour::CloseMidFrame) {
      uint8_t half[PCS_HEADER_SIZE / 2] = {'P', 'C', 'S', 'C'};
      sl_send_all(&c, half, sizeof half, deadline);
      break;
    }
    if (behaviour_ == Behaviour::BadMagic || behaviour_ == Behaviour::OversizeResult) {
      uint8_t raw[PCS_HEADER_SIZE];
      pcs_header bad{behaviour_ == Behaviour::BadMagic ? 0x50545448u /* "HTTP" */ : PCS_MAGIC,
                     PCS_PROTOCOL_VERSION, PCS_MSG_RESULT, h.step, behaviour_ == Behaviour::BadMagic ? 0u : 0xffffffffu};
      pcs_encode_header(&bad, raw);
      sl_send_all(&c, raw, sizeof raw, deadline);
      pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline);  // the client's ABORT or close
      break;
    }
    if (behaviour_ == Behaviour::Heartbeats)
      for (int beat = 0; beat < 3; ++beat) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        pcs_send_frame(&c, PCS_MSG_HEARTBEAT, h.step, nullptr, 0, deadline);
      }
    double sum = 0;
    for (double v : in) sum += v;
    for (size_t i = 0; i < out.size(); ++i) out[i] = 2.0 * sum + static_cast<double>(i);
    if (behaviour_ == Behaviour::NanResult) out[0] = std::nan("");
    n = pcs_encode_values(t + dt, dt, out.data(), static_cast<uint32_t>(out.size()), buf.data(),
                          static_cast<uint32_t>(buf.size()));
    uint64_t step = behaviour_ == Behaviour::WrongStep ? h.step + 1 : h.step;
    pcs_send_frame(&c, PCS_MSG_RESULT, step, buf.data(), static_cast<uint32_t>(n), deadline);
    ++steps_;
  }
  sl_close(&c);
}

}  // namespace testing_support
