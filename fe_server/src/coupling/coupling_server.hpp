// Server side of the coupling protocol: one session per run() (fe_server's
// --sessions calls run() again on the same listener). A session has
// one client per port table: one FMU, or one per co-simulated part (piston,
// valve) when several tables are given. Accepts them in any order, checks
// each HELLO (protocol version, port-table hash, time step, subcycles,
// token), then per coupling step k: block on STEP k from every client →
// apply all port loads through the user-load hook → advance `subcycles` FE
// steps → send each client its RESULT k. Ends when every client has said
// BYE, on an ABORT, a deadline or a link error (every client is told),
// always with the history flushed.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>

#include "loads/cavity_load.hpp"
#include "config/port_table.hpp"
#include "coupling/coupling_advice.hpp"
#include "coupling/port_map.hpp"
#include "coupling/exit_codes.hpp"
#include "output/history.hpp"
#include "loads/mechanical_load.hpp"
#include "socketlib/protocol.h"
#include "solver/solver.hpp"

namespace fe {

struct ServerOptions {
  std::string listen_host = "127.0.0.1";
  int listen_port = 0;
  std::string token;
  std::string port_file;        // if set, the bound port is written here
  double accept_timeout = 300;  // s
  double step_timeout = 0;      // s; 0: the port table's timeout
  // A connection has this long to deliver a complete HELLO; strangers that
  // do not are dropped (logged) while the server keeps listening.
  double handshake_timeout = 5;  // s
  bool quiet = false;
  // SIGTERM during a session: the host is asked to checkpoint (both
  // sides, at the same step) and given this long to do it before the
  // session stops without one. SLURM sends SIGTERM KillWait (default 30 s)
  // before SIGKILL.
  double stop_grace = 20;  // s
};

class CouplingServer {
 public:
  // One client per table; the PortMap given to run() serves
  // config::combine_port_tables(tables), whose variables are the tables' in order.
  CouplingServer(const ServerOptions& opt, std::vector<config::PortTable> tables);
  ~CouplingServer();
  // Bind now, so the port is known (and written to port_file) before run().
  void bind();
  // Keep the listener open after run() has accepted its session, for the
  // next one (--sessions); otherwise run() closes it once its clients are in.
  void set_keep_listening(bool keep) { keep_listening_ = keep; }
  // After run(): close the session's connections, ready for the next run().
  void end_session();
  int port() const { return port_; }
  // Checkpoints: `save(k)` is called when every client has sent CHECKPOINT
  // k, saves the state after k coupling steps and returns the file's path
  // (told to the clients); it throws to refuse. Without it CHECKPOINT is
  // refused ("started without --checkpoint").
  void set_checkpointer(std::function<std::string(uint64_t)> save) { checkpointer_ = std::move(save); }
  // A server restarted from a checkpoint after `step` coupling steps: every
  // client must open the session with RESUME step.
  // `previous`: a checkpoint of an earlier step (FILE.prev) and its step,
  // named in the refusal when the host resumes at that step instead.
  void set_resume(uint64_t step, const std::string& previous = "", long previous_step = -1) {
    resume_ = true;
    resume_step_ = step;
    previous_ = previous;
    previous_step_ = previous_step;
  }
  // Opens the session's results: called once the session is agreed (the
  // hosts connected and, in a restart, their RESUME matched this server's
  // checkpoint), so a refused restart leaves every file as it was. It may
  // throw (a checkpoint that does not load): the session then ends with
  // kExitInput, the hosts told why.
  using OpenHistory = std::function<History&()>;
  // Serve one session. Returns an exit code; `message` says what happened.
  ExitCode run(Solver& solver, PortMap& ports, const OpenHistory& open_history, std::string& message);
  // fe_server across ranks: this server is rank 0's; every coupling step it
  // tells the other ranks (follow_session) to step with the host's inputs,
  // and at the session's end its exit code.
  void set_domain(const Domain* domain) { dom_ = domain; }

