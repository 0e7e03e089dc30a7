#include "coupling_server.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "socketlib/protocol.h"

namespace fe {

using config::Quantity;

static int64_t deadline_after(double seconds) {
  return sl_now_ms() + static_cast<int64_t>(std::ceil(seconds * 1000.0));
}

static std::string link_error(int rc, const sl_socket& s) {
  std::string m = std::string(sl_err_name(rc)) + ": " + sl_strerror(rc);
  if (rc == SL_ESYSTEM && s.sys_errno) m += std::string(" (") + std::strerror(s.sys_errno) + ")";
  return m;
}

PortMap::PortMap(const config::PortTable& table, CavityPressureLoad& load, MechanicalLoad& mech)
    : table_(table), load_(load), mech_(mech) {
  for (const auto& v : table.to_fe) {
    const int m = mech.slot_of_port(v.port_id);
    in_mech_.push_back(m >= 0);
    if (m >= 0) {
      if (v.quantity != Quantity::Force)
        throw config::InputError(v.where, "a mechanical port takes a force from the host, not " +
                                              std::string(config::long_name(v.quantity)));
      in_slot_.push_back(m);
      continue;
    }
    int slot = load.slot_of_port(v.port_id);
    const bool ok = slot >= 0 && (v.quantity == Quantity::Pressure || v.quantity == Quantity::Wave ||
                                  v.quantity == Quantity::Impedance);
    if (!ok)
      throw config::InputError(v.where, std::string("fe_server cannot apply ") + config::long_name(v.quantity) +
                                            " at port " + v.port_label +
                                            " yet: hydraulic ports take pressure, or wave and impedance");
    in_slot_.push_back(slot);
  }
  for (const auto& v : table.to_host) {
    const int m = mech.slot_of_port(v.port_id);
    out_mech_.push_back(m >= 0);
    if (m >= 0) {
      out_slot_.push_back(m);
      continue;
    }
    int slot = load.slot_of_port(v.port_id);
    bool ok = slot >= 0 && (v.quantity == Quantity::Flow || v.quantity == Quantity::Displacement ||
                            v.quantity == Quantity::Velocity || v.quantity == Quantity::Pressure);
    if (!ok)
      throw config::InputError(v.where, std::string("fe_server cannot return ") + config::long_name(v.quantity) +
                                            " at port " + v.port_label +
                                            " yet: hydraulic ports return flow, pressure, displacement and velocity");
    out_slot_.push_back(slot);
  }
  const size_t slots = load.slot_count();
  wave_.assign(slots, 0.0);
  impedance_.assign(slots, 0.0);
  flow_sum_.assign(slots, 0.0);
  pressure_sum_.assign(slots, 0.0);
}

void PortMap::apply_inputs(const std::vector<double>& in) {
  std::vector<char> tlm(wave_.size(), 0);
  for (size_t i = 0; i < in.size(); ++i) {
    if (in_mech_[i]) {
      mech_.set_force(in_slot_[i], in[i]);
      continue;
    }
    const size_t slot = static_cast<size_t>(in_slot_[i]);
    switch (table_.to_fe[i].quantity) {
      case Quantity::Pressure: load_.set_pressure(in_slot_[i], in[i]); break;
      case Quantity::Wave: wave_[slot] = in[i], tlm[slot] = 1; break;
      case Quantity::Impedance: impedance_[slot] = in[i], tlm[slot] = 1; break;
      default: break;
    }
  }
  for (size_t slot = 0; slot < tlm.size(); ++slot)
    if (tlm[slot]) load_.set_wave(static_cast<int>(slot), wave_[slot], impedance_[slot]);
  std::fill(flow_sum_.begin(), flow_sum_.end(), 0.0);
  std::fill(pressure_sum_.begin(), pressure_sum_.end(), 0.0);
  substeps_ = 0;
}

void PortMap::accumulate(const Solver& s) {
  for (size_t slot = 0; slot < flow_sum_.size(); ++slot) {
    flow_sum_[slot] += load_.flow(static_cast<int>(slot), s.v());
    pressure_sum_[slot] += load_.pressure(static_cast<int>(slot));
  }
  ++substeps_;
}

void PortMap::measure_outputs(const Solver& s, std::vector<double>& out) {
  out.resize(table_.to_host.size());
  const double n = substeps_ > 0 ? static_cast<double>(substeps_) : 1.0;
  for (size_t i = 0; i < out.size(); ++i) {
    const int slot = out_slot_[i];
    if (out_mech_[i]) {
      switch (table_.to_host[i].quantity) {
        case Quantity::Displacement: out[i] = mech_.displacement(slot, s.x()); break;
        case Quantity::Velocity: out[i] = mech_.velocity(slot, s.v()); break;
        case Quantity::Force: out[i] = mech_.force(slot); break;
        default: out[i] = 0.0;
      }
      continue;
    }
    switch (table_.to_host[i].quantity) {
      case Quantity::Flow: out[i] = flow_sum_[static_cast<size_t>(slot)] / n; break;
      case Quantity::Pressure: out[i] = pressure_sum_[static_cast<size_t>(slot)] / n; break;
      case Quantity::Displacement: out[i] = load_.displacement(slot, s.x()); break;
      case Quantity::Velocity: {
        const double a = load_.area(slot);
        out[i] = a > 0.0 ? load_.flow(slot, s.v()) / a : 0.0;
        break;
      }
      default: out[i] = 0.0;
    }
  }
}

CouplingServer::CouplingServer(const ServerOptions& opt, const config::PortTable& table)
    : opt_(opt), table_(table) {
  size_t n = std::max(table.to_fe.size(), table.to_host.size());
  buf_.resize(std::max<size_t>(pcs_values_size(static_cast<uint32_t>(n)), PCS_MAX_REASON + PCS_MAX_TOKEN + 64));
}

CouplingServer::~CouplingServer() {
  sl_close(&conn_);
  sl_close(&listener_);
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
    }
    std::rename(tmp.c_str(), opt_.port_file.c_str());
  }
}

