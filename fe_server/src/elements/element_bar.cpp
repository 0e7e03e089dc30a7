#include "elements/element_bar.hpp"

namespace fe {

BarState::BarState(const Model& m, const std::vector<int>* owner, int rank)
    : force(m.bars.size(), 0.0), area(m.bars.size(), 0.0), EA(m.bars.size(), 0.0), length0(m.bars.size(), 0.0),
      length(m.bars.size(), 0.0) {
  for (size_t e = 0; e < m.bars.size(); ++e) {
    const BarElement& b = m.bars[e];
    const Part& part = m.parts.at(b.part);
    const Material& mat = m.materials.at(part.material);
    area[e] = part.bar_area;
    length0[e] = length[e] = (m.x0[static_cast<size_t>(b.n2)] - m.x0[static_cast<size_t>(b.n1)]).norm();
    if (mat.rigid || (owner && (*owner)[e] != rank)) continue;
    elements.push_back(static_cast<int>(e));
    EA[e] = mat.E * part.bar_area;
  }
}

void bar_forces(const Model& m, BarState& s, const std::vector<Vec3>& x, const std::vector<Vec3>&, double,
                std::vector<Vec3>& f, ElementWork& w) {
  for (int ei : s.elements) {
    const size_t e = static_cast<size_t>(ei);
    const BarElement& b = m.bars[e];
    const size_t i = static_cast<size_t>(b.n1), j = static_cast<size_t>(b.n2);
    Vec3 axis = x[j] - x[i];
    const double len = axis.norm();
    axis /= len;
    const double old = s.force[e];
    s.force[e] = s.EA[e] * (len - s.length0[e]) / s.length0[e];
    f[i] += s.force[e] * axis;
    f[j] -= s.force[e] * axis;
    w.internal += 0.5 * (old + s.force[e]) * (len - s.length[e]);
    s.length[e] = len;
  }
}

}  // namespace fe
