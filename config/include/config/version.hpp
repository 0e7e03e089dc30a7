// What every executable prints for --version: its name, the project's
// version (CMakeLists.txt's project()), and the coupling protocol, which
// fe_server, tlm_host and an FMU must share (an FMU made by another version
// is refused by its protocol number, readably).
#pragma once

#include <string>

namespace config {

// "fe_server 0.1.0 (percussion co-simulation; coupling protocol 5)"
std::string version_line(const std::string& tool);

// "0.1.0": the project's version alone (an FMU's version attribute).
const char* project_version();

}  // namespace config
