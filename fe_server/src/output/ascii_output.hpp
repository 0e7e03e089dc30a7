// LS-DYNA's ASCII time-history files, for users whose post-processing
// scripts read them: glstat (global energies), matsum (per part), rcforc
// (contact resultants), nodout (history nodes) and elout (history solids),
// each written when the deck asks for it with its *DATABASE_<NAME> card and
// at that card's DT. The HDF5 history stays the primary output; these
// files carry the same values at the same times (conventions: history.hpp).
//
// The layouts are LS-DYNA's as its ASCII translator writes them (the lines,
// labels and Fortran-style E fields of LSTC's l2a for each file), so a
// script that parses LS-DYNA's files parses these:
//   glstat  a block per output time: "dt of cycle N is controlled by ...",
//           then "time....", "kinetic energy....", ... with %14.5E values;
//   matsum  " time =" and per part "mat.#=", inten, kinen, momenta, rigid
//           body velocities (momentum / mass), hgeng;
//   rcforc  a slave and a master line per contact (in deck order, 1-based):
//           time, x, y, z force on that side's nodes, mass in contact;
//   nodout  "n o d a l   p r i n t   o u t" blocks: displacement, velocity,
//           acceleration and coordinates per node;
//   elout   "e l e m e n t   s t r e s s" blocks: six stresses, the
//           effective plastic strain and the current yield stress (0 for an
//           elastic material) per solid.
// What differs from LS-DYNA, by design: "internal energy" is the elements'
// (springs and hourglass apart, as their own lines); total energy / initial
// energy is the total over (the initial total + external work); matsum's
// internal energy covers solids (1D bars and springs show 0); a node shared
// by parts counts in each by its share of the adjacent elements; elout lists
// hex8 solids only (axisymmetric and bar histories are in the HDF5).
//
// The files go next to the results file, named as LS-DYNA names them.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "config/checkpoint.hpp"
#include "model/model.hpp"
#include "solver/solver.hpp"

namespace fe {

class AsciiOutput {
 public:
  // dir: where the files go. resume: continue the files of a restarted run
  // (state() cuts them back to the checkpoint's bytes) instead of creating them.
  AsciiOutput(const std::string& dir, const Model& model, double fe_dt, bool resume = false);
  ~AsciiOutput();
  AsciiOutput(const AsciiOutput&) = delete;
  AsciiOutput& operator=(const AsciiOutput&) = delete;
  // After every FE step: the files whose interval is due get their block.
  void record(const Solver& s);
  // How many of the files due after FE step n read every node's velocity
  // (glstat, matsum): across ranks each such read gathers them at rank 0,
  // and the other ranks (FollowerHistory) take part as often.
  static int velocity_reads(const Model& model, double fe_dt, long n);
  void flush();
  // The bytes written to each file (checkpoints; flush() first).
  void state(config::StateIO& io);
  // Names of the files written, in a fixed order.
  std::vector<std::string> files() const;

 private:
  struct File {
    std::string name, path;
    long every = 1;  // FE steps between blocks
    std::FILE* out = nullptr;
  };
  void glstat(std::FILE* f, const Solver& s);
  void matsum(std::FILE* f, const Solver& s);
  void rcforc(std::FILE* f, const Solver& s);
  void nodout(std::FILE* f, const Solver& s);
  void elout(std::FILE* f, const Solver& s);
  void header(std::FILE* f) const;
  const Model& m_;
  double dt_;
  StableStep limit_;
  std::vector<File> files_;
  // Per part (Model::parts order): its nodes and each one's share of the node's mass.
  std::vector<int> part_ids_;
  std::vector<std::vector<int>> part_nodes_;
  std::vector<std::vector<double>> part_share_;
  std::chrono::steady_clock::time_point last_wall_;
  long last_step_ = 0;
};

}  // namespace fe
