#include "elements/element_bar.hpp"

namespace fe {

BarState::BarState(const Model& m) : force(m.bars.size(), 0.0), area(m.bars.size(), 0.0), EA(m.bars.size(), 0.0) {
  for (size_t e = 0; e < m.bars.size(); ++e) {
    const Part& part = m.parts.at(m.bars[e].part);
    const Material& mat = m.materials.at(part.material);
    area[e] = part.bar_area;
    if (mat.rigid) continue;
    elements.push_back(static_cast<int>(e));
    EA[e] = mat.E * part.bar_area;
  }
}

void bar_forces(const Model& m, BarState& s, const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt,
                std::vector<Vec3>& f, ElementWork& w) {
  for (int ei : s.elements) {
    const size_t e = static_cast<size_t>(ei);
    const BarElement& b = m.bars[e];
    const size_t i = static_cast<size_t>(b.n1), j = static_cast<size_t>(b.n2);
    Vec3 axis = x[j] - x[i];
    const double len = axis.norm();
    axis /= len;
    // Axial stress rate from the elongation rate (hypoelastic, like the solids).
    const double rate = (v[j] - v[i]).dot(axis) / len;
    const double old = s.force[e];
    s.force[e] += dt * s.EA[e] * rate;
    f[i] += s.force[e] * axis;
    f[j] -= s.force[e] * axis;
    w.internal += 0.5 * (old + s.force[e]) * rate * len * dt;
  }
}

}  // namespace fe
