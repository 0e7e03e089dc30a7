// A piecewise-linear table y(x) from a parameter string "x1:y1; x2:y2; ...",
// evaluated with GSL's linear interpolation and held constant outside its
// range (a valve's area stays at its end value past the stroke).
#pragma once

#include <gsl/gsl_interp.h>

#include <memory>
#include <string>
#include <vector>

#include "config/keyword_reader.hpp"

namespace tlm {

class Table {
 public:
  Table() = default;
  // Throws config::InputError at `where` for a malformed or non-increasing table.
  Table(const std::string& text, const config::SourceLocation& where, const std::string& what);
  // Throws std::runtime_error for a NaN x (GSL would return NaN with its
  // error handler off, and abort with it on).
  double operator()(double x) const;
  bool empty() const { return x_.empty(); }
  double min_x() const { return x_.front(); }
  double max_x() const { return x_.back(); }

 private:
  std::vector<double> x_, y_;
  std::string what_;
  std::shared_ptr<gsl_interp> interp_;
  std::shared_ptr<gsl_interp_accel> accel_;
};

}  // namespace tlm
