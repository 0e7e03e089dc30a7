// modelDescription.xml for a port table (FMI 2.0 co-simulation).
#pragma once

#include <string>

#include "config/port_table.hpp"

namespace fmugen {

std::string model_description_xml(const config::PortTable& table, const std::string& description);

// Text of documentation/externalDependencies.txt.
std::string external_dependencies_text(const config::PortTable& table);

}  // namespace fmugen
