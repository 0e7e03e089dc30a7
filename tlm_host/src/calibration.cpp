#include "calibration.hpp"

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>
#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "config/stop_signal.hpp"

namespace tlm {

namespace {

// A report figure: name, unit, getter.
struct FigureDef {
  const char* name;
  const char* unit;
  double PercussionFigures::*member;
};

const FigureDef kFigures[] = {
    {"frequency", "Hz", &PercussionFigures::frequency}, {"v_impact", "m/s", &PercussionFigures::v_impact},
    {"stroke", "m", &PercussionFigures::stroke},        {"p_in", "Pa", &PercussionFigures::p_in},
    {"q_in", "m3/s", &PercussionFigures::q_in},         {"P_in", "W", &PercussionFigures::P_in},
    {"W", "J", &PercussionFigures::W},                  {"P_out", "W", &PercussionFigures::P_out},
    {"efficiency", "1", &PercussionFigures::efficiency},
};

// The unit suffixes a target value may carry, as factors to SI. Bar is
// gauge-free: the report's pressures are absolute, and so is a target.
const std::map<std::string, double>& unit_factors() {
  static const std::map<std::string, double> u = {
      {"", 1.0},       {"Hz", 1.0},       {"m/s", 1.0},    {"m", 1.0},     {"mm", 1e-3},
      {"Pa", 1.0},     {"kPa", 1e3},      {"MPa", 1e6},    {"bar", 1e5},   {"m3/s", 1.0},
      {"l/min", 1e-3 / 60.0},             {"l/s", 1e-3},   {"J", 1.0},     {"W", 1.0},
      {"kW", 1e3},     {"%", 1e-2},
  };
  return u;
}

std::string short_number(double v) {
  std::ostringstream o;
  o << std::setprecision(6) << v;
  return o.str();
}

// Where a parameter's value goes in a run: "comp.param=value" with every
// digit a double carries, so the run uses the value the solver chose.
std::string assignment(const std::string& name, double value) {
  std::ostringstream o;
  o << name << "=" << std::setprecision(17) << value;
  return o.str();
}

class TempFolder {
 public:
  TempFolder() {
    const char* base = std::getenv("TMPDIR");
    std::string templ = std::string(base && *base ? base : "/tmp") + "/tlm_fit.XXXXXX";
    if (!mkdtemp(templ.data())) throw std::runtime_error("cannot make a temporary folder under " + templ);
    path_ = templ;
  }
  ~TempFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

// Everything the solver's callbacks need.
struct Evaluator {
  const FitProblem& problem;
  const ModelSpec model;  // read once; every run starts from a copy
  TempFolder folder;
  int runs = 0, failed_runs = 0;
  std::string last_failure;

  // Each target's simulated figure at parameter values p (SI): every
  // condition run once. Throws what a run or its report throws.
  std::vector<double> simulate(const std::vector<double>& p) {
    std::vector<PercussionFigures> figs;
    for (const FitCondition& c : problem.conditions) {
      std::vector<std::string> overrides = problem.common_overrides;
      overrides.insert(overrides.end(), c.overrides.begin(), c.overrides.end());
      for (size_t j = 0; j < p.size(); ++j) overrides.push_back(assignment(problem.parameters[j].name, p[j]));
      figs.push_back(run_percussion(model, overrides, folder.file("run.h5")));
      ++runs;
    }
    std::vector<double> out;
    for (const FitTarget& t : problem.targets) {
      size_t k = 0;
      while (problem.conditions[k].name != t.condition) ++k;
      out.push_back(fit_figure(figs[k], t.figure));
    }
    return out;
  }

  std::vector<double> relative(const std::vector<double>& simulated) const {
    std::vector<double> r;
    for (size_t i = 0; i < simulated.size(); ++i)
      r.push_back((simulated[i] - problem.targets[i].value) / std::fabs(problem.targets[i].value));
    return r;
  }

