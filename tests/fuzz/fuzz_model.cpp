// Fuzz target: the TLM host's model reader and the system it builds
// (components configured, ports and signals connected; no run).
#include <cstdint>
#include <string>

#include "model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    tlm::ModelSpec spec = tlm::parse_model(text, "fuzz.tlm");
    tlm::System sys(std::move(spec));
    (void)sys.stability_warnings(1e-6);
  } catch (const std::exception&) {
  }
  return 0;
}
