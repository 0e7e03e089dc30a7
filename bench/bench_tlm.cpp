// TLM host cost on the monolithic hammer: ns per component-step, the
// simulation loop alone (HDF5 logging every `log_every` steps included, as
// in a real run). Usage: bench_tlm [stoptime]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_args.hpp"
#include "model.hpp"
#include "process.hpp"

int main(int argc, char** argv) {
  const char* usage = "usage: bench_tlm [STOPTIME]   simulated seconds of the monolithic hammer (default 0.2)";
  bench::help_or_nothing(argc, argv, usage);
  const double stop = bench::positive_arg(argc, argv, 1, 0.2, "STOPTIME (simulated seconds)", usage);
  testing_support::TempDir dir;
  tlm::ModelSpec spec = tlm::read_model(PCS_SCENES_DIR "/hammer_monolithic/model.tlm");
  spec.apply_override("simulation.stoptime=" + std::to_string(stop));
  const size_t components = spec.components.size();
  const double dt = spec.dt;
  tlm::System sys(std::move(spec));
  auto t0 = std::chrono::steady_clock::now();
  sys.run(dir.file("r.h5"), false);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double steps = static_cast<double>(sys.steps_done());
  std::printf("monolithic hammer: %zu components, %.0f steps of %g s, %.3f s wall\n", components, steps, dt, s);
  std::printf("  %.1f ns per component-step, %.3f us per step, %.2f s wall per simulated second\n",
              1e9 * s / (steps * static_cast<double>(components)), 1e6 * s / steps, s / stop);
  std::printf("csv:tlm_cost,%zu,%.3f,%.4f\n", components, 1e9 * s / (steps * static_cast<double>(components)), s / stop);
  return 0;
}
