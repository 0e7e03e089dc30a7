// The primary stress pulse at a tool's gauge as the scene tests measure it,
// from the down-going stress σ_d = (σ + ρ·c0·v)/2 (1D wave relations: the
// section's force over its area and the cut's mean velocity).
#pragma once

#include <cstddef>
#include <vector>

namespace testing_support {

struct StressPulse {
  bool whole = false;       // the record holds the pulse's end
  double length = 0.0;      // s, between the half-level crossings
  double plateau = 0.0;     // Pa, the mean over the pulse's middle half
  int plateau_samples = 0;  // samples in that mean
  double energy = 0.0;      // J, W = (A·c0/E)·∫σ_d² over the pulse
};

// t, sd: times and σ_d from just before the pulse; level: the 1D estimate
// (compression negative). The pulse starts where σ_d first passes half the
// level and ends where it comes back, at least min_length later (the front's
// ringing crosses the half level too). W integrates tail_samples beyond the
// end, where the pulse's last decay lies.
inline StressPulse primary_stress_pulse(const std::vector<double>& t, const std::vector<double>& sd, double level,
                                        double min_length, size_t tail_samples, double area, double c0, double E) {
  StressPulse p;
  size_t rise = 0;
  while (rise < sd.size() && sd[rise] > 0.5 * level) ++rise;
  size_t fall = rise;
  while (fall < sd.size() && !(sd[fall] > 0.5 * level && t[fall] > t[rise] + min_length)) ++fall;
  if (fall >= sd.size()) return p;
  p.whole = true;
  p.length = t[fall] - t[rise];
  double sum = 0.0;
  for (size_t i = rise; i < fall; ++i)
    if (t[i] > t[rise] + 0.25 * p.length && t[i] < t[fall] - 0.25 * p.length) sum += sd[i], ++p.plateau_samples;
  p.plateau = p.plateau_samples ? sum / p.plateau_samples : 0.0;
  for (size_t i = rise; i + 1 < fall + tail_samples && i + 1 < sd.size(); ++i)
    p.energy += area * c0 / E * 0.5 * (sd[i] * sd[i] + sd[i + 1] * sd[i + 1]) * (t[i + 1] - t[i]);
  return p;
}

}  // namespace testing_support
