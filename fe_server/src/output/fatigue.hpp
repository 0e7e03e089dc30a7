// Fatigue counted while the FE run goes (*PCS_FATIGUE_PART, docs/fatigue.md):
// per element of the parts named, an equivalent stress from the element's
// stress after every FE step, times the part's notch factor, fed to its own
// streaming rainflow counter (fatigue/rainflow.hpp); each closed cycle's
// Miner damage is summed at once. Memory per element (the reversals not yet
// closed), never per step.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/checkpoint.hpp"
#include "fatigue/damage.hpp"
#include "fatigue/rainflow.hpp"
#include "model/model.hpp"
#include "solver/solver.hpp"

namespace fe {

// The equivalent stresses a part's fatigue may use, of a Voigt stress (xx,
// yy, zz, xy, yz, zx; axisymmetric: rr, yy, θθ, ry, 0, 0):
// von Mises signed by the hydrostatic stress (a compressive wave counts as
// compression, so a blow's pulse and its tensile reflection make one cycle of
// their full range), and the principal stress of largest magnitude, signed
// (a crack opens normal to it).
double signed_von_mises(const Eigen::Matrix<double, 6, 1>& s);
double largest_principal(const Eigen::Matrix<double, 6, 1>& s, bool axisymmetric);

class FatigueTracker {
 public:
  // fe_dt: the FE step, for each card's sampling interval DT.
  FatigueTracker(const Model& m, double fe_dt);
  bool empty() const { return cells_.empty(); }
  // After every FE step: each tracked element's stress, one sample (at its
  // card's interval).
  void sample(const Solver& s);
  // Damage so far of every element of the field output (the axisymmetric
  // elements, else the solids, in the model's order), the residue's half
  // cycles included; 0 for elements of parts without a fatigue card.
  std::vector<double> damage_field() const;
  // The hot spots: the `top` elements with the most damage, with part,
  // element id, centroid, cycles counted, largest range, damage, and the
  // time to crack initiation at this run's rate (time / damage).
  std::string report(double time, size_t top = 5) const;
  // Every tracked element, a CSV row each (element, part, centroid, cycles,
  // largest range, damage, time to initiation).
  void write_csv(const std::string& path, double time) const;
  void state(config::StateIO& io);

 private:
  // Hot, every sample: the element, its part's card and its turning points
  // (32 bytes); cold, at a reversal only: the reversals held, the damage.
  struct Cell {
    uint32_t element = 0;  // index into m.axis (axisymmetric) or m.solids
    uint32_t def = 0;      // into m.fatigue
    fatigue::TurningPoints points;
  };
  struct Count {
    fatigue::ReversalCounter reversals;
    fatigue::Damage damage;
    double largest_range = 0.0;
  };
  // The cell's damage with its residue counted as half cycles (a copy finishes).
  double damage_with_residue(size_t i) const;
  Vec3 centroid(size_t element) const;
  int element_id(size_t element) const;
  const Model& m_;
  bool axisymmetric_ = false;
  std::vector<Cell> cells_;
  std::vector<Count> counts_;  // per cell
  std::vector<long> every_;    // per card: FE steps between samples
  std::vector<char> due_;      // per card: sampled at this step
};

}  // namespace fe
