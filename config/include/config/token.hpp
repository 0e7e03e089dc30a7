// Session tokens: where fe_server, tlm_host and the FMU take them from.
// Never from a command line (every local user sees it in `ps` and
// /proc/PID/cmdline): from a file only its owner can read, or from the
// environment (/proc/PID/environ is private to the owner and root).
#pragma once

#include <cstddef>
#include <string>

namespace config {

// The environment variables, in the order they are consulted.
inline constexpr const char* kTokenEnv = "PCS_TOKEN";            // the token itself
inline constexpr const char* kTokenFileEnv = "PCS_TOKEN_FILE";  // a file holding it

// Every token, wherever it comes from, is 16 to 255 printable ASCII
// characters (0x21..0x7e: no blank, no control byte, no NUL). The length
// checked is the HMAC key used: a NUL or a non-ASCII byte would make the two
// differ (a NUL cut the key short, so "\0" + 30 characters was the empty key).
// 16 characters of a random hex or base64 string carry at least 64 bits.
inline constexpr size_t kMinTokenLength = 16;
inline constexpr size_t kMaxTokenLength = 255;

// Throws std::runtime_error naming `source` (a file, a variable, a parameter)
// and what to do, unless `token` is as above.
void check_token(const std::string& token, const std::string& source);

// The token in `path`: its first line, surrounding blanks removed. Refused
// (std::runtime_error naming the file and what to do) unless the file is a
// regular file owned by the current user with no permission for group or
// others (like ssh's private keys), and the token passes check_token.
std::string read_token_file(const std::string& path);

// $PCS_TOKEN if set, else the file named by $PCS_TOKEN_FILE (checked as
// above), else "". A non-empty token passes check_token. `source` (if given) receives where it came from.
std::string token_from_environment(std::string* source = nullptr);

// The message for a --token option, which is refused.
std::string token_on_command_line_refused(const std::string& program);

}  // namespace config
