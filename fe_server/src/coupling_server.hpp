// Server side of the coupling protocol: one session per run. Accepts one
// host, checks its HELLO (protocol version, port-table hash, time step,
// subcycles, token), then per coupling step k: block on STEP k → apply the
// port loads through the user-load hook → advance `subcycles` FE steps →
// send RESULT k. Ends on BYE, ABORT, a deadline or a link error, always with
// the history flushed.
#pragma once

#include <string>

#include "cavity_load.hpp"
#include "config/port_table.hpp"
#include "exit_codes.hpp"
#include "history.hpp"
#include "mechanical_load.hpp"
#include "socketlib/socketlib.h"
#include "solver.hpp"

namespace fe {

struct ServerOptions {
  std::string listen_host = "127.0.0.1";
  int listen_port = 0;
  std::string token;
  std::string port_file;        // if set, the bound port is written here
  double accept_timeout = 300;  // s
  double step_timeout = 0;      // s; 0: the port table's timeout
  bool quiet = false;
};

// Maps the table's variables to the model: which load each input sets and
// what each output measures. Throws config::InputError for a variable the
// model cannot serve.
//
// One coupling step: apply_inputs (pressure, or wave and impedance), then
// after each of the k FE sub-steps accumulate(); measure_outputs returns flow
// and pressure averaged over the sub-steps (so the oil volume exchanged is
// the volume the surface swept in the coupling step) and displacement and
// velocity at its end.
class PortMap {
 public:
  PortMap(const config::PortTable& table, CavityPressureLoad& load, MechanicalLoad& mech);
  void apply_inputs(const std::vector<double>& in);
  void accumulate(const Solver& s);
  void measure_outputs(const Solver& s, std::vector<double>& out);

 private:
  const config::PortTable& table_;
  CavityPressureLoad& load_;
  MechanicalLoad& mech_;
  std::vector<int> in_slot_, out_slot_;  // hydraulic slot, or mechanical slot when *_mech_ is set
  std::vector<char> in_mech_, out_mech_;
  std::vector<double> wave_, impedance_;         // per slot, TLM mode
  std::vector<double> flow_sum_, pressure_sum_;  // per slot, over the sub-steps
  int substeps_ = 0;
};

class CouplingServer {
 public:
  CouplingServer(const ServerOptions& opt, const config::PortTable& table);
  ~CouplingServer();
  // Bind now, so the port is known (and written to port_file) before run().
  void bind();
  int port() const { return port_; }
  // Serve one session. Returns an exit code; `message` says what happened.
  ExitCode run(Solver& solver, PortMap& ports, History& history, std::string& message);

 private:
  ExitCode handshake(std::string& message);
  const ServerOptions opt_;
  const config::PortTable& table_;
  sl_socket listener_ = SL_SOCKET_INIT;
  sl_socket conn_ = SL_SOCKET_INIT;
  int port_ = 0;
  std::vector<uint8_t> buf_;
};

}  // namespace fe