  // Relative residuals at the solver's variables x.
  std::vector<double> residuals(const std::vector<double>& x) {
    std::vector<double> p(x.size());
    for (size_t j = 0; j < x.size(); ++j) p[j] = problem.parameters[j].value(x[j]);
    return relative(simulate(p));
  }
};

// Whether the targets determine every parameter: the Jacobian of the
// relative residuals by the solver's variables, at the solution, must have
// full column rank. A column near zero is a parameter the targets do not
// see; two columns nearly parallel are parameters that act only together
// (an orifice's Cd and A). Either way the targets can be met with the
// fitted values arbitrary along that direction: a silent wrong answer for
// whoever reads them as the design's. Returns "" or what to change.
// The bound: singular values below 1e-3 of the largest. A 1 % difference
// step on figures that are smooth to ~0.01 % leaves a noise floor near
// 1e-2 of a column's norm at worst, so 1e-3 is a direction the targets do
// not resolve at all, not one they resolve poorly.
std::string unresolved(const gsl_matrix* J, const FitProblem& p) {
  const size_t n = J->size1, np = J->size2;
  gsl_matrix* A = gsl_matrix_alloc(n, np);
  gsl_matrix* V = gsl_matrix_alloc(np, np);
  gsl_vector* S = gsl_vector_alloc(np);
  gsl_vector* work = gsl_vector_alloc(np);
  gsl_matrix_memcpy(A, J);
  gsl_linalg_SV_decomp(A, V, S, work);  // S descending
  std::string why;
  const double smax = gsl_vector_get(S, 0), smin = gsl_vector_get(S, np - 1);
  if (!(smin > 1e-3 * smax)) {
    // The direction the targets do not see: the parameters with the
    // largest share in the last right-singular vector.
    std::vector<std::string> names;
    for (size_t j = 0; j < np; ++j)
      if (std::fabs(gsl_matrix_get(V, j, np - 1)) > 0.3) names.push_back(p.parameters[j].name);
    std::string list;
    for (size_t i = 0; i < names.size(); ++i) list += (i ? (i + 1 == names.size() ? " and " : ", ") : "") + names[i];
    std::ostringstream o;
    o << "the targets do not determine " << list
      << (names.size() > 1 ? ": they fix only a combination of them" : ": they do not depend on it")
      << " (smallest singular value " << std::setprecision(2) << (smax > 0 ? smin / smax : 0.0)
      << " of the largest); fit fewer parameters or add targets that tell them apart";
    why = o.str();
  }
  gsl_matrix_free(A);
  gsl_matrix_free(V);
  gsl_vector_free(S);
  gsl_vector_free(work);
  return why;
}

// A trial step whose run fails (the hammer stops cycling, a value leaves its
// range) must be refused by the trust region, not end the fit: it gets a
// residual far above any the start had.
constexpr double kFailedResidual = 1e3;

struct Context {
  Evaluator* ev;
  size_t n, p;
  int stop_signal = 0;  // a stop signal during a run: no exception crosses GSL's C frames
};

int f_cb(const gsl_vector* x, void* params, gsl_vector* f) {
  auto* c = static_cast<Context*>(params);
  std::vector<double> xv(c->p);
  for (size_t j = 0; j < c->p; ++j) xv[j] = gsl_vector_get(x, j);
  std::vector<double> r;
  try {
    if (c->stop_signal) throw config::StopRequested(c->stop_signal);
    r = c->ev->residuals(xv);
  } catch (const config::StopRequested& e) {
    c->stop_signal = e.signo();
    r.assign(c->n, kFailedResidual);
  } catch (const std::exception& e) {
    ++c->ev->failed_runs;
    c->ev->last_failure = e.what();
    r.assign(c->n, kFailedResidual);
  }
  for (size_t i = 0; i < c->n; ++i) gsl_vector_set(f, i, r[i]);
  return GSL_SUCCESS;
}

// Forward differences at the relative step the header explains.
constexpr double kStep = 0.01;

int df_cb(const gsl_vector* x, void* params, gsl_matrix* J) {
  auto* c = static_cast<Context*>(params);
  gsl_vector* f0 = gsl_vector_alloc(c->n);
  gsl_vector* f1 = gsl_vector_alloc(c->n);
  gsl_vector* xs = gsl_vector_alloc(c->p);
  f_cb(x, params, f0);
  for (size_t j = 0; j < c->p; ++j) {
    gsl_vector_memcpy(xs, x);
    gsl_vector_set(xs, j, gsl_vector_get(x, j) + kStep);
    f_cb(xs, params, f1);
    for (size_t i = 0; i < c->n; ++i)
      gsl_matrix_set(J, i, j, (gsl_vector_get(f1, i) - gsl_vector_get(f0, i)) / kStep);
  }
  gsl_vector_free(f0);
  gsl_vector_free(f1);
  gsl_vector_free(xs);
  return GSL_SUCCESS;
}

}  // namespace

PercussionFigures run_percussion(const ModelSpec& model, const std::vector<std::string>& overrides, const std::string& h5) {
  ModelSpec spec = model;
  for (const auto& o : overrides) spec.apply_override(o);
  const ReportSettings report = report_settings(spec);
  {
    System sys(std::move(spec));
    sys.run(h5, false);
  }
  return evaluate_percussion(h5, report);
}

const std::vector<std::pair<std::string, std::string>>& fit_figure_names() {
  static const std::vector<std::pair<std::string, std::string>> names = [] {
    std::vector<std::pair<std::string, std::string>> n;
    for (const auto& f : kFigures) n.emplace_back(f.name, f.unit);
    return n;
  }();
  return names;
}

double parse_fit_value(const std::string& text) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw std::invalid_argument("'" + text + "': expected a number with an optional unit (80l/min, 150bar, 20Hz)");
  }
  const std::string unit = text.substr(used);
  const auto it = unit_factors().find(unit);
  if (it == unit_factors().end()) {
    std::string known;
    for (const auto& [u, f] : unit_factors())
      if (!u.empty()) known += (known.empty() ? "" : ", ") + u;
    throw std::invalid_argument("'" + text + "': unknown unit '" + unit + "' (known: " + known + ")");
  }
  v *= it->second;
  if (!std::isfinite(v)) throw std::invalid_argument("'" + text + "': not a finite number");
  return v;
}

