// Sound radiated by a vibrating surface (issue 35, radiated noise): the
// building blocks the housing's noise will be computed with, each checked
// against a closed form in tests/acoustics.
//
// - Equivalent radiated power (ERP, as LS-DYNA defines it): rho c sum A v_n²,
//   the power the surface would radiate if every patch radiated as a plane
//   wave (radiation efficiency 1): an upper bound above the coincidence
//   frequency, far too high below it.
// - The Rayleigh integral: the pressure of a surface in a rigid baffle, each
//   patch a monopole of strength v_n A doubled by the baffle,
//   p(x) = (i omega rho / 2 pi) sum v_n A exp(-i k R) / R (time factor
//   exp(i omega t)). Exact for a plane surface in an infinite baffle; for a
//   housing it is the estimate of the ISO 3744 positions.
// - A-weighting (IEC 61672-1) and the one-third-octave bands (IEC 61260-1,
//   base 10), for L_WA and its spectrum.
#pragma once

#include <complex>
#include <vector>

namespace acoustics {

struct Patch {
  double x[3] = {0, 0, 0};  // centre, m
  double area = 0.0;        // m²
  std::complex<double> vn;  // normal velocity amplitude, m/s (complex: its phase)
};

// rho c sum A |v_n|² / 2 (amplitudes: the time average of a harmonic
// motion), W. For a real-valued instant velocity v, pass v·sqrt(2) to get
// rho c A v².
double equivalent_radiated_power(const std::vector<Patch>& patches, double rho, double c);

// The Rayleigh integral at point x for angular frequency omega: the complex
// pressure amplitude, Pa. The patches should be small against the
// wavelength (k·size < 0.5 keeps the discretisation error under about 1 %).
std::complex<double> rayleigh_pressure(const std::vector<Patch>& patches, const double x[3], double omega, double rho,
                                       double c);

// The A-weighting of IEC 61672-1 at frequency f, dB (0 at 1 kHz).
double a_weighting_db(double f);

// The exact mid-band frequencies of the one-third-octave bands (IEC 61260-1,
// base 10: 1000 · 10^(n/10)) from the band holding f_lo to the one holding
// f_hi, and a band's edges (the mid-band times 10^(∓1/20)).
std::vector<double> third_octave_centres(double f_lo, double f_hi);
double band_lower_edge(double centre);
double band_upper_edge(double centre);

// The A-weighted level of band powers (W, one per centre), dB re 1 pW:
// L_WA = 10 lg(sum P_i 10^(A_i/10) / 1e-12).
double a_weighted_power_level(const std::vector<double>& centres, const std::vector<double>& power_w);

}  // namespace acoustics
