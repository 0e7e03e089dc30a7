// The benchmarks' positional arguments: each a positive number with a
// default. `-h`/`--help` prints the usage and exits 0; anything that is not
// a positive number exits 2 saying which argument and what it should be.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "config/version.hpp"

namespace bench {

// The usage line is printed for --help and after a bad argument; --version
// prints the version line every executable of the project prints.
inline void help_or_nothing(int argc, char** argv, const char* usage) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) {
      std::printf("%s\n", usage);
      std::exit(0);
    }
    if (std::strcmp(argv[i], "--version") == 0) {
      const char* slash = std::strrchr(argv[0], '/');
      std::printf("%s\n", config::version_line(slash ? slash + 1 : argv[0]).c_str());
      std::exit(0);
    }
  }
}

// Argument i (1-based) as a positive finite number, or `fallback` if absent.
inline double positive_arg(int argc, char** argv, int i, double fallback, const char* what, const char* usage) {
  if (argc <= i) return fallback;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(argv[i], &end);
  if (errno != 0 || end == argv[i] || *end != '\0' || !std::isfinite(v) || !(v > 0.0)) {
    std::fprintf(stderr, "%s: argument %d '%s': %s must be a positive number\n%s\n", argv[0], i, argv[i], what, usage);
    std::exit(2);
  }
  return v;
}

// Argument i as a whole number of at least 1 (a count), or `fallback`.
inline int count_arg(int argc, char** argv, int i, int fallback, const char* what, const char* usage) {
  const double v = positive_arg(argc, argv, i, fallback, what, usage);
  if (v != std::floor(v) || v > 1e9) {
    std::fprintf(stderr, "%s: argument %d '%s': %s must be a whole number\n%s\n", argv[0], i, argv[i], what, usage);
    std::exit(2);
  }
  return static_cast<int>(v);
}

}  // namespace bench