double fit_figure(const PercussionFigures& f, const std::string& name) {
  for (const auto& d : kFigures)
    if (name == d.name) return f.*(d.member);
  for (const auto& [label, value] : f.peaks)
    if (name == "peak_" + label) return value;
  throw std::invalid_argument("no report figure named '" + name + "'");
}

double FitParameter::value(double x) const {
  return bounded ? lo + (hi - lo) * 0.5 * (1.0 + std::tanh(x)) : start * std::exp(x);
}

double FitParameter::x_start() const { return bounded ? std::atanh(2.0 * (start - lo) / (hi - lo) - 1.0) : 0.0; }

FitParameter parse_fit_parameter(const std::string& full_text, const ModelSpec& model) {
  FitParameter p;
  const size_t colon = full_text.find(':');
  const std::string text = full_text.substr(0, colon);
  if (colon != std::string::npos) {
    const std::string range = full_text.substr(colon + 1);
    const size_t dots = range.find("..");
    if (dots == std::string::npos)
      throw std::invalid_argument("--fit '" + full_text + "': expected bounds as LO..HI after the colon");
    p.bounded = true;
    p.lo = parse_fit_value(range.substr(0, dots));
    p.hi = parse_fit_value(range.substr(dots + 2));
    if (!(p.lo >= 0.0 && p.hi > p.lo))
      throw std::invalid_argument("--fit '" + full_text + "': bounds need 0 <= LO < HI");
  }
  const size_t eq = text.find('=');
  p.name = text.substr(0, eq);
  const size_t dot = p.name.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == p.name.size())
    throw std::invalid_argument("--fit '" + text + "': expected COMPONENT.PARAMETER or COMPONENT.PARAMETER=START");
  const std::string comp = p.name.substr(0, dot), key = p.name.substr(dot + 1);
  const ComponentSpec* c = model.find(comp);
  if (!c) throw std::invalid_argument("--fit '" + text + "': no component named '" + comp + "' in " + model.source);
  if (eq != std::string::npos) {
    p.start = parse_fit_value(text.substr(eq + 1));
  } else {
    if (!c->params.has(key))
      throw std::invalid_argument("--fit '" + p.name + "': " + model.source + " does not set " + key + " of " + comp +
                                  "; give a start value as " + p.name + "=VALUE");
    try {
      p.start = c->params.given_number(key);
    } catch (const std::exception&) {
      throw std::invalid_argument("--fit '" + p.name + "': not a single number in " + model.source +
                                  " (a table or a text cannot be fitted)");
    }
  }
  if (!(p.start > 0.0) || !std::isfinite(p.start))
    throw std::invalid_argument("--fit '" + p.name + "': the start value " + short_number(p.start) +
                                " is not positive (fitted parameters are positive: areas, coefficients, pressures)");
  if (p.bounded && !(p.start > p.lo && p.start < p.hi))
    throw std::invalid_argument("--fit '" + full_text + "': the start value " + short_number(p.start) +
                                " is not inside the bounds " + short_number(p.lo) + ".." + short_number(p.hi));
  return p;
}

