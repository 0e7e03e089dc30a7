// The elements' owners on P ranks (domain decomposition, solver.hpp).
//
// METIS (Karypis & Kumar, METIS 5 manual, METIS_PartMeshDual): the dual
// graph of the deformable elements (two elements are neighbours when they
// share a face: 4 nodes for hexahedra, an edge of 2 for axisymmetric
// quads, 1 node where bars are in the model), cut into P parts of equal
// work with few shared faces. Chosen over a recursive coordinate
// bisection because a hammer's parts are not boxes: a bisection plane cuts
// through a piston and a housing alike, where METIS follows the mesh's
// connectivity (the halo is what a rank sends every step). The work
// weights are the measured costs per element-cycle (bench/RESULTS.md:
// hex8 ~130 ns, axisymmetric quad ~36 ns, bar ~14 ns): 9, 3, 1. A fixed
// seed: the same deck gives the same partition every run, on every rank.
// Rigid elements do no work and belong to no rank; springs and dampers
// (few) run on rank 0.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace fe {

struct Partition {
  int rank = 0, ranks = 1;
  // Owner rank per element, in model order (-1: rigid); empty when serial.
  std::vector<int> solid, axi, bar;
  bool owns_solid(size_t e) const { return ranks == 1 || solid[e] == rank; }
  bool owns_axi(size_t e) const { return ranks == 1 || axi[e] == rank; }
  bool owns_bar(size_t e) const { return ranks == 1 || bar[e] == rank; }
  bool owns_discretes() const { return rank == 0; }
  bool serial() const { return ranks == 1; }
  // Deformable elements per rank, and how the cut was made.
  std::vector<long> elements_per_rank;
  std::string method;
};

// The same result on every rank (the deck and the seed are the same).
// Throws std::runtime_error when there are fewer deformable elements than
// ranks, or METIS fails.
Partition partition_elements(const Model& m, int ranks, int rank);

}  // namespace fe
