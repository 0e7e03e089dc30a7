#include "solver/mass_scaling.hpp"

#include <cmath>
#include <cstdio>

#include "elements/element_axi4.hpp"
#include "elements/element_hex8.hpp"
#include "elements/element_tet4.hpp"

namespace fe {

namespace {

// The factor f on the step of an element (its density times f²) that
// brings its stable step up to `target`; `step0` is its step without
// stiffness damping (bulk viscosity's Q2 only). Undamped the step goes as
// √ρ, so f = target/step0. With stiffness damping β the highest mode is
// damped less as it slows, so that ratio of the damped steps would add more
// mass than needed: f comes from the frequency ω that allows the target
// exactly, (2/ω)·(√(1 + ζ²) − ζ) = T with ζ = Q2 + β·ω/2, which squared is
// the quadratic (T²/4 + β·T/2)·ω² + Q2·T·ω − 1 = 0, and ω ∝ 1/√ρ.
double step_factor(double step0, double target, double q2, double beta) {
  if (beta == 0.0 || !(step0 > 0.0)) return target / step0;
  const double omega0 = 2.0 * (std::sqrt(1.0 + q2 * q2) - q2) / step0;
  const double a = 0.25 * target * target + 0.5 * beta * target, b = q2 * target;
  const double omega = (-b + std::sqrt(b * b + 4.0 * a)) / (2.0 * a);
  return omega0 / omega;
}

}  // namespace

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
    const double dt_e = solid_stable_step(x, e, mat.lambda(), mat.mu(), mat.rho, m.bulk_q2);
    const double f = step_factor(dt_e, dt / m.dt_scale, m.bulk_q2, m.parts.at(e.part).stiffness_damping);
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
    const double dt_e = axi4_stable_step(x, mat.lambda(), mat.mu(), mat.rho, m.bulk_q2, fixed_r);
    const double f = step_factor(dt_e, dt / m.dt_scale, m.bulk_q2, m.parts.at(e.part).stiffness_damping);
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