  // A connection in its handshake: HELLO expected, then (after our
  // CHALLENGE) AUTH.
  struct Pending {
    sl_socket conn = SL_SOCKET_INIT;
    int64_t deadline = 0;  // the whole handshake must be done by then
    std::string peer;      // address:port, for the log
    std::string address;   // the peer's address alone: the per-peer share
    // Part of a frame stays readable until it is whole: such a connection is
    // polled again only after a short pause, so a slow drip costs no CPU.
    int64_t pause_until = 0;
    // When it last moved its handshake on (accepted, HELLO read): under a
    // flood the connection idle the longest is dropped first (make_room).
    int64_t progressed = 0;
    bool challenged = false;  // HELLO answered with CHALLENGE; AUTH expected
    int which = -1;           // the client whose port table the HELLO named
    uint8_t client_nonce[PCS_NONCE_SIZE] = {};
    uint8_t server_nonce[PCS_NONCE_SIZE] = {};
  };
  enum class HandshakeProgress { Waiting, Bound, Refused };
  // One look at a connection in its handshake (accept_clients calls it when
  // the connection is readable; the handshake fuzz target drives it too):
  // refuses foreign magic or an oversize length at once, waits while a frame
  // is partial (setting p.pause_until), else reads the frame and answers it.
  // Bound: the handshake is complete for client p.which. Refused: `why`
  // says why (the peer was told where it speaks the protocol).
  HandshakeProgress handshake_step(Pending& p, std::string& why);

