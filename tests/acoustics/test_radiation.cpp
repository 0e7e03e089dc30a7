// The radiation building blocks against closed forms (issue 35): the
// baffled circular piston (on-axis pressure, far-field directivity, radiated
// power) through the discretised Rayleigh integral; ERP of a rigid piston;
// the A-weighting against IEC 61672-1's table; the one-third-octave bands.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "acoustics/radiation.hpp"

namespace {

constexpr double kRho = 1.21, kC = 343.0;

// A piston of radius a in the plane z = 0, velocity amplitude u, in rings
// of width h and sectors of about h: k·h = 0.25 at the highest ka tested
// keeps the monopole sum within about 0.5 % of the integral.
std::vector<acoustics::Patch> piston(double a, double u, int rings) {
  std::vector<acoustics::Patch> out;
  const double h = a / rings;
  for (int i = 0; i < rings; ++i) {
    const double r0 = i * h, r1 = (i + 1) * h, rm = 0.5 * (r0 + r1);
    const int sectors = std::max(6, static_cast<int>(std::ceil(2.0 * M_PI * rm / h)));
    const double area = M_PI * (r1 * r1 - r0 * r0) / sectors;
    for (int j = 0; j < sectors; ++j) {
      const double phi = 2.0 * M_PI * (j + 0.5) / sectors;
      acoustics::Patch p;
      // The ring's centroid radius (2/3 (r1³ - r0³)/(r1² - r0²)), not its middle.
      const double rc = 2.0 / 3.0 * (r1 * r1 * r1 - r0 * r0 * r0) / (r1 * r1 - r0 * r0);
      p.x[0] = rc * std::cos(phi), p.x[1] = rc * std::sin(phi), p.x[2] = 0.0;
      p.area = area;
      p.vn = u;
      out.push_back(p);
    }
  }
  return out;
}

// The power through a far hemisphere of radius r: ∫ |p|²/(2 rho c) dS, an
// axisymmetric field (a ring per step in θ, 180 steps).
double hemisphere_power(const std::vector<acoustics::Patch>& patches, double omega, double r) {
  double power = 0.0;
  const int n = 180;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * 0.5 * M_PI / n;
    const double x[3] = {r * std::sin(th), 0.0, r * std::cos(th)};
    const double p = std::abs(acoustics::rayleigh_pressure(patches, x, omega, kRho, kC));
    power += p * p / (2.0 * kRho * kC) * 2.0 * M_PI * r * r * std::sin(th) * (0.5 * M_PI / n);
  }
  return power;
}

}  // namespace

// On the axis of a baffled piston: |p(z)| = 2 rho c u |sin(k/2 (sqrt(z² + a²) - z))|
// (Kinsler et al., Fundamentals of Acoustics, 7.4), near field and far.
TEST(Rayleigh, TheBaffledPistonsOnAxisPressureIsTheClosedForm) {
  const double a = 0.1, u = 0.01;
  for (double ka : {1.0, 5.0}) {
    const double k = ka / a, omega = k * kC;
    const auto patches = piston(a, u, static_cast<int>(std::ceil(ka / 0.25)) * 2);
    for (double z : {0.05, 0.1, 0.3, 1.0, 5.0}) {
      const double x[3] = {0.0, 0.0, z};
      const double want = 2.0 * kRho * kC * u * std::fabs(std::sin(0.5 * k * (std::sqrt(z * z + a * a) - z)));
      const double got = std::abs(acoustics::rayleigh_pressure(patches, x, omega, kRho, kC));
      // 1 % of the near field's largest pressure (2 rho c u): the on-axis
      // nulls of the near field are points where a relative error means nothing.
      EXPECT_NEAR(got, want, 0.01 * 2.0 * kRho * kC * u) << "ka " << ka << ", z " << z;
    }
  }
}

