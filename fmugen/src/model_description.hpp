// modelDescription.xml for a port table (FMI 2.0 co-simulation).
#pragma once

#include <string>

#include "config/port_table.hpp"

namespace fmugen {

// Who made the FMU, and when: generationTool and generationDateAndTime.
struct Generation {
  std::string tool = "fmugen";
  std::string date;  // ISO 8601 UTC ("2026-12-03T14:00:00Z"); empty: left out
};

// An empty description: the table's own ($FMU_SETTINGS description), else
// one made from its ports (default_description).
std::string model_description_xml(const config::PortTable& table, const std::string& description,
                                  const Generation& generation = {});

// The same FMU as FMI 3.0 co-simulation (fmugen --fmi 3).
std::string model_description_xml3(const config::PortTable& table, const std::string& description,
                                   const Generation& generation = {});

// What the FMU couples, from its ports: "one_dof: fe_server co-simulation,
// hydraulic port chamber_A, mechanic port piston (pressure coupling, 1e-05 s)".
std::string default_description(const config::PortTable& table);

// documentation/index.html: every variable and parameter with unit and
// meaning, how to reach the server and give the token, the coupling.
std::string documentation_html(const config::PortTable& table, const std::string& description,
                               const Generation& generation);

// Text of documentation/externalDependencies.txt.
std::string external_dependencies_text(const config::PortTable& table);

}  // namespace fmugen
