#include "acoustics/radiation.hpp"

#include <cmath>
#include <stdexcept>

namespace acoustics {

double equivalent_radiated_power(const std::vector<Patch>& patches, double rho, double c) {
  double sum = 0.0;
  for (const Patch& p : patches) sum += p.area * std::norm(p.vn);
  return 0.5 * rho * c * sum;
}

std::complex<double> rayleigh_pressure(const std::vector<Patch>& patches, const double x[3], double omega, double rho,
                                       double c) {
  const double k = omega / c;
  std::complex<double> sum = 0.0;
  for (const Patch& p : patches) {
    const double dx = x[0] - p.x[0], dy = x[1] - p.x[1], dz = x[2] - p.x[2];
    const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(r > 0.0)) throw std::invalid_argument("rayleigh_pressure: a field point on a patch's centre");
    sum += p.vn * p.area * std::exp(std::complex<double>(0.0, -k * r)) / r;
  }
  return std::complex<double>(0.0, omega * rho / (2.0 * M_PI)) * sum;
}

double a_weighting_db(double f) {
  // IEC 61672-1, Annex E: the poles at 20.6, 107.7, 737.9 and 12194 Hz;
  // A1000 = -2.000 dB normalises it to 0 dB at 1 kHz.
  const double f2 = f * f;
  const double p1 = 20.598997 * 20.598997, p2 = 107.65265 * 107.65265, p3 = 737.86223 * 737.86223,
               p4 = 12194.217 * 12194.217;
  const double ra = p4 * f2 * f2 / ((f2 + p1) * std::sqrt((f2 + p2) * (f2 + p3)) * (f2 + p4));
  return 20.0 * std::log10(ra) + 2.000;
}

std::vector<double> third_octave_centres(double f_lo, double f_hi) {
  if (!(f_lo > 0.0) || !(f_hi >= f_lo)) throw std::invalid_argument("third_octave_centres: need 0 < f_lo <= f_hi");
  std::vector<double> out;
  const int n0 = static_cast<int>(std::lround(10.0 * std::log10(f_lo / 1000.0)));
  const int n1 = static_cast<int>(std::lround(10.0 * std::log10(f_hi / 1000.0)));
  for (int n = n0; n <= n1; ++n) out.push_back(1000.0 * std::pow(10.0, n / 10.0));
  return out;
}

double band_lower_edge(double centre) { return centre * std::pow(10.0, -1.0 / 20.0); }
double band_upper_edge(double centre) { return centre * std::pow(10.0, 1.0 / 20.0); }

double a_weighted_power_level(const std::vector<double>& centres, const std::vector<double>& power_w) {
  if (centres.size() != power_w.size()) throw std::invalid_argument("a_weighted_power_level: one power per band");
  double sum = 0.0;
  for (size_t i = 0; i < centres.size(); ++i) sum += power_w[i] * std::pow(10.0, a_weighting_db(centres[i]) / 10.0);
  return 10.0 * std::log10(sum / 1e-12);
}

}  // namespace acoustics
