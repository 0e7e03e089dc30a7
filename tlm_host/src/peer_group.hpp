// Components that wait on a peer process in their step (FmuQ: fmi2DoStep
// blocks until fe_server answers), stepped at the same time.
//
// When the host loads one FMU per co-simulated part and all of them talk to
// one fe_server session, the server advances only once it has every FMU's
// STEP: stepping them one after the other would deadlock. TLM makes running
// them together safe: Q components within a step depend only on the C
// components' wave variables of that step, never on each other's results,
// so their order does not change the answer. Each member but the last runs
// on its own long-lived worker thread; the last runs on the caller's.
// Members must not share nodes or write each other's inputs (FmuQs don't).
//
// The other two ways are the ways of importers that step FMUs one after the
// other in one thread (--peers): Sequential gives every member its inputs
// first, then steps each (fe_server then runs the step as soon as the first
// FMU steps: the results are the parallel ones, bit for bit); OneByOne gives
// each member its inputs and steps it before the next (Hopsan's sequential
// solver), which fe_server refuses with the reason.
#pragma once

#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "component.hpp"

namespace tlm {

class PeerGroup {
 public:
  enum class Stepping { Parallel, Sequential, OneByOne };
  explicit PeerGroup(std::vector<Component*> members, Stepping how = Stepping::Parallel);
  ~PeerGroup();
  PeerGroup(const PeerGroup&) = delete;
  PeerGroup& operator=(const PeerGroup&) = delete;
  // simulate_one_step(t) of every member, concurrently; returns when all are
  // done and rethrows the first member's exception, if any.
  void step(double t);
  const std::vector<Component*>& members() const { return members_; }

 private:
  void work(size_t index);
  std::vector<Component*> members_;
  Stepping how_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  unsigned long generation_ = 0;
  size_t pending_ = 0;
  double t_ = 0.0;
  bool quit_ = false;
  std::vector<std::exception_ptr> errors_;
};

}  // namespace tlm
