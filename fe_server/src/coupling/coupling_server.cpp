#include "coupling/coupling_server.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "config/stop_signal.hpp"
#include "socketlib/protocol.h"

namespace fe {

static int64_t deadline_after(double seconds) {
  return sl_now_ms() + static_cast<int64_t>(std::ceil(seconds * 1000.0));
}

static std::string link_error(int rc, const sl_socket& s) {
  std::string m = std::string(sl_err_name(rc)) + ": " + sl_strerror(rc);
  if (rc == SL_ESYSTEM && s.sys_errno) m += std::string(" (") + std::strerror(s.sys_errno) + ")";
  return m;
}

CouplingServer::CouplingServer(const ServerOptions& opt, std::vector<config::PortTable> tables)
    : opt_(opt), tables_(std::move(tables)) {
  size_t in = 0, out = 0, widest = 0;
  for (const auto& t : tables_) {
    Client c;
    c.table = &t;
    c.in_offset = in;
    c.out_offset = out;
    clients_.push_back(std::move(c));
    in += t.to_fe.size();
    out += t.to_host.size();
    widest = std::max({widest, t.to_fe.size(), t.to_host.size()});
  }
  if (tables_.empty()) throw std::invalid_argument("CouplingServer: no port table");
  if (pcs_auth_init() != SL_OK) throw std::runtime_error("cannot initialise libsodium (needed for the handshake)");
  timeout_ = tables_.front().timeout;
  for (const auto& t : tables_) timeout_ = std::max(timeout_, t.timeout);
  if (opt_.step_timeout > 0) timeout_ = opt_.step_timeout;
  // A split session's STEP and INPUTS carry the importer's thread too.
  buf_.resize(std::max<size_t>(pcs_tagged_values_size(static_cast<uint32_t>(widest)), PCS_MAX_REASON + 64));
  frame_in_.resize(widest);
  peek_.resize(PCS_HEADER_SIZE + buf_.size());
}

CouplingServer::~CouplingServer() {
  for (auto& c : clients_) sl_close(&c.conn);
  sl_close(&listener_);
}

void CouplingServer::end_session() {
  for (auto& c : clients_) {
    sl_close(&c.conn);
    c.conn = SL_SOCKET_INIT;
  }
}

std::string CouplingServer::name_of(const Client& c) const {
  return clients_.size() > 1 ? " from " + c.table->model_name : "";
}

void CouplingServer::abort_all(uint64_t step, uint32_t code, const std::string& why) {
  for (auto& c : clients_)
    if (c.conn.fd >= 0) pcs_send_abort(&c.conn, step, code, why.c_str(), deadline_after(1.0));
}

void CouplingServer::bind() {
  int rc = sl_listen(opt_.listen_host.c_str(), opt_.listen_port, &listener_);
  if (rc != SL_OK)
    throw std::runtime_error("cannot listen on " + opt_.listen_host + ":" + std::to_string(opt_.listen_port) +
                             ": " + link_error(rc, listener_));
  port_ = sl_local_port(&listener_);
  if (!opt_.port_file.empty()) {
    // Written to a temporary name and renamed, so a reader never sees half a number.
    std::string tmp = opt_.port_file + ".tmp";
    {
      std::ofstream f(tmp);
      f << port_ << "\n";
      if (!f.flush()) throw std::runtime_error("--port-file: cannot write '" + tmp + "'");
    }
    if (std::rename(tmp.c_str(), opt_.port_file.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      std::remove(tmp.c_str());
      throw std::runtime_error("--port-file: cannot write '" + opt_.port_file + "': " + why);
    }
  }
}

// Refuses the peer: ABORT with the reason (best effort), which is returned.
static std::string refuse(sl_socket& conn, const std::string& reason) {
  pcs_send_abort(&conn, 0, SL_EREFUSED_BY_PEER, reason.c_str(), deadline_after(1.0));
  return reason;
}

CouplingServer::HandshakeProgress CouplingServer::handshake_step(Pending& p, std::string& why) {
  constexpr int64_t kPartialFramePauseMs = 20;
  const int n = sl_peek(&p.conn, peek_.data(), peek_.size());
  if (n == SL_ECLOSED) {
    why = p.challenged ? "closed the connection during the handshake" : "closed the connection without a HELLO";
    return HandshakeProgress::Refused;
  }
  if (n < 0) {
    why = std::string(sl_err_name(n)) + ": " + sl_strerror(n);
    return HandshakeProgress::Refused;
  }
  const size_t have = static_cast<size_t>(n);
  if (have == 0) {  // readable yet nothing to peek: look again after a pause, not in a spin
    p.pause_until = sl_now_ms() + kPartialFramePauseMs;
    return HandshakeProgress::Waiting;
  }
  uint8_t magic[4];  // the protocol's magic as it arrives on the wire
  for (int b = 0; b < 4; ++b) magic[b] = static_cast<uint8_t>(PCS_MAGIC >> (8 * b));
  // Only a whole frame is read, so the server never waits on a stranger;
  // foreign magic or a length beyond any handshake frame is refused at once.
  if (std::memcmp(peek_.data(), magic, std::min<size_t>(have, 4)) != 0) {
    why = "foreign bytes (not this protocol's magic)";
    return HandshakeProgress::Refused;
  }
  pcs_header h{};
  if (have >= PCS_HEADER_SIZE) pcs_decode_header(peek_.data(), &h);
  if (have >= PCS_HEADER_SIZE && h.payload_size > buf_.size()) {
    why = "a frame of " + std::to_string(h.payload_size) + " bytes, more than any handshake message";
    return HandshakeProgress::Refused;
  }
  if (have < PCS_HEADER_SIZE || have < PCS_HEADER_SIZE + static_cast<size_t>(h.payload_size)) {
    p.pause_until = sl_now_ms() + kPartialFramePauseMs;  // the rest is still on its way
    return HandshakeProgress::Waiting;
  }
  bool bound = false;
  why = advance_handshake(p, bound);
  if (!why.empty()) return HandshakeProgress::Refused;
  p.progressed = sl_now_ms();
  return bound ? HandshakeProgress::Bound : HandshakeProgress::Waiting;
}

std::string CouplingServer::advance_handshake(Pending& p, bool& bound) {
  bound = false;
  pcs_header h{};
  // The frame is whole in the socket's buffer (accept_clients peeked it), so
  // this does not wait.
  const int rc = pcs_recv_frame(&p.conn, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline_after(1.0));
  if (rc == SL_EVERSION && h.type == PCS_MSG_ABORT) return "the host aborted (another protocol version)";
  if (rc == SL_EVERSION)
    return refuse(p.conn, "protocol version mismatch: server speaks " + std::to_string(PCS_PROTOCOL_VERSION) +
                              ", client " + std::to_string(h.version));
  if (rc != SL_OK) return "no valid frame: " + link_error(rc, p.conn);
  if (h.type == PCS_MSG_ABORT) {
    pcs_abort a{};
    pcs_decode_abort(buf_.data(), h.payload_size, &a);
    return std::string("the host aborted the handshake: ") + a.reason;
  }
  if (!p.challenged) return on_hello(p, h);
  const std::string why = on_auth(p, h);
  bound = why.empty();
  return why;
}

std::string CouplingServer::on_hello(Pending& p, const pcs_header& h) {
  if (h.type != PCS_MSG_HELLO) return refuse(p.conn, std::string("expected HELLO, got ") + pcs_msg_name(h.type));
  pcs_hello hello{};
  if (pcs_decode_hello(buf_.data(), h.payload_size, &hello) != SL_OK) return refuse(p.conn, "malformed HELLO");
  int which = -1;
  std::string hashes;
  for (size_t i = 0; i < clients_.size(); ++i) {
    const config::PortTable& t = *clients_[i].table;
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(t.hash()));
    hashes += (hashes.empty() ? "" : ", ") + std::string(buf) + " (" + t.source + ")";
    if (t.hash() != hello.table_hash) continue;
    if (clients_[i].conn.fd >= 0)
      return refuse(p.conn, "a second FMU presented the port table of " + t.source + ", which is already connected");
    which = static_cast<int>(i);
  }
  if (which < 0) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(hello.table_hash));
    return refuse(p.conn, "port table mismatch (host " + std::string(buf) + ", server " + hashes +
                              "): host and server must use the same ports.cfg");
  }
  const config::PortTable& table = *clients_[static_cast<size_t>(which)].table;
  if (hello.dt != table.dt || hello.subcycles != static_cast<uint32_t>(table.subcycles))
    return refuse(p.conn, "time step or subcycles differ between host and server");
  p.which = which;
  std::memcpy(p.client_nonce, hello.client_nonce, PCS_NONCE_SIZE);
  pcs_random_nonce(p.server_nonce);
  pcs_challenge ch{};
  std::memcpy(ch.server_nonce, p.server_nonce, PCS_NONCE_SIZE);  // no proof yet: the host proves first (auth.h)
  const int n = pcs_encode_challenge(&ch, buf_.data(), static_cast<uint32_t>(buf_.size()));
  const int rc = pcs_send_frame(&p.conn, PCS_MSG_CHALLENGE, 0, buf_.data(), static_cast<uint32_t>(n), p.deadline);
  if (rc != SL_OK) return "cannot send CHALLENGE: " + link_error(rc, p.conn);
  p.challenged = true;
  return "";
}

