// Command-line options read one at a time, shared by the programs:
//   config::Args args(argc, argv);
//   while (args.next()) { if (args.is("--out")) out = args.value(); else ... }
// value(), real() and integer() take the word after the current option and
// throw std::invalid_argument with a message that names the option.
#pragma once

#include <stdexcept>
#include <string>

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
  bool is(const char* option) const { return current_ == option; }
  bool is_option() const { return !current_.empty() && current_[0] == '-'; }
  std::string value() {
    if (i_ + 1 >= argc_) throw std::invalid_argument(current_ + " needs a value");
    return argv_[++i_];
  }
  double real() {
    const std::string option = current_, v = value();
    try {
      size_t used = 0;
      const double d = std::stod(v, &used);
      if (used == v.size()) return d;
    } catch (const std::exception&) {
    }
    throw std::invalid_argument(option + ": expected a number, got '" + v + "'");
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
  [[noreturn]] void unknown() const { throw std::invalid_argument("unknown argument " + current_); }

 private:
  int argc_;
  char** argv_;
  int i_ = 0;
  std::string current_;
};

}  // namespace config
