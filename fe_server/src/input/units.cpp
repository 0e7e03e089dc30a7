#include "input/units.hpp"

#include <cmath>
#include <cstdio>

namespace fe {

namespace {

const UnitSystem kSystems[] = {
    {"m, kg, s (N, Pa)", 1.0, 1.0, 1.0},
    {"mm, t, s (N, MPa)", 1e-3, 1e3, 1.0},
    {"mm, kg, ms (kN, GPa)", 1e-3, 1.0, 1e-3},
    {"mm, g, ms (N, MPa)", 1e-3, 1e-3, 1e-3},
    {"cm, g, us (1e7 N, Mbar)", 1e-2, 1e-3, 1e-6},
    {"m, t, s (kN, kPa)", 1.0, 1e3, 1.0},
    {"in, lbf s^2/in, s (lbf, psi)", 0.0254, 175.126835, 1.0},
};

// What a solid of a machine can be, in SI.
constexpr double kWaveMin = 20.0, kWaveMax = 2e4;       // m/s: soft rubber to beryllium
constexpr double kDensityMin = 1.0, kDensityMax = 2.5e4;  // kg/m³: foams to tungsten
constexpr double kSizeMin = 1e-3, kSizeMax = 100.0;       // m across

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

}  // namespace

std::vector<UnitSystem> deck_unit_systems(const Model& m, std::string* why) {
  double size = 0.0;
  if (!m.x0.empty()) {
    Vec3 lo = m.x0.front(), hi = m.x0.front();
    for (const Vec3& x : m.x0) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    size = (hi - lo).norm();
  }
  std::vector<UnitSystem> fit;
  std::string first_miss;
  for (const UnitSystem& u : kSystems) {
    bool ok = true;
    for (const auto& [pid, part] : m.parts) {
      const auto it = m.materials.find(part.material);  // a spring's or damper's material is not a solid's
      if (it == m.materials.end()) continue;
      const Material& mat = it->second;
      if (mat.rigid || !(mat.rho > 0.0) || !(mat.E > 0.0)) continue;
      const double c = std::sqrt(mat.E / mat.rho) * u.length / u.time;
      const double rho = mat.rho * u.mass / (u.length * u.length * u.length);
      if (c < kWaveMin || c > kWaveMax || rho < kDensityMin || rho > kDensityMax) {
        ok = false;
        break;
      }
    }
    const double size_si = size * u.length;
    if (ok && size > 0.0 && (size_si < kSizeMin || size_si > kSizeMax)) ok = false;
    if (ok) fit.push_back(u);
  }
  if (fit.empty() && why) {
    // Name the first deformable part, in SI reading, and the model's size.
    for (const auto& [pid, part] : m.parts) {
      const auto it = m.materials.find(part.material);
      if (it == m.materials.end()) continue;
      const Material& mat = it->second;
      if (mat.rigid || !(mat.rho > 0.0) || !(mat.E > 0.0)) continue;
      *why = "part " + std::to_string(pid) + (part.title.empty() ? "" : " (" + part.title + ")") + ": E = " +
             num(mat.E) + ", RO = " + num(mat.rho) + " give a bar wave speed sqrt(E/RO) = " +
             num(std::sqrt(mat.E / mat.rho)) + " length units per time unit, and the model is " + num(size) +
             " length units across";
      break;
    }
    if (why->empty()) *why = "the model is " + num(size) + " length units across";
  }
  return fit;
}

namespace {

// The factor a port table's variable must carry for a deck in system u:
// to fe_server SI → deck units, to the host deck units → SI.
double expected_scale(config::Quantity q, bool to_fe, const UnitSystem& u) {
  using config::Quantity;
  const double L = u.length, T = u.time;
  double deck_in_si = 1.0;  // one deck unit of the quantity, in SI
  switch (q) {
    case Quantity::Pressure:
    case Quantity::Wave: deck_in_si = u.stress(); break;
    case Quantity::Impedance: deck_in_si = u.stress() * T / (L * L * L); break;
    case Quantity::Flow: deck_in_si = L * L * L / T; break;
    case Quantity::Displacement: deck_in_si = L; break;
    case Quantity::Velocity: deck_in_si = L / T; break;
    case Quantity::Force: deck_in_si = u.force(); break;
    case Quantity::Signal: return 0.0;  // a signal has no unit to check
  }
  return to_fe ? 1.0 / deck_in_si : deck_in_si;
}

bool scales_fit(const config::PortTable& t, const UnitSystem& u, std::string* first_bad) {
  for (int dir = 0; dir < 2; ++dir)
    for (const auto& v : dir == 0 ? t.to_fe : t.to_host) {
      const double e = expected_scale(v.quantity, dir == 0, u);
      if (e == 0.0) continue;
      if (std::fabs(v.scale / e - 1.0) > 1e-6) {
        if (first_bad)
          *first_bad = v.where.str() + ": " + v.name() + " has scale " + num(v.scale) + ", where a deck in " + u.name +
                       " needs " + num(e);
        return false;
      }
    }
  return true;
}

}  // namespace

void check_units(const Model& m, const std::vector<config::PortTable>& tables) {
  std::string why;
  const std::vector<UnitSystem> fit = deck_unit_systems(m, &why);
  config::SourceLocation where{m.source, 1};
  for (const auto& [pid, part] : m.parts) {
    const auto it = m.materials.find(part.material);
    if (it != m.materials.end() && !it->second.rigid) {
      where = it->second.where.file.empty() ? where : it->second.where;
      break;
    }
  }
  if (fit.empty()) {
    std::string systems;
    for (const UnitSystem& u : kSystems) systems += std::string(systems.empty() ? "" : "; ") + u.name;
    throw config::InputError(
        where, "the deck's units do not fit together: " + why +
                   ". In no consistent unit system is that a solid (a wave speed of 20 to 20 000 m/s, a density of "
                   "1 to 25 000 kg/m³) of a machine's size (1 mm to 100 m): check E, RO and the coordinates against "
                   "one system (" + systems + ")");
  }
  for (const auto& t : tables) {
    std::string bad;
    bool any = false;
    for (const UnitSystem& u : fit) any = any || scales_fit(t, u, nullptr);
    if (any) continue;
    scales_fit(t, fit.front(), &bad);
    throw config::InputError(where, "the port table " + t.source + " does not convert to the deck's units (" +
                                        fit.front().name + ", from its materials and size): " + bad);
  }
}

}  // namespace fe