std::string CouplingServer::on_auth(Pending& p, const pcs_header& h) {
  if (h.type != PCS_MSG_AUTH) return refuse(p.conn, std::string("expected AUTH, got ") + pcs_msg_name(h.type));
  pcs_auth auth{};
  if (pcs_decode_auth(buf_.data(), h.payload_size, &auth) != SL_OK) return refuse(p.conn, "malformed AUTH");
  const config::PortTable& table = *clients_[static_cast<size_t>(p.which)].table;
  if (clients_[static_cast<size_t>(p.which)].conn.fd >= 0)
    return refuse(p.conn, "a second FMU presented the port table of " + table.source + ", which is already connected");
  if (!pcs_auth_check(opt_.token.data(), opt_.token.size(), PCS_ROLE_HOST, p.client_nonce, p.server_nonce,
                      table.hash(), auth.client_proof))
    return refuse(p.conn, "wrong or missing token (the host's proof does not match)");
  pcs_hello_ack ack{table.hash(), table.dt, static_cast<uint32_t>(table.subcycles), {}, static_cast<uint32_t>(clients_.size())};
  pcs_auth_proof(opt_.token.data(), opt_.token.size(), PCS_ROLE_SERVER, p.client_nonce, p.server_nonce, table.hash(),
                 ack.server_proof);
  const int n = pcs_encode_hello_ack(&ack, buf_.data(), static_cast<uint32_t>(buf_.size()));
  const int rc = pcs_send_frame(&p.conn, PCS_MSG_HELLO_ACK, 0, buf_.data(), static_cast<uint32_t>(n), p.deadline);
  if (rc != SL_OK) return "cannot send HELLO_ACK: " + link_error(rc, p.conn);
  return "";
}