void check_fit_problem(const FitProblem& p) {
  if (p.parameters.empty()) throw std::invalid_argument("--fit: no parameter to fit");
  if (p.targets.size() < p.parameters.size())
    throw std::invalid_argument("--fit: " + std::to_string(p.parameters.size()) + " parameters need at least as many targets, got " +
                                std::to_string(p.targets.size()) + " (--target CONDITION:FIGURE=VALUE)");
  for (size_t i = 0; i < p.parameters.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (p.parameters[i].name == p.parameters[j].name)
        throw std::invalid_argument("--fit: " + p.parameters[i].name + " is named twice");
  for (const FitTarget& t : p.targets) {
    bool found = false;
    for (const auto& c : p.conditions) found = found || c.name == t.condition;
    if (!found) throw std::invalid_argument("--target: no condition named '" + t.condition + "' (--condition NAME:C.P=V,...)");
    bool known = t.figure.rfind("peak_", 0) == 0;
    for (const auto& [name, unit] : fit_figure_names()) known = known || name == t.figure;
    if (!known) {
      std::string list;
      for (const auto& [name, unit] : fit_figure_names()) list += (list.empty() ? "" : ", ") + name + " [" + unit + "]";
      throw std::invalid_argument("--target: no figure named '" + t.figure + "'; the report has " + list +
                                  " and peak_LABEL for each peak row of *REPORT");
    }
    if (t.value == 0.0) throw std::invalid_argument("--target " + t.condition + ":" + t.figure + ": a target of 0 has no relative residual");
  }
  if (p.max_iterations < 1) throw std::invalid_argument("--max-iterations: at least 1");
  if (!(p.tolerance > 0.0)) throw std::invalid_argument("--tolerance: must be positive");
}

FitResult run_fit(const FitProblem& p, const std::function<void(const std::string&)>& progress) {
  check_fit_problem(p);
  Evaluator ev{p, read_model(p.model_path), {}, 0, 0, {}};
  const size_t n = p.targets.size(), np = p.parameters.size();
  // The start must run: a fit from a model that does not cycle has nothing to follow.
  try {
    std::vector<double> x_start;
    for (const auto& par : p.parameters) x_start.push_back(par.x_start());
    ev.residuals(x_start);
  } catch (const config::StopRequested&) {
    throw;
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("the model at the start values: ") + e.what());
  }

  Context ctx{&ev, n, np};
  gsl_multifit_nlinear_fdf fdf;
  fdf.f = f_cb;
  fdf.df = df_cb;
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = np;
  fdf.params = &ctx;
  gsl_multifit_nlinear_parameters params = gsl_multifit_nlinear_default_parameters();
  params.trs = gsl_multifit_nlinear_trs_lm;
  params.scale = gsl_multifit_nlinear_scale_more;
  gsl_multifit_nlinear_workspace* w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &params, n, np);
  gsl_vector* x0 = gsl_vector_alloc(np);
  for (size_t j = 0; j < np; ++j) gsl_vector_set(x0, j, p.parameters[j].x_start());
  gsl_error_handler_t* old = gsl_set_error_handler_off();

  FitResult r;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    gsl_multifit_nlinear_init(x0, &fdf, w);
    if (ctx.stop_signal) throw config::StopRequested(ctx.stop_signal);
    // Stops: a step below 1e-4 in ln(value), i.e. 0.01 % of a parameter,
    // far below what the 1 % difference step resolves; a gradient or a
    // cost decrease near round-off.
    const double xtol = 1e-4, gtol = 1e-10, ftol = 1e-10;
    int info = 0, status = GSL_CONTINUE;
    for (int it = 1; it <= p.max_iterations && status == GSL_CONTINUE; ++it) {
      status = gsl_multifit_nlinear_iterate(w);
      if (ctx.stop_signal) throw config::StopRequested(ctx.stop_signal);
      r.iterations = it;
      if (status == GSL_ENOPROG) {
        r.stop_reason = "no further progress (the trust region shrank to nothing)";
        break;
      }
      if (status != GSL_SUCCESS) {
        r.stop_reason = std::string("the solver stopped: ") + gsl_strerror(status);
        break;
      }
      status = gsl_multifit_nlinear_test(xtol, gtol, ftol, &info, w);
      if (progress) {
        const gsl_vector* x = gsl_multifit_nlinear_position(w);
        const double cost = gsl_blas_dnrm2(gsl_multifit_nlinear_residual(w));
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::ostringstream o;
        o << "tlm_fit: iteration " << it << ": |r| = " << std::setprecision(4) << cost << ",";
        for (size_t j = 0; j < np; ++j)
          o << " " << p.parameters[j].name << " = " << short_number(p.parameters[j].value(gsl_vector_get(x, j)));
        o << " (" << ev.runs << " runs, " << std::fixed << std::setprecision(0) << wall << " s)";
        progress(o.str());
      }
      if (status == GSL_SUCCESS) {
        r.stop_reason = info == 1 ? "converged: the step is below 0.01 % of every parameter"
                                  : info == 2 ? "converged: the gradient vanishes" : "converged: the cost no longer falls";
      }
    }
    if (status == GSL_CONTINUE) r.stop_reason = "stopped after " + std::to_string(p.max_iterations) + " iterations (--max-iterations)";
  } catch (...) {
    gsl_set_error_handler(old);
    gsl_vector_free(x0);
    gsl_multifit_nlinear_free(w);
    throw;
  }
  gsl_set_error_handler(old);

  if (r.iterations > 0) r.unresolved = unresolved(gsl_multifit_nlinear_jac(w), p);
  const gsl_vector* x = gsl_multifit_nlinear_position(w);
  std::vector<double> xv(np);
  for (size_t j = 0; j < np; ++j) {
    xv[j] = gsl_vector_get(x, j);
    r.fitted.push_back(p.parameters[j].value(xv[j]));
  }
  gsl_vector_free(x0);
  gsl_multifit_nlinear_free(w);

  // The figures at the fitted values, from a run of their own (the solver's
  // last residual may belong to a difference step).
  r.simulated = ev.simulate(r.fitted);
  r.residual = ev.relative(r.simulated);
  r.targets_met = std::all_of(r.residual.begin(), r.residual.end(), [&](double res) { return std::fabs(res) <= p.tolerance; });
  r.runs = ev.runs;
  r.failed_runs = ev.failed_runs;
  if (ev.failed_runs > 0) r.stop_reason += "; " + std::to_string(ev.failed_runs) + " trial run(s) failed and were refused, the last: " + ev.last_failure;
  return r;
}

