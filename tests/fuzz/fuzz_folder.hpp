// A private folder for a fuzz target's files, made once and removed at exit,
// so neither a fuzz run nor the replay in the test suite leaves anything in /tmp.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

namespace fuzz_support {

inline std::string& folder_path() {
  static std::string path;
  return path;
}

inline void remove_folder() {
  std::error_code ec;
  std::filesystem::remove_all(folder_path(), ec);
}

// The folder, made on the first call as /tmp/<prefix>_XXXXXX.
inline const std::string& private_folder(const char* prefix) {
  static const bool made = [&] {
    std::string templ = std::string("/tmp/") + prefix + "_XXXXXX";
    if (!mkdtemp(templ.data())) std::abort();
    folder_path() = templ;
    std::atexit(remove_folder);
    return true;
  }();
  (void)made;
  return folder_path();
}

}  // namespace fuzz_support