 private:
  ExitCode run_steps(Solver& solver, PortMap& ports, const OpenHistory& open_history, std::string& message);
  void tell_ranks(double kind, double code, const std::vector<double>& in);
  const Domain* dom_ = nullptr;
  bool ranks_stopped_ = false;  // an FE step failed: every rank stopped at once
  std::vector<double> command_;
  struct Client {
    const config::PortTable* table = nullptr;
    sl_socket conn = SL_SOCKET_INIT;
    size_t in_offset = 0, out_offset = 0;  // of its variables in the combined table
    bool stepped = false;  // its STEP of the current round has been read
    // Several FMUs (gather_round): what it said this round, and the inputs
    // its importer set (INPUTS) since its last STEP, for step `pushed_for`.
    bool bye = false, checkpoint = false;
    uint64_t next_step = 0;  // the index of the next STEP it will send
    static constexpr uint64_t kNoInputs = UINT64_MAX;
    uint64_t pushed_for = kNoInputs;
    std::vector<double> pushed;
    // The importer's thread (process and thread id) that set `pushed`, and
    // the one its last STEP came from.
    uint64_t push_thread = 0, step_thread = 0;
    // Steps run with its INPUTS before its own STEP of them came (a
    // sequential importer stepping another FMU first), oldest first: each
    // STEP that comes must carry the same values.
    std::deque<std::pair<uint64_t, std::vector<double>>> unconfirmed;
    bool push_valid() const { return pushed_for == next_step; }  // set since its last STEP
  };
  // A session of several FMUs: reads what every client sends until round
  // `k` can run: at least one FMU's STEP k, and from every other one its
  // STEP k or the INPUTS its importer set since its last step from the
  // thread a STEP k came from (an importer that steps its FMUs one after the
  // other in that thread has set the inputs of them all when it steps the
  // first; INPUTS set on another thread may not be its last, a parallel
  // importer's, and wait for their FMU's STEP); or BYE or CHECKPOINT from
  // all. INPUTS are answered at once, so that everything an
  // importer set before it stepped an FMU is here before that STEP is read:
  // a sequential importer that sets every FMU's inputs and then steps them
  // one after the other gets the results a parallel one gets, bit for bit.
  // `in` gets the round's inputs; byes and checkpoints are counted as in
  // run_steps. Returns kExitOk or the session's end (`message` set, the
  // clients told).
  ExitCode gather_round(uint64_t k, std::vector<double>& in, size_t& byes, size_t& checkpoints, std::string& message);
  // One client's frame of round k (h read whole into buf_), in a session of
  // one FMU or several: a STEP's values into `in`, BYE or CHECKPOINT noted
  // on the client, INPUTS kept and answered (several FMUs only), anything
  // else refused with the session's end.
  ExitCode on_round_frame(Client& c, const pcs_header& h, uint64_t k, std::vector<double>& in, std::string& message);
  std::vector<double> frame_in_;  // the values of the frame on_round_frame reads
  // Waits for every client until the accept deadline. Up to kMaxPending
  // connections are in their handshake at once; a connection's frame is read
  // only once it has arrived whole, so a silent or slow stranger blocks
  // nothing. A stranger (port scan, silence past handshake_timeout, foreign
  // bytes, oversize length, wrong token or table) is refused, logged with its
  // address and reason, and the server keeps listening.
  // Under a connection flood the server never stops accepting: a new
  // connection that finds no room evicts the one whose handshake has stood
  // still the longest (Pending::progressed), from its own address if that
  // address holds more than kMaxPendingPerPeer, and tells it SL_ECROWDED so
  // a real host evicted anyway tries again. A host that answers at once
  // stays the freshest; connections that say nothing, or a valid HELLO (the
  // table hash is public) and then nothing, age and go first. (Preferring
  // to evict connections without a HELLO let a flood of valid HELLOs fill
  // the table, and then each newcomer, the real host too, was the first to
  // go, within a millisecond.)
  ExitCode accept_clients(std::string& message);
  // While a session runs, a new connection (the next session's host, come
  // early; a second importer) is answered at once with ABORT SL_EBUSY and
  // closed, instead of sitting in the listen backlog until its deadline runs
  // out in silence; the FMU retries until its deadline and says so. One
  // connection per kBusyCheckMs, its HELLO awaited at most kBusyDrainMs (so
  // the close does not reset the connection before the client reads the
  // ABORT): a flood of strangers costs the session at most a few per cent.
  void turn_away_while_busy();
  // A session of several FMUs whose round `step` one FMU (`late`) never
  // joined by the round's deadline, while another's STEP came: the reason a
  // sequential importer deadlocks there, and what to change; "" when no
  // other FMU's STEP came either (a plain time-out): one read this round
  // (Client::stepped), or one waiting unread in its socket.
  std::string split_master_hint(const Client& late, uint64_t step);
  // The share of the step time-out a round of several FMUs may take: the
  // FMUs wait their own time-out (the port table's, as the server's unless
  // --step-timeout or server.timeout set another), so they are still
  // listening when told. A host slower than this between two FMUs' steps is
  // taken for a lost link at 0.8 of the time-out instead of 1.
  static constexpr double kSplitRoundShare = 0.8;
  int64_t next_busy_check_ = 0;
  static constexpr int64_t kBusyCheckMs = 200;
  static constexpr int64_t kBusyDrainMs = 5;
  static constexpr size_t kMaxPending = 128;
  static constexpr size_t kMaxPendingPerPeer = 64;
  // Makes room for one more connection from `address` (see accept_clients):
  // tells the one evicted SL_ECROWDED, closes and removes it; true if it
  // evicted.
  static bool make_room(std::vector<Pending>& pending, const std::string& address);
  // Reads the whole frame waiting on p.conn (HELLO, or AUTH once
  // challenged) and answers it (handshake_step's second half). Returns "" while the handshake goes on or
  // is complete (p.which bound when `bound` is set), else the reason for
  // refusing, already told to the peer.
  std::string advance_handshake(Pending& p, bool& bound);
  std::string on_hello(Pending& p, const pcs_header& h);
  std::string on_auth(Pending& p, const pcs_header& h);
  // A stop by signal: `message` says which and where, the clients are told.
  ExitCode stop(uint64_t step, const std::string& where, std::string& message);
  // The first look at a stop signal in a session that can checkpoint: ask
  // every client for a checkpoint (STOPPING) and keep
  // serving until the host's CHECKPOINT, BYE or the grace's end. True if
  // the clients were asked.
  bool ask_for_checkpoint(uint64_t step);
  // Receive client c's next frame by `deadline`: the wait for its first byte
  // may end at a stop signal (nothing read yet: then the host is asked for a
  // checkpoint and the wait goes on, or SL_EINTERRUPTED when it cannot be),
  // the frame itself is read whole.
  int receive(Client& c, pcs_header& h, uint64_t step, int64_t deadline);
  bool stopping_ = false;          // a stop signal came; the host was asked to checkpoint
  int64_t stop_deadline_ = 0;      // ms: the grace's end
  long checkpointed_at_ = -1;      // the step of this session's last checkpoint
  // Tells every connected client why the session ends (best effort).
  void abort_all(uint64_t step, uint32_t code, const std::string& why);
  std::string name_of(const Client& c) const;
  // RESUME from every client, checked against resume_step_ and answered.
  ExitCode resume_clients(std::string& message);
  std::function<std::string(uint64_t)> checkpointer_;
  bool resume_ = false;
  uint64_t resume_step_ = 0;
  std::string previous_;
  long previous_step_ = -1;
  const ServerOptions opt_;
  const std::vector<config::PortTable> tables_;
  std::vector<Client> clients_;
  double timeout_ = 60.0;
  sl_socket listener_ = SL_SOCKET_INIT;
  bool keep_listening_ = false;
  int port_ = 0;
  std::vector<uint8_t> buf_;
  std::vector<uint8_t> peek_;  // what handshake_step looks at
};

// The other ranks' side of a session (CouplingServer::set_domain): each
// coupling step the host's inputs from rank 0, the same FE steps, until
// rank 0 says the session ended; returns its exit code.
ExitCode follow_session(const Domain& domain, Solver& solver, PortMap& ports, FollowerHistory& history, size_t inputs,
                        size_t outputs, int subcycles);

}  // namespace fe
