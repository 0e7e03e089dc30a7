// Discrete springs and dampers between two nodes (*ELEMENT_DISCRETE with
// *MAT_SPRING_ELASTIC / *MAT_DAMPER_VISCOUS): force along the line of the
// nodes, tension positive, k·(stretch + OFFSET) + c·(rate of stretch).
#pragma once

#include <vector>

#include "elements/element_work.hpp"
#include "model/model.hpp"

namespace fe {

// Adds the forces to f; the spring energy (stored now) and the damping power to w.
void discrete_forces(const Model& m, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f,
                     ElementWork& w);

}  // namespace fe
