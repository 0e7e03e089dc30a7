#include "solver/mass_scaling.hpp"

#include <cstdio>

#include "elements/element_axi4.hpp"
#include "elements/element_hex8.hpp"
#include "elements/element_tet4.hpp"

namespace fe {

std::string MassScalingReport::summary() const {
  std::string s;
  char buf[160];
  for (const auto& [pid, mm] : per_part) {
    if (mm.second <= 0.0) continue;
    std::snprintf(buf, sizeof buf, "part %d: added %.4g kg to %.4g kg (%.2f %%)\n", pid, mm.second, mm.first,
                  100.0 * mm.second / mm.first);
    s += buf;
  }
  return s;
}

MassScalingReport apply_mass_scaling(Model& m, double dt) {
  MassScalingReport r;
  for (auto& e : m.solids) {
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const Mat83 x = hex8_gather(m.x0, e);
    const double volume = solid_volume(x, e);
    auto& part = r.per_part[e.part];
    part.first += mat.rho * volume;
    if (mat.rigid) continue;
    // With stiffness damping a heavier element is damped less at its highest
    // mode, so f² times the density gives at least f times the step.
    const double dt_e = solid_stable_step(x, e, mat.lambda(), mat.mu(), mat.rho, m.bulk_q2, m.parts.at(e.part).stiffness_damping);
    const double f = dt / (m.dt_scale * dt_e);
    if (f <= 1.0) continue;
    const double added = (f * f - 1.0) * mat.rho * volume;
    e.mass_scale = f * f;
    for (int k = 0; k < 8; ++k) m.mass[static_cast<size_t>(e.n[k])] += added * solid_mass_share(e, k);
    part.second += added;
    ++r.elements_scaled;
  }
  for (auto& e : m.bars) {
    const Part& p = m.parts.at(e.part);
    const Material& mat = m.materials.at(p.material);
    const double L = (m.x0[static_cast<size_t>(e.n2)] - m.x0[static_cast<size_t>(e.n1)]).norm();
    auto& part = r.per_part[e.part];
    part.first += mat.rho * p.bar_area * L;
    if (mat.rigid) continue;
    const double f = dt / (m.dt_scale * L / std::sqrt(mat.E / mat.rho));
    if (f <= 1.0) continue;
    const double added = (f * f - 1.0) * mat.rho * p.bar_area * L;
    e.mass_scale = f * f;
    m.mass[static_cast<size_t>(e.n1)] += added / 2.0;
    m.mass[static_cast<size_t>(e.n2)] += added / 2.0;
    part.second += added;
    ++r.elements_scaled;
  }
  for (auto& e : m.axis) {
    const Material& mat = m.materials.at(m.parts.at(e.part).material);
    const Mat42 x = axi4_gather(m.x0, e);
    bool fixed_r[4];
    for (int k = 0; k < 4; ++k) fixed_r[k] = m.fixed[static_cast<size_t>(e.n[k])][0];
    const Eigen::Vector4d mass = axi4_lumped_masses(x, mat.rho);
    auto& part = r.per_part[e.part];
    part.first += mass.sum();
    if (mat.rigid) continue;
    const double dt_e =
        axi4_stable_step(x, mat.lambda(), mat.mu(), mat.rho, m.bulk_q2, fixed_r, m.parts.at(e.part).stiffness_damping);
    const double f = dt / (m.dt_scale * dt_e);
    if (f <= 1.0) continue;
    e.mass_scale = f * f;
    for (int k = 0; k < 4; ++k) m.mass[static_cast<size_t>(e.n[k])] += (f * f - 1.0) * mass(k);
    part.second += (f * f - 1.0) * mass.sum();
    ++r.elements_scaled;
  }
  for (auto& rb : m.rigid_bodies) {  // bodies carry their nodes' masses (or *PART_INERTIA's)
    if (rb.inertia_given) continue;
    rb.mass = 0.0;
    for (int i : rb.nodes) rb.mass += m.mass[static_cast<size_t>(i)];
  }
  return r;
}

}  // namespace fe
