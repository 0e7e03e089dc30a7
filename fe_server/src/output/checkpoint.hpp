// fe_server's checkpoints: the solver, its user loads and the history's
// place, after a whole number of coupling steps (config/checkpoint.hpp for
// the file). A restart reads the same deck and port tables, restores this
// state and continues the results file where the checkpoint was taken.
//
// Identity records come first and are checked before any state is read:
// the deck's content (SHA-256 of the deck file: a changed material is
// another deck even with the same mesh), the port tables' hash, and the
// FE step. The coupling step the state belongs to is returned, for the
// host's RESUME to be checked against.
#pragma once

#include <cstdint>
#include <string>

#include "loads/user_load.hpp"
#include "output/history.hpp"
#include "solver/solver.hpp"

namespace fe {

struct CheckpointIdentity {
  std::string deck_digest;   // config::file_sha256 of the deck
  uint64_t table_hash = 0;   // the combined port table's hash; 0 standalone
  uint64_t coupling_step = 0;  // completed coupling steps (standalone: FE steps)
};

// Flushes the history and writes the file (atomically).
void save_checkpoint(const std::string& path, const CheckpointIdentity& id, Solver& solver, UserLoad* loads,
                     History& history);
// Reads only the identity records: throws config::CheckpointError naming
// what differs (before anything is opened to continue).
void check_checkpoint(const std::string& path, const CheckpointIdentity& expected);
// The coupling step of a checkpoint file, or -1 if it is none of this deck
// and port table (for naming FILE.prev in a refusal).
long checkpoint_step(const std::string& path, const CheckpointIdentity& expected);
// Restores into a solver, loads and history built from the same deck (the
// history opened to resume). Throws config::CheckpointError naming what
// differs. Returns the coupling step.
uint64_t load_checkpoint(const std::string& path, const CheckpointIdentity& expected, Solver& solver,
                         UserLoad* loads, History& history);

}  // namespace fe
