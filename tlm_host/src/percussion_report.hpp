// Post-processing of a percussion run, from its HDF5 results alone (so an
// old run can be evaluated again): blows, impact velocity and frequency,
// stroke, mean inlet pressure and flow, input power P_in = mean(p_in·Q_in),
// output power W·f with the blow energy W = ½·m·v_impact², efficiency, and
// peak pressures. Only whole cycles after `settle` seconds count.
// An optional low-pass filter (a Gaussian with the given −3 dB frequency,
// GSL's gsl_filter_gaussian) smooths pressures and flows first; the thesis
// evaluated at 500 Hz.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tlm {

struct ReportSettings {
  std::string piston = "piston";  // HammerPistonQ component: x, v, F_contact
  double piston_mass = 0.0;       // kg, for W
  std::string inlet_p, inlet_q;   // dataset names
  std::vector<std::pair<std::string, std::string>> peaks;  // label, dataset
  double settle = 0.3;            // s
  double lowpass = 0.0;           // Hz; 0: none
  double v_blow = 1.0;            // m/s: slower contacts are not blows
};

struct PercussionFigures {
  int blows = 0;
  double frequency = 0, v_impact = 0, v_impact_sd = 0, stroke = 0;
  double p_in = 0, q_in = 0, P_in = 0, W = 0, P_out = 0, efficiency = 0;
  std::vector<std::pair<std::string, double>> peaks;  // label, Pa
  std::vector<double> impact_times;                   // s, the blows evaluated
};

// Throws std::runtime_error if fewer than 3 blows follow the settle time.
PercussionFigures evaluate_percussion(const std::string& h5_path, const ReportSettings& s);
std::string format_figures(const PercussionFigures& f);
// The same figures in SI units as one JSON object, for scripts.
std::string figures_json(const PercussionFigures& f);

// Gaussian low-pass of uniformly sampled data (dt apart) at cutoff_hz (−3 dB).
std::vector<double> lowpass_gaussian(const std::vector<double>& x, double dt, double cutoff_hz);

}  // namespace tlm
