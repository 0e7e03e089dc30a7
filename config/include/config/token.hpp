// Session tokens: where fe_server, tlm_host and the FMU take them from.
// Never from a command line (every local user sees it in `ps` and
// /proc/PID/cmdline): from a file only its owner can read, or from the
// environment (/proc/PID/environ is private to the owner and root).
#pragma once

#include <string>

namespace config {

// The environment variables, in the order they are consulted.
inline constexpr const char* kTokenEnv = "PCS_TOKEN";            // the token itself
inline constexpr const char* kTokenFileEnv = "PCS_TOKEN_FILE";  // a file holding it

// The token in `path`: its first line, surrounding blanks removed. Refused
// (std::runtime_error naming the file and what to do) unless the file is a
// regular file owned by the current user with no permission for group or
// others (like ssh's private keys), and the token is 1 to 255 bytes.
std::string read_token_file(const std::string& path);

// $PCS_TOKEN if set, else the file named by $PCS_TOKEN_FILE (checked as
// above), else "". `source` (if given) receives where it came from.
std::string token_from_environment(std::string* source = nullptr);

// The message for a --token option, which is refused.
std::string token_on_command_line_refused(const std::string& program);

}  // namespace config
