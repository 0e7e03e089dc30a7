// Fuzz target: tlm_host's --set overrides. Each input line is one
// "component.parameter=value" applied to the monolithic hammer model, then
// the system is built: every value must be range-checked where it is read
// (a clear error), never crash or overflow.
#include <cstdint>
#include <sstream>
#include <string>

#include "config/keyword_reader.hpp"
#include "model.hpp"

namespace {
const tlm::ModelSpec& base() {
  static const tlm::ModelSpec spec = tlm::read_model(PCS_SCENES_DIR "/hammer_monolithic/model.tlm");
  return spec;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  tlm::ModelSpec spec = base();
  std::istringstream lines(std::string(reinterpret_cast<const char*>(data), size));
  std::string line;
  try {
    for (int n = 0; n < 16 && std::getline(lines, line); ++n) spec.apply_override(line);
    tlm::System sys(std::move(spec));
    (void)sys.stability_warnings(1e-6);
  } catch (const std::exception&) {
  }
  return 0;
}
