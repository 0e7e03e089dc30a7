// The model's own queries: node lookup, mass, relaxation, a material's
// hardening curve, a load curve's value and a segment's area and corner
// shares (model.hpp).
#include "model/model.hpp"

#include <algorithm>

namespace fe {

using config::InputError;

int Model::index_of(int node_id, const config::SourceLocation& where) const {
  auto it = node_index.find(node_id);
  if (it == node_index.end()) throw InputError(where, "node " + std::to_string(node_id) + " is not defined in *NODE");
  return it->second;
}

double Model::total_mass() const {
  double m = 0;
  for (double mi : mass) m += mi;
  return m;
}

bool Model::relaxes() const {
  if (relaxation.idrflg) return true;
  for (const auto& [id, c] : curves)
    if (c.sidr >= 1) return true;
  return false;
}

double Material::yield_stress(double ep, double* slope) const {
  if (hardening_strain.empty()) {
    *slope = beta * plastic_modulus;
    return yield + beta * plastic_modulus * ep;
  }
  const auto& a = hardening_strain;
  const auto& o = hardening_stress;
  size_t k = static_cast<size_t>(std::upper_bound(a.begin(), a.end(), ep) - a.begin());
  k = std::clamp<size_t>(k, 1, a.size() - 1);  // the first or last segment beyond the ends
  *slope = (o[k] - o[k - 1]) / (a[k] - a[k - 1]);
  return o[k - 1] + *slope * (ep - a[k - 1]);
}

double Curve::value(double t) const {
  const double x = (t - offa) / sfa;
  if (x <= a.front()) return sfo * o.front() + offo;
  if (x >= a.back()) return sfo * o.back() + offo;
  const size_t k = static_cast<size_t>(std::upper_bound(a.begin(), a.end(), x) - a.begin());
  const double w = (x - a[k - 1]) / (a[k] - a[k - 1]);
  return sfo * ((1.0 - w) * o[k - 1] + w * o[k]) + offo;
}

Vec3 segment_area_vector(const Segment& s, const std::vector<Vec3>& x) {
  if (s.line()) {
    // The ring a 2D line segment sweeps about the y axis: 2π·r̄·L along the
    // outward normal (to the right of n0 → n1), r̄ the mean radius (Pappus).
    const Vec3& a = x[static_cast<size_t>(s.n[0])];
    const Vec3& b = x[static_cast<size_t>(s.n[1])];
    const Vec3 d = b - a;
    return 2.0 * 3.141592653589793 * 0.5 * (a.x() + b.x()) * Vec3(d.y(), -d.x(), 0.0);
  }
  // Half the cross product of the diagonals: exact for a planar quad, the
  // mean area vector for a warped one, and for a triangle (n4 = n3) equal to
  // ½(x2 − x1) × (x3 − x1).
  const Vec3& a = x[static_cast<size_t>(s.n[0])];
  const Vec3& b = x[static_cast<size_t>(s.n[1])];
  const Vec3& c = x[static_cast<size_t>(s.n[2])];
  const Vec3& d = x[static_cast<size_t>(s.n[3])];
  return 0.5 * (c - a).cross(d - b);
}

void segment_corner_weights(const Segment& s, const std::vector<Vec3>& x, double w[4]) {
  w[0] = w[1] = w[2] = w[3] = 0.0;
  if (s.line()) {
    const double ra = x[static_cast<size_t>(s.n[0])].x(), rb = x[static_cast<size_t>(s.n[1])].x();
    const double sum = ra + rb;
    if (!(sum > 0.0)) {  // a line on the axis sweeps no area: any split is exact
      w[0] = w[1] = 0.5;
      return;
    }
    w[0] = (2.0 * ra + rb) / (3.0 * sum);
    w[1] = (ra + 2.0 * rb) / (3.0 * sum);
    return;
  }
  const int nc = s.corners();
  for (int k = 0; k < nc; ++k) w[k] = 1.0 / nc;
}

}  // namespace fe