ExitCode CouplingServer::accept_clients(std::string& message) {
  std::vector<Pending> pending;
  size_t bound = 0;
  const int64_t accept_deadline = deadline_after(opt_.accept_timeout);
  const int64_t handshake_ms = static_cast<int64_t>(std::ceil(opt_.handshake_timeout * 1000.0));
  auto refused = [&](Pending& p, const std::string& why) {
    std::cerr << "fe_server: refused " << p.peer << ": " << why << std::endl;
    sl_close(&p.conn);
  };
  std::vector<sl_socket*> set;
  std::vector<int> ready;
  std::vector<size_t> polled;  // the pending connection behind each set entry after the listener
  std::vector<size_t> done;    // pending connections handled in this round
  long evicted = 0;             // connections evicted to make room (make_room)
  int64_t next_eviction_note = 0;
  while (bound < clients_.size()) {
    const int64_t now = sl_now_ms();
    for (auto it = pending.begin(); it != pending.end();) {
      if (now < it->deadline) {
        ++it;
        continue;
      }
      std::ostringstream why;
      why << "no complete " << (it->challenged ? "AUTH" : "HELLO") << " within " << opt_.handshake_timeout << " s";
      refused(*it, why.str());
      it = pending.erase(it);
    }
    if (now >= accept_deadline) {
      for (auto& p : pending) sl_close(&p.conn);
      std::ostringstream m;
      m << (bound == 0 ? std::string("no host connected")
                       : std::to_string(bound) + " of " + std::to_string(clients_.size()) + " FMUs connected")
        << " within " << opt_.accept_timeout << " s";
      message = m.str();
      abort_all(0, SL_ETIMEDOUT, message);
      return kExitAcceptTimeout;
    }
    set.clear();
    polled.clear();
    set.push_back(&listener_);  // always: a full table evicts (make_room), it never stops accepting
    int64_t wake = accept_deadline;
    for (size_t k = 0; k < pending.size(); ++k) {
      Pending& p = pending[k];
      wake = std::min(wake, p.deadline);
      if (now < p.pause_until) {
        wake = std::min(wake, p.pause_until);
        continue;
      }
      set.push_back(&p.conn);
      polled.push_back(k);
    }
    ready.assign(set.size(), 0);
    const int rc = sl_wait_any(set.data(), set.size(), wake, ready.data());
    if (rc == SL_EINTERRUPTED) {
      for (auto& p : pending) refused(p, "the server is stopping");
      return stop(0, "while waiting for the host", message);
    }
    if (rc < 0) {
      message = "waiting for the host: " + link_error(rc, listener_);
      abort_all(0, static_cast<uint32_t>(-rc), message);
      return kExitLinkLost;
    }
    // Connections first (their indices follow the listener's), then new ones.
    const size_t offset = 1;
    done.clear();
    for (size_t i = offset; i < set.size(); ++i) {
      if (!ready[i]) continue;
      const size_t k = polled[i - offset];
      Pending& p = pending[k];
      std::string why;
      const HandshakeProgress progress = handshake_step(p, why);
      if (progress == HandshakeProgress::Refused) {
        refused(p, why);
        done.push_back(k);
      } else if (progress == HandshakeProgress::Bound) {
        Client& c = clients_[static_cast<size_t>(p.which)];
        c.conn = p.conn;
        p.conn = SL_SOCKET_INIT;
        ++bound;
        if (!opt_.quiet) std::cout << "fe_server: host " << p.peer << " accepted" << name_of(c) << std::endl;
        done.push_back(k);
      }
    }
    std::sort(done.begin(), done.end());
    for (auto it = done.rbegin(); it != done.rend(); ++it) pending.erase(pending.begin() + static_cast<long>(*it));
    if (ready[0]) {
      sl_socket conn = SL_SOCKET_INIT;
      const int arc = sl_accept(&listener_, sl_now_ms(), &conn);
      if (arc == SL_OK) {
        char peer[96];
        sl_peer_name(&conn, peer, sizeof peer);
        Pending p;
        p.conn = conn;
        p.deadline = sl_now_ms() + handshake_ms;
        p.progressed = sl_now_ms();
        p.peer = peer;
        const size_t colon = p.peer.rfind(':');
        p.address = colon == std::string::npos ? p.peer : p.peer.substr(0, colon);
        if (make_room(pending, p.address)) {
          ++evicted;
          if (sl_now_ms() >= next_eviction_note) {  // a flood must not flood the log too
            std::cerr << "fe_server: " << evicted << " connection(s) evicted so far that had sent no valid HELLO, "
                      << "to make room for new ones (a connection flood?)" << std::endl;
            next_eviction_note = sl_now_ms() + 1000;
          }
        }
        pending.push_back(std::move(p));
      } else if (arc != SL_ETIMEDOUT) {  // the connection vanished before accept: SL_ETIMEDOUT, nothing to do
        message = "cannot accept a connection: " + link_error(arc, listener_);
        for (auto& p : pending) sl_close(&p.conn);
        abort_all(0, static_cast<uint32_t>(-arc), message);
        return kExitLinkLost;
      }
    }
  }
  for (auto& p : pending) refused(p, "the session is complete");
  return kExitOk;
}

bool CouplingServer::make_room(std::vector<Pending>& pending, const std::string& address) {
  size_t same = 0;
  for (const Pending& p : pending) same += p.address == address;
  const bool over_share = same >= kMaxPendingPerPeer;
  if (pending.size() < kMaxPending && !over_share) return false;
  // The one idle the longest; of equals the first accepted.
  size_t victim = pending.size();
  for (size_t k = 0; k < pending.size(); ++k) {
    if (over_share && pending[k].address != address) continue;
    if (victim == pending.size() || pending[k].progressed < pending[victim].progressed) victim = k;
  }
  if (victim == pending.size()) return false;
  sl_socket& conn = pending[victim].conn;
  // What it sent is read first: closing a socket with unread bytes resets
  // the connection, and the peer would lose the ABORT that says why.
  // At most a few KiB: a handshake is smaller, and a peer that keeps
  // sending cannot hold the server here.
  uint8_t unread[512];
  for (int round = 0, n; round < 8 && (n = sl_peek(&conn, unread, sizeof unread)) > 0; ++round)
    if (sl_recv_all(&conn, unread, static_cast<size_t>(n), sl_now_ms()) != SL_OK) break;
  pcs_send_abort(&conn, 0, static_cast<uint32_t>(-SL_ECROWDED),
                 "crowded: too many connections in their handshake (a connection flood?); try again", sl_now_ms());
  sl_close(&conn);
  pending.erase(pending.begin() + static_cast<long>(victim));
  return true;
}

