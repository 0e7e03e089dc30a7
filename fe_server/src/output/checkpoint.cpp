#include "output/checkpoint.hpp"

#include <stdexcept>

namespace fe {

namespace {
// The same sequence saves and restores (StateIO); the identity first.
uint64_t identity(config::StateIO& io, const CheckpointIdentity& id) {
  io.expect("kind", std::string("fe_server"), "the checkpoint's program");
  io.expect("deck digest", id.deck_digest, "the deck's contents (SHA-256)");
  io.expect("port table hash", id.table_hash, "the port tables' hash");
  uint64_t step = id.coupling_step;
  io.value("coupling step", step);
  return step;
}

uint64_t exchange(config::StateIO& io, const CheckpointIdentity& id, Solver& solver, UserLoad* loads,
                  History& history) {
  const uint64_t step = identity(io, id);
  solver.state(io);
  uint64_t has_loads = loads != nullptr;
  io.value("user loads", has_loads);
  if (has_loads != (loads != nullptr))
    throw config::CheckpointError(std::string("the checkpoint was taken ") + (has_loads ? "with" : "without") +
                                  " user loads, this run has " + (loads ? "some" : "none"));
  if (loads) loads->state(io);
  history.state(io);
  return step;
}
}  // namespace

void save_checkpoint(const std::string& path, const CheckpointIdentity& id, Solver& solver, UserLoad* loads,
                     History& history) {
  history.flush();
  config::StateWriter w;
  exchange(w, id, solver, loads, history);
  w.write(path);
}

void check_checkpoint(const std::string& path, const CheckpointIdentity& expected) {
  config::StateReader r(path);
  try {
    identity(r, expected);
  } catch (const config::CheckpointError& e) {
    throw config::CheckpointError("checkpoint '" + path + "': " + e.what());
  }
}

long checkpoint_step(const std::string& path, const CheckpointIdentity& expected) {
  try {
    config::StateReader r(path);
    return static_cast<long>(identity(r, expected));
  } catch (const std::exception&) {
    return -1;
  }
}

uint64_t load_checkpoint(const std::string& path, const CheckpointIdentity& expected, Solver& solver,
                         UserLoad* loads, History& history) {
  config::StateReader r(path);
  try {
    const uint64_t step = exchange(r, expected, solver, loads, history);
    r.finish();
    return step;
  } catch (const config::CheckpointError& e) {
    throw config::CheckpointError("checkpoint '" + path + "': " + e.what());
  }
}

}  // namespace fe