std::string format_fit(const FitProblem& p, const FitResult& r) {
  std::ostringstream o;
  o << "fit on " << p.model_path << ": " << r.iterations << " iteration(s), " << r.runs << " model runs; " << r.stop_reason << "\n\n";
  o << std::left << std::setw(28) << "parameter" << std::setw(16) << "start" << std::setw(16) << "fitted" << "change\n";
  for (size_t j = 0; j < p.parameters.size(); ++j) {
    const double change = 100.0 * (r.fitted[j] / p.parameters[j].start - 1.0);
    o << std::setw(28) << p.parameters[j].name << std::setw(16) << short_number(p.parameters[j].start) << std::setw(16)
      << short_number(r.fitted[j]) << std::showpos << std::fixed << std::setprecision(2) << change << " %"
      << std::noshowpos << std::defaultfloat << "\n";
  }
  std::ostringstream notes;
  for (size_t j = 0; j < p.parameters.size(); ++j) {
    if (p.parameters[j].bounded) {
      const double span = p.parameters[j].hi - p.parameters[j].lo;
      if (std::min(r.fitted[j] - p.parameters[j].lo, p.parameters[j].hi - r.fitted[j]) < 1e-3 * span)
        notes << p.parameters[j].name << " ends on a bound: the targets want it beyond " << short_number(p.parameters[j].lo)
              << ".." << short_number(p.parameters[j].hi) << "\n";
    }
  }
  if (!r.unresolved.empty()) notes << "NOT A DESIGN: " << r.unresolved << "\n";
  o << notes.str();
  o << "\n" << std::setw(36) << "target (SI)" << std::setw(16) << "wanted" << std::setw(16) << "got" << "residual\n";
  for (size_t i = 0; i < p.targets.size(); ++i) {
    const FitTarget& t = p.targets[i];
    std::string unit;
    for (const auto& [name, u] : fit_figure_names())
      if (name == t.figure) unit = u;
    if (unit.empty()) unit = "Pa";
    o << std::setw(36) << (t.condition + ": " + t.figure + " [" + unit + "]") << std::setw(16) << short_number(t.value)
      << std::setw(16) << short_number(r.simulated[i]) << std::showpos << std::fixed << std::setprecision(3)
      << 100.0 * r.residual[i] << " %" << std::noshowpos << std::defaultfloat
      << (std::fabs(r.residual[i]) <= p.tolerance ? "" : "  (beyond the tolerance)") << "\n";
  }
  o << "\n" << (r.targets_met ? "every target within " : "NOT every target within ") << 100.0 * p.tolerance
    << " %; to use the fit:\n ";
  for (size_t j = 0; j < p.parameters.size(); ++j)
    o << " --set " << p.parameters[j].name << "=" << std::setprecision(10) << r.fitted[j];
  o << "\n";
  return o.str();
}

}  // namespace tlm