ExitCode CouplingServer::stop(uint64_t step, const std::string& where, std::string& message) {
  const int signo = config::stop_signal();
  message = "stopped by " + config::signal_name(signo) + " " + where;
  abort_all(step, SL_EINTERRUPTED, "fe_server " + message);
  return stopped_by(signo);
}

ExitCode CouplingServer::resume_clients(std::string& message) {
  for (Client& c : clients_) {
    pcs_header h{};
    const int rc = pcs_recv_frame(&c.conn, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline_after(timeout_));
    if (rc == SL_EINTERRUPTED) return stop(resume_step_, "waiting for RESUME" + name_of(c), message);
    if (rc != SL_OK) {
      message = "link lost waiting for RESUME" + name_of(c) + ": " + link_error(rc, c.conn);
      abort_all(resume_step_, static_cast<uint32_t>(-rc), message);
      return kExitLinkLost;
    }
    std::string why;
    if (h.type != PCS_MSG_RESUME)
      why = "this fe_server continues from its checkpoint after step " + std::to_string(resume_step_) + ", but the host" +
            name_of(c) + " sent " + pcs_msg_name(h.type) + " " + std::to_string(h.step) +
            ": restart the host from its checkpoint of that step (tlm_host --restart)";
    else if (h.step != resume_step_)
      why = "the host" + name_of(c) + " resumes after step " + std::to_string(h.step) + ", this fe_server's checkpoint is after step " +
            std::to_string(resume_step_) + ": both sides must restart from checkpoints of the same step" +
            (previous_step_ >= 0 && static_cast<uint64_t>(previous_step_) == h.step
                 ? " (" + previous_ + " is fe_server's checkpoint of step " + std::to_string(h.step) +
                       ": restart fe_server with --restart " + previous_ + ")"
                 : std::string());
    if (!why.empty()) {
      message = why;
      abort_all(resume_step_, SL_EUNEXPECTED, why);
      return kExitInput;
    }
    const int src = pcs_send_frame(&c.conn, PCS_MSG_RESUME, resume_step_, nullptr, 0, deadline_after(timeout_));
    if (src != SL_OK) {
      message = "cannot confirm RESUME" + name_of(c) + ": " + link_error(src, c.conn);
      abort_all(resume_step_, static_cast<uint32_t>(-src), message);
      return kExitLinkLost;
    }
  }
  if (!opt_.quiet) std::cout << "fe_server: the host resumes after step " << resume_step_ << std::endl;
  return kExitOk;
}

bool CouplingServer::ask_for_checkpoint(uint64_t step) {
  // SIGTERM is what batch systems send before they kill (SLURM at the wall
  // time, scancel); Ctrl-C (SIGINT) and SIGHUP stop at once, as before.
  if (!checkpointer_ || config::stop_signal() != SIGTERM) return false;
  for (Client& c : clients_)
    if (pcs_send_frame(&c.conn, PCS_MSG_STOPPING, step, nullptr, 0, deadline_after(1.0)) != SL_OK) return false;
  stopping_ = true;
  stop_deadline_ = sl_now_ms() + static_cast<int64_t>(1000.0 * opt_.stop_grace);
  // From here the waits must not end at the first signal: the host has the
  // grace to checkpoint. A second signal ends them (and the session).
  sl_set_stop_flag(config::second_stop_flag());
  if (!opt_.quiet)
    std::cout << "fe_server: " << config::signal_name(config::stop_signal()) << ": asking the host for a checkpoint at step "
              << step << " (within " << opt_.stop_grace << " s)" << std::endl;
  return true;
}

int CouplingServer::receive(Client& c, pcs_header& h, uint64_t step, int64_t deadline) {
  for (;;) {
    sl_socket* s = &c.conn;
    int ready = 0;
    const int64_t until = stopping_ ? std::min(stop_deadline_, deadline) : deadline;
    const int rc = sl_wait_any(&s, 1, until, &ready);
    if (rc == SL_EINTERRUPTED) {
      if (!stopping_ && ask_for_checkpoint(step)) continue;
      return rc;
    }
    if (rc == 0) return SL_ETIMEDOUT;
    if (rc < 0) return rc;
    break;
  }
  const volatile sig_atomic_t* flag = sl_get_stop_flag();
  sl_set_stop_flag(nullptr);
  const int rc = pcs_recv_frame(&c.conn, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline);
  sl_set_stop_flag(flag);
  return rc;
}

namespace {
constexpr double kCommandStep = 0.0, kCommandEnd = 1.0;
}

void CouplingServer::tell_ranks(double kind, double code, const std::vector<double>& in) {
  if (!dom_ || !dom_->parallel()) return;
  command_.assign(2, 0.0);
  command_[0] = kind, command_[1] = code;
  command_.insert(command_.end(), in.begin(), in.end());
  dom_->broadcast_waiting(command_.data(), command_.size() * sizeof(double));
}

ExitCode CouplingServer::run(Solver& solver, PortMap& ports, const OpenHistory& open_history, std::string& message) {
  // A failed FE step fails on every rank alike (solver.hpp); anything else
  // ends here with the session's code, which the other ranks are told.
  ranks_stopped_ = false;
  const ExitCode code = run_steps(solver, ports, open_history, message);
  if (ranks_stopped_) return code;
  size_t n_in = 0;  // all clients' inputs, as follow_session expects them
  for (const auto& t : tables_) n_in += t.to_fe.size();
  tell_ranks(kCommandEnd, static_cast<double>(code), std::vector<double>(n_in, 0.0));
  return code;
}

