// fe_server across MPI ranks: strong scaling of the FE step and the halo
// exchange's volume and time, on the hex8 bar impact (the bench_fe mesh made
// longer: >= 50k elements). Run it alone (one rank: it also times 1 and 2
// threads, to compare threads with ranks on one node) and under
// `mpirun -n P`; bench/run_benchmarks.py interleaves the runs and writes
// bench/RESULTS.md.
//
//   bench_mpi [h_mm] [steps]     one line of key=value pairs from rank 0
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bench_args.hpp"
#include "impact_decks.hpp"
#include "input/deck_reader.hpp"
#include "parallel/domain.hpp"
#include "solver/solver.hpp"

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct Timing {
  double fastest = 0, median = 0, slowest = 0;  // s per FE step, over five slices
};

// Steps in five slices, each between barriers (the slowest rank's time);
// interference from the shared machine only adds time, so the fastest slice
// is the cost.
Timing time_steps(fe::Solver& s, int steps, const fe::Domain& d) {
  std::vector<double> per;
  const int slice = std::max(1, steps / 5);
  for (int k = 0; k < 5; ++k) {
    d.any(false);  // a barrier
    const double t0 = now();
    for (int i = 0; i < slice; ++i) s.step();
    d.any(false);
    per.push_back((now() - t0) / slice);
  }
  std::sort(per.begin(), per.end());
  return {per.front(), per[2], per.back()};
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage =
      "usage: [mpirun -n P] bench_mpi [H_MM [STEPS]]   hex8 bar impact, element size in mm (default 1.5: 58k "
      "hexes), timed steps (default 200)";
  bench::help_or_nothing(argc, argv, usage);
  fe::Domain::init(&argc, &argv);
  const fe::Domain& d = fe::Domain::world();
  const double h = bench::positive_arg(argc, argv, 1, 1.5, "H_MM (element size in mm)", usage) * 1e-3;
  const int steps = bench::count_arg(argc, argv, 2, 200, "STEPS (timed steps)", usage);
  // Ø20 mm piston 50 mm long on a tool 250 mm long, contact between them.
  const fe::Model m = fe::parse_deck(fe_test::bar_impact_deck(0.05, 0.25, 0.01, h, 8.0, fe_test::kE), "impact.k");
  const double dt = 0.9 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt, d);
  for (int i = 0; i < 20; ++i) s.step();  // warm up (caches, the first step's half Δt)
  const fe::Domain::Traffic before = d.traffic();
  const Timing t = time_steps(s, steps, d);
  const fe::Domain::Traffic after = d.traffic();
  const int timed = 5 * std::max(1, steps / 5);
  // Per rank: its halo (shared nodes, bytes and seconds per step); rank 0 prints the largest.
  const double mine[4] = {static_cast<double>(s.shared_nodes()),
                          static_cast<double>(after.bytes - before.bytes) / timed,
                          (after.seconds - before.seconds) / timed, static_cast<double>(after.messages - before.messages) / timed};
  std::vector<double> all(4 * static_cast<size_t>(d.size()));
  d.allgather(mine, 4, all.data());
  double worst[4] = {0, 0, 0, 0};
  for (int r = 0; r < d.size(); ++r)
    for (int k = 0; k < 4; ++k) worst[k] = std::max(worst[k], all[4 * static_cast<size_t>(r) + static_cast<size_t>(k)]);
  Timing two;
  if (!d.parallel()) {  // one node's other choice: threads
    fe::Solver s2(m, dt);
    s2.set_threads(2);
    for (int i = 0; i < 20; ++i) s2.step();
    two = time_steps(s2, steps, d);
  }
  if (d.rank() == 0) {
    size_t elements;
    elements = m.solids.size();
    std::printf("ranks=%d elements=%zu nodes=%zu step_fastest_us=%.3f step_median_us=%.3f step_slowest_us=%.3f "
                "shared_nodes_max=%.0f halo_bytes_per_step_max=%.0f halo_us_per_step_max=%.3f messages_per_step=%.0f "
                "threads2_fastest_us=%.3f threads2_median_us=%.3f method=\"%s\"\n",
                d.size(), elements, m.x0.size(), 1e6 * t.fastest, 1e6 * t.median, 1e6 * t.slowest, worst[0], worst[1],
                1e6 * worst[2], worst[3], 1e6 * two.fastest, 1e6 * two.median, s.partition().method.c_str());
  }
  fe::Domain::finalize();
  return 0;
}
