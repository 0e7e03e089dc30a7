// Fuzz target: the port-configuration reader and what derives from it.
#include <cstdint>
#include <string>

#include "config/port_table.hpp"
#include "model_description.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    config::PortTable t = config::parse_port_table(text, "fuzz.cfg");
    (void)t.hash();
    (void)config::fmu_variables(t);
    (void)fmugen::model_description_xml(t, "fuzz");
  } catch (const std::exception&) {
    // Rejected input must fail with an exception, never crash.
  }
  return 0;
}
