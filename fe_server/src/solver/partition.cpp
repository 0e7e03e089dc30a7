#include "solver/partition.hpp"

#include <algorithm>
#include <stdexcept>

#ifdef PCS_HAVE_METIS
#include <metis.h>
#endif

namespace fe {

namespace {
bool rigid(const Model& m, int part) { return m.materials.at(m.parts.at(part).material).rigid; }
}  // namespace

Partition partition_elements(const Model& m, int ranks, int rank) {
  Partition p;
  p.rank = rank;
  p.ranks = ranks;
  if (ranks <= 1) {
    p.method = "serial";
    return p;
  }
  p.solid.assign(m.solids.size(), -1);
  p.axi.assign(m.axis.size(), -1);
  p.bar.assign(m.bars.size(), -1);
  // The deformable elements as one mesh: (kind, index) in model order.
  struct Ref {
    std::vector<int>* owner;
    size_t index;
  };
  std::vector<Ref> refs;
#ifdef PCS_HAVE_METIS
  std::vector<idx_t> eptr{0}, eind, vwgt;
  idx_t ncommon = 4;
  auto add = [&](std::vector<int>& owner, size_t e, const int* nodes, int count, idx_t weight, idx_t common) {
    refs.push_back({&owner, e});
    eind.insert(eind.end(), nodes, nodes + count);
    eptr.push_back(static_cast<idx_t>(eind.size()));
    vwgt.push_back(weight);
    ncommon = std::min(ncommon, common);
  };
  for (size_t e = 0; e < m.solids.size(); ++e)
    if (!rigid(m, m.solids[e].part)) add(p.solid, e, m.solids[e].n, 8, 9, 4);
  for (size_t e = 0; e < m.axis.size(); ++e)
    if (!rigid(m, m.axis[e].part)) add(p.axi, e, m.axis[e].n, 4, 3, 2);
  for (size_t e = 0; e < m.bars.size(); ++e)
    if (!rigid(m, m.bars[e].part)) {
      const int n[2] = {m.bars[e].n1, m.bars[e].n2};
      add(p.bar, e, n, 2, 1, 1);
    }
  if (refs.size() < static_cast<size_t>(ranks))
    throw std::runtime_error("the model has " + std::to_string(refs.size()) + " deformable elements for " +
                             std::to_string(ranks) + " ranks: run it on fewer ranks");
  idx_t ne = static_cast<idx_t>(refs.size()), nn = static_cast<idx_t>(m.x0.size()), nparts = ranks, objval = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 1;
  std::vector<idx_t> epart(refs.size()), npart(m.x0.size());
  const int rc = METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), vwgt.data(), nullptr, &ncommon, &nparts,
                                    nullptr, options, &objval, epart.data(), npart.data());
  if (rc != METIS_OK) throw std::runtime_error("METIS_PartMeshDual failed (" + std::to_string(rc) + ")");
  p.elements_per_rank.assign(static_cast<size_t>(ranks), 0);
  for (size_t k = 0; k < refs.size(); ++k) {
    (*refs[k].owner)[refs[k].index] = static_cast<int>(epart[k]);
    ++p.elements_per_rank[static_cast<size_t>(epart[k])];
  }
  p.method = "METIS dual graph, " + std::to_string(objval) + " cut faces";
  return p;
#else
  (void)refs;
  throw std::runtime_error("this fe_server was built without METIS: it cannot partition across ranks");
#endif
}

}  // namespace fe