ExitCode follow_session(const Domain& domain, Solver& solver, PortMap& ports, FollowerHistory& history, size_t inputs,
                        size_t outputs, int subcycles) {
  std::vector<double> command(2 + inputs), in(inputs), out(outputs);
  for (;;) {
    domain.broadcast_waiting(command.data(), command.size() * sizeof(double));
    if (command[0] == kCommandEnd) return static_cast<ExitCode>(static_cast<int>(command[1]));
    std::copy(command.begin() + 2, command.end(), in.begin());
    ports.apply_inputs(in);
    // The steps to the coupling step's end, as the leader takes them (run_steps).
    solver.set_horizon(solver.time() + solver.dt_cap() * subcycles);
    do {
      solver.step();
      ports.accumulate(solver);
      history.record(solver);
    } while (!solver.reached_horizon());
    ports.measure_outputs(solver, out);
  }
}

std::string CouplingServer::split_master_hint(const Client& late, uint64_t step) {
  // Another FMU's STEP of this round came (it was read, or it waits unread
  // in its socket): the importer is inside that FMU's step and will not step
  // this one until it returns, which it cannot before this one's inputs.
  std::string others;
  for (Client& c : clients_) {
    if (&c == &late) continue;
    sl_socket* s = &c.conn;
    int ready = 0;
    const bool in = c.stepped || sl_wait_any(&s, 1, sl_now_ms(), &ready) > 0;
    if (in) others += (others.empty() ? "" : ", ") + std::string("'") + c.table->model_name + "'";
  }
  if (others.empty()) return "";
  std::ostringstream m;
  m << "FMU '" << late.table->model_name << "' sent no STEP " << step << " within " << kSplitRoundShare * timeout_
    << " s, and its importer set none of its inputs since its last step, while the STEP " << step << " of " << others
    << " came: an importer that steps its FMUs one after another waits inside the first FMU's step for a result "
       "that needs every FMU's inputs of the same step. Such an importer must set the inputs of every FMU before it "
       "steps the first, in the thread it steps them from (fmi2SetReal on each, then fmi2DoStep on each: an FMU "
       "sends fe_server its inputs when they are set, those set in initialization with its first step); one that "
       "sets and steps each FMU in turn (Hopsan's sequential solver) deadlocks here. Use one FMU "
       "for the whole model (one port table), or an importer that sets every FMU's inputs first or steps them in "
       "parallel (tlm_host does either: --peers)";
  return m.str();
}

ExitCode CouplingServer::on_round_frame(Client& c, const pcs_header& h, uint64_t k, std::vector<double>& in,
                                        std::string& message) {
  auto reject = [&](const std::string& why, ExitCode code) {
    message = why;
    abort_all(h.step, SL_EUNEXPECTED, why);
    return code;
  };
  const bool split = clients_.size() > 1;
  // The step this client's next STEP or CHECKPOINT must name: the oldest one
  // run with its INPUTS and not yet confirmed, else this round's.
  const uint64_t due = c.unconfirmed.empty() ? k : c.unconfirmed.front().first;
  auto out_of_order = [&] {
    return reject("step index out of order" + name_of(c) + ": expected " + std::to_string(due) + ", got " +
                      std::to_string(h.step),
                  kExitLinkLost);
  };
  switch (h.type) {
    case PCS_MSG_BYE:
      c.bye = true;
      return kExitOk;
    case PCS_MSG_ABORT: {
      pcs_abort a{};
      pcs_decode_abort(buf_.data(), h.payload_size, &a);
      message = "host aborted at step " + std::to_string(k) + name_of(c) + ": " + a.reason;
      sl_close(&c.conn);
      abort_all(k, SL_EREFUSED_BY_PEER, message);
      return kExitPeerAbort;
    }
    case PCS_MSG_RESUME:
      return reject("the host resumes from its checkpoint at step " + std::to_string(h.step) + name_of(c) +
                        ", but this fe_server started afresh: start it with --restart and its checkpoint of that step",
                    kExitInput);
    case PCS_MSG_CHECKPOINT:
      if (h.step != due || !c.unconfirmed.empty()) return out_of_order();
      c.checkpoint = true;
      return kExitOk;
    case PCS_MSG_INPUTS:
      if (!split) break;  // one FMU sends its inputs with its STEP
      [[fallthrough]];
    case PCS_MSG_STEP: {
      // Decoded into frame_in_ (no allocation on the per-step path); a
      // split session's frames carry the importer's thread first.
      const size_t want = c.table->to_fe.size();
      double* values = frame_in_.data();
      double t = 0, dt = 0;
      uint32_t count = 0;
      uint64_t thread = 0;
      const int rc = split ? pcs_decode_tagged_values(buf_.data(), h.payload_size, &thread, &t, &dt, values,
                                                      static_cast<uint32_t>(want), &count)
                           : pcs_decode_values(buf_.data(), h.payload_size, &t, &dt, values,
                                               static_cast<uint32_t>(want), &count);
      if (h.type == PCS_MSG_STEP && h.step != due) return out_of_order();
      if (rc != SL_OK || count != want)
        return reject(std::string(pcs_msg_name(h.type)) + " " + std::to_string(h.step) + name_of(c) + " carries " +
                          std::to_string(count) + " values, expected " + std::to_string(want),
                      kExitLinkLost);
      for (size_t i = 0; i < want; ++i)
        if (!std::isfinite(values[i]))
          return reject(c.table->to_fe[i].name() + " is not finite at step " + std::to_string(h.step), kExitNumerical);
      const auto same = [&](const std::vector<double>& used) {
        return std::memcmp(values, used.data(), want * sizeof(double)) == 0;
      };
      // The importer changed inputs fe_server has already stepped with.
      auto changed = [&](uint64_t step) {
        return reject("FMU '" + c.table->model_name + "''s inputs for step " + std::to_string(step) +
                          " changed after fe_server had run that step with the values its importer set before it "
                          "stepped another FMU of the session: an importer that steps its FMUs one after another "
                          "must set the inputs of them all before it steps the first (one that sets and steps each "
                          "FMU in turn, as Hopsan's sequential solver does, cannot run a session split into several "
                          "FMUs), and step them all by the same communication step",
                      kExitLinkLost);
      };
      if (h.type == PCS_MSG_INPUTS) {
        if (h.step != c.next_step)
          return reject("INPUTS " + std::to_string(h.step) + name_of(c) + ", expected INPUTS " + std::to_string(c.next_step),
                        kExitLinkLost);
        if (!c.unconfirmed.empty() && !same(c.unconfirmed.back().second)) return changed(c.unconfirmed.back().first);
        c.pushed.assign(values, values + want);
        c.pushed_for = h.step;
        c.push_thread = thread;
        const int sent = pcs_send_frame(&c.conn, PCS_MSG_INPUTS, h.step, nullptr, 0, deadline_after(timeout_));
        if (sent != SL_OK) {
          message = "cannot confirm INPUTS " + std::to_string(h.step) + name_of(c) + ": " + link_error(sent, c.conn);
          abort_all(k, static_cast<uint32_t>(-sent), message);
          return kExitLinkLost;
        }
        return kExitOk;
      }
      if (!c.unconfirmed.empty()) {  // the STEP of a step already run with its INPUTS
        if (!same(c.unconfirmed.front().second)) return changed(due);
        c.unconfirmed.pop_front();
        ++c.next_step;
        return kExitOk;
      }
      std::copy(values, values + want, in.begin() + static_cast<std::ptrdiff_t>(c.in_offset));
      c.stepped = true;
      c.step_thread = thread;
      c.next_step = k + 1;
      return kExitOk;
    }
    default:
      break;
  }
  return reject(std::string("expected STEP") + name_of(c) + ", got " + pcs_msg_name(h.type), kExitLinkLost);
}

