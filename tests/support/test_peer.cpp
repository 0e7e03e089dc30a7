#include "test_peer.hpp"

#include <cstdlib>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace testing_support {

std::string session_token() {
  const char* t = std::getenv("PCS_TOKEN");
  return t ? t : "";
}

TestPeer::TestPeer(const config::PortTable& table, Behaviour b, std::string token)
    : table_(table), behaviour_(b), token_(std::move(token)) {
  if (pcs_auth_init() != SL_OK) throw std::runtime_error("TestPeer: cannot initialise libsodium");
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
  std::vector<uint8_t> buf(PCS_MAX_REASON + 1024);
  pcs_header h{};
  // As fe_server drops a connection to make room under a flood: telling it
  // so, or with the ABORT lost (the HELLO crossed the close).
  if (behaviour_ == Behaviour::CrowdedOnce || behaviour_ == Behaviour::ClosedOnce) {
    if (sl_accept(&listener_, deadline, &c) != SL_OK ||
        pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline) != SL_OK) {
      error_ = "no first HELLO";
      sl_close(&c);
      return;
    }
    if (behaviour_ == Behaviour::CrowdedOnce)
      pcs_send_abort(&c, 0, static_cast<uint32_t>(-SL_ECROWDED), "crowded: too many connections (test peer)", deadline);
    sl_close(&c);
    ++crowded_;
  }
  if (sl_accept(&listener_, deadline, &c) != SL_OK) {
    error_ = "no client";
    return;
  }
  if (pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline) != SL_OK ||
      h.type != PCS_MSG_HELLO) {
    error_ = "no HELLO";
    sl_close(&c);
    return;
  }
  pcs_hello hello{};
  pcs_decode_hello(buf.data(), h.payload_size, &hello);
  if (behaviour_ == Behaviour::Busy) {  // as fe_server answers a host while another session runs
    pcs_send_abort(&c, 0, static_cast<uint32_t>(-SL_EBUSY), "busy: running another session (test peer)", deadline);
    error_ = "busy";
    sl_close(&c);
    return;
  }
  if (behaviour_ == Behaviour::SilentAfterHello) {  // until the client gives up or closes
    pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline);
    error_ = "silent after HELLO";
    sl_close(&c);
    return;
  }
  if (hello.table_hash != table_.hash()) {
    pcs_send_abort(&c, 0, 1, "test peer refuses: port table", deadline);
    error_ = "refused";
    sl_close(&c);
    return;
  }
  // The server's half of the challenge-response (socketlib/auth.h).
  pcs_challenge ch{};
  pcs_random_nonce(ch.server_nonce);
  int cn = pcs_encode_challenge(&ch, buf.data(), static_cast<uint32_t>(buf.size()));
  pcs_send_frame(&c, PCS_MSG_CHALLENGE, 0, buf.data(), static_cast<uint32_t>(cn), deadline);
  pcs_auth auth{};
  if (pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline) != SL_OK ||
      h.type != PCS_MSG_AUTH || pcs_decode_auth(buf.data(), h.payload_size, &auth) != SL_OK ||
      (behaviour_ != Behaviour::AcceptAnyProof &&
       !pcs_auth_check(token_.data(), token_.size(), PCS_ROLE_HOST, hello.client_nonce, ch.server_nonce,
                       table_.hash(), auth.client_proof))) {
    if (h.type != PCS_MSG_ABORT) pcs_send_abort(&c, 0, 1, "test peer refuses: token", deadline);
    error_ = h.type == PCS_MSG_ABORT ? "client aborted the handshake" : "refused";
    sl_close(&c);
    return;
  }
  pcs_hello_ack ack{table_.hash() + (behaviour_ == Behaviour::OtherTable ? 1 : 0), table_.dt,
                    static_cast<uint32_t>(table_.subcycles), {}};
  pcs_auth_proof(token_.data(), token_.size(), PCS_ROLE_SERVER, hello.client_nonce, ch.server_nonce, table_.hash(),
                 ack.server_proof);
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
    if (behaviour_ == Behaviour::EndlessHeartbeats) {  // "still computing", until the client leaves
      while (sl_now_ms() < deadline &&
             pcs_send_frame(&c, PCS_MSG_HEARTBEAT, h.step, nullptr, 0, deadline) == SL_OK)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      break;
    }
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
      // The client's ABORT (a garbage frame is told, not reset), or its close.
      const int arc = pcs_recv_frame(&c, &h, buf.data(), static_cast<uint32_t>(buf.size()), deadline);
      if (arc == SL_OK && h.type == PCS_MSG_ABORT) {
        pcs_abort a{};
        pcs_decode_abort(buf.data(), h.payload_size, &a);
        error_ = std::string("client sent ABORT: ") + a.reason;
      } else {
        error_ = std::string("client closed without ABORT: ") + sl_err_name(arc);
      }
      sl_close(&c);
      return;
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

