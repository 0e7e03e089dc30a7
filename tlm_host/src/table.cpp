#include "table.hpp"

#include <gsl/gsl_errno.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace tlm {

Table::Table(const std::string& text, const config::SourceLocation& where, const std::string& what) : what_(what) {
  std::stringstream ss(text);
  std::string pair;
  while (std::getline(ss, pair, ';')) {
    pair = config::trim(pair);
    if (pair.empty()) continue;
    size_t colon = pair.find(':');
    if (colon == std::string::npos) throw config::InputError(where, what + ": '" + pair + "' is not x:y");
    x_.push_back(config::parse_real(pair.substr(0, colon), where, what + " x"));
    y_.push_back(config::parse_real(pair.substr(colon + 1), where, what + " y"));
    if (x_.size() > 1 && !(x_.back() > x_[x_.size() - 2]))
      throw config::InputError(where, what + ": x values must increase (" + pair + ")");
  }
  if (x_.size() < 2) throw config::InputError(where, what + ": a table needs at least two points x:y");
  interp_.reset(gsl_interp_alloc(gsl_interp_linear, x_.size()), gsl_interp_free);
  accel_.reset(gsl_interp_accel_alloc(), gsl_interp_accel_free);
  if (!interp_ || !accel_ || gsl_interp_init(interp_.get(), x_.data(), y_.data(), x_.size()) != GSL_SUCCESS)
    throw config::InputError(where, what + ": GSL cannot set up the table's interpolation");
}

double Table::operator()(double x) const {
  if (std::isnan(x)) throw std::runtime_error(what_ + ": the table's input is NaN");
  if (x <= x_.front()) return y_.front();
  if (x >= x_.back()) return y_.back();
  return gsl_interp_eval(interp_.get(), x_.data(), y_.data(), x, accel_.get());
}

}  // namespace tlm