ExitCode CouplingServer::handshake(std::string& message) {
  const double timeout = opt_.step_timeout > 0 ? opt_.step_timeout : table_.timeout;
  const int64_t deadline = deadline_after(timeout);
  pcs_header h{};
  int rc = pcs_recv_frame(&conn_, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline);
  auto refuse = [&](const std::string& reason) {
    pcs_send_abort(&conn_, 0, SL_EREFUSED_BY_PEER, reason.c_str(), deadline_after(1.0));
    message = "session refused: " + reason;
    return kExitHandshake;
  };
  if (rc == SL_EVERSION)
    return refuse("protocol version mismatch: server speaks " + std::to_string(PCS_PROTOCOL_VERSION) +
                  ", client " + std::to_string(h.version));
  if (rc != SL_OK) {
    message = "no valid HELLO from the host: " + link_error(rc, conn_);
    return rc == SL_EBADMAGIC ? kExitHandshake : kExitLinkLost;
  }
  if (h.type != PCS_MSG_HELLO) return refuse(std::string("expected HELLO, got ") + pcs_msg_name(h.type));
  pcs_hello hello{};
  if (pcs_decode_hello(buf_.data(), h.payload_size, &hello) != SL_OK) return refuse("malformed HELLO");
  if (hello.table_hash != table_.hash()) {
    char buf[160];
    std::snprintf(buf, sizeof buf, " (server %016llx, host %016llx)",
                  static_cast<unsigned long long>(table_.hash()),
                  static_cast<unsigned long long>(hello.table_hash));
    return refuse("port table mismatch" + std::string(buf) + ": host and server must use the same ports.cfg; server has " +
                  table_.source);
  }
  if (hello.dt != table_.dt || hello.subcycles != static_cast<uint32_t>(table_.subcycles))
    return refuse("time step or subcycles differ between host and server");
  if (!pcs_token_equal(hello.token, opt_.token.c_str()))
    return refuse(opt_.token.empty() ? "this server expects no token" : "wrong or missing token");
  pcs_hello_ack ack{table_.hash(), table_.dt, static_cast<uint32_t>(table_.subcycles)};
  int n = pcs_encode_hello_ack(&ack, buf_.data(), static_cast<uint32_t>(buf_.size()));
  rc = pcs_send_frame(&conn_, PCS_MSG_HELLO_ACK, 0, buf_.data(), static_cast<uint32_t>(n), deadline);
  if (rc != SL_OK) {
    message = "cannot send HELLO_ACK: " + link_error(rc, conn_);
    return kExitLinkLost;
  }
  return kExitOk;
}