std::string raw_client_handshake(sl_socket& s, const config::PortTable& t, const std::string& token,
                                 uint16_t header_version, bool check_server) {
  if (pcs_auth_init() != SL_OK) return "cannot initialise libsodium";
  const int64_t deadline = sl_now_ms() + 5000;
  pcs_hello hello{PCS_PROTOCOL_VERSION, t.hash(), t.dt, static_cast<uint32_t>(t.subcycles), {}};
  pcs_random_nonce(hello.client_nonce);
  uint8_t payload[256], frame[512], buf[2048];
  const int n = pcs_encode_hello(&hello, payload, sizeof payload);
  pcs_header h{PCS_MAGIC, header_version, PCS_MSG_HELLO, 0, static_cast<uint32_t>(n)};
  pcs_encode_header(&h, frame);
  std::copy(payload, payload + n, frame + PCS_HEADER_SIZE);
  if (sl_send_all(&s, frame, PCS_HEADER_SIZE + static_cast<size_t>(n), deadline) != SL_OK) return "cannot send HELLO";
  auto answer = [&](uint16_t want) -> std::string {
    const int rc = pcs_recv_frame(&s, &h, buf, sizeof buf, deadline);
    if ((rc == SL_OK || rc == SL_EVERSION) && h.type == PCS_MSG_ABORT) {
      pcs_abort a{};
      pcs_decode_abort(buf, h.payload_size, &a);
      return std::string("ABORT: ") + a.reason;
    }
    if (rc != SL_OK) return sl_err_name(rc);
    if (h.type != want) return std::string("unexpected ") + pcs_msg_name(h.type);
    return "";
  };
  std::string why = answer(PCS_MSG_CHALLENGE);
  if (!why.empty()) return why;
  pcs_challenge ch{};
  if (pcs_decode_challenge(buf, h.payload_size, &ch) != SL_OK) return "malformed CHALLENGE";
  pcs_auth auth{};
  pcs_auth_proof(token.data(), token.size(), PCS_ROLE_HOST, hello.client_nonce, ch.server_nonce, t.hash(),
                 auth.client_proof);
  const int an = pcs_encode_auth(&auth, payload, sizeof payload);
  if (pcs_send_frame(&s, PCS_MSG_AUTH, 0, payload, static_cast<uint32_t>(an), deadline) != SL_OK)
    return "cannot send AUTH";
  why = answer(PCS_MSG_HELLO_ACK);
  if (!why.empty()) return why;
  pcs_hello_ack ack{};
  if (pcs_decode_hello_ack(buf, h.payload_size, &ack) != SL_OK) return "malformed HELLO_ACK";
  if (check_server && !pcs_auth_check(token.data(), token.size(), PCS_ROLE_SERVER, hello.client_nonce,
                                      ch.server_nonce, t.hash(), ack.server_proof))
    return "the server's proof does not match the token";
  return "";
}

}  // namespace testing_support
