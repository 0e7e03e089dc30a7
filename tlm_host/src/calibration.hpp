// Calibration: fit named parameters of a model to named targets of its
// percussion report (measured flow, frequency, pressure ...), over one or
// more running conditions, by nonlinear least squares (GSL's trust-region
// solver, Levenberg–Marquardt steps).
//
// Each residual is relative, (simulated − target) / |target|, so a flow in
// m³/s and a frequency in Hz weigh alike. Each parameter is fitted as
// ln(value / start): positive by construction (areas, discharge
// coefficients, pressures, masses), and a step of the same size means the
// same relative change for every parameter. The Jacobian is a forward
// difference of one model run per parameter at a relative step of 1 %:
// a percussion run's figures are sampled on the logged time grid and over
// whole blows, so they are not smooth below ~0.01 %, and 1 % stays well
// above that while still resolving the local slope.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "model.hpp"
#include "percussion_report.hpp"

namespace tlm {

struct FitCondition {
  std::string name;                    // as targets name it
  std::vector<std::string> overrides;  // "comp.param=value", applied after the common ones
};

struct FitTarget {
  std::string condition;  // a FitCondition's name
  std::string figure;     // see fit_figure_names()
  double value = 0.0;     // SI
};

struct FitParameter {
  std::string name;    // "comp.param"
  double start = 0.0;  // > 0
  // Optional bounds (lo < start < hi, lo ≥ 0): a discharge coefficient has no
  // meaning above 1, and a fit that wanders there has found no design. With
  // bounds the fitted variable is x with value = lo + (hi − lo)·(1 + tanh x)/2,
  // so every trial stays inside; without, value = start·e^x.
  bool bounded = false;
  double lo = 0.0, hi = 0.0;
  double value(double x) const;
  double x_start() const;
};

struct FitProblem {
  std::string model_path;
  std::vector<std::string> common_overrides;  // every run's --set
  std::vector<FitCondition> conditions;
  std::vector<FitTarget> targets;
  std::vector<FitParameter> parameters;
  int max_iterations = 30;
  double tolerance = 0.01;  // every |relative residual| at most this for "targets met"
};

struct FitResult {
  std::vector<double> fitted;               // per parameter
  std::vector<double> simulated;            // per target, at the fitted values (SI)
  std::vector<double> residual;             // per target, relative
  int iterations = 0, runs = 0, failed_runs = 0;
  bool targets_met = false;                 // every |residual| ≤ tolerance
  // Non-empty when the targets do not determine every parameter (the
  // Jacobian at the solution is rank-deficient): says which, and the fit is
  // then no answer even with every target met.
  std::string unresolved;
  std::string stop_reason;  // the solver's (converged on step, gradient or cost; or why not)
  bool succeeded() const { return targets_met && unresolved.empty(); }
};

// One run of `model` with `overrides` applied in order (as --set), its
// results in `h5` (overwritten), and its percussion report.
PercussionFigures run_percussion(const ModelSpec& model, const std::vector<std::string>& overrides,
                                 const std::string& h5);

// The figures a target may name, with their SI units ("frequency", "Hz"), ...
const std::vector<std::pair<std::string, std::string>>& fit_figure_names();

// "80l/min", "150bar", "20Hz", "78mm", "12kW", or a plain SI number → SI.
// Throws std::invalid_argument naming the text.
double parse_fit_value(const std::string& text);

// "name", "name=start", "name:lo..hi" or "name=start:lo..hi" → FitParameter;
// a missing start comes from the model file (which must then set it to a
// positive number).
FitParameter parse_fit_parameter(const std::string& text, const ModelSpec& model);

// One percussion figure from a report by name (throws for an unknown name).
double fit_figure(const PercussionFigures& f, const std::string& name);

// Reads the problem's model and checks every name before the first run:
// conditions exist, targets' figures exist, parameters are numeric and
// positive, at least as many targets as parameters. Throws
// std::invalid_argument with what to change.
void check_fit_problem(const FitProblem& p);

// Runs the fit. `progress` (may be empty) gets one line per iteration.
// Throws config::StopRequested at a stop signal, std::runtime_error when a
// run at the start values fails.
FitResult run_fit(const FitProblem& p, const std::function<void(const std::string&)>& progress);

// The table users read: parameters (start, fitted, change) and targets
// (wanted, got, residual), then the --set lines to use the fit.
std::string format_fit(const FitProblem& p, const FitResult& r);

}  // namespace tlm
