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
#ifndef _WIN32
  // (On Windows, the FMU's DLL, stat says nothing of owners and ACLs: the
  // file's rights are the folder's, a user's profile is private by default.)
  if (st.st_uid != ::geteuid())
    throw std::runtime_error("token file '" + path + "' belongs to another user: use a file of your own");
  if (st.st_mode & (S_IRWXG | S_IRWXO)) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::runtime_error("token file '" + path + "' is open to other users (mode " + mode +
                             "): run chmod 600 '" + path + "'");
  }
#endif
  std::ifstream f(path);
  std::string line;
  if (!f || !std::getline(f, line)) throw std::runtime_error("token file '" + path + "' cannot be read or is empty");
  const char* blanks = " \t\r\n";
  const size_t a = line.find_first_not_of(blanks);
  const size_t b = line.find_last_not_of(blanks);
  const std::string token = a == std::string::npos ? "" : line.substr(a, b - a + 1);
  if (token.empty()) throw std::runtime_error("token file '" + path + "': the first line holds no token");
  check_token(token, "token file '" + path + "'");
  return token;
}

void check_token(const std::string& token, const std::string& source) {
  const std::string make =
      "; make one with: head -c 24 /dev/urandom | base64 > token && chmod 600 token";
  for (size_t i = 0; i < token.size(); ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c < 0x21 || c > 0x7e) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", c);
      throw std::runtime_error(source + ": the token holds byte " + code + " at position " + std::to_string(i + 1) +
                               "; a token is printable ASCII without blanks (0x21..0x7e)" + make);
    }
  }
  if (token.size() < kMinTokenLength)
    throw std::runtime_error(source + ": the token has " + std::to_string(token.size()) + " characters, at least " +
                             std::to_string(kMinTokenLength) + " are required" + make);
  if (token.size() > kMaxTokenLength)
    throw std::runtime_error(source + ": the token is longer than " + std::to_string(kMaxTokenLength) +
                             " characters");
}

std::string token_from_environment(std::string* source) {
  if (const char* t = std::getenv(kTokenEnv); t && *t) {
    check_token(t, std::string("$") + kTokenEnv);
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
