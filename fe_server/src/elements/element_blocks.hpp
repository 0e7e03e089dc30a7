// What the batched element loops share: elements processed in fixed blocks
// (a block is one task for the thread pool), each element writing its nodal
// forces into its own slot, and a gather that sums each node's slots in
// element order. The sums and the energy partials (reduced in block order)
// therefore do not depend on which thread ran which block: results are
// bit-identical for any thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "elements/element_work.hpp"
#include "model/model.hpp"
#include "parallel/thread_pool.hpp"

namespace fe {

// The central-difference stable step of a mode of angular frequency ω
// damped at ζ of critical, (2/ω)·(√(1 + ζ²) − ζ). An element's highest mode
// takes ζ = Q2 + β·ω/2: the linear bulk viscosity's Q2 (as LS-DYNA counts
// it, though it acts on volume changes only: on the safe side) and the
// stiffness damping β·K of its part (Part::stiffness_damping), which damps
// a mode of frequency ω at β·ω/2. 0 for ω ≤ 0.
inline double damped_stable_step(double omega, double q2, double beta) {
  if (!(omega > 0.0)) return 0.0;
  const double zeta = q2 + 0.5 * beta * omega;
  return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
}

// Energy partials of one block and its first inverted element.
struct BlockResult {
  double internal = 0.0, hourglass = 0.0, damping_power = 0.0;
  long inverted = -1;     // index into the loop's element list, -1 if none
  double measure = 0.0;   // its volume or area
  // Each element's current stable step (its initial one scaled by its
  // characteristic length now over then): the smallest, and its element
  // (index into the loop's list, -1 if none).
  double step_limit = 1e300;
  long step_worst = -1;
  std::vector<double> part_internal, part_hourglass;  // per part (sized once)
  void reset() {
    internal = hourglass = damping_power = measure = 0.0;
    step_limit = 1e300;
    inverted = step_worst = -1;
    std::fill(part_internal.begin(), part_internal.end(), 0.0);
    std::fill(part_hourglass.begin(), part_hourglass.end(), 0.0);
  }
};

// A batch's current stable steps (`lanes` of them, the first `used` real)
// into the block's smallest: a vector min, the lane looked for only when it
// is the block's smallest so far. first: the batch's first element's index.
inline void note_step_limits(const double* limit, int lanes, int used, size_t first, BlockResult& r) {
  double least = 1e300;
  for (int l = 0; l < lanes; ++l) least = limit[l] < least ? limit[l] : least;
  if (!(least < r.step_limit)) return;
  for (int l = 0; l < used; ++l)
    if (limit[l] == least) {
      r.step_limit = least, r.step_worst = static_cast<long>(first + static_cast<size_t>(l));
      return;
    }
}

// The smallest current stable step of the blocks into w when it is below
// what w holds (of another loop): `kind` names the loop (ElementWork),
// `to_model(k)` maps element k of the loop's list to the model's index.
template <class ToModel>
void note_loop_limit(const std::vector<BlockResult>& blocks, int kind, ToModel to_model, ElementWork& w) {
  double least = 1e300;
  long k = -1;
  for (const BlockResult& r : blocks)
    if (r.step_limit < least) least = r.step_limit, k = r.step_worst;
  if (k >= 0 && least < w.step_limit) w.step_limit = least, w.limit_kind = kind, w.limit_element = to_model(k);
}

// The dense index of each part (Model::parts order).
int part_slot(const Model& m, int part_id);

// Per node, whether some output reads its elements' corner forces (the
// nodes of the cross sections): NodalGather keeps them slotted.
std::vector<char> corner_force_nodes(const Model& m);

// Runs task(b) for b in [0, blocks), on the pool when there is one.
inline void run_blocks(size_t blocks, ThreadPool* pool, const std::function<void(size_t)>& task) {
  if (pool)
    pool->run(blocks, task);
  else
    for (size_t b = 0; b < blocks; ++b) task(b);
}

// Adds the blocks' energy partials to w in block order. Returns the first
// inverted element (index into the loop's list, its measure in *measure),
// or -1.
long sum_blocks(const std::vector<BlockResult>& blocks, ElementWork& w, double* measure);

// How each element's corner forces reach the nodes, bit-identical for any
// thread count. A node whose elements all lie in one block of the element
// loop (one task, run by one thread in element order) is *direct*: the
// block adds its corner forces to the node as it goes. Any other node
// (shared between blocks, or a kept node whose corner forces something
// reads later: a cross section) is *slotted*: element k's corner a writes
// `width` doubles (x, y[, z]) at slot (k·corners + a)·width, and add_to sums
// each such node's slots in element order after the loop. Direct nodes save
// the slots' memory traffic (most nodes of a mesh are inside a block).
class NodalGather {
 public:
  // node_of(k, a): node index of corner a of element k; block: elements per
  // task of the element loop (0: no direct nodes); keep(node): the node
  // must be slotted.
  void build(size_t nodes, size_t elements, int corners, int width, size_t block,
             const std::function<int(size_t, int)>& node_of, const std::function<bool(int)>& keep);
  // The corners of element k whose nodes are direct: bit a for corner a.
  unsigned direct_corners(size_t k) const { return direct_[k]; }
  // f[node] += Σ its slots, in element order, for the slotted nodes.
  void add_to(const std::vector<double>& force, std::vector<Vec3>& f, ThreadPool* pool) const;

 private:
  std::vector<int> node_, start_, slot_;
  std::vector<unsigned char> direct_;  // per element: its direct corners (at most 8)
  int width_ = 3;
};

}  // namespace fe
