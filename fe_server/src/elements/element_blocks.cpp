#include "elements/element_blocks.hpp"

#include <algorithm>

namespace fe {

long sum_blocks(const std::vector<BlockResult>& blocks, ElementWork& w, double* measure) {
  for (const BlockResult& r : blocks) {
    if (r.inverted >= 0) {
      *measure = r.measure;
      return r.inverted;
    }
    w.internal += r.internal;
    w.hourglass += r.hourglass;
    w.damping_power += r.damping_power;
    if (w.part_internal)
      for (size_t p = 0; p < r.part_internal.size(); ++p) {
        (*w.part_internal)[p] += r.part_internal[p];
        (*w.part_hourglass)[p] += r.part_hourglass[p];
      }
  }
  return -1;
}

int part_slot(const Model& m, int part_id) {
  return static_cast<int>(std::distance(m.parts.begin(), m.parts.find(part_id)));
}

std::vector<char> corner_force_nodes(const Model& m) {
  std::vector<char> kept(m.x0.size(), 0);
  for (const CrossSection& cs : m.cross_sections)
    for (int i : cs.nodes) kept[static_cast<size_t>(i)] = 1;
  return kept;
}

void NodalGather::build(size_t nodes, size_t elements, int corners, int width, size_t block,
                        const std::function<int(size_t, int)>& node_of, const std::function<bool(int)>& keep) {
  width_ = width;
  std::vector<std::vector<int>> slots(nodes);
  constexpr size_t kNone = static_cast<size_t>(-1), kMany = static_cast<size_t>(-2);
  std::vector<size_t> block_of(nodes, kNone);  // the one block a node's elements lie in, or kMany
  for (size_t k = 0; k < elements; ++k)
    for (int a = 0; a < corners; ++a) {
      const size_t i = static_cast<size_t>(node_of(k, a));
      slots[i].push_back(static_cast<int>((k * static_cast<size_t>(corners) + static_cast<size_t>(a)) * static_cast<size_t>(width)));
      const size_t b = block > 0 ? k / block : kMany;
      block_of[i] = block_of[i] == kNone || block_of[i] == b ? b : kMany;
    }
  direct_.assign(elements, 0);
  for (size_t k = 0; k < elements; ++k)
    for (int a = 0; a < corners; ++a) {
      const int i = node_of(k, a);
      if (block_of[static_cast<size_t>(i)] != kMany && !keep(i)) direct_[k] |= static_cast<unsigned char>(1u << a);
    }
  node_.clear();
  slot_.clear();
  start_.assign(1, 0);
  for (size_t i = 0; i < nodes; ++i) {
    if (slots[i].empty() || (block_of[i] != kMany && !keep(static_cast<int>(i)))) continue;
    node_.push_back(static_cast<int>(i));
    slot_.insert(slot_.end(), slots[i].begin(), slots[i].end());
    start_.push_back(static_cast<int>(slot_.size()));
  }
}

namespace {
// One task's nodes, for a fixed width (the compiler unrolls the components).
template <int Width>
void add_slots(const std::vector<int>& node, const std::vector<int>& start, const std::vector<int>& slot,
               const double* force, std::vector<Vec3>& f, size_t first, size_t last) {
  for (size_t i = first; i < last; ++i) {
    double sum[Width] = {};
    for (int j = start[i]; j < start[i + 1]; ++j) {
      const double* p = force + slot[static_cast<size_t>(j)];
      for (int c = 0; c < Width; ++c) sum[c] += p[c];
    }
    Vec3& fi = f[static_cast<size_t>(node[i])];
    for (int c = 0; c < Width; ++c) fi[c] += sum[c];
  }
}
}  // namespace

void NodalGather::add_to(const std::vector<double>& force, std::vector<Vec3>& f, ThreadPool* pool) const {
  constexpr size_t kNodes = 1024;  // per task
  const size_t n = node_.size();
  run_blocks((n + kNodes - 1) / kNodes, pool, [&](size_t b) {
    const size_t first = b * kNodes, last = std::min(n, (b + 1) * kNodes);
    if (width_ == 3)
      add_slots<3>(node_, start_, slot_, force.data(), f, first, last);
    else
      add_slots<2>(node_, start_, slot_, force.data(), f, first, last);
  });
}

}  // namespace fe
