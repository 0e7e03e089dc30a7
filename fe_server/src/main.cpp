// fe_server: the explicit FE side of the co-simulation.
//
//   fe_server --model DECK.k --ports ports.cfg [--listen HOST:PORT] [--token-file F]
//             [--port-file F] [--out results.h5] [--accept-timeout S] [--step-timeout S]
//   fe_server --model DECK.k --out results.h5           (standalone, no host)
#include <arpa/inet.h>
#include <sched.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <memory>
#include <string>

#include "loads/cavity_load.hpp"
#include "loads/squeeze_film.hpp"
#include "config/cli.hpp"
#include "config/port_table.hpp"
#include "config/stop_signal.hpp"
#include "config/token.hpp"
#include "config/version.hpp"
#include "coupling/coupling_advice.hpp"
#include "coupling/coupling_server.hpp"
#include "input/deck_reader.hpp"
#include "coupling/exit_codes.hpp"
#include "input/units.hpp"
#include "output/checkpoint.hpp"
#include "output/history.hpp"
#include "solver/mass_scaling.hpp"
#include "socketlib/auth.h"
#include "socketlib/socketlib.h"
#include "solver/solver.hpp"

namespace {

int usage(std::ostream& os, int rc) {
  os << "usage: fe_server --model DECK.k [--ports ports.cfg] [options]\n"
        "       mpirun -n P fe_server ... (or srun): the same run on P ranks, the elements partitioned\n"
        "                        (METIS), rank 0 the host's only link; results as on one rank up to round-off\n"
        "  --model FILE          keyword deck of the structure\n"
        "  --ports FILE          port configuration; without it the deck runs standalone. Repeat it\n"
        "                        for one FMU per part (piston, valve): the session then waits for\n"
        "                        one client per file and steps them together\n"
        "  --listen HOST:PORT    where to wait for tlm_host (default 127.0.0.1:0 = any free port)\n"
        "  --token-file FILE     session token, first line of FILE (mode 600, yours); else $PCS_TOKEN,\n"
        "                        else the file named by $PCS_TOKEN_FILE: 16 to 255 printable characters,\n"
        "                        required with --ports. Never on the command line\n"
        "  --insecure-no-token   loopback only: serve without a token, so that any local user can\n"
        "                        connect (a cluster node has many); warns at start\n"
        "  --port-file FILE      write the bound port number to FILE\n"
        "  --out FILE            HDF5 time histories (default fe_results.h5)\n"
        "  --keywords            print the LS-DYNA keywords the deck reader reads (Markdown) and exit\n"
        "  --accept-timeout S    give up if no host connects within S seconds (default 300); until then\n"
        "                        strangers are refused and logged and the server keeps listening\n"
        "  --handshake-timeout S a connection must complete the handshake (HELLO, then AUTH) within\n"
        "                        S seconds (default 5)\n"
        "  --step-timeout S      per-step receive deadline (default: the port table's timeout)\n"
        "  --sessions N          serve N sessions one after another on the same port and token (0: until\n"
        "                        stopped), each from the deck's initial state into its own results file\n"
        "                        (--out fe_{session}.h5, or _<n> added before .h5)\n"
        "  --threads N           threads for the element and node loops (default: every core, and one\n"
        "                        less when listening on loopback, where tlm_host shares the machine);\n"
        "                        results are bit-identical for any N\n"
        "  --checkpoint FILE     where checkpoints go (default: the results file with .ckpt for .h5). Standalone:\n"
        "                        written at a stop signal and every --checkpoint-every minutes; in a\n"
        "                        session: when the host asks (tlm_host --checkpoint-every, or its stop)\n"
        "  --checkpoint-every M  standalone: a checkpoint every M minutes of wall time (0: only at a stop)\n"
        "  --restart FILE        continue from a checkpoint of this deck (and port tables): the results\n"
        "                        file is continued from the checkpoint's row; in a session the host must\n"
        "                        resume from its checkpoint of the same step\n"
        "  --stop-grace S        SIGTERM in a session asks the host for a checkpoint of both sides\n"
        "                        and waits up to S seconds for it (default 20; SLURM kills 30 s after\n"
        "                        its SIGTERM)\n"
        "  --quiet               no progress output\n"
        "  --accept-energy-error  end with 0 although the energy account is beyond its bound (1 % of the\n"
        "                        largest energy; otherwise exit 11); the results carry the attribute\n"
        "                        accept_energy_error\n"
        "  --approximate         run what the deck asks for as the nearest thing fe_server has (IHQ > 3\n"
        "                        as viscous hourglass control, solid ELFORM as 1 or 10, ...),\n"
        "                        each listed in the log and the results' attribute approximations;\n"
        "                        without it such a deck is refused (exit 3) saying what it would become\n"
        "  --check               read the deck (and --ports) as a run would, print what the model holds\n"
        "                        and its stable step, and exit: 0 if it would run, 3 with every error\n"
        "  --allow-coarse-coupling  run TLM ports whose omega*T exceeds 0.71 (a frequency error above\n"
        "                        10 % by fe_server's estimate), and pressure ports whose table sends the\n"
        "                        host's impedance beyond omega*T = 1 (unstable); otherwise refused at\n"
        "                        step 0, exit 3\n"
        "  -h, --help, --version  this text; the version\n"
        "Exit codes: 0 ok, 2 usage, 3 input rejected, 4 no host (every connection refused or none came),\n"
        "            6 link lost, 7 host aborted, 8 non-finite values, 9 internal error,\n"
        "            10 the host ended the session after a checkpoint (--restart continues),\n"
        "            11 finished with the energy account beyond its bound (results kept),\n"
        "            128 + N stopped by signal N (130 Ctrl-C, 143 SIGTERM) with results flushed.\n";
  return rc;
}

// Loopback only for "localhost" and literal addresses in 127.0.0.0/8 or ::1;
// any other name (even one that starts with "127.") may resolve elsewhere.
bool is_loopback(const std::string& host) {
  if (host == "localhost") return true;
  unsigned char a[16];
  if (inet_pton(AF_INET, host.c_str(), a) == 1) return a[0] == 127;
  static const unsigned char v6_loopback[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  return inet_pton(AF_INET6, host.c_str(), a) == 1 && std::memcmp(a, v6_loopback, 16) == 0;
}

// The results file of session n: {session} in `out` replaced by n; without
// it, "_n" before the extension when there is more than one session.
std::string session_path(const std::string& out, int n, int sessions) {
  const std::string key = "{session}";
  const size_t at = out.find(key);
  if (at != std::string::npos) return out.substr(0, at) + std::to_string(n) + out.substr(at + key.size());
  if (sessions == 1) return out;
  const size_t dot = out.rfind('.');
  const size_t slash = out.rfind('/');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return has_ext ? out.substr(0, dot) + "_" + std::to_string(n) + out.substr(dot) : out + "_" + std::to_string(n);
}

// Threads when --threads is not given: every core the process may use, one
// less when tlm_host runs on the same machine (a co-simulation on loopback),
// whose process needs a core of its own: on 2 cores the FE then runs on one
// (measured: bench/RESULTS.md, thread scaling).
int default_threads(bool machine_to_ourselves) {
  cpu_set_t set;
  int cores = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
  if (cores < 1) cores = 1;
  return machine_to_ourselves ? cores : std::max(1, cores - 1);
}

// The FE step for a requested step: as is if stable, else with selective
// mass scaling when the deck allows it (DT2MS < 0); the solver refuses an
// unstable step with the limiting element named.
void prepare_step(fe::Model& model, double dt, bool quiet) {
  const fe::StableStep crit = fe::Solver::stable_dt(model);
  if (dt <= model.dt_scale * crit.dt || !(model.dt2ms < 0.0)) return;
  fe::MassScalingReport r = fe::apply_mass_scaling(model, dt);
  if (!quiet)
    std::cout << "fe_server: mass scaling for dt = " << dt << " s (" << r.elements_scaled << " elements):\n"
              << r.summary();
}

// Exit code from the energy balance: a warning above its bound, a failure
// (exit 8) far above it, where the state cannot be trusted.
// The energy account's verdict at the end of a run: beyond its bound the
// run ends with its own code (11), the results kept, unless the user waived
// the check (--accept-energy-error), which the results then carry.
fe::ExitCode energy_verdict(const std::string& energy, bool drift, bool failed, const fe::Model& model) {
  if (!drift && !failed) return fe::kExitOk;
  const bool waived = model.run_attributes.count("accept_energy_error") != 0;
  const std::string how = failed ? "more than " + std::to_string(static_cast<int>(fe::History::kEnergyFailFactor)) +
                                       " times its bound"
                                 : "beyond its bound";
  if (waived) {
    std::cerr << "fe_server: warning: the " << energy << " is " << how
              << "; accepted by --accept-energy-error (the results say so in their attribute accept_energy_error)\n";
    return fe::kExitOk;
  }
  std::cerr << "fe_server: error: the " << energy << " is " << how
            << ": the run is not to be trusted (check contacts, hourglass energy, mass scaling and the step); the "
               "history is kept. --accept-energy-error accepts it\n";
  return fe::kExitEnergy;
}

// The deck's dynamic relaxation, if any, then the transient's start at
// t = 0 from the settled state; its report on stdout (a relaxation that did
// not converge is a warning on stderr: the transient starts anyway), its
// progress every 5 s. A stop signal ends it (128 + N, nothing written yet);
// a blow-up in it is exit 8.
fe::ExitCode relax(fe::Solver& solver, const fe::Model& model, bool quiet) {
  auto last = std::chrono::steady_clock::now();
  auto keep_going = [&](const fe::Solver::RelaxationReport& r) {
    // Across ranks: asked on every rank at the same step; they agree.
    if (solver.domain().any(config::stop_signal() != 0)) return false;
    if (!quiet && std::chrono::steady_clock::now() - last > std::chrono::seconds(5)) {
      last = std::chrono::steady_clock::now();
      std::cout << "fe_server: dynamic relaxation, " << r.steps << " steps (" << r.time << " s), kinetic energy "
                << r.kinetic / r.peak << " of its peak" << std::endl;
    }
    return true;
  };
  fe::Solver::RelaxationReport r;
  try {
    r = solver.relax(keep_going);
  } catch (const std::exception& e) {
    std::cerr << "fe_server: dynamic relaxation: " << e.what() << "\n";
    return fe::kExitNumerical;
  }
  if (!r.ran) return fe::kExitOk;
  if (r.stopped) {
    const int signo = config::stop_signal() ? config::stop_signal() : SIGTERM;  // across ranks another may have seen it
    std::cerr << "fe_server: stopped by " << config::signal_name(signo) << " during the dynamic relaxation, after "
              << r.steps << " steps (" << r.time << " s); nothing written\n";
    return fe::stopped_by(signo);
  }
  solver.begin_transient();
  std::ostringstream s;
  s << r.steps << " steps (" << r.time << " s): kinetic energy " << r.kinetic << " J, " << r.kinetic / r.peak
    << " of its peak " << r.peak << " J (DRTOL " << model.relaxation.drtol << "); residual: the largest out-of-balance "
    << "force on one part " << r.resultant << " N (" << (r.worst.empty() ? "none" : r.worst) << ")";
  if (r.load > 0.0) s << ", " << 100.0 * r.resultant / r.load << " % of the largest support force " << r.load << " N";
  if (!r.converged)
    std::cerr << "fe_server: warning: dynamic relaxation did not converge within "
              << (r.time >= model.relaxation.drterm ? "DRTERM" : "its step limit") << " after " << s.str()
              << "; the transient starts from there\n";
  else if (!quiet)
    std::cout << "fe_server: dynamic relaxation converged after " << s.str() << std::endl;
  return fe::kExitOk;
}

// Checkpointing as the command line asked for it.
struct CheckpointOptions {
  std::string path;        // where checkpoints go ("" : checkpointing off)
  double every_s = 0.0;    // standalone: wall seconds between checkpoints (0: only at a stop)
  std::string restart;     // continue from this checkpoint
  std::string deck_digest;
  bool enabled() const { return !path.empty(); }
};

// The default checkpoint name: the results file's, .h5 → .ckpt.
std::string default_checkpoint_path(const std::string& out) {
  const bool h5 = out.size() > 3 && out.compare(out.size() - 3, 3, ".h5") == 0;
  return (h5 ? out.substr(0, out.size() - 3) : out) + ".ckpt";
}

// What the partition gave: said once by rank 0.
std::string ranks_text(const fe::Solver& solver) {
  const fe::Partition& p = solver.partition();
  std::ostringstream s;
  s << "fe_server: " << p.ranks << " ranks (" << p.method << "), elements per rank";
  for (long n : p.elements_per_rank) s << " " << n;
  s << "; rank 0 shares " << solver.shared_nodes() << " nodes with other ranks";
  return s.str();
}

// *PCS_FATIGUE_PART: the hot spots to the log, every counted element to
// <results>_fatigue.csv beside the results.
void report_fatigue(const fe::History& history, double time, const std::string& out, bool quiet) {
  const std::string report = history.fatigue_report(time);
  if (report.empty()) return;
  const std::string base = out.size() > 3 && out.compare(out.size() - 3, 3, ".h5") == 0 ? out.substr(0, out.size() - 3) : out;
  history.write_fatigue_table(base + "_fatigue.csv", time);
  if (!quiet) std::cout << "fe_server: " << report << "fe_server: every counted element in " << base << "_fatigue.csv\n";
}

// --check: what the deck holds and the step it allows, without a run.
int check_summary(const fe::Model& m, const std::string& deck, const std::vector<config::PortTable>& tables) {
  size_t tets = 0;
  for (const auto& e : m.solids) tets += e.tet4;
  const fe::StableStep step = fe::Solver::stable_dt(m);
  std::cout << "fe_server --check " << deck << ": it would run\n"
            << "  " << m.node_ids.size() << " nodes; " << m.solids.size() - tets << " hexahedra, " << tets
            << " tetrahedra, " << m.axis.size() << " axisymmetric quads, " << m.bars.size() << " bars, "
            << m.discretes.size() << " springs and dampers; " << m.parts.size() << " parts, " << m.materials.size()
            << " materials, " << m.rigid_bodies.size() << " rigid bodies\n"
            << "  " << m.contacts.size() << " contacts, " << m.ties.size() << " tied interfaces, "
            << m.loading_sets.size() << " cavity surfaces (*USER_LOADING_SET), " << tables.size() << " port tables\n"
            << "  total mass " << m.total_mass() << " kg; stable step " << step.dt * m.dt_scale << " s (TSSFAC "
            << m.dt_scale << " of " << step.dt << " s, " << step.limited_by << ")";
  if (tables.empty() && m.end_time > 0.0)
    std::cout << "; to its end time " << m.end_time << " s: about " << std::ceil(m.end_time / (step.dt * m.dt_scale))
              << " steps";
  std::cout << "\n";
  return fe::kExitOk;
}

int run_standalone(fe::Model& model, const std::string& out, bool quiet, int threads, const CheckpointOptions& ck) {
  if (!(model.end_time > 0.0)) {
    std::cerr << "fe_server: " << model.source
              << ": a standalone run needs *CONTROL_TERMINATION with ENDTIM > 0\n";
    return fe::kExitInput;
  }
  const fe::Domain& dom = fe::Domain::world();
  const fe::StableStep crit = fe::Solver::stable_dt(model);
  double dt = model.dt2ms < 0.0 ? -model.dt2ms : model.dt_scale * crit.dt;
  if (!std::isfinite(dt) || dt > 1e299) {
    std::cerr << "fe_server: the model has no element that limits the time step\n";
    return fe::kExitInput;
  }
  prepare_step(model, dt, quiet);
  fe::Solver solver(model, dt, dom);
  solver.set_threads(threads);
  for (const auto& note : solver.notes()) std::cerr << "fe_server: note: " << note << "\n";
  if (dom.parallel() && !quiet) std::cout << ranks_text(solver) << std::endl;
  std::unique_ptr<fe::SqueezeFilmLoad> films;
  try {
    films = std::make_unique<fe::SqueezeFilmLoad>(model);
  } catch (const std::exception& e) {
    std::cerr << "fe_server: " << e.what() << "\n";
    return fe::kExitInput;
  }
  const bool resume = !ck.restart.empty();
  // A restart's state is the settled one: no relaxation again.
  if (!resume)
    if (const fe::ExitCode code = relax(solver, model, quiet); code != fe::kExitOk) return code;
  if (!films->empty()) solver.set_user_load(films.get());  // with the transient, as the host's loads
  fe::UserLoad* loads = films->empty() ? nullptr : films.get();
  // Without *DATABASE_ DT cards: 10000 rows over the run.
  std::unique_ptr<fe::History> history_owner;
  fe::FollowerHistory follower(model, dt);  // ranks other than 0: no files
  fe::CheckpointIdentity id{ck.deck_digest, 0, 0};
  long first = 0;
  const bool writes = dom.rank() == 0;
  try {
    if (resume) fe::check_checkpoint(ck.restart, id);
    if (writes) history_owner = std::make_unique<fe::History>(out, model, nullptr, dt, model.end_time / 1e4, resume);
    if (resume) {
      first = static_cast<long>(fe::load_checkpoint(ck.restart, id, solver, loads, *history_owner));
      if (!quiet)
        std::cout << "fe_server: restarted from " << ck.restart << " at step " << first << " (t = " << solver.time()
                  << " s); " << out << " continues after its row " << history_owner->rows() << std::endl;
    }
  } catch (const std::exception& e) {
    std::cerr << "fe_server: " << e.what() << "\n";
    return fe::kExitInput;
  }
  // The run ends on the start step's last multiple at or after ENDTIM, in
  // however many steps the model's stable step lets it (solver.hpp).
  const long steps = static_cast<long>(std::ceil(model.end_time / dt));
  const double t_stop = static_cast<double>(steps) * dt;
  solver.set_horizon(t_stop);
  const bool nothing_left = solver.time() > t_stop - 0.5 * dt;  // a restart from the end
  if (!writes) {  // a follower: the same steps; its errors are rank 0's too (solver.hpp)
    try {
      for (long k = first; !nothing_left && (k == first || !solver.reached_horizon()); ++k) {
        if ((k & 63) == 0 && dom.any(config::stop_signal() != 0)) return fe::stopped_by(SIGTERM);
        solver.step();
        follower.record(solver);
      }
    } catch (const std::exception&) {
      return fe::kExitNumerical;
    }
    return fe::kExitOk;
  }
  fe::History& history = *history_owner;
  const auto t0 = std::chrono::steady_clock::now();
  auto last = t0, last_checkpoint = t0;
  bool in_step = false;
  long taken = first;
  auto checkpoint = [&](long k) {
    id.coupling_step = static_cast<uint64_t>(k);
    fe::save_checkpoint(ck.path, id, solver, loads, history);
    if (!quiet) std::cout << "fe_server: checkpoint at step " << k << " (t = " << solver.time() << " s) in " << ck.path << std::endl;
  };
  try {
    for (long k = first; !nothing_left && (k == first || !solver.reached_horizon()); ++k) {
      taken = k + 1;
      // Across ranks they agree every 64 steps on whether any saw a stop signal.
      const bool stop = dom.parallel() ? (k & 63) == 0 && dom.any(config::stop_signal() != 0) : config::stop_signal() != 0;
      if (stop) {
        const int signo = config::stop_signal() ? config::stop_signal() : SIGTERM;
        history.flush();
        std::string saved;
        if (ck.enabled()) {
          checkpoint(k);
          saved = "; checkpoint in " + ck.path + " (--restart " + ck.path + " continues)";
        }
        std::cerr << "fe_server: stopped by " << config::signal_name(signo) << " at step " << k << " (t = "
                  << solver.time() << " s); history up to that step (" << history.rows() << " rows) kept in " << out
                  << saved << "\n";
        return fe::stopped_by(signo);
      }
      if (ck.enabled() && ck.every_s > 0.0 && (k & 255) == 0 &&
          std::chrono::steady_clock::now() - last_checkpoint > std::chrono::duration<double>(ck.every_s)) {
        checkpoint(k);
        last_checkpoint = std::chrono::steady_clock::now();
      }
      in_step = true;  // a failure here is every rank's (solver.hpp)
      solver.step();
      in_step = false;
      history.record(solver, {}, {});
      if (!quiet && (k & 1023) == 0 && std::chrono::steady_clock::now() - last > std::chrono::seconds(5)) {
        last = std::chrono::steady_clock::now();
        std::cout << "fe_server: t = " << solver.time() << " of " << model.end_time << " s ("
                  << static_cast<int>(100.0 * solver.time() / t_stop) << " %)" << std::endl;
      }
    }
  } catch (const std::exception& e) {
    history.flush();
    std::cerr << "fe_server: " << e.what() << "; history up to the last completed step kept in " << out << "\n";
    // Rank 0's own failure (writing the history): the others would wait for it.
    if (dom.parallel() && !in_step) dom.abort(fe::kExitNumerical);
    return fe::kExitNumerical;
  }
  history.flush();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  bool drift = false, failed = false;
  const std::string energy = history.energy_summary(solver, &drift, &failed);
  std::ostringstream shrunk;
  if (solver.shrunk_steps() > 0)
    shrunk << "; the stable step shrank as " << solver.limiting_element() << " deformed: the last step " << solver.dt()
           << " s";
  if (!quiet)
    std::cout << "fe_server: standalone run, " << taken - first << " steps of at most " << dt << " s (limited at the start by " << crit.limited_by
              << ")"
              << shrunk.str() << ", " << wall << " s wall; " << energy << "; " << history.rows() << " history rows in " << out
              << (history.snapshots() ? "; " + std::to_string(history.snapshots()) + " field snapshots in " +
                                            history.fields_path() + " (open it in ParaView)"
                                      : std::string())
              << "\n";
  const std::string hourglass = fe::hourglass_warning(solver.energies());
  if (!hourglass.empty()) std::cerr << "fe_server: warning: " << hourglass << "\n";
  report_fatigue(history, solver.time(), out, quiet);
  return energy_verdict(energy, drift, failed, model);
}

// What fe_server refuses before a run across ranks starts.
void check_for_ranks(const CheckpointOptions& ck, const fe::Model& model) {
  if (!model.fatigue.empty())
    throw config::InputError(model.fatigue.front().where,
                             "*PCS_FATIGUE_PART: fatigue is counted on one rank only (each element's stress after every "
                             "FE step would cross the ranks): run without mpirun, or without the card");
  if (ck.enabled())
    throw std::invalid_argument("--checkpoint, --checkpoint-every and --restart work on one rank only for now: "
                                "run without mpirun to checkpoint");
}

int run_main(int argc, char** argv);

}  // namespace

int main(int argc, char** argv) {
  if (!fe::Domain::built_with_mpi() && fe::Domain::launched_ranks() > 1) {
    std::cerr << "fe_server: started on " << fe::Domain::launched_ranks()
              << " ranks, but this fe_server was built without MPI (libopenmpi-dev and libmetis-dev: "
                 "scripts/install_deps.sh, then rebuild); each rank would run the whole model alone\n";
    return fe::kExitUsage;
  }
  fe::Domain::init(&argc, &argv);
  const int rc = run_main(argc, argv);
  fe::Domain::finalize();
  return rc;
}

namespace {

int run_main(int argc, char** argv) {
  const fe::Domain& dom = fe::Domain::world();
  // Ranks other than 0 say nothing: their errors are rank 0's (solver.hpp).
  static std::ofstream null_stream;  // outlives main: cout and cerr are flushed at exit
  if (dom.rank() != 0) {
    std::cout.rdbuf(null_stream.rdbuf());
    std::cerr.rdbuf(null_stream.rdbuf());
  }
  std::signal(SIGPIPE, SIG_IGN);
  config::install_stop_handlers();
  std::string deck, listen = "127.0.0.1:0", out = "fe_results.h5";
  std::vector<std::string> ports_paths;
  fe::ServerOptions opt;
  std::string token_file;
  bool no_token = false;
  bool accept_energy_error = false, allow_coarse_coupling = false, approximate = false, check_only = false;
  int threads = 0;  // 0: the default below
  int sessions = 1;
  CheckpointOptions ck;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("--model")) deck = args.value();
      else if (args.is("--ports")) ports_paths.push_back(args.value());
      else if (args.is("--listen")) listen = args.value();
      else if (args.is("--token")) throw std::invalid_argument(config::token_on_command_line_refused("fe_server"));
      else if (args.is("--token-file")) token_file = args.value();
      else if (args.is("--insecure-no-token")) no_token = true;
      else if (args.is("--port-file")) opt.port_file = args.value();
      else if (args.is("--out")) out = args.value();
      // Deadlines are kept in milliseconds: up to 10⁶ s (11 days) keeps them exact.
      else if (args.is("--accept-timeout")) opt.accept_timeout = args.real(1e-3, 1e6);
      else if (args.is("--step-timeout")) opt.step_timeout = args.real(1e-3, 1e6);
      else if (args.is("--handshake-timeout")) opt.handshake_timeout = args.real(1e-3, 3600);
      else if (args.is("--quiet")) opt.quiet = true;
      else if (args.is("--accept-energy-error")) accept_energy_error = true;
      else if (args.is("--allow-coarse-coupling")) allow_coarse_coupling = true;
      else if (args.is("--approximate")) approximate = true;
      else if (args.is("--check")) check_only = true;
      else if (args.is("--checkpoint")) ck.path = args.value();
      else if (args.is("--checkpoint-every")) ck.every_s = 60.0 * args.real(1e-3, 1e6);
      else if (args.is("--restart")) ck.restart = args.value();
      else if (args.is("--stop-grace")) opt.stop_grace = args.real(0.0, 3600);
      else if (args.is("--sessions")) {
        sessions = args.integer();
        if (sessions < 0) throw std::invalid_argument("--sessions must be 0 (until stopped) or more, got " + std::to_string(sessions));
      }
      else if (args.is("--threads")) {
        threads = args.integer();
        if (threads < 1 || threads > 1024) throw std::invalid_argument("--threads must be 1..1024, got " + std::to_string(threads));
      }
      else if (args.is("-h") || args.is("--help")) return usage(std::cout, fe::kExitOk);
      else if (args.is("--version")) return std::cout << config::version_line("fe_server") << "\n", fe::kExitOk;
      else if (args.is("--keywords")) {
        std::cout << fe::deck_keyword_coverage();
        return fe::kExitOk;
      }
      else args.unknown();
    }
    if (deck.empty()) throw std::invalid_argument("--model is required");
    if (ck.path.empty() && (ck.every_s > 0.0 || !ck.restart.empty())) ck.path = default_checkpoint_path(out);
    if (!ck.restart.empty() && sessions != 1)
      throw std::invalid_argument("--restart continues one session: it cannot be combined with --sessions " +
                                  std::to_string(sessions));
    char host[256];
    if (sl_parse_endpoint(listen.c_str(), host, sizeof host, &opt.listen_port) != SL_OK)
      throw std::invalid_argument("--listen '" + listen + "' is not HOST:PORT");
    opt.listen_host = host;
    // Across ranks, one thread each: the ranks take the cores.
    if (threads == 0) threads = dom.parallel() ? 1 : default_threads(ports_paths.empty() || !is_loopback(opt.listen_host));
    opt.token = token_file.empty() ? config::token_from_environment() : config::read_token_file(token_file);
    if (no_token) {
      if (!opt.token.empty() || !token_file.empty())
        throw std::invalid_argument("--insecure-no-token and a token (--token-file, $PCS_TOKEN or $PCS_TOKEN_FILE) "
                                    "contradict each other: give one");
      if (!is_loopback(opt.listen_host))
        throw std::invalid_argument("--insecure-no-token is for loopback only, and --listen " + listen +
                                    " is not: give a token with --token-file");
    } else if (!ports_paths.empty() && opt.token.empty() && !check_only) {  // --check serves no session
      throw std::invalid_argument("a session needs a token of at least " + std::to_string(config::kMinTokenLength) +
                                  " characters, on loopback too (every local user can reach a loopback port): "
                                  "head -c 24 /dev/urandom | base64 > token && chmod 600 token, then --token-file "
                                  "token (or $PCS_TOKEN); --insecure-no-token serves without one on loopback");
    }
  } catch (const std::exception& e) {
    // The error alone, so that it does not scroll away behind the usage.
    std::cerr << "fe_server: " << e.what() << "\n(fe_server --help lists the options)\n";
    return fe::kExitUsage;
  }

  fe::Model model;
  std::vector<config::PortTable> tables;
  config::PortTable table;  // all clients' ports together
  try {
    fe::DeckWarnings warnings;
    warnings.approximate = approximate;
    model = fe::read_deck(deck, &warnings);
    for (const auto& w : warnings.messages) std::cerr << w << "\n";
    if (!warnings.substitutions.empty()) {
      std::string list;
      for (const auto& sub : warnings.substitutions) list += (list.empty() ? "" : "; ") + sub;
      model.run_attributes["approximations"] = list;
    }
    if (accept_energy_error) model.run_attributes["accept_energy_error"] = "yes: the energy check was waived";
    if (allow_coarse_coupling)
      model.run_attributes["allow_coarse_coupling"] = "yes: TLM ports may exceed omega*T = " +
                                                      std::to_string(fe::max_tlm_omega_t()) +
                                                      ", pressure ports omega*T = " +
                                                      std::to_string(fe::kMaxPressureOmegaT);
    if (dom.parallel()) check_for_ranks(ck, model);
    // In a session the host decides when to checkpoint: always ready (on one rank).
    if (!ports_paths.empty() && ck.path.empty() && !dom.parallel()) ck.path = default_checkpoint_path(out);
    if (ck.enabled()) ck.deck_digest = config::file_sha256(deck);
    if (ports_paths.empty()) {
      fe::check_units(model, {});
      if (check_only) return check_summary(model, deck, tables);
      return run_standalone(model, out, opt.quiet, threads, ck);
    }
    for (const auto& p : ports_paths) tables.push_back(config::read_port_table(p));
    fe::check_units(model, tables);
    table = config::combine_port_tables(tables);
    if (check_only) {  // what a session checks before its first step
      fe::CavityPressureLoad load(model, table);  // every hydraulic port has its surfaces
      fe::MechanicalLoad mech(model, table);
      fe::PortMap ports(table, load, mech);
      std::cout << fe::coupling_stability_text(fe::coupling_stability(model, table, 1.4e9), table, 1.4e9);
      prepare_step(model, table.dt / table.subcycles, false);
      const fe::Solver probe(model, table.dt / table.subcycles, dom);  // refuses an unstable step
      return check_summary(model, deck, tables);
    }
  } catch (const std::exception& e) {
    std::cerr << "fe_server: " << e.what() << "\n";
    return fe::kExitInput;
  }

  std::unique_ptr<fe::History> history;
  try {
    const fe::Model pristine = model;  // each session starts from the deck's state (mass scaling included)
    fe::CouplingServer server(opt, tables);
    if (dom.rank() == 0) server.bind();  // rank 0 owns the link; it tells the others what to do
    if (dom.rank() == 0 && no_token)
      std::cerr << "fe_server: WARNING: --insecure-no-token: any local user can connect to port " << server.port()
                << " and drive this session" << std::endl;
    server.set_domain(&dom);
    fe::ExitCode worst = fe::kExitOk;
    for (int session = 1; sessions == 0 || session <= sessions; ++session) {
      const bool last = sessions != 0 && session == sessions;
      model = pristine;
      fe::CavityPressureLoad load(model, table);
      fe::MechanicalLoad mech(model, table);
      fe::SqueezeFilmLoad films(model);
      fe::UserLoads loads;
      loads.add(&load);
      loads.add(&mech);
      if (!films.empty()) loads.add(&films);
      fe::PortMap ports(table, load, mech);
      const bool quiet = opt.quiet || session > 1;  // the model's report once
      // Printed before mass scaling: the estimate is about the physical piston.
      const auto stability = fe::coupling_stability(model, table, 1.4e9);
      if (!quiet) std::cout << fe::coupling_stability_text(stability, table, 1.4e9);
      ports.set_coupling_guard(stability, table.dt, allow_coarse_coupling);
      prepare_step(model, table.dt / table.subcycles, quiet);
      fe::Solver solver(model, table.dt / table.subcycles, dom);
      solver.set_threads(threads);
      if (!quiet)
        for (const auto& note : solver.notes()) std::cerr << "fe_server: note: " << note << "\n";
      if (dom.parallel() && !quiet) std::cout << ranks_text(solver) << std::endl;
      // Before the host's loads: they start with the transient. A host that
      // connected meanwhile waits (its handshake deadline is the port
      // table's timeout).
      const bool resume = !ck.restart.empty();
      if (!resume)  // a checkpoint holds the settled state
        if (const fe::ExitCode code = relax(solver, model, quiet); code != fe::kExitOk) return code;
      solver.set_user_load(&loads);
      if (dom.rank() != 0) {  // the same steps as rank 0, on its word
        fe::FollowerHistory follower(model, table.dt / table.subcycles);
        fe::ExitCode code = fe::kExitNumerical;
        try {
          code = fe::follow_session(dom, solver, ports, follower, table.to_fe.size(), table.to_host.size(), table.subcycles);
        } catch (const std::exception&) {  // a failed FE step: rank 0 fails alike, says why and serves the next session
          code = fe::kExitNumerical;
        }
        if (code >= fe::kExitStopped || code == fe::kExitAcceptTimeout || code == fe::kExitCheckpointed) return code;
        if (code != fe::kExitOk) worst = code;
        continue;
      }
      const std::string path = session_path(out, session, sessions);
      const fe::CheckpointIdentity id{ck.deck_digest, table.hash(), 0};
      if (resume) {
        // Only the checkpoint is read here: the results files are continued
        // (cut back to the checkpoint's rows) once the host's RESUME matched
        // it (open_history), so a refused restart leaves them as they were.
        try {
          fe::check_checkpoint(ck.restart, id);
          const std::string previous = ck.restart + ".prev";
          server.set_resume(static_cast<uint64_t>(fe::checkpoint_step(ck.restart, id)), previous,
                            fe::checkpoint_step(previous, id));
        } catch (const std::exception& e) {
          std::cerr << "fe_server: " << e.what() << "\n";
          return fe::kExitInput;
        }
      }
      // Without *DATABASE_ DT cards: a row per coupling step.
      auto open_history = [&]() -> fe::History& {
        if (history) return *history;
        history = std::make_unique<fe::History>(path, model, &table, table.dt / table.subcycles, table.dt, resume);
        if (resume) {
          const uint64_t step = fe::load_checkpoint(ck.restart, id, solver, &loads, *history);
          if (!opt.quiet)
            std::cout << "fe_server: restarted from " << ck.restart << " after coupling step " << step << " (t = "
                      << solver.time() << " s); " << path << " continues after its row " << history->rows()
                      << std::endl;
        }
        return *history;
      };
      // A new results file exists (and opens, 0 rows) before the host comes.
      if (!resume) open_history();
      if (ck.enabled()) {
        const std::string ck_path = session_path(ck.path, session, sessions);
        server.set_checkpointer([&, id, ck_path](uint64_t k) {
          fe::CheckpointIdentity at = id;
          at.coupling_step = k;
          fe::save_checkpoint(ck_path, at, solver, &loads, *history);
          if (!opt.quiet)
            std::cout << "fe_server: checkpoint after coupling step " << k << " (t = " << solver.time() << " s) in "
                      << ck_path << std::endl;
          return ck_path;
        });
      }
      if (!opt.quiet)
        std::cout << "fe_server: " << (sessions == 1 ? std::string() : "session " + std::to_string(session) + ": ")
                  << "listening on " << opt.listen_host << ":" << server.port() << " (model " << table.model_name
                  << (tables.size() > 1 ? ", " + std::to_string(tables.size()) + " FMUs" : "") << ", "
                  << model.node_ids.size() << " nodes, dt " << table.dt / table.subcycles << " s × " << table.subcycles
                  << " per coupling step, " << solver.threads() << (solver.threads() == 1 ? " thread" : " threads")
                  << ")" << std::endl;
      server.set_keep_listening(!last);
      std::string message;
      fe::ExitCode code = server.run(solver, ports, open_history, message);
      server.end_session();
      const std::string tag = sessions == 1 ? "fe_server: " : "fe_server: session " + std::to_string(session) + ": ";
      if (!history) {  // a restart the host did not agree to, or no host: nothing was opened
        std::cerr << tag << message << "; " << path << " left as it was" << std::endl;
        return code;
      }
      history->flush();
      if (code == fe::kExitOk) {
        bool drift = false, failed = false;
        const std::string energy = history->energy_summary(solver, &drift, &failed);
        if (!opt.quiet) std::cout << tag << message << "; " << energy << "; history (" << history->rows() << " rows) in " << path << std::endl;
        const std::string hourglass = fe::hourglass_warning(solver.energies());
        if (!hourglass.empty()) std::cerr << tag << "warning: " << hourglass << "\n";
        report_fatigue(*history, solver.time(), path, opt.quiet);
        code = energy_verdict(energy, drift, failed, model);
      } else {
        std::cerr << tag << message << "; history up to the last completed step (" << history->rows()
                  << " rows) kept in " << path << std::endl;
      }
      history.reset();
      // A signal, or no host within --accept-timeout, ends the server; any
      // other failed session is reported and the next one is served.
      if (code >= fe::kExitStopped || code == fe::kExitAcceptTimeout || code == fe::kExitCheckpointed) return code;
      if (code != fe::kExitOk) worst = code;
    }
    return worst;
  } catch (const config::InputError& e) {
    std::cerr << "fe_server: " << e.what() << "\n";
    return fe::kExitInput;
  } catch (const std::exception& e) {
    if (history) history->flush();
    std::cerr << "fe_server: " << e.what() << "\n";
    // Across ranks the others may be waiting for this one: end them all.
    if (dom.parallel()) dom.abort(fe::kExitInput);
    return fe::kExitInput;
  }
}

}  // namespace
