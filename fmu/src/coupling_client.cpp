#include "coupling_client.hpp"

#ifdef _WIN32
#include <windows.h>
#else
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

#include "config/token.hpp"

namespace pcs_fmu {

std::string describe_link_error(int code, const sl_socket& s) {
  std::string m = std::string(sl_err_name(code)) + ": " + sl_strerror(code);
  if (code == SL_ESYSTEM && s.sys_errno) m += std::string(" (") + std::strerror(s.sys_errno) + ")";
  return m;
}

static int64_t deadline_after(double seconds) {
  return sl_now_ms() + static_cast<int64_t>(std::ceil(seconds * 1000.0));
}

CouplingClient::CouplingClient(const config::PortTable& table) : table_(table) {
  size_t n = std::max(table.to_fe.size(), table.to_host.size());
  // A split session's STEP and INPUTS carry the thread too.
  buf_.resize(std::max<size_t>(pcs_tagged_values_size(static_cast<uint32_t>(n)), PCS_MAX_REASON + 64));
}

CouplingClient::~CouplingClient() { sl_close(&sock_); }

void CouplingClient::fail(int code, const std::string& what) {
  std::string msg = what + ": " + describe_link_error(code, sock_);
  // The server is told why (a garbage frame, a time-out, a stop signal in a
  // wait), not left with a reset connection, unless it is gone or ended the
  // session itself. Best effort: one small frame, a short deadline.
  if (sock_.fd >= 0 && code != SL_ECLOSED && code != SL_EREFUSED_BY_PEER)
    pcs_send_abort(&sock_, 0, static_cast<uint32_t>(-code), ("the host stops: " + msg).c_str(), deadline_after(1.0));
  sl_close(&sock_);
  throw LinkError(code, msg);
}

void CouplingClient::receive_handshake_frame(pcs_header& h, uint16_t want, const std::string& where,
                                             int64_t deadline) {
  int rc = pcs_recv_frame(&sock_, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline);
  if (h.type == PCS_MSG_ABORT && (rc == SL_OK || rc == SL_EVERSION)) {
    pcs_abort a{};
    pcs_decode_abort(buf_.data(), h.payload_size, &a);
    sl_close(&sock_);
    if (a.code == static_cast<uint32_t>(-SL_EBUSY)) throw LinkError(SL_EBUSY, where + " is " + a.reason);
    if (a.code == static_cast<uint32_t>(-SL_ECROWDED))
      throw LinkError(SL_ECROWDED, where + " dropped this connection: " + a.reason);
    throw LinkError(SL_EREFUSED_BY_PEER, where + " refused the session: " + a.reason);
  }
  if (rc == SL_EVERSION)  // fail() tells the server, in an ABORT it can read whatever its version
    fail(rc, "protocol version mismatch: client speaks " + std::to_string(PCS_PROTOCOL_VERSION) + ", server " +
                 std::to_string(h.version));
  if (rc != SL_OK) fail(rc, "no handshake answer from " + where);
  if (h.type != want) fail(SL_EUNEXPECTED, std::string("expected ") + pcs_msg_name(want) + ", got " + pcs_msg_name(h.type));
}

void CouplingClient::connect(const std::string& host, int port, const std::string& token,
                             double timeout_s) {
  timeout_s_ = timeout_s;
  const int64_t start = sl_now_ms(), deadline = deadline_after(timeout_s);
  const std::string where = "fe_server at " + host + ":" + std::to_string(port);
  auto tell = [&](bool warning, const std::string& what) {
    if (progress_) progress_(warning, what);
  };
  char until[96];
  std::snprintf(until, sizeof until, " (server.timeout: %g s)", timeout_s);
  tell(false, "connecting to " + where + until);
  // In slices of kProgressMs, so a long wait is never silent: a server not
  // (yet) listening, or one busy with another session, is retried until the
  // deadline and said to be so every few seconds.
  int64_t next_note = start + kProgressMs;
  bool told_busy = false, told_crowded = false;
  for (;;) {
    try {
      connect_once(host, port, token, std::min(deadline, sl_now_ms() + kProgressMs), deadline);
      return;
    } catch (const LinkError& e) {
      // Crowded, or closed in the handshake without a word: a server that
      // made room under a connection flood (its ABORT can be lost when our
      // HELLO crossed its close); a server that has gone is refused next time.
      const bool crowded = e.code() == SL_ECROWDED || (e.code() == SL_ECLOSED && connected_once_);
      const bool waiting = e.code() == SL_EREFUSED || e.code() == SL_EBUSY || crowded ||
                           (e.code() == SL_ETIMEDOUT && !connected_once_);
      const int64_t now = sl_now_ms();
      if (!waiting || now >= deadline) throw;
      // Said at once the first time: the user can act on it (another
      // session runs; someone floods the server's port).
      const bool first_told = (e.code() == SL_EBUSY && !told_busy) || (crowded && !told_crowded);
      told_busy = told_busy || e.code() == SL_EBUSY;
      told_crowded = told_crowded || crowded;
      if (now >= next_note || first_told) {
        char waited[160];
        std::snprintf(waited, sizeof waited, "; retrying until %g s have passed (%.0f s so far)", timeout_s,
                      (now - start) / 1000.0);
        const std::string what = e.code() == SL_EBUSY || crowded
                                     ? std::string(e.what())
                                     : "no answer from " + where + " (is fe_server started, on this host and port?)";
        tell(true, what + waited);
        next_note = now + kProgressMs;
      }
      if (e.code() == SL_EBUSY || crowded) {
        // The session ends when it ends: try again now and then, not in a
        // tight loop; a flood is outlasted by asking again soon. In slices of
        // at most 100 ms that look at the importer's stop flag, as every wait
        // of the link does (a stop signal ends it within 200 ms).
        const int64_t until = std::min<int64_t>(now + (crowded ? kCrowdedRetryMs : kBusyRetryMs), deadline);
        const volatile sig_atomic_t* stop = sl_get_stop_flag();
        while (sl_now_ms() < until && !(stop && *stop)) {
          struct timespec ts = {0, std::min<int64_t>(100, std::max<int64_t>(1, until - sl_now_ms())) * 1000000L};
          nanosleep(&ts, nullptr);
        }
      }
    }
  }
}

void CouplingClient::connect_once(const std::string& host, int port, const std::string& token,
                                  int64_t connect_deadline, int64_t deadline) {
  connected_once_ = false;
  const std::string where = "fe_server at " + host + ":" + std::to_string(port);
  // A token we cannot use is refused before anything goes out (an ABORT
  // saying why would tell a peer, maybe not the real server, its length).
  if (!token.empty()) {  // empty: a server started with --insecure-no-token
    try {
      config::check_token(token, "the session token");
    } catch (const std::exception& e) {
      throw LinkError(SL_EINVAL, e.what());
    }
  }
  int rc = sl_connect(host.c_str(), port, connect_deadline, &sock_);
  if (rc != SL_OK) {
    const std::string why = "cannot connect to " + where + ": " + describe_link_error(rc, sock_);
    sl_close(&sock_);
    throw LinkError(rc, why);
  }
  connected_once_ = true;
  if (pcs_auth_init() != SL_OK) fail(SL_ESYSTEM, "cannot initialise libsodium");
  pcs_hello hello{};
  hello.protocol_version = PCS_PROTOCOL_VERSION;
  hello.table_hash = table_.hash();
  hello.dt = table_.dt;
  hello.subcycles = static_cast<uint32_t>(table_.subcycles);
  pcs_random_nonce(hello.client_nonce);
  int n = pcs_encode_hello(&hello, buf_.data(), static_cast<uint32_t>(buf_.size()));
  if (n < 0) fail(n, "cannot encode HELLO");
  rc = pcs_send_frame(&sock_, PCS_MSG_HELLO, 0, buf_.data(), static_cast<uint32_t>(n), deadline);
  if (rc != SL_OK) fail(rc, "cannot send HELLO to " + where);

  // CHALLENGE: the server's nonce. We prove first; the server proves in
  // HELLO_ACK, only to a host that knew the token (socketlib/auth.h says why).
  pcs_header h{};
  receive_handshake_frame(h, PCS_MSG_CHALLENGE, where, deadline);
  pcs_challenge ch{};
  if (pcs_decode_challenge(buf_.data(), h.payload_size, &ch) != SL_OK) fail(SL_EMALFORMED, "malformed CHALLENGE");
  pcs_auth auth{};
  pcs_auth_proof(token.data(), token.size(), PCS_ROLE_HOST, hello.client_nonce, ch.server_nonce, table_.hash(),
                 auth.client_proof);
  n = pcs_encode_auth(&auth, buf_.data(), static_cast<uint32_t>(buf_.size()));
  rc = pcs_send_frame(&sock_, PCS_MSG_AUTH, 0, buf_.data(), static_cast<uint32_t>(n), deadline);
  if (rc != SL_OK) fail(rc, "cannot send AUTH to " + where);

  receive_handshake_frame(h, PCS_MSG_HELLO_ACK, where, deadline);
  pcs_hello_ack ack{};
  rc = pcs_decode_hello_ack(buf_.data(), h.payload_size, &ack);
  if (rc != SL_OK) fail(rc, "malformed HELLO_ACK");
  if (!pcs_auth_check(token.data(), token.size(), PCS_ROLE_SERVER, hello.client_nonce, ch.server_nonce,
                      table_.hash(), ack.server_proof)) {
    const std::string reason =
        "wrong or missing token: the server could not prove it knows our token (the tokens differ, or this is not "
        "the real fe_server)";
    pcs_send_abort(&sock_, 0, SL_EREFUSED_BY_PEER,
                   "wrong or missing token (the server's proof does not match the host's token)", deadline);
    fail(SL_EREFUSED_BY_PEER, where + ": " + reason);
  }
  session_fmus_ = ack.session_fmus;
  early_results_.clear();
  // The server checked the same things; checking again here means a faulty
  // or foreign server cannot make us exchange values that mean something else.
  if (ack.table_hash != table_.hash() || ack.dt != table_.dt ||
      ack.subcycles != static_cast<uint32_t>(table_.subcycles)) {
    std::string reason = "server's port table differs from ours (" + table_.source + ")";
    pcs_send_abort(&sock_, 0, SL_EREFUSED_BY_PEER, reason.c_str(), deadline);
    fail(SL_EREFUSED_BY_PEER, reason);
  }
}

void CouplingClient::step(uint64_t k, double time, double dt, const std::vector<double>& inputs,
                          std::vector<double>& outputs) {
  if (!connected()) throw LinkError(SL_EINVAL, "not connected to fe_server");
  confirm_resume();  // the server answers RESUME once every FMU of the session has connected
  const int64_t deadline = deadline_after(timeout_s_);
  const auto count = static_cast<uint32_t>(inputs.size());
  const auto cap = static_cast<uint32_t>(buf_.size());
  int n = split_session() ? pcs_encode_tagged_values(caller_thread(), time, dt, inputs.data(), count, buf_.data(), cap)
                          : pcs_encode_values(time, dt, inputs.data(), count, buf_.data(), cap);
  if (n < 0) fail(n, "cannot encode STEP");
  int rc = pcs_send_frame(&sock_, PCS_MSG_STEP, k, buf_.data(), static_cast<uint32_t>(n), deadline);
  std::string at = " at step " + std::to_string(k) + " (t = " + std::to_string(time) + " s)";
  if (rc != SL_OK) fail(rc, "cannot send STEP" + at);
  if (!early_results_.empty() && early_results_.front().first == k) {
    outputs = std::move(early_results_.front().second);
    early_results_.erase(early_results_.begin());
    return;
  }
  pcs_header h{};
  rc = next_frame(h, k, deadline);
  if (rc == SL_OK && h.type == PCS_MSG_ABORT) {
    pcs_abort a{};
    pcs_decode_abort(buf_.data(), h.payload_size, &a);
    sl_close(&sock_);
    throw LinkError(SL_EREFUSED_BY_PEER, "fe_server aborted" + at + ": " + a.reason);
  }
  if (rc != SL_OK) fail(rc, "no RESULT" + at);
  if (h.type != PCS_MSG_RESULT || h.step != k) {
    std::string what = std::string("expected RESULT ") + std::to_string(k) + ", got " +
                       pcs_msg_name(h.type) + " " + std::to_string(h.step);
    pcs_send_abort(&sock_, k, SL_EUNEXPECTED, what.c_str(), deadline);
    fail(SL_EUNEXPECTED, what);
  }
  decode_result(h, outputs, at);
}

void CouplingClient::decode_result(const pcs_header& h, std::vector<double>& outputs, const std::string& at) {
  double t_back = 0, dt_back = 0;
  uint32_t count = 0;
  outputs.resize(table_.to_host.size());
  const int rc = pcs_decode_values(buf_.data(), h.payload_size, &t_back, &dt_back, outputs.data(),
                                   static_cast<uint32_t>(outputs.size()), &count);
  if (rc != SL_OK || count != outputs.size())
    fail(SL_EMALFORMED, "RESULT" + at + " carries " + std::to_string(count) + " values, expected " +
                            std::to_string(outputs.size()));
}

int CouplingClient::next_frame(pcs_header& h, uint64_t k, int64_t deadline) {
  for (;;) {
    const int rc = pcs_recv_frame(&sock_, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline);
    if (rc != SL_OK) return rc;
    if (h.type == PCS_MSG_STOPPING) {  // the server is stopping and asks for a checkpoint; its RESULT follows
      stop_requested_ = true;
      continue;
    }
    if (h.type == PCS_MSG_HEARTBEAT && h.step == k) {  // the server is alive and still computing
      deadline = deadline_after(timeout_s_);
      continue;
    }
    return rc;
  }
}

uint64_t CouplingClient::caller_thread() {
#ifdef _WIN32
  return (static_cast<uint64_t>(GetCurrentProcessId()) << 32) ^ static_cast<uint64_t>(GetCurrentThreadId());
#else
  return (static_cast<uint64_t>(getpid()) << 32) ^ static_cast<uint64_t>(syscall(SYS_gettid));
#endif
}

void CouplingClient::send_inputs(uint64_t k, double time, double dt, const std::vector<double>& inputs) {
  if (!connected()) throw LinkError(SL_EINVAL, "not connected to fe_server");
  const int64_t deadline = deadline_after(timeout_s_);
  const int n = pcs_encode_tagged_values(caller_thread(), time, dt, inputs.data(), static_cast<uint32_t>(inputs.size()),
                                         buf_.data(), static_cast<uint32_t>(buf_.size()));
  if (n < 0) fail(n, "cannot encode INPUTS");
  const std::string at = " for step " + std::to_string(k) + " (t = " + std::to_string(time) + " s)";
  int rc = pcs_send_frame(&sock_, PCS_MSG_INPUTS, k, buf_.data(), static_cast<uint32_t>(n), deadline);
  if (rc != SL_OK) fail(rc, "cannot send INPUTS" + at);
  for (;;) {
    pcs_header h{};
    rc = next_frame(h, k, deadline);
    if (rc == SL_OK && h.type == PCS_MSG_ABORT) {
      pcs_abort a{};
      pcs_decode_abort(buf_.data(), h.payload_size, &a);
      sl_close(&sock_);
      throw LinkError(SL_EREFUSED_BY_PEER, "fe_server aborted at the inputs" + at + ": " + a.reason);
    }
    if (rc != SL_OK) fail(rc, "no answer to INPUTS" + at);
    if (h.type == PCS_MSG_INPUTS && h.step == k && h.payload_size == 0) return;
    if (h.type == PCS_MSG_RESULT && h.step >= k) {  // a step the server ran with these inputs before
      std::vector<double> out;
      decode_result(h, out, " " + std::to_string(h.step) + " (early)");
      early_results_.emplace_back(h.step, std::move(out));
      continue;
    }
    if (h.type == PCS_MSG_HEARTBEAT) continue;  // of a step run before this FMU's own STEP of it
    const std::string what = "expected the answer to INPUTS " + std::to_string(k) + ", got " + pcs_msg_name(h.type) +
                             " " + std::to_string(h.step);
    pcs_send_abort(&sock_, k, SL_EUNEXPECTED, what.c_str(), deadline);
    fail(SL_EUNEXPECTED, what);
  }
}

void CouplingClient::send_request(uint16_t type, uint64_t k) {
  if (!connected()) throw LinkError(SL_EINVAL, "not connected to fe_server");
  const int rc = pcs_send_frame(&sock_, type, k, nullptr, 0, deadline_after(timeout_s_));
  if (rc != SL_OK) fail(rc, std::string("cannot send ") + pcs_msg_name(type) + " " + std::to_string(k));
}

pcs_header CouplingClient::await_answer(uint16_t type, uint64_t k) {
  const std::string what = std::string(pcs_msg_name(type)) + " " + std::to_string(k);
  pcs_header h{};
  int rc = SL_OK;
  for (;;) {  // a checkpoint of a large model may take a while: heartbeats say it is alive
    rc = pcs_recv_frame(&sock_, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline_after(timeout_s_));
    if (rc == SL_OK && h.type == PCS_MSG_STOPPING) {  // the server asks for a checkpoint
      stop_requested_ = true;
      continue;
    }
    if (rc != SL_OK || h.type != PCS_MSG_HEARTBEAT) break;
  }
  if (rc == SL_OK && h.type == PCS_MSG_ABORT) {
    pcs_abort a{};
    pcs_decode_abort(buf_.data(), h.payload_size, &a);
    sl_close(&sock_);
    throw LinkError(SL_EREFUSED_BY_PEER, "fe_server refused " + what + ": " + a.reason);
  }
  if (rc != SL_OK) fail(rc, "no answer to " + what);
  if (h.type != type || h.step != k) {
    const std::string got = std::string("expected ") + what + ", got " + pcs_msg_name(h.type) + " " + std::to_string(h.step);
    pcs_send_abort(&sock_, k, SL_EUNEXPECTED, got.c_str(), deadline_after(1.0));
    fail(SL_EUNEXPECTED, got);
  }
  return h;
}

std::string CouplingClient::checkpoint(uint64_t k) {
  confirm_resume();  // a checkpoint right after resuming: the RESUME's answer comes first
  send_request(PCS_MSG_CHECKPOINT, k);
  const pcs_header h = await_answer(PCS_MSG_CHECKPOINT, k);
  pcs_reader r{buf_.data(), h.payload_size, 0, 0};
  std::vector<char> path(4096);
  pcs_get_str(&r, path.data(), static_cast<uint32_t>(path.size()));
  if (r.error) fail(SL_EMALFORMED, "malformed CHECKPOINT answer");
  return path.data();
}

void CouplingClient::resume(uint64_t k) {
  send_request(PCS_MSG_RESUME, k);
  resume_pending_ = true;
  resume_step_ = k;
}

void CouplingClient::confirm_resume() {
  if (!resume_pending_) return;
  resume_pending_ = false;
  await_answer(PCS_MSG_RESUME, resume_step_);
}

void CouplingClient::bye() {
  if (!connected()) return;
  (void)pcs_send_frame(&sock_, PCS_MSG_BYE, 0, nullptr, 0, deadline_after(timeout_s_));
  sl_close(&sock_);
}

void CouplingClient::abort(const std::string& reason) {
  if (!connected()) return;
  pcs_send_abort(&sock_, 0, SL_EREFUSED_BY_PEER, reason.c_str(), deadline_after(1.0));
  sl_close(&sock_);
}

}  // namespace pcs_fmu
