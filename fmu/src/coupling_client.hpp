// Client side of the coupling protocol: connect with a deadline, HELLO
// handshake, one STEP/RESULT exchange per coupling step, BYE or ABORT.
// Values cross in wire units (already scaled); the FMU instance scales them.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/port_table.hpp"
#include "socketlib/protocol.h"

namespace pcs_fmu {

// A link failure with a message that names the cause; `code` is an sl_error.
class LinkError : public std::runtime_error {
 public:
  LinkError(int code, const std::string& message) : std::runtime_error(message), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

class CouplingClient {
 public:
  explicit CouplingClient(const config::PortTable& table);
  ~CouplingClient();
  CouplingClient(const CouplingClient&) = delete;
  CouplingClient& operator=(const CouplingClient&) = delete;

  // Connect (retrying while refused, while the server is busy with another
  // session, or after it dropped us under a connection flood) and shake
  // hands, all before now + timeout_s. Throws LinkError, e.g. when the
  // server refuses the token. The wait is told to the progress
  // callback when it starts and every kProgressMs while it lasts (warning
  // set: the importer's user should see it).
  void connect(const std::string& host, int port, const std::string& token, double timeout_s);
  using Progress = std::function<void(bool warning, const std::string& message)>;
  void set_progress(Progress p) { progress_ = std::move(p); }
  static constexpr int64_t kProgressMs = 5000;
  static constexpr int64_t kBusyRetryMs = 1000;
  // After the server dropped us to make room (SL_ECROWDED, a flood).
  static constexpr int64_t kCrowdedRetryMs = 50;
  // Send STEP k with `inputs` and wait up to timeout_s for RESULT k.
  // Throws LinkError (timed out, peer closed, ABORT with its reason, ...).
  void step(uint64_t k, double time, double dt, const std::vector<double>& inputs,
            std::vector<double>& outputs);
  // A session of several FMUs (the server says so in its HELLO_ACK): the
  // inputs the importer set for step k, sent before the step (INPUTS k) and
  // answered before this returns, so that an importer that sets every FMU's
  // inputs and then steps them one after the other in one thread does not
  // deadlock (coupling_server.hpp, gather_round). Each INPUTS and each STEP
  // of such a session carries the calling thread (caller_thread()): the
  // server takes INPUTS for final only when another FMU steps from the
  // thread that set them.
  bool split_session() const { return session_fmus_ > 1; }
  void send_inputs(uint64_t k, double time, double dt, const std::vector<double>& inputs);
  // This process and thread, as one number: the same for every FMU library
  // of the process called from the same thread.
  static uint64_t caller_thread();
  // Ask the server to save its state after k completed steps (CHECKPOINT k);
  // returns the path of the server's checkpoint. Throws LinkError.
  std::string checkpoint(uint64_t k);
  // First exchange of a restarted session: sends RESUME k; the server's
  // answer (agreed, or an ABORT saying why not: LinkError) is awaited at the
  // first step, since the server answers once every FMU of the session has
  // connected, and the importer may connect them one after another.
  void resume(uint64_t k);
  // Waits for that answer now (no-op when none is pending): a restarted host
  // confirms both sides agree before it touches its results.
  void confirm_resume();
  // Clean end of the session (best effort).
  void bye();
  // Tell the peer why we stop (best effort), then close.
  void abort(const std::string& reason);
  bool connected() const { return sock_.fd >= 0; }
  // The server is stopping (it got a stop signal) and asks for a checkpoint
  // of both sides; it keeps serving meanwhile.
  bool stop_requested() const { return stop_requested_; }

 private:
  [[noreturn]] void fail(int code, const std::string& what);
  // One attempt: connect by connect_deadline, shake hands by deadline.
  void connect_once(const std::string& host, int port, const std::string& token, int64_t connect_deadline,
                    int64_t deadline);
  // Receive one handshake frame of type `want`; an ABORT, another version or
  // another type ends the connection with a LinkError naming the cause.
  // Send a frame of `type` for step k (empty payload); wait for the server's
  // answer of the same type and step (heartbeats restart the wait, STOPPING
  // is noted); its payload stays in buf_.
  void send_request(uint16_t type, uint64_t k);
  pcs_header await_answer(uint16_t type, uint64_t k);
  void receive_handshake_frame(pcs_header& h, uint16_t want, const std::string& where, int64_t deadline);
  config::PortTable table_;  // a copy: the client may outlive the table it was given
  sl_socket sock_ = SL_SOCKET_INIT;
  double timeout_s_ = 60.0;
  std::vector<uint8_t> buf_;
  bool stop_requested_ = false;
  bool connected_once_ = false;  // the last attempt got a connection (a time-out after it is the handshake's)
  Progress progress_;
  bool resume_pending_ = false;  // RESUME sent, its answer not yet read
  uint32_t session_fmus_ = 1;
  // RESULTs that came while an INPUTS awaited its answer (the server ran
  // steps with this FMU's inputs while the importer stepped another FMU by
  // a longer communication step): step, values.
  std::vector<std::pair<uint64_t, std::vector<double>>> early_results_;
  // RESULT k's values (payload in buf_) into `outputs`; fails naming `at`.
  void decode_result(const pcs_header& h, std::vector<double>& outputs, const std::string& at);
  // Reads one frame by `deadline` for step k's exchange: notes STOPPING,
  // skips heartbeats of step k; returns the first other frame's rc (header
  // in h, payload in buf_).
  int next_frame(pcs_header& h, uint64_t k, int64_t deadline);
  uint64_t resume_step_ = 0;
};

// The one-line reason for a link error code ("timed out: ...").
std::string describe_link_error(int code, const sl_socket& s);

}  // namespace pcs_fmu