ExitCode CouplingServer::gather_round(uint64_t k, std::vector<double>& in, size_t& byes, size_t& checkpoints,
                                      std::string& message) {
  for (Client& c : clients_) c.stepped = c.bye = c.checkpoint = false;
  // The round's deadline comes before the FMUs' own (a fifth of the step
  // time-out earlier), so that a round one FMU never joins can be told to
  // the others while they still listen (split_master_hint).
  const int64_t round_deadline = deadline_after(kSplitRoundShare * timeout_);
  const auto decided = [](const Client& c) { return c.stepped || c.bye || c.checkpoint; };
  // Its INPUTS are final: set since its last step, from a thread another FMU stepped from this round.
  const auto final_push = [&](const Client& c) {
    if (!c.push_valid()) return false;
    for (const Client& d : clients_)
      if (d.stepped && d.step_thread == c.push_thread) return true;
    return false;
  };
  std::vector<sl_socket*> socks;
  std::vector<Client*> open;
  std::vector<int> ready;
  for (;;) {
    size_t steps = 0, inputs = 0;
    byes = checkpoints = 0;
    for (const Client& c : clients_) {
      steps += c.stepped;
      byes += c.bye;
      checkpoints += c.checkpoint;
      inputs += c.stepped || (!c.bye && !c.checkpoint && final_push(c));
    }
    const size_t n = clients_.size();
    if (byes == n || checkpoints == n) return kExitOk;
    if (steps > 0 && inputs + byes + checkpoints == n) break;
    socks.clear();
    open.clear();
    for (Client& c : clients_)
      if (!decided(c)) {
        socks.push_back(&c.conn);
        open.push_back(&c);
      }
    ready.assign(socks.size(), 0);
    const int64_t until = stopping_ ? std::min(stop_deadline_, round_deadline) : round_deadline;
    const int rc = sl_wait_any(socks.data(), socks.size(), until, ready.data());
    if (rc == SL_EINTERRUPTED) {
      if (!stopping_ && ask_for_checkpoint(k)) continue;
      return stop(k, "waiting for STEP " + std::to_string(k), message);
    }
    if (rc < 0) {
      message = "link lost waiting for STEP " + std::to_string(k) + ": " + link_error(rc, open.front()->conn);
      abort_all(k, static_cast<uint32_t>(-rc), message);
      return kExitLinkLost;
    }
    if (rc == 0) {
      if (stopping_ && sl_now_ms() >= stop_deadline_)
        return stop(k, "at coupling step " + std::to_string(k) + "; the host did not checkpoint within " +
                           std::to_string(opt_.stop_grace) + " s",
                    message);
      if (sl_now_ms() < round_deadline) continue;
      for (Client* c : open)
        if (!final_push(*c))
          if (const std::string hint = split_master_hint(*c, k); !hint.empty()) {
            message = hint;
            abort_all(k, static_cast<uint32_t>(-SL_ETIMEDOUT), message);
            return kExitLinkLost;
          }
      message = "link lost waiting for STEP " + std::to_string(k) + name_of(*open.front()) + ": " +
                link_error(SL_ETIMEDOUT, open.front()->conn);
      abort_all(k, static_cast<uint32_t>(-SL_ETIMEDOUT), message);
      return kExitLinkLost;
    }
    for (size_t i = 0; i < open.size(); ++i) {
      if (!ready[i]) continue;
      Client& c = *open[i];
      pcs_header h{};
      const int r = receive(c, h, k, deadline_after(timeout_));
      if (r == SL_EINTERRUPTED) return stop(k, "waiting for STEP " + std::to_string(k) + name_of(c), message);
      if (r != SL_OK) {
        message = "link lost waiting for STEP " + std::to_string(k) + name_of(c) + ": " + link_error(r, c.conn);
        abort_all(k, static_cast<uint32_t>(-r), message);
        return kExitLinkLost;
      }
      if (const ExitCode code = on_round_frame(c, h, k, in, message); code != kExitOk) return code;
    }
  }
  // The FMUs that did not step yet take the inputs their importer set.
  for (Client& c : clients_)
    if (!c.stepped && !c.bye && !c.checkpoint) {
      std::copy(c.pushed.begin(), c.pushed.end(), in.begin() + static_cast<std::ptrdiff_t>(c.in_offset));
      c.unconfirmed.emplace_back(k, c.pushed);
    }
  return kExitOk;
}

