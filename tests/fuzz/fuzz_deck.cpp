// Fuzz target: the FE keyword deck reader, the stable-step estimate and a
// few solver steps on whatever model it accepts.
#include <cstdint>
#include <string>

#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    fe::Model m = fe::parse_deck(text, "fuzz.k");
    const fe::StableStep st = fe::Solver::stable_dt(m);
    if (st.dt > 0.0 && st.dt < 1e299 && m.node_ids.size() < 1000) {
      fe::Solver s(m, 0.5 * m.dt_scale * st.dt);
      for (int k = 0; k < 3; ++k) s.step();
    }
  } catch (const std::exception&) {
  }
  return 0;
}
