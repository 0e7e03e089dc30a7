// Hopsan model files (.hmf, Hopsan's XML model format; libxml2) read into
// the same ModelSpec as our model.tlm, so a user's Hopsan circuit runs in
// tlm_host without being typed again.
//
// What is read: the top-level system's components, their parameters (a
// number, or the name of a system parameter), their connections, and the
// simulation settings (timestep, stop time; logsamples sets log_every).
// Hopsan component types map onto ours by a table (hopsan_loader.cpp) with
// their parameters and units; a start value of a node variable is used where
// ours has it (a volume's initial pressure) and must keep Hopsan's default
// elsewhere. Anything else — a component type or parameter without a
// mapping, an expression, a nested subsystem, a sensor whose signal is used
// — is refused with the component's name, type and the file's line: never
// approximated. Where our component differs from Hopsan's by design, the
// loader says so once per component (notes()).
#pragma once

#include <string>
#include <vector>

#include "model.hpp"

namespace tlm {

struct HmfModel {
  ModelSpec spec;
  std::vector<std::string> notes;  // differences by design, per component
};

// Throws config::InputError (file:line) for what it cannot read exactly.
HmfModel read_hmf(const std::string& path);

// The mapping table as a Markdown page (tlm_host --hopsan-types;
// docs/hopsan_types.md is its output, checked by a test).
std::string hopsan_mapping_markdown();

}  // namespace tlm
