#include "output/fatigue.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "output/field_output.hpp"

namespace fe {

double signed_von_mises(const Eigen::Matrix<double, 6, 1>& s) { return std::copysign(von_mises(s), s(0) + s(1) + s(2)); }

double largest_principal(const Eigen::Matrix<double, 6, 1>& s, bool axisymmetric) {
  auto largest = [](double a, double b) { return std::fabs(a) >= std::fabs(b) ? a : b; };
  if (axisymmetric) {  // the in-plane pair (rr, yy, ry) and the hoop stress
    const double c = 0.5 * (s(0) + s(1)), r = std::hypot(0.5 * (s(0) - s(1)), s(3));
    return largest(largest(c + r, c - r), s(2));
  }
  // The eigenvalues of the symmetric 3×3 tensor in closed form (trigonometric).
  const double xx = s(0), yy = s(1), zz = s(2), xy = s(3), yz = s(4), zx = s(5);
  const double p1 = xy * xy + yz * yz + zx * zx;
  const double q = (xx + yy + zz) / 3.0;
  if (p1 <= 1e-30 * (xx * xx + yy * yy + zz * zz)) return largest(largest(xx, yy), zz);
  const double p2 = (xx - q) * (xx - q) + (yy - q) * (yy - q) + (zz - q) * (zz - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  const double b11 = (xx - q) / p, b22 = (yy - q) / p, b33 = (zz - q) / p, b12 = xy / p, b23 = yz / p, b13 = zx / p;
  const double det = b11 * (b22 * b33 - b23 * b23) - b12 * (b12 * b33 - b23 * b13) + b13 * (b12 * b23 - b22 * b13);
  const double phi = std::acos(std::clamp(0.5 * det, -1.0, 1.0)) / 3.0;
  const double e1 = q + 2.0 * p * std::cos(phi), e3 = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  const double e2 = 3.0 * q - e1 - e3;
  return largest(largest(e1, e2), e3);
}

FatigueTracker::FatigueTracker(const Model& m, double fe_dt)
    : m_(m), axisymmetric_(m.solids.empty() && !m.axis.empty()), every_(m.fatigue.size(), 1), due_(m.fatigue.size(), 1) {
  for (size_t k = 0; k < m.fatigue.size(); ++k) {
    const FatigueDef& d = m.fatigue[k];
    if (d.dt > 0.0 && fe_dt > 0.0) every_[k] = std::max(1L, std::lround(d.dt / fe_dt));
    const size_t n = axisymmetric_ ? m.axis.size() : m.solids.size();
    for (size_t e = 0; e < n; ++e) {
      if ((axisymmetric_ ? m.axis[e].part : m.solids[e].part) != d.part) continue;
      cells_.push_back({static_cast<uint32_t>(e), static_cast<uint32_t>(k), {}});
      counts_.push_back({{}, fatigue::Damage{d.curve, d.mean, d.su, 0.0, 0.0}, 0.0});
    }
  }
}

namespace {

// Signed von Mises without a gate: its turning points are those of its
// signed square (x -> sign(x)·x² keeps the order), which needs no square
// root per sample; the root is taken at a reversal only.
bool squared_domain(const FatigueDef& d) { return d.stress == 0 && d.gate == 0.0; }

// von_mises(s)², signed, without its root.
double signed_von_mises_squared(const Eigen::Matrix<double, 6, 1>& s) {
  const double a = s(0) - s(1), b = s(1) - s(2), c = s(2) - s(0);
  const double vm2 = 0.5 * (a * a + b * b + c * c) + 3.0 * (s(3) * s(3) + s(4) * s(4) + s(5) * s(5));
  return std::copysign(vm2, s(0) + s(1) + s(2));
}

double from_squared(double r2) { return std::copysign(std::sqrt(std::fabs(r2)), r2); }

}  // namespace

void FatigueTracker::sample(const Solver& s) {
  bool any = false;
  for (size_t k = 0; k < every_.size(); ++k) any |= (due_[k] = s.step_count() % every_[k] == 0) != 0;
  if (!any) return;
  for (size_t i = 0; i < cells_.size(); ++i) {
    Cell& c = cells_[i];
    if (!due_[c.def]) continue;
    const FatigueDef& d = m_.fatigue[c.def];
    const auto& sg = axisymmetric_ ? s.axi_stress(c.element) : s.stress(c.element);
    double r;
    if (squared_domain(d)) {
      if (!c.points.next(signed_von_mises_squared(sg), 0.0, &r)) continue;  // the common case: no reversal
      r = d.kf * from_squared(r);
    } else {
      const double eq = d.kf * (d.stress == 0 ? signed_von_mises(sg) : largest_principal(sg, axisymmetric_));
      if (!c.points.next(eq, d.gate, &r)) continue;
    }
    Count& n = counts_[i];
    auto sink = [&n](const fatigue::Cycle& y) {
      n.damage.add(y);
      n.largest_range = std::max(n.largest_range, y.range);
    };
    n.reversals.push(r, sink);
  }
}

double FatigueTracker::damage_with_residue(size_t i) const {
  fatigue::ReversalCounter copy = counts_[i].reversals;
  fatigue::Damage d = counts_[i].damage;
  auto sink = [&d](const fatigue::Cycle& y) { d.add(y); };
  double r;
  if (cells_[i].points.last(&r)) {
    const FatigueDef& def = m_.fatigue[cells_[i].def];
    copy.push(squared_domain(def) ? def.kf * from_squared(r) : r, sink);
  }
  copy.finish(sink);
  return d.damage;
}

std::vector<double> FatigueTracker::damage_field() const {
  std::vector<double> out(axisymmetric_ ? m_.axis.size() : m_.solids.size(), 0.0);
  for (size_t i = 0; i < cells_.size(); ++i) out[cells_[i].element] = damage_with_residue(i);
  return out;
}

Vec3 FatigueTracker::centroid(size_t e) const {
  Vec3 x = Vec3::Zero();
  if (axisymmetric_) {
    for (int k = 0; k < 4; ++k) x += m_.x0[static_cast<size_t>(m_.axis[e].n[k])] / 4.0;
  } else {
    for (int k = 0; k < 8; ++k) x += m_.x0[static_cast<size_t>(m_.solids[e].n[k])] / 8.0;
  }
  return x;
}

int FatigueTracker::element_id(size_t e) const { return axisymmetric_ ? m_.axis[e].id : m_.solids[e].id; }

std::string FatigueTracker::report(double time, size_t top) const {
  std::vector<std::pair<double, size_t>> ranked;
  for (size_t i = 0; i < cells_.size(); ++i) ranked.emplace_back(damage_with_residue(i), i);
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::ostringstream r;
  r << "fatigue after " << time << " s (" << cells_.size() << " elements counted; the mesh's stress"
    << (std::any_of(m_.fatigue.begin(), m_.fatigue.end(), [](const FatigueDef& d) { return d.kf != 1.0; })
            ? " times each part's notch factor"
            : ": fillets finer than the mesh are not resolved, a notch factor KF raises them")
    << "):\n";
  char line[320];
  for (size_t k = 0; k < std::min(top, ranked.size()); ++k) {
    const size_t i = ranked[k].second;
    const Cell& c = cells_[i];
    const Count& n = counts_[i];
    const Vec3 x = centroid(c.element);
    const double d = ranked[k].first;
    const int part = m_.fatigue[c.def].part, id = element_id(c.element);
    if (d > 0.0)
      std::snprintf(line, sizeof line,
                    "  %zu. part %d element %d at (%.4g, %.4g, %.4g) m: %.1f cycles, largest range %.4g, damage %.4g, "
                    "crack initiation after %.4g s (%.4g h) of this load\n",
                    k + 1, part, id, x.x(), x.y(), x.z(), n.damage.cycles, n.largest_range, d, time / d, time / d / 3600.0);
    else
      std::snprintf(line, sizeof line,
                    "  %zu. part %d element %d at (%.4g, %.4g, %.4g) m: %.1f cycles, largest range %.4g, no damage "
                    "(below the endurance limit)\n",
                    k + 1, part, id, x.x(), x.y(), x.z(), n.damage.cycles, n.largest_range);
    r << line;
  }
  return r.str();
}

void FatigueTracker::write_csv(const std::string& path, double time) const {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write the fatigue table '" + path + "'");
  f << "element,part,x,y,z,cycles,largest_range,damage,time_to_initiation_s\n";
  f.precision(10);
  for (size_t i = 0; i < cells_.size(); ++i) {
    const Vec3 x = centroid(cells_[i].element);
    const double d = damage_with_residue(i);
    f << element_id(cells_[i].element) << "," << m_.fatigue[cells_[i].def].part << "," << x.x() << "," << x.y() << ","
      << x.z() << "," << counts_[i].damage.cycles << "," << counts_[i].largest_range << "," << d << ","
      << (d > 0.0 ? time / d : std::numeric_limits<double>::infinity()) << "\n";
  }
}

void FatigueTracker::state(config::StateIO& io) {
  // Every counter's reversals in one list, with each cell's count; the rest per cell.
  const size_t n = cells_.size();
  std::vector<double> held, extreme(n), first(n), damage(n), cycles(n), largest(n);
  std::vector<int> count(n), direction(n), started(n);
  if (io.saving())
    for (size_t i = 0; i < n; ++i) {
      const auto& h = counts_[i].reversals.held();
      held.insert(held.end(), h.begin(), h.end());
      count[i] = static_cast<int>(h.size());
      const fatigue::TurningPoints& p = cells_[i].points;
      direction[i] = p.direction, started[i] = p.started ? 1 : 0, extreme[i] = p.extreme, first[i] = p.first;
      damage[i] = counts_[i].damage.damage, cycles[i] = counts_[i].damage.cycles, largest[i] = counts_[i].largest_range;
    }
  io.list("fatigue held reversals", held);
  io.array("fatigue held count", count);
  io.array("fatigue direction", direction);
  io.array("fatigue started", started);
  io.array("fatigue extreme", extreme);
  io.array("fatigue first", first);
  io.array("fatigue damage", damage);
  io.array("fatigue cycles", cycles);
  io.array("fatigue largest range", largest);
  if (io.saving()) return;
  size_t at = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(count[i]);
    if (count[i] < 0 || k > held.size() - at) throw config::CheckpointError("fatigue: the checkpoint's reversals do not add up");
    counts_[i].reversals.restore(std::vector<double>(held.begin() + static_cast<long>(at), held.begin() + static_cast<long>(at + k)));
    at += k;
    fatigue::TurningPoints& p = cells_[i].points;
    p.direction = static_cast<signed char>(direction[i] > 0 ? 1 : direction[i] < 0 ? -1 : 0);
    p.started = started[i] != 0, p.extreme = extreme[i], p.first = first[i];
    counts_[i].damage.damage = damage[i], counts_[i].damage.cycles = cycles[i], counts_[i].largest_range = largest[i];
  }
}

}  // namespace fe