ExitCode CouplingServer::run(Solver& solver, PortMap& ports, History& history, std::string& message) {
  if (listener_.fd < 0) bind();
  int rc = sl_accept(&listener_, deadline_after(opt_.accept_timeout), &conn_);
  if (rc != SL_OK) {
    message = "no host connected within " + std::to_string(opt_.accept_timeout) + " s: " + link_error(rc, listener_);
    return rc == SL_ETIMEDOUT ? kExitAcceptTimeout : kExitLinkLost;
  }
  sl_close(&listener_);  // one session per run
  ExitCode code = handshake(message);
  if (code != kExitOk) return code;
  if (!opt_.quiet) std::cout << "fe_server: session accepted" << std::endl;

  const double timeout = opt_.step_timeout > 0 ? opt_.step_timeout : table_.timeout;
  std::vector<double> in(table_.to_fe.size()), out(table_.to_host.size());
  uint64_t expected = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    pcs_header h{};
    rc = pcs_recv_frame(&conn_, &h, buf_.data(), static_cast<uint32_t>(buf_.size()), deadline_after(timeout));
    if (rc != SL_OK) {
      message = "link lost waiting for STEP " + std::to_string(expected) + ": " + link_error(rc, conn_);
      if (rc == SL_EBADMAGIC || rc == SL_EOVERSIZE || rc == SL_EVERSION)
        pcs_send_abort(&conn_, expected, static_cast<uint32_t>(-rc), message.c_str(), deadline_after(1.0));
      return kExitLinkLost;
    }
    if (h.type == PCS_MSG_BYE) break;
    if (h.type == PCS_MSG_ABORT) {
      pcs_abort a{};
      pcs_decode_abort(buf_.data(), h.payload_size, &a);
      message = "host aborted at step " + std::to_string(expected) + ": " + a.reason;
      return kExitPeerAbort;
    }
    auto reject = [&](const std::string& why, ExitCode c) {
      pcs_send_abort(&conn_, h.step, SL_EUNEXPECTED, why.c_str(), deadline_after(1.0));
      message = why;
      return c;
    };
    if (h.type != PCS_MSG_STEP) return reject(std::string("expected STEP, got ") + pcs_msg_name(h.type), kExitLinkLost);
    if (h.step != expected)
      return reject("step index out of order: expected " + std::to_string(expected) + ", got " + std::to_string(h.step),
                    kExitLinkLost);
    double t = 0, dt = 0;
    uint32_t count = 0;
    if (pcs_decode_values(buf_.data(), h.payload_size, &t, &dt, in.data(), static_cast<uint32_t>(in.size()), &count) !=
            SL_OK ||
        count != in.size())
      return reject("STEP " + std::to_string(h.step) + " carries " + std::to_string(count) + " values, expected " +
                        std::to_string(in.size()),
                    kExitLinkLost);
    for (size_t i = 0; i < in.size(); ++i)
      if (!std::isfinite(in[i]))
        return reject(table_.to_fe[i].name() + " is not finite at step " + std::to_string(h.step), kExitNumerical);

    ports.apply_inputs(in);
    // Heartbeats keep the host's deadline from expiring during a long step.
    const double beat = std::min(1.0, 0.25 * timeout);
    auto last_beat = std::chrono::steady_clock::now();
    for (int s = 0; s < table_.subcycles; ++s) {
      solver.step();
      ports.accumulate(solver);
      // The history keeps every FE step (a stress pulse is resolved however
      // long the coupling step); port outputs are the last coupling step's.
      if (s + 1 < table_.subcycles) history.record(solver, in, out);
      if (std::chrono::duration<double>(std::chrono::steady_clock::now() - last_beat).count() > beat) {
        rc = pcs_send_frame(&conn_, PCS_MSG_HEARTBEAT, h.step, nullptr, 0, deadline_after(timeout));
        if (rc != SL_OK) {
          message = "cannot send HEARTBEAT " + std::to_string(h.step) + ": " + link_error(rc, conn_);
          return kExitLinkLost;
        }
        last_beat = std::chrono::steady_clock::now();
      }
    }
    ports.measure_outputs(solver, out);
    for (size_t i = 0; i < out.size(); ++i)
      if (!std::isfinite(out[i])) {
        history.record(solver, in, out);
        return reject(table_.to_host[i].name() + " became non-finite at step " + std::to_string(h.step) +
                          " (FE instability?)",
                      kExitNumerical);
      }
    history.record(solver, in, out);

    int n = pcs_encode_values(solver.time(), table_.dt, out.data(), static_cast<uint32_t>(out.size()), buf_.data(),
                              static_cast<uint32_t>(buf_.size()));
    rc = pcs_send_frame(&conn_, PCS_MSG_RESULT, h.step, buf_.data(), static_cast<uint32_t>(n), deadline_after(timeout));
    if (rc != SL_OK) {
      message = "cannot send RESULT " + std::to_string(h.step) + ": " + link_error(rc, conn_);
      return kExitLinkLost;
    }
    ++expected;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ostringstream s;
  s << "session ended by the host after " << expected << " coupling steps (t = " << solver.time() << " s), "
    << wall << " s wall, " << (expected ? 1e6 * wall / static_cast<double>(expected) : 0.0) << " us per step";
  message = s.str();
  return kExitOk;
}

}  // namespace fe