// In the far field the directivity is 2 J1(ka sin θ)/(ka sin θ), and the
// radiated power rho c pi a² u²/2 (1 - J1(2ka)/(ka)): the hemisphere's
// intensity integrated numerically.
TEST(Rayleigh, TheFarFieldsDirectivityAndPowerAreTheClosedForms) {
  const double a = 0.1, u = 0.01, r = 30.0;
  for (double ka : {0.5, 2.0, 5.0}) {
    const double k = ka / a, omega = k * kC;
    const auto patches = piston(a, u, static_cast<int>(std::ceil(ka / 0.25)) * 2);
    const double x0[3] = {0.0, 0.0, r};
    const double on_axis = std::abs(acoustics::rayleigh_pressure(patches, x0, omega, kRho, kC));
    for (double deg : {20.0, 40.0, 60.0}) {
      const double th = deg * M_PI / 180.0, s = ka * std::sin(th);
      const double x[3] = {r * std::sin(th), 0.0, r * std::cos(th)};
      const double want = std::fabs(2.0 * std::cyl_bessel_j(1, s) / s);
      EXPECT_NEAR(std::abs(acoustics::rayleigh_pressure(patches, x, omega, kRho, kC)) / on_axis, want, 0.01)
          << "ka " << ka << ", " << deg << " deg";
    }
    const double power = hemisphere_power(patches, omega, r);
    const double want = kRho * kC * M_PI * a * a * u * u / 2.0 * (1.0 - std::cyl_bessel_j(1, 2.0 * ka) / ka);
    EXPECT_NEAR(power, want, 0.02 * want) << "ka " << ka;
  }
}

// ERP is rho c A u²/2 for a rigid piston, whatever its frequency; the
// radiated power approaches it only far above ka = 1 (radiation efficiency
// 1 - J1(2ka)/(ka): 0.56 at ka 0.5, 0.99 at ka 10), the reason ERP is an
// upper bound and the sound power needs the efficiency.
TEST(Erp, ARigidPistonsErpIsRhoCAUSquaredAndItsPowerOnlyFarAboveKaOne) {
  const double a = 0.1, u = 0.01;
  const auto patches = piston(a, u, 80);  // k·h = 0.125 at ka 10
  const double erp = acoustics::equivalent_radiated_power(patches, kRho, kC);
  EXPECT_NEAR(erp, kRho * kC * M_PI * a * a * u * u / 2.0, 1e-12 * erp);
  for (double ka : {0.5, 10.0}) {
    const double efficiency = 1.0 - std::cyl_bessel_j(1, 2.0 * ka) / ka;
    const double power = hemisphere_power(patches, ka / a * kC, 60.0);
    EXPECT_NEAR(power / erp, efficiency, 0.02) << "ka " << ka;
  }
}

// IEC 61672-1 Table 3's A-weighting, rounded to 0.1 dB there, and given
// at the exact base-10 mid-band frequencies 1000·10^(n/10) that its nominal
// ones (31.5, 250, 16000 Hz ...) name.
TEST(AWeighting, MatchesTheStandardsTable) {
  const std::vector<std::pair<int, double>> table = {{-20, -70.4}, {-15, -39.4}, {-10, -19.1}, {-6, -8.6}, {0, 0.0},
                                                     {3, 1.2},     {6, 1.0},     {9, -1.1},    {10, -2.5}, {12, -6.6}};
  for (const auto& [n, db] : table) {
    const double f = 1000.0 * std::pow(10.0, n / 10.0);
    EXPECT_NEAR(acoustics::a_weighting_db(f), db, 0.05 + 1e-9) << f << " Hz";
  }
  EXPECT_NEAR(acoustics::a_weighting_db(1000.0), 0.0, 1e-3) << "A1000 = -2.000 dB normalises it to 0 at 1 kHz";
}

// The base-10 one-third octaves: 1000 · 10^(n/10), ten to a decade, each
// band's edges a factor 10^(1/10) apart; L_WA of equal band powers.
TEST(ThirdOctaves, BandsAreBaseTenAndTheWeightedLevelSumsThem) {
  const auto c = acoustics::third_octave_centres(100.0, 10000.0);
  ASSERT_EQ(c.size(), 21u);
  EXPECT_DOUBLE_EQ(c[10], 1000.0);
  EXPECT_NEAR(c[0], 100.0, 1e-9);
  EXPECT_NEAR(c[1], 125.89, 0.01);
  for (double f : c) EXPECT_NEAR(acoustics::band_upper_edge(f) / acoustics::band_lower_edge(f), std::pow(10.0, 0.1), 1e-12);
  // 1 mW in the 1 kHz band alone: 90 dB(A) (to the 0.0003 dB of A1000's
  // three decimals); in two bands, their weighted powers summed.
  EXPECT_NEAR(acoustics::a_weighted_power_level({1000.0}, {1e-3}), 90.0, 1e-3);
  const double two = acoustics::a_weighted_power_level({100.0, 1000.0}, {1e-3, 1e-3});
  const double w100 = std::pow(10.0, acoustics::a_weighting_db(100.0) / 10.0),
               w1000 = std::pow(10.0, acoustics::a_weighting_db(1000.0) / 10.0);
  EXPECT_NEAR(two, 10.0 * std::log10(1e9 * (w100 + w1000)), 1e-9);
}
