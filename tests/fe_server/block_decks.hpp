// A structured block of hexahedra or of tetrahedra (six per cell), shared
// by the tetrahedron's tests and bench_fe's element costs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace fe_test {

constexpr double kBlockRho = 7850.0;

// A structured block of nx×ny×nz cells of size h (z from 0 up), each cell a
// hexahedron (tets = false) or six tetrahedra around its diagonal from
// corner 1 to corner 7 (the same split in every cell, so neighbours share
// their faces' diagonals). `move` shifts the interior nodes by a fixed
// pattern (a fraction of h) so that no element is regular.
struct Block {
  std::string deck;
  int nodes = 0, elements = 0;
};
// hex_layers: the first layers of cells stay hexahedra in a tetrahedral
// block (part 2, ELFORM 1; they share their nodes with the tetrahedra).
inline Block block_deck(int nx, int ny, int nz, double h, bool tets, double E, double nu, double move = 0.0,
                        const std::string& elform = "10", int hex_layers = 0) {
  std::ostringstream d;
  d << "*KEYWORD\n*NODE\n";
  auto id = [&](int i, int j, int k) { return 1 + i + (nx + 1) * (j + (ny + 1) * k); };
  std::vector<Eigen::Vector3d> x;
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Eigen::Vector3d p(i * h, j * h, k * h);
        const bool inside = i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz;
        if (inside) p += move * h * Eigen::Vector3d(std::sin(1.0 + i + 2 * j), std::cos(2.0 + k + j), std::sin(3.0 + i * k));
        x.push_back(p);
        d.precision(17);
        d << id(i, j, k) << "," << p.x() << "," << p.y() << "," << p.z() << "\n";
      }
  d << "*PART\nblock\n1,1,1\n*PART\nhexahedra\n2,2,1\n*SECTION_SOLID\n1," << (tets ? elform : "1")
    << "\n2,1\n*MAT_ELASTIC\n1," << kBlockRho << "," << E << "," << nu << "\n*ELEMENT_SOLID\n";
  Block b;
  b.nodes = static_cast<int>(x.size());
  int eid = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int c[8] = {id(i, j, k),         id(i + 1, j, k),         id(i + 1, j + 1, k),     id(i, j + 1, k),
                          id(i, j, k + 1),     id(i + 1, j, k + 1),     id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
        if (!tets || k < hex_layers) {
          d << ++eid << (tets ? ",2" : ",1");
          for (int a : c) d << "," << a;
          d << "\n";
          continue;
        }
        static constexpr int kSplit[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        for (const auto& t : kSplit) {
          int n[4] = {c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
          auto at = [&](int node) { return x[static_cast<size_t>(node - 1)]; };
          if ((at(n[1]) - at(n[0])).cross(at(n[2]) - at(n[0])).dot(at(n[3]) - at(n[0])) < 0.0) std::swap(n[1], n[2]);
          // Even permutations keep the orientation and change which corner
          // is N4 (and so which corner a face repeats in its slots).
          if (eid % 3 == 1) n[0] = std::exchange(n[1], std::exchange(n[2], n[0]));
          if (eid % 3 == 2) n[1] = std::exchange(n[2], std::exchange(n[3], n[1]));
          // LS-DYNA's eight-node form, N4 repeated, for every other element.
          d << ++eid << ",1," << n[0] << "," << n[1] << "," << n[2] << "," << n[3];
          if (eid % 2) d << "," << n[3] << "," << n[3] << "," << n[3] << "," << n[3];
          d << "\n";
        }
      }
  b.elements = eid;
  b.deck = d.str();
  return b;
}

}  // namespace fe_test
