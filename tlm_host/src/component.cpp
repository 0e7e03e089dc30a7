#include "component.hpp"

#include "config/nearest.hpp"

#include <initializer_list>
#include <sstream>

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

namespace {

// Plausible ranges of the physical parameters, by their names across the
// library (SI units): a value outside is a unit slip (bar or MPa for Pa,
// cm³ for m³, g for kg) or a typo, refused where it is written. Wide on
// purpose: a percussion unit's parameters sit orders of magnitude inside.
struct Plausible {
  const char* what;
  double lo, hi;
  const char* unit;
  std::initializer_list<const char*> keys;
};
const Plausible kPlausible[] = {
    {"pressure", -1e5, 1e9, "Pa (absolute; 1 bar = 1e5 Pa)",
     {"p", "p0", "pa0", "p_init", "p1_0", "p2_0", "p_vap", "p_max", "p_crack", "p_h"}},
    {"volume", 0.0, 10.0, "m³ (1 cm³ = 1e-6 m³)", {"V", "V0", "V_1", "V_2", "V_min", "V_dead"}},
    {"mass", 0.0, 1e6, "kg", {"m", "m_tool", "m_l", "ML"}},
    {"area", 0.0, 10.0, "m² (1 mm² = 1e-6 m²)", {"A", "A_1", "A_2", "A_s", "A_c", "A_A", "A_B", "Ap"}},
    {"bulk modulus", 1e5, 1e12, "Pa (oil: about 1.4e9)", {"beta", "beta_e", "Beta_e"}},
    {"density", 0.01, 1e5, "kg/m³ (oil: about 870)", {"rho"}},
};

// The plausibility table's row for a parameter name, or nullptr.
const Plausible* plausible_range(const std::string& key) {
  for (const auto& r : kPlausible)
    for (const char* k : r.keys)
      if (key == k) return &r;
  return nullptr;
}

}  // namespace

double ParameterSet::real(const std::string& key, double fallback, Unit unit) {
  const Plausible* range = plausible_range(key);
  const std::string table_unit = range ? std::string(range->unit) : "";
  if (range && table_unit != unit.text && table_unit.rfind(std::string(unit.text) + " ", 0) != 0)
    throw std::logic_error("parameter " + key + " declared in " + unit.text + ", the plausibility table's unit is " +
                           table_unit);
  asked_[key] = unit.text;
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  it->second.used = true;
  const double v = config::parse_real(it->second.value, it->second.where, "parameter " + key);
  if (range && !(v >= range->lo && v <= range->hi)) {
    std::ostringstream s;
    s << "parameter " << key << " = " << it->second.value << " is outside the plausible range of a " << range->what
      << ", " << range->lo << " to " << range->hi << " " << range->unit;
    throw config::InputError(it->second.where, s.str());
  }
  return v;
}

double ParameterSet::real(const std::string& key, Unit unit) {
  if (!has(key)) throw config::InputError(where_, "parameter " + key + " [" + unit.text + "] is required");
  return real(key, 0.0, unit);
}

double ParameterSet::given_number(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw config::InputError(where_, "parameter " + key + " is not given");
  return config::parse_real(it->second.value, it->second.where, "parameter " + key);
}

double ParameterSet::positive(const std::string& key, double fallback, Unit unit) {
  double v = real(key, fallback, unit);
  if (!(v > 0.0)) {
    auto it = values_.find(key);
    throw config::InputError(it != values_.end() ? it->second.where : where_,
                             "parameter " + key + " must be positive, got " + std::to_string(v));
  }
  return v;
}

int ParameterSet::integer(const std::string& key, int fallback, int lo, int hi) {
  const double v = real(key, fallback, "1");
  if (!(v >= lo && v <= hi) || v != std::floor(v)) {
    auto it = values_.find(key);
    throw config::InputError(it != values_.end() ? it->second.where : where_,
                             "parameter " + key + " must be a whole number from " + std::to_string(lo) + " to " +
                                 std::to_string(hi) + ", got " + (it != values_.end() ? it->second.value : ""));
  }
  return static_cast<int>(v);
}

std::string ParameterSet::text(const std::string& key, const std::string& fallback) {
  asked_.emplace(key, "");
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  it->second.used = true;
  return it->second.value;
}

void ParameterSet::check_all_used(const std::string& component) const {
  for (const auto& [key, e] : values_) {
    if (e.used) continue;
    // Say what it has: the nearest name, and every parameter it read, with
    // the unit it declared.
    std::vector<std::string> names;
    for (const auto& [n, unit] : asked_) names.push_back(n);
    const std::string near = config::nearest(key, names);
    std::string list;
    for (const auto& [n, unit] : asked_) {
      if (values_.count(n) && !values_.at(n).used) continue;  // given, not read: not one of its parameters
      list += (list.empty() ? "" : ", ") + n + (unit.empty() ? "" : " [" + unit + "]");
    }
    throw config::InputError(e.where, "component " + component + " has no parameter '" + key + "'" +
                                          (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                          (list.empty() ? "" : "; its parameters: " + list));
  }
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
