#include "config/version.hpp"

#include "socketlib/protocol.h"

namespace config {

std::string version_line(const std::string& tool) {
  return tool + " " PCS_PROJECT_VERSION " (percussion co-simulation; coupling protocol " +
         std::to_string(PCS_PROTOCOL_VERSION) + ")";
}

const char* project_version() { return PCS_PROJECT_VERSION; }

}  // namespace config
