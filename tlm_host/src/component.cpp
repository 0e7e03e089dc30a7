#include "component.hpp"

#include <gsl/gsl_errno.h>

#include <cmath>

namespace tlm {

// GSL's default error handler prints and calls abort(): one bad parameter in
// a sweep (valve.Cd = 1e200) killed tlm_host with SIGABRT, no step, no time,
// its results file empty and the FMU's folder left behind. Off for every
// program that links the TLM library (this file always is: every component
// derives from Component); each GSL call's status is checked where it is
// made and becomes an exception that the step loop reports with the step,
// the time and the component.
namespace {
[[maybe_unused]] const bool gsl_handler_off = [] {
  gsl_set_error_handler_off();
  return true;
}();
}  // namespace

void ParameterSet::set(const std::string& key, const std::string& value, const config::SourceLocation& where) {
  values_[key] = Entry{value, where, false};
}

double ParameterSet::real(const std::string& key, double fallback) {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  it->second.used = true;
  return config::parse_real(it->second.value, it->second.where, "parameter " + key);
}

double ParameterSet::real(const std::string& key) {
  if (!has(key)) throw config::InputError(where_, "parameter " + key + " is required");
  return real(key, 0.0);
}

double ParameterSet::positive(const std::string& key, double fallback) {
  double v = real(key, fallback);
  if (!(v > 0.0)) {
    auto it = values_.find(key);
    throw config::InputError(it != values_.end() ? it->second.where : where_,
                             "parameter " + key + " must be positive, got " + std::to_string(v));
  }
  return v;
}

int ParameterSet::integer(const std::string& key, int fallback, int lo, int hi) {
  const double v = real(key, fallback);
  if (!(v >= lo && v <= hi) || v != std::floor(v)) {
    auto it = values_.find(key);
    throw config::InputError(it != values_.end() ? it->second.where : where_,
                             "parameter " + key + " must be a whole number from " + std::to_string(lo) + " to " +
                                 std::to_string(hi) + ", got " + (it != values_.end() ? it->second.value : ""));
  }
  return static_cast<int>(v);
}

std::string ParameterSet::text(const std::string& key, const std::string& fallback) {
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  it->second.used = true;
  return it->second.value;
}

void ParameterSet::check_all_used(const std::string& component) const {
  for (const auto& [key, e] : values_)
    if (!e.used) throw config::InputError(e.where, "component " + component + " has no parameter '" + key + "'");
}

Port* Component::port(const std::string& port_name) {
  for (auto& p : ports_)
    if (p.name == port_name) return &p;
  return nullptr;
}

SignalPort* Component::signal(const std::string& signal_name) {
  for (auto& s : signals_)
    if (s.name == signal_name) return &s;
  return nullptr;
}

void Component::add_signal_output(const std::string& signal_name, double* value) {
  signals_.push_back(SignalPort{signal_name, true, value, nullptr, false});
}

void Component::add_signal_input(const std::string& signal_name, const double** source, const double* fallback) {
  *source = fallback;
  signals_.push_back(SignalPort{signal_name, false, nullptr, source, fallback != nullptr});
}

Port& Component::add_port(const std::string& port_name, Kind side, bool mechanical) {
  ports_.push_back(Port{port_name, side, nullptr, mechanical});
  return ports_.back();
}

}  // namespace tlm
