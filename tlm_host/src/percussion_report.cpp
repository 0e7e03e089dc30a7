#include "percussion_report.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_filter.h>
#include <gsl/gsl_statistics_double.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "h5io/timeseries.hpp"

namespace tlm {

std::vector<double> lowpass_gaussian(const std::vector<double>& x, double dt, double cutoff_hz) {
  if (!(cutoff_hz > 0.0) || x.size() < 3) return x;
  // A Gaussian kernel of standard deviation σ has H(f) = exp(−2π²σ²f²);
  // H = 1/√2 at f_c gives σ = sqrt(ln 2 / 4π²) / f_c ≈ 0.1325 / f_c.
  const double sigma = std::sqrt(std::log(2.0) / (4.0 * M_PI * M_PI)) / cutoff_hz / dt;  // samples
  if (sigma < 0.5) return x;
  size_t K = 2 * static_cast<size_t>(std::ceil(3.0 * sigma)) + 1;
  K = std::min(K, x.size() % 2 ? x.size() : x.size() - 1);
  const double alpha = static_cast<double>(K - 1) / (2.0 * sigma);  // GSL's width parameter
  std::vector<double> y(x.size());
  gsl_filter_gaussian_workspace* w = gsl_filter_gaussian_alloc(K);
  if (!w) throw std::runtime_error("report: GSL cannot allocate a Gaussian filter of " + std::to_string(K) + " points");
  gsl_vector_const_view in = gsl_vector_const_view_array(x.data(), x.size());
  gsl_vector_view out = gsl_vector_view_array(y.data(), y.size());
  const int status = gsl_filter_gaussian(GSL_FILTER_END_PADVALUE, alpha, 0, &in.vector, &out.vector, w);
  gsl_filter_gaussian_free(w);
  if (status != GSL_SUCCESS) throw std::runtime_error(std::string("report: the Gaussian filter failed: ") + gsl_strerror(status));
  return y;
}

PercussionFigures evaluate_percussion(const std::string& path, const ReportSettings& s) {
  const auto t = h5io::read_series(path, "time");
  const auto x = h5io::read_series(path, "components/" + s.piston + "/x");
  const auto v = h5io::read_series(path, "components/" + s.piston + "/v");
  const auto F = h5io::read_series(path, "components/" + s.piston + "/F_contact");
  if (t.size() < 3) throw std::runtime_error(path + ": too few samples for a report");
  const double dt = t[1] - t[0];

  // Blows: contact onsets after the settle time with the piston coming down
  // fast (the tool bouncing back into a slow piston is not a blow).
  std::vector<size_t> blows;
  std::vector<double> v_imp;
  for (size_t i = 1; i < t.size(); ++i)
    if (t[i] >= s.settle && F[i - 1] <= 0.0 && F[i] > 0.0 && v[i - 1] < -s.v_blow) {
      blows.push_back(i);
      v_imp.push_back(std::fabs(v[i - 1]));
    }
  if (blows.size() < 3)
    throw std::runtime_error(path + ": only " + std::to_string(blows.size()) + " blow(s) after t = " +
                             std::to_string(s.settle) + " s; run longer or check that the hammer cycles");
  PercussionFigures f;
  f.blows = static_cast<int>(blows.size());
  for (size_t i : blows) f.impact_times.push_back(t[i]);
  const size_t first = blows.front(), last = blows.back();  // whole cycles between these
  f.frequency = static_cast<double>(blows.size() - 1) / (t[last] - t[first]);
  f.v_impact = gsl_stats_mean(v_imp.data(), 1, v_imp.size());
  f.v_impact_sd = gsl_stats_sd(v_imp.data(), 1, v_imp.size());
  f.stroke = *std::max_element(x.begin() + static_cast<long>(first), x.begin() + static_cast<long>(last));
  double w_sum = 0.0;
  for (double vi : v_imp) w_sum += 0.5 * s.piston_mass * vi * vi;
  f.W = w_sum / static_cast<double>(v_imp.size());
  f.P_out = f.W * f.frequency;

  auto window = [&](const std::string& name) {
    auto all = lowpass_gaussian(h5io::read_series(path, name), dt, s.lowpass);
    return std::vector<double>(all.begin() + static_cast<long>(first), all.begin() + static_cast<long>(last));
  };
  if (!s.inlet_p.empty() && !s.inlet_q.empty()) {
    const auto p = window(s.inlet_p), q = window(s.inlet_q);
    f.p_in = gsl_stats_mean(p.data(), 1, p.size());
    f.q_in = gsl_stats_mean(q.data(), 1, q.size());
    double power = 0.0;
    for (size_t i = 0; i < p.size(); ++i) power += p[i] * q[i];
    f.P_in = power / static_cast<double>(p.size());
    f.efficiency = f.P_in > 0.0 ? f.P_out / f.P_in : 0.0;
  }
  for (const auto& [label, name] : s.peaks) {
    const auto p = window(name);
    f.peaks.push_back({label, gsl_stats_max(p.data(), 1, p.size())});
  }
  return f;
}

std::string format_figures(const PercussionFigures& f) {
  char buf[256];
  std::ostringstream o;
  std::snprintf(buf, sizeof buf, "  blows evaluated      %d\n", f.blows);
  o << buf;
  std::snprintf(buf, sizeof buf, "  impact frequency     %.2f Hz\n", f.frequency);
  o << buf;
  std::snprintf(buf, sizeof buf, "  impact velocity      %.3f m/s (sd %.3f)\n", f.v_impact, f.v_impact_sd);
  o << buf;
  std::snprintf(buf, sizeof buf, "  stroke               %.1f mm\n", 1e3 * f.stroke);
  o << buf;
  std::snprintf(buf, sizeof buf, "  inlet pressure       %.1f bar abs\n", 1e-5 * f.p_in);
  o << buf;
  std::snprintf(buf, sizeof buf, "  inlet flow           %.1f l/min\n", 6e4 * f.q_in);
  o << buf;
  std::snprintf(buf, sizeof buf, "  input power p*Q      %.2f kW\n", 1e-3 * f.P_in);
  o << buf;
  std::snprintf(buf, sizeof buf, "  blow energy W        %.0f J\n", f.W);
  o << buf;
  std::snprintf(buf, sizeof buf, "  output power W*f     %.2f kW (efficiency %.0f %%)\n", 1e-3 * f.P_out,
                100.0 * f.efficiency);
  o << buf;
  for (const auto& [label, p] : f.peaks) {
    std::snprintf(buf, sizeof buf, "  peak %-15s %.1f bar abs\n", label.c_str(), 1e-5 * p);
    o << buf;
  }
  return o.str();
}

std::string figures_json(const PercussionFigures& f) {
  std::ostringstream o;
  o.precision(10);
  o << "{\n  \"blows\": " << f.blows << ",\n  \"frequency_Hz\": " << f.frequency
    << ",\n  \"impact_velocity_m_s\": " << f.v_impact << ",\n  \"impact_velocity_sd_m_s\": " << f.v_impact_sd
    << ",\n  \"stroke_m\": " << f.stroke << ",\n  \"inlet_pressure_Pa\": " << f.p_in
    << ",\n  \"inlet_flow_m3_s\": " << f.q_in << ",\n  \"input_power_W\": " << f.P_in
    << ",\n  \"blow_energy_J\": " << f.W << ",\n  \"output_power_W\": " << f.P_out
    << ",\n  \"efficiency\": " << f.efficiency << ",\n  \"peak_pressure_Pa\": {";
  for (size_t i = 0; i < f.peaks.size(); ++i)
    o << (i ? ", " : "") << "\"" << f.peaks[i].first << "\": " << f.peaks[i].second;
  o << "},\n  \"impact_times_s\": [";
  for (size_t i = 0; i < f.impact_times.size(); ++i) o << (i ? ", " : "") << f.impact_times[i];
  o << "]\n}\n";
  return o.str();
}

}  // namespace tlm
