#include "elements/element_discrete.hpp"

namespace fe {

void discrete_forces(const Model& m, const std::vector<Vec3>& x, const std::vector<Vec3>& v, std::vector<Vec3>& f,
                     ElementWork& w) {
  for (const auto& d : m.discretes) {
    const size_t i = static_cast<size_t>(d.n1), j = static_cast<size_t>(d.n2);
    Vec3 axis = x[j] - x[i];
    const double len = axis.norm();
    axis /= len;
    // Tension positive: stretch plus the initial offset (LS-DYNA's OFFSET).
    const double stretch = len - d.length0 + d.offset;
    const double rate = (v[j] - v[i]).dot(axis);
    const double force = d.k * stretch + d.c * rate;
    f[i] += force * axis;  // tension pulls node i towards j and j towards i
    f[j] -= force * axis;
    w.spring_energy += 0.5 * d.k * stretch * stretch;
    w.damping_power += d.c * rate * rate;
  }
}

}  // namespace fe