void CouplingServer::turn_away_while_busy() {
  if (listener_.fd < 0) return;
  const int64_t now = sl_now_ms();
  if (now < next_busy_check_) return;
  next_busy_check_ = now + kBusyCheckMs;
  sl_socket conn = SL_SOCKET_INIT;
  if (sl_accept(&listener_, now, &conn) != SL_OK) return;  // none pending (a deadline of now: no wait)
  char peer[96];
  sl_peer_name(&conn, peer, sizeof peer);
  uint8_t hello[256];
  pcs_header h{};
  (void)pcs_recv_frame(&conn, &h, hello, sizeof hello, sl_now_ms() + kBusyDrainMs);
  pcs_send_abort(&conn, 0, static_cast<uint32_t>(-SL_EBUSY),
                 "busy: running another session, one at a time (with --sessions the next one starts when "
                 "this one ends)",
                 sl_now_ms() + 100);
  sl_close(&conn);
  if (!opt_.quiet) std::cerr << "fe_server: " << peer << " turned away: busy with this session" << std::endl;
}

ExitCode CouplingServer::run_steps(Solver& solver, PortMap& ports, const OpenHistory& open_history,
                                   std::string& message) {
  stopping_ = false;
  checkpointed_at_ = -1;
  if (listener_.fd < 0) bind();
  const ExitCode accepted = accept_clients(message);
  if (accepted != kExitOk) return accepted;
  if (!keep_listening_) sl_close(&listener_);  // no further session: strangers get "connection refused"
  if (!opt_.quiet) std::cout << "fe_server: session accepted" << std::endl;

  const size_t n_in = clients_.back().in_offset + clients_.back().table->to_fe.size();
  const size_t n_out = clients_.back().out_offset + clients_.back().table->to_host.size();
  std::vector<double> in(n_in), out(n_out);
  if (resume_)
    if (const ExitCode code = resume_clients(message); code != kExitOk) return code;
  uint64_t expected = resume_ ? resume_step_ : 0;
  for (Client& c : clients_) {
    c.next_step = expected;
    c.pushed_for = Client::kNoInputs;
    c.unconfirmed.clear();
  }
  History* opened = nullptr;
  try {
    opened = &open_history();
  } catch (const std::exception& e) {
    message = e.what();
    abort_all(expected, SL_EUNEXPECTED, "fe_server cannot continue: " + message);
    return kExitInput;
  }
  History& history = *opened;
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    // Only on the way out: no string is built on the per-step path.
    auto here = [&] {
      return "at coupling step " + std::to_string(expected) + " (t = " + std::to_string(solver.time()) + " s)";
    };
    auto no_checkpoint = [&] { return here() + "; the host did not checkpoint within " + std::to_string(opt_.stop_grace) + " s"; };
    if (config::stop_signal() && !stopping_ && !ask_for_checkpoint(expected)) return stop(expected, here(), message);
    if (stopping_ && sl_now_ms() >= stop_deadline_) return stop(expected, no_checkpoint(), message);
    turn_away_while_busy();
    size_t byes = 0, checkpoints = 0;
    if (clients_.size() > 1) {
      if (const ExitCode code = gather_round(expected, in, byes, checkpoints, message); code != kExitOk) return code;
    } else {
      Client& c = clients_.front();
      c.stepped = c.bye = c.checkpoint = false;
      pcs_header h{};
      int rc = receive(c, h, expected, deadline_after(timeout_));
      if (rc == SL_ETIMEDOUT && stopping_ && sl_now_ms() >= stop_deadline_) return stop(expected, no_checkpoint(), message);
      if (rc == SL_EINTERRUPTED)
        return stop(expected, "waiting for STEP " + std::to_string(expected) + name_of(c), message);
      if (rc != SL_OK) {
        message = "link lost waiting for STEP " + std::to_string(expected) + name_of(c) + ": " + link_error(rc, c.conn);
        abort_all(expected, static_cast<uint32_t>(-rc), message);
        return kExitLinkLost;
      }
      if (const ExitCode code = on_round_frame(c, h, expected, in, message); code != kExitOk) return code;
      byes = c.bye;
      checkpoints = c.checkpoint;
    }
    if (byes == clients_.size()) break;
    if (checkpoints == clients_.size()) {
      std::string path;
      try {
        if (!checkpointer_) throw std::runtime_error("fe_server was started without --checkpoint");
        path = checkpointer_(expected);
        checkpointed_at_ = static_cast<long>(expected);
      } catch (const std::exception& e) {
        message = "cannot checkpoint at step " + std::to_string(expected) + ": " + e.what();
        abort_all(expected, SL_EUNEXPECTED, message);
        return kExitInput;
      }
      for (Client& c : clients_) {
        uint8_t payload[4200];
        pcs_writer w{payload, sizeof payload, 0, 0};
        pcs_put_str(&w, path.c_str());
        const int rc = w.overflow ? SL_EOVERSIZE
                                  : pcs_send_frame(&c.conn, PCS_MSG_CHECKPOINT, expected, payload, w.len, deadline_after(timeout_));
        if (rc != SL_OK) {
          message = "cannot confirm CHECKPOINT " + std::to_string(expected) + name_of(c) + ": " + link_error(rc, c.conn);
          abort_all(expected, static_cast<uint32_t>(-rc), message);
          return kExitLinkLost;
        }
      }
      continue;
    }
    if (checkpoints > 0) {
      message = "at step " + std::to_string(expected) + " some FMUs asked for a checkpoint while others stepped on";
      abort_all(expected, SL_EUNEXPECTED, message);
      return kExitLinkLost;
    }
    if (byes > 0) {
      message = "at step " + std::to_string(expected) + " some FMUs ended the session while others stepped on";
      abort_all(expected, SL_EUNEXPECTED, message);
      return kExitLinkLost;
    }

    ports.apply_inputs(in);
    if (const std::string why = ports.check_coupling(); !why.empty()) {  // before the other ranks step
      message = "at coupling step " + std::to_string(expected) + ": " + why;
      abort_all(expected, SL_EUNEXPECTED, message);
      return kExitInput;
    }
    tell_ranks(kCommandStep, 0.0, in);
    // Heartbeats keep the host's deadline from expiring during a long step.
    const double beat = std::min(1.0, 0.25 * timeout_);
    auto last_beat = std::chrono::steady_clock::now();
    const int subcycles = tables_.front().subcycles;
    // A lost link ends the session after the coupling step: across ranks
    // the others are inside the same FE steps and finish them too.
    ExitCode lost = kExitOk;
    // The FE steps end on the coupling step's end: `subcycles` of them while
    // the model's stable step allows, more when it has shrunk (solver.hpp).
    solver.set_horizon(solver.time() + solver.dt_cap() * subcycles);
    for (bool last = false; !last;) {
      try {
        solver.step();
      } catch (const std::exception& e) {
        // The step failed on every rank alike (solver.hpp): the host is told
        // why; the other ranks have stopped with it and are not told.
        message = "the FE step failed at coupling step " + std::to_string(expected) + ": " + e.what();
        abort_all(expected, SL_EUNEXPECTED, message);
        ranks_stopped_ = true;
        return kExitNumerical;
      }
      ports.accumulate(solver);
      last = solver.reached_horizon();
      // The history sees every FE step and writes the rows the deck asks
      // for (a stress gauge can be resolved however long the coupling step);
      // port outputs are the last coupling step's.
      if (!last) history.record(solver, in, out);
      if (lost == kExitOk && std::chrono::duration<double>(std::chrono::steady_clock::now() - last_beat).count() > beat) {
        for (Client& c : clients_) {
          int rc = pcs_send_frame(&c.conn, PCS_MSG_HEARTBEAT, expected, nullptr, 0, deadline_after(timeout_));
          if (rc != SL_OK) {
            message = "cannot send HEARTBEAT " + std::to_string(expected) + name_of(c) + ": " + link_error(rc, c.conn);
            abort_all(expected, static_cast<uint32_t>(-rc), message);
            lost = kExitLinkLost;
            break;
          }
        }
        last_beat = std::chrono::steady_clock::now();
      }
    }
    if (lost != kExitOk) return lost;
    ports.measure_outputs(solver, out);
    history.record(solver, in, out);
    for (size_t i = 0; i < out.size(); ++i)
      if (!std::isfinite(out[i])) {
        const config::Variable* v = nullptr;
        for (const Client& c : clients_)
          if (i >= c.out_offset && i < c.out_offset + c.table->to_host.size()) v = &c.table->to_host[i - c.out_offset];
        message = (v ? v->name() : std::string("an output")) + " became non-finite at step " + std::to_string(expected) +
                  " (FE instability?)";
        abort_all(expected, SL_EUNEXPECTED, message);
        return kExitNumerical;
      }
    for (Client& c : clients_) {
      const size_t count = c.table->to_host.size();
      int n = pcs_encode_values(solver.time(), c.table->dt, out.data() + c.out_offset, static_cast<uint32_t>(count),
                                buf_.data(), static_cast<uint32_t>(buf_.size()));
      int rc = pcs_send_frame(&c.conn, PCS_MSG_RESULT, expected, buf_.data(), static_cast<uint32_t>(n),
                              deadline_after(timeout_));
      if (rc != SL_OK) {
        message = "cannot send RESULT " + std::to_string(expected) + name_of(c) + ": " + link_error(rc, c.conn);
        abort_all(expected, static_cast<uint32_t>(-rc), message);
        return kExitLinkLost;
      }
    }
    ++expected;
  }
  if (stopping_ && checkpointed_at_ != static_cast<long>(expected)) {
    message = "stopped by " + config::signal_name(config::stop_signal()) + ": the host ended the session at coupling step " +
              std::to_string(expected) + " without the checkpoint it was asked for";
    return stopped_by(config::stop_signal());
  }
  if (checkpointed_at_ == static_cast<long>(expected)) {
    std::ostringstream s;
    if (stopping_) s << "stopped by " << config::signal_name(config::stop_signal()) << ": ";
    s << "the host ended the session after the checkpoint at coupling step " << expected << " (t = " << solver.time()
      << " s); --restart continues from it";
    message = s.str();
    return stopping_ ? stopped_by(config::stop_signal()) : kExitCheckpointed;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ostringstream s;
  s << "session ended by the host after " << expected << " coupling steps (t = " << solver.time() << " s), "
    << wall << " s wall, " << (expected ? 1e6 * wall / static_cast<double>(expected) : 0.0) << " us per step";
  message = s.str();
  return kExitOk;
}

}  // namespace fe
