#include <cmath>
#include <limits>
#include <stdexcept>

#include "fatigue/damage.hpp"
#include "fatigue/rainflow.hpp"

namespace fatigue {

std::vector<double> reversals(const std::vector<double>& history, double gate) {
  // The streaming counter's own turning points, collected.
  std::vector<double> out;
  TurningPoints points;
  double r;
  for (double x : history)
    if (points.next(x, gate, &r)) out.push_back(r);
  if (points.last(&r)) out.push_back(r);
  return out;
}

std::vector<Cycle> rainflow_whole(const std::vector<double>& history, double gate) {
  std::vector<Cycle> cycles;
  auto emit = [&](double a, double b, double count) {
    const double hi = std::max(a, b), lo = std::min(a, b);
    cycles.push_back({hi - lo, 0.5 * (hi + lo), count});
  };
  std::vector<double> s;
  for (double r : reversals(history, gate)) {
    s.push_back(r);
    // Four points s1..s4: the inner range s2-s3 is a full cycle when the
    // ranges on both sides are at least as large.
    while (s.size() >= 4) {
      const size_t n = s.size();
      const double inner = std::fabs(s[n - 2] - s[n - 3]);
      if (inner <= std::fabs(s[n - 3] - s[n - 4]) && inner <= std::fabs(s[n - 1] - s[n - 2])) {
        emit(s[n - 3], s[n - 2], 1.0);
        s.erase(s.begin() + static_cast<long>(n - 3), s.begin() + static_cast<long>(n - 1));
      } else {
        break;
      }
    }
  }
  for (size_t i = 1; i < s.size(); ++i) emit(s[i - 1], s[i], 0.5);
  return cycles;
}

std::vector<Cycle> rainflow(const std::vector<double>& history, double gate) {
  std::vector<Cycle> cycles;
  RainflowCounter counter(gate);
  auto sink = [&](const Cycle& c) { cycles.push_back(c); };
  for (double x : history) counter.add(x, sink);
  counter.finish(sink);
  return cycles;
}

std::string SnCurve::check() const {
  if (!(sa_ref > 0.0) || !std::isfinite(sa_ref)) return "the reference amplitude must be positive";
  if (!(n_ref >= 1.0) || !std::isfinite(n_ref)) return "the reference cycle count must be at least 1";
  if (!(m > 0.0) || !std::isfinite(m)) return "the slope m must be positive";
  if (!(endurance >= 0.0) || !std::isfinite(endurance)) return "the endurance limit must be 0 or more";
  return "";
}

double SnCurve::cycles_to_failure(double sa) const {
  const double inf = std::numeric_limits<double>::infinity();
  if (!(sa > 0.0)) return inf;
  if (std::isinf(sa)) return 0.0;
  if (sa > endurance || endurance == 0.0) return n_ref * std::pow(sa_ref / sa, m);
  if (!haibach) return inf;
  // Below the knee the curve goes on from its point there with slope 2m - 1.
  const double n_knee = n_ref * std::pow(sa_ref / endurance, m);
  return n_knee * std::pow(endurance / sa, 2.0 * m - 1.0);
}

MeanStress mean_stress_from_name(const std::string& name) {
  if (name == "none") return MeanStress::None;
  if (name == "goodman") return MeanStress::Goodman;
  if (name == "gerber") return MeanStress::Gerber;
  if (name == "swt") return MeanStress::Swt;
  throw std::invalid_argument("mean-stress correction '" + name + "': expected none, goodman, gerber or swt");
}

const char* to_string(MeanStress m) {
  switch (m) {
    case MeanStress::None: return "none";
    case MeanStress::Goodman: return "goodman";
    case MeanStress::Gerber: return "gerber";
    case MeanStress::Swt: return "swt";
  }
  return "?";
}

double equivalent_amplitude(double sa, double sm, MeanStress how, double su) {
  const double inf = std::numeric_limits<double>::infinity();
  switch (how) {
    case MeanStress::None: return sa;
    case MeanStress::Goodman:  // Sa / (1 - Sm/Su), tensile means only
      if (sm <= 0.0) return sa;
      return sm >= su ? inf : sa / (1.0 - sm / su);
    case MeanStress::Gerber:  // Sa / (1 - (Sm/Su)^2), tensile means only
      if (sm <= 0.0) return sa;
      return sm >= su ? inf : sa / (1.0 - (sm / su) * (sm / su));
    case MeanStress::Swt: {  // sqrt(Smax * Sa): no damage without tension
      const double smax = sm + sa;
      return smax <= 0.0 ? 0.0 : std::sqrt(smax * sa);
    }
  }
  return sa;
}

void Damage::add(const Cycle& c) {
  cycles += c.count;
  const double sa = equivalent_amplitude(0.5 * c.range, c.mean, mean, su);
  const double n = curve.cycles_to_failure(sa);
  if (std::isinf(n)) return;
  damage += n > 0.0 ? c.count / n : std::numeric_limits<double>::infinity();
}

}  // namespace fatigue
