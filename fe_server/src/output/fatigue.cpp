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

double signed_von_mises(const Eigen::Matrix<double, 6, 1>& s) {
  const double vm = von_mises(s);
  return s(0) + s(1) + s(2) < 0.0 ? -vm : vm;
}

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

FatigueTracker::FatigueTracker(const Model& m) : m_(m), axisymmetric_(m.solids.empty() && !m.axis.empty()) {
  for (size_t k = 0; k < m.fatigue.size(); ++k) {
    const FatigueDef& d = m.fatigue[k];
    const size_t n = axisymmetric_ ? m.axis.size() : m.solids.size();
    for (size_t e = 0; e < n; ++e) {
      const int part = axisymmetric_ ? m.axis[e].part : m.solids[e].part;
      if (part != d.part) continue;
      Cell c;
      c.element = e;
      c.def = k;
      c.counter = fatigue::RainflowCounter(d.gate);
      c.damage = fatigue::Damage{d.curve, d.mean, d.su, 0.0, 0.0};
      cells_.push_back(std::move(c));
    }
  }
}

void FatigueTracker::sample(const Solver& s) {
  for (Cell& c : cells_) {
    const auto& sg = axisymmetric_ ? s.axi_stress(c.element) : s.stress(c.element);
    const FatigueDef& d = m_.fatigue[c.def];
    const double eq = d.kf * (d.stress == 0 ? signed_von_mises(sg) : largest_principal(sg, axisymmetric_));
    c.counter.add(eq, [&c](const fatigue::Cycle& y) {
      c.damage.add(y);
      c.largest_range = std::max(c.largest_range, y.range);
    });
  }
}

double FatigueTracker::damage_with_residue(const Cell& c) const {
  fatigue::RainflowCounter copy = c.counter;
  fatigue::Damage d = c.damage;
  copy.finish([&d](const fatigue::Cycle& y) { d.add(y); });
  return d.damage;
}

std::vector<double> FatigueTracker::damage_field() const {
  std::vector<double> out(axisymmetric_ ? m_.axis.size() : m_.solids.size(), 0.0);
  for (const Cell& c : cells_) out[c.element] = damage_with_residue(c);
  return out;
}

Vec3 FatigueTracker::centroid(const Cell& c) const {
  Vec3 x = Vec3::Zero();
  if (axisymmetric_) {
    for (int k = 0; k < 4; ++k) x += m_.x0[static_cast<size_t>(m_.axis[c.element].n[k])] / 4.0;
  } else {
    for (int k = 0; k < 8; ++k) x += m_.x0[static_cast<size_t>(m_.solids[c.element].n[k])] / 8.0;
  }
  return x;
}

std::string FatigueTracker::report(double time, size_t top) const {
  std::vector<std::pair<double, const Cell*>> ranked;
  for (const Cell& c : cells_) ranked.emplace_back(damage_with_residue(c), &c);
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::ostringstream r;
  r << "fatigue after " << time << " s (" << cells_.size() << " elements counted; the mesh's stress"
    << (std::any_of(m_.fatigue.begin(), m_.fatigue.end(), [](const FatigueDef& d) { return d.kf != 1.0; })
            ? " times each part's notch factor"
            : ": fillets finer than the mesh are not resolved, a notch factor KF raises them")
    << "):\n";
  char line[320];
  for (size_t i = 0; i < std::min(top, ranked.size()); ++i) {
    const Cell& c = *ranked[i].second;
    const Vec3 x = centroid(c);
    const double d = ranked[i].first;
    const int id = axisymmetric_ ? m_.axis[c.element].id : m_.solids[c.element].id;
    if (d > 0.0)
      std::snprintf(line, sizeof line,
                    "  %zu. part %d element %d at (%.4g, %.4g, %.4g) m: %.1f cycles, largest range %.4g, damage %.4g, "
                    "crack initiation after %.4g s (%.4g h) of this load\n",
                    i + 1, m_.fatigue[c.def].part, id, x.x(), x.y(), x.z(), c.damage.cycles, c.largest_range, d, time / d,
                    time / d / 3600.0);
    else
      std::snprintf(line, sizeof line,
                    "  %zu. part %d element %d at (%.4g, %.4g, %.4g) m: %.1f cycles, largest range %.4g, no damage "
                    "(below the endurance limit)\n",
                    i + 1, m_.fatigue[c.def].part, id, x.x(), x.y(), x.z(), c.damage.cycles, c.largest_range);
    r << line;
  }
  return r.str();
}

void FatigueTracker::write_csv(const std::string& path, double time) const {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write the fatigue table '" + path + "'");
  f << "element,part,x,y,z,cycles,largest_range,damage,time_to_initiation_s\n";
  f.precision(10);
  for (const Cell& c : cells_) {
    const Vec3 x = centroid(c);
    const double d = damage_with_residue(c);
    f << (axisymmetric_ ? m_.axis[c.element].id : m_.solids[c.element].id) << "," << m_.fatigue[c.def].part << "," << x.x() << ","
      << x.y() << "," << x.z() << "," << c.damage.cycles << "," << c.largest_range << "," << d << ","
      << (d > 0.0 ? time / d : std::numeric_limits<double>::infinity()) << "\n";
  }
}

void FatigueTracker::state(config::StateIO& io) {
  // Every counter's reversals in one list, with each cell's count; the rest per cell.
  const size_t n = cells_.size();
  std::vector<double> held, extreme(n), damage(n), cycles(n), largest(n);
  std::vector<int> count(n), direction(n), started(n);
  if (io.saving())
    for (size_t i = 0; i < n; ++i) {
      const Cell& c = cells_[i];
      const auto& h = c.counter.held_reversals();
      held.insert(held.end(), h.begin(), h.end());
      count[i] = static_cast<int>(h.size());
      direction[i] = c.counter.direction();
      extreme[i] = c.counter.extreme();
      started[i] = c.counter.started() ? 1 : 0;
      damage[i] = c.damage.damage;
      cycles[i] = c.damage.cycles;
      largest[i] = c.largest_range;
    }
  io.list("fatigue held reversals", held);
  io.array("fatigue held count", count);
  io.array("fatigue direction", direction);
  io.array("fatigue extreme", extreme);
  io.array("fatigue started", started);
  io.array("fatigue damage", damage);
  io.array("fatigue cycles", cycles);
  io.array("fatigue largest range", largest);
  if (io.saving()) return;
  size_t at = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(count[i]);
    if (k > held.size() - at) throw config::CheckpointError("fatigue: the checkpoint's reversals do not add up");
    cells_[i].counter.restore(std::vector<double>(held.begin() + static_cast<long>(at), held.begin() + static_cast<long>(at + k)),
                              direction[i], extreme[i], started[i] != 0);
    at += k;
    cells_[i].damage.damage = damage[i];
    cells_[i].damage.cycles = cycles[i];
    cells_[i].largest_range = largest[i];
  }
}

}  // namespace fe
