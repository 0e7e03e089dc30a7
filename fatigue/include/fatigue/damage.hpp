// Damage from counted cycles: an S-N curve (Basquin with an endurance
// limit), a mean-stress correction, and Palmgren-Miner summation.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "fatigue/rainflow.hpp"

namespace fatigue {

// Basquin: N(Sa) = n_ref * (sa_ref / Sa)^m for an amplitude Sa above the
// endurance limit, no damage at or below it (endurance 0: none). With
// haibach, below the limit the curve goes on with slope 2m - 1 (Haibach's
// extension for variable amplitude: small cycles damage once large ones
// have started a crack) instead of stopping. Stresses in any one unit.
struct SnCurve {
  double sa_ref = 0.0;  // amplitude at n_ref cycles
  double n_ref = 0.0;   // cycles at sa_ref
  double m = 0.0;       // slope (Basquin's exponent, as 1/|b|); steel about 5-12
  double endurance = 0.0;
  bool haibach = false;
  // Cycles to failure at the (fully reversed) amplitude sa; infinity where
  // the curve gives no damage.
  double cycles_to_failure(double sa) const;
  // "" when valid, else what is wrong (for an error message).
  std::string check() const;
};

// The mean-stress correction: the fully reversed amplitude that does the
// damage of amplitude sa at mean sm. Su: the ultimate strength (Goodman,
// Gerber). Compressive means get no credit (the amplitude is kept), the
// usual and conservative choice; SWT gives no damage where the largest
// stress is not tensile.
enum class MeanStress { None, Goodman, Gerber, Swt };
MeanStress mean_stress_from_name(const std::string& name);  // throws std::invalid_argument naming the choices
const char* to_string(MeanStress m);
// Equivalent amplitude; infinity for a mean at or beyond Su (Goodman, Gerber):
// a cycle that fails at once.
double equivalent_amplitude(double sa, double sm, MeanStress how, double su);

// Palmgren-Miner: D = sum of count / N over the cycles.
struct Damage {
  SnCurve curve;
  MeanStress mean = MeanStress::None;
  double su = 0.0;
  double damage = 0.0;
  double cycles = 0.0;  // counted, half cycles as 0.5
  void operator()(const Cycle& c) { add(c); }
  void add(const Cycle& c);
};

}  // namespace fatigue
