// Command-line options read one at a time, shared by the programs:
//   config::Args args(argc, argv);
//   while (args.next()) { if (args.is("--out")) out = args.value(); else ... }
// value(), real() and integer() take the word after the current option and
// throw std::invalid_argument with a message that names the option.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/nearest.hpp"

namespace config {

class Args {
 public:
  Args(int argc, char** argv) : argc_(argc), argv_(argv) {}
  bool next() {
    if (++i_ >= argc_) return false;
    current_ = argv_[i_];
    return true;
  }
  const std::string& current() const { return current_; }
  // Every option the program tests for is remembered, so that an unknown
  // one, tested against all of them first, can be told the nearest.
  bool is(const char* option) {
    if (option[0] == '-') asked_.push_back(option);
    return current_ == option;
  }
  bool is_option() const { return !current_.empty() && current_[0] == '-'; }
  std::string value() {
    if (i_ + 1 >= argc_) throw std::invalid_argument(current_ + " needs a value");
    return argv_[++i_];
  }
  // A finite number within [lo, hi].
  double real(double lo = -1e300, double hi = 1e300) {
    const std::string option = current_, v = value();
    double d = 0.0;
    try {
      size_t used = 0;
      d = std::stod(v, &used);
      if (used != v.size()) throw std::invalid_argument(v);
    } catch (const std::exception&) {
      throw std::invalid_argument(option + ": expected a number, got '" + v + "'");
    }
    if (!(d >= lo && d <= hi)) {  // also refuses NaN and infinity
      std::ostringstream m;
      m << option << ": expected a number from " << lo << " to " << hi << ", got '" << v << "'";
      throw std::invalid_argument(m.str());
    }
    return d;
  }
  int integer() {
    const std::string option = current_, v = value();
    try {
      size_t used = 0;
      const int n = std::stoi(v, &used);
      if (used == v.size()) return n;
    } catch (const std::exception&) {
    }
    throw std::invalid_argument(option + ": expected an integer, got '" + v + "'");
  }
  [[noreturn]] void unknown() const {
    const std::string near = nearest(current_, asked_);
    throw std::invalid_argument("unknown argument " + current_ + (near.empty() ? "" : " (did you mean " + near + "?)"));
  }

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
  std::string current_;
  std::vector<std::string> asked_;
};

}  // namespace config
