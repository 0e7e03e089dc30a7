#include "config/token.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace config {

std::string read_token_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::runtime_error("token file '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw std::runtime_error("token file '" + path + "' is not a regular file");
  if (st.st_uid != ::geteuid())
    throw std::runtime_error("token file '" + path + "' belongs to another user: use a file of your own");
  if (st.st_mode & (S_IRWXG | S_IRWXO)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::runtime_error("token file '" + path + "' is open to other users (mode " + mode +
                             "): run chmod 600 '" + path + "'");
  }
  std::ifstream f(path);
  std::string line;
  if (!f || !std::getline(f, line)) throw std::runtime_error("token file '" + path + "' cannot be read or is empty");
  const char* blanks = " \t\r\n";
  const size_t a = line.find_first_not_of(blanks);
  const size_t b = line.find_last_not_of(blanks);
  const std::string token = a == std::string::npos ? "" : line.substr(a, b - a + 1);
  if (token.empty()) throw std::runtime_error("token file '" + path + "': the first line holds no token");
  if (token.size() > 255) throw std::runtime_error("token file '" + path + "': the token is longer than 255 bytes");
  return token;
}

std::string token_from_environment(std::string* source) {
  if (const char* t = std::getenv(kTokenEnv); t && *t) {
    if (std::strlen(t) > 255) throw std::runtime_error(std::string("$") + kTokenEnv + " is longer than 255 bytes");
    if (source) *source = std::string("$") + kTokenEnv;
    return t;
  }
  if (const char* f = std::getenv(kTokenFileEnv); f && *f) {
    if (source) *source = std::string("$") + kTokenFileEnv + " (" + f + ")";
    return read_token_file(f);
  }
  if (source) source->clear();
  return "";
}

std::string token_on_command_line_refused(const std::string& program) {
  return "--token is not accepted: a command line is visible to every local user (ps, /proc/PID/cmdline). "
         "Put the token in a file only you can read (chmod 600) and pass --token-file FILE, or set $" +
         std::string(kTokenEnv) + " or $" + kTokenFileEnv + " for " + program;
}

}  // namespace config
