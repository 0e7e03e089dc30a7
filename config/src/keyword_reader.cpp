#include "config/keyword_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef _WIN32  // the FMU's win64 DLL: no FIFOs to block on; binary mode, not text
#include <io.h>
#define PCS_READ_FLAGS (O_RDONLY | O_BINARY)
#else
#define PCS_READ_FLAGS (O_RDONLY | O_NONBLOCK | O_CLOEXEC)
#endif

#include <cctype>
#include <cerrno>
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace config {

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::string to_upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string to_lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

namespace {
// Opens without blocking (a FIFO would wait for a writer), checks on the open
// descriptor that it is a regular file within the bound, then reads it whole.
template <class Bytes>
Bytes read_regular_file(const std::string& path, const std::string& what, uint64_t max_bytes) {
  auto fail = [&](const std::string& why) -> Bytes {
    throw std::runtime_error("cannot open " + what + " '" + path + "': " + why);
  };
  const int fd = ::open(path.c_str(), PCS_READ_FLAGS);
  if (fd < 0) return fail(std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return fail(S_ISDIR(st.st_mode) ? "it is a folder" : "not a regular file (a device, FIFO or socket)");
  }
  const auto size = static_cast<uint64_t>(st.st_size);
  if (size > max_bytes) {
    ::close(fd);
    return fail(std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
                " this reader accepts");
  }
  Bytes out(static_cast<size_t>(size), 0);
  size_t have = 0;
  int err = 0;
  while (have < out.size()) {
    const ssize_t n = ::read(fd, &out[have], out.size() - have);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) err = errno;
    if (n <= 0) break;  // 0: the file shrank while it was read; what was there is kept
    have += static_cast<size_t>(n);
  }
  ::close(fd);
  if (err != 0) return fail(std::strerror(err));
  out.resize(have);
  return out;
}
}  // namespace

std::string read_text_file(const std::string& path, const std::string& what, uint64_t max_bytes) {
  return read_regular_file<std::string>(path, what, max_bytes);
}

std::vector<uint8_t> read_binary_file(const std::string& path, const std::string& what, uint64_t max_bytes) {
  return read_regular_file<std::vector<uint8_t>>(path, what, max_bytes);
}

double parse_real(const std::string& text, const SourceLocation& where, const std::string& what) {
  std::string t = trim(text);
  // Fortran-style exponents ("1.0d-6") appear in decks written by older tools.
  for (char& c : t)
    if (c == 'd' || c == 'D') c = 'e';
  // E-less exponent: a plain decimal mantissa, then a sign and digits only.
  const size_t sign = t.find_last_of("+-");
  if (sign != std::string::npos && sign > 0 && t.find_first_of("eE") == std::string::npos) {
    const std::string mantissa = t.substr(0, sign), exponent = t.substr(sign + 1);
    const size_t inner_sign = mantissa.find_last_of("+-");
    if (!exponent.empty() && exponent.find_first_not_of("0123456789") == std::string::npos &&
        mantissa.find_first_not_of("+-.0123456789") == std::string::npos &&
        mantissa.find_first_of("0123456789") != std::string::npos && (inner_sign == std::string::npos || inner_sign == 0))
      t = mantissa + "e" + t.substr(sign);
  }
  errno = 0;
  char* end = nullptr;
  double v = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE)
    throw InputError(where, what + ": expected a number, got '" + trim(text) + "'");
  // No input of this project means infinity or NaN; either would only
  // surface later as a deadline already past or an unstable state.
  if (!std::isfinite(v)) throw InputError(where, what + ": expected a finite number, got '" + trim(text) + "'");
  return v;
}

long parse_integer(const std::string& text, const SourceLocation& where, const std::string& what) {
  std::string t = trim(text);
  errno = 0;
  char* end = nullptr;
  long v = std::strtol(t.c_str(), &end, 10);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE)
    throw InputError(where, what + ": expected an integer, got '" + trim(text) + "'");
  return v;
}

static std::string describe(size_t i, const char* name) {
  return "field " + std::to_string(i + 1) + " (" + name + ")";
}

const std::string& Card::field(size_t i, const char* name) const {
  if (i >= fields.size())
    fail(describe(i, name) + " is missing: the card has " + std::to_string(fields.size()) +
         " field(s)");
  return fields[i];
}

double Card::real(size_t i, const char* name) const {
  return parse_real(field(i, name), where, describe(i, name));
}

double Card::real_or(size_t i, const char* name, double fallback) const {
  if (i >= fields.size() || fields[i].empty()) return fallback;
  return real(i, name);
}

long Card::integer(size_t i, const char* name) const {
  return parse_integer(field(i, name), where, describe(i, name));
}

long Card::integer_or(size_t i, const char* name, long fallback) const {
  if (i >= fields.size() || fields[i].empty()) return fallback;
  return integer(i, name);
}

std::vector<std::string> split_fixed(const std::string& line, const std::vector<int>& widths) {
  std::vector<std::string> out;
  size_t pos = 0;
  for (size_t k = 0; pos < line.size() && !widths.empty(); ++k) {
    size_t w = static_cast<size_t>(widths[std::min(k, widths.size() - 1)]);
    out.push_back(trim(line.substr(pos, w)));
    pos += w;
  }
  return out;
}

static std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(trim(cur));
  return out;
}

static bool is_block_header(const std::string& t) {
  return (!t.empty() && t[0] == '*') || t.rfind("$FMU_", 0) == 0;
}

static std::string directory_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

namespace {
struct ParseState {
  bool follow_includes = false, blank_cards = false;
  std::vector<std::string> include_paths;  // from *INCLUDE_PATH, in the order read
  std::string master_dir;                  // the master deck's folder (with its '/'), "" for the working one
  uint64_t include_bytes = 0;              // read through *INCLUDE so far, every file counted each time
  long include_files = 0;
};
// An include tree is bounded as a whole, not only by its depth: a fan-out of
// 10 over 8 levels names one small file 10^8 times and once took 3.3 GB
// before it ended in bad_alloc. The bounds are far above any real model's
// tree (a few dozen files) and below this machine's memory.
constexpr uint64_t kMaxIncludeTreeBytes = 2ull << 30;  // 2 GiB
constexpr long kMaxIncludeFiles = 10000;
}  // namespace

static std::vector<Block> parse_impl(const std::string& text, const std::string& name, ParseState& st, int depth);

static std::vector<Block> read_impl(const std::string& path, ParseState& st, int depth, const SourceLocation* from) {
  std::string text;
  try {
    if (from && ++st.include_files > kMaxIncludeFiles)
      throw std::runtime_error("*INCLUDE: more than " + std::to_string(kMaxIncludeFiles) +
                               " files read in one include tree (a file included many times over?)");
    const uint64_t left = kMaxIncludeTreeBytes - std::min(kMaxIncludeTreeBytes, st.include_bytes);
    std::error_code ec;
    if (from) {
      const uint64_t size = std::filesystem::file_size(path, ec);  // ec: not there or not a file, said below
      if (!ec && size > left)
        throw std::runtime_error("*INCLUDE '" + path + "' (" + std::to_string(size) + " bytes) would take the include " +
                                 "tree past the " + std::to_string(kMaxIncludeTreeBytes) + " bytes it may read (" +
                                 std::to_string(st.include_bytes) + " read so far)");
    }
    // The bound again as the file is read: it may have grown since.
    text = read_text_file(path, "include file", from ? left : kMaxInputFileBytes);
    if (from) st.include_bytes += text.size();
  } catch (const std::runtime_error& e) {
    if (from) throw InputError(*from, e.what());
    throw;
  }
  return parse_impl(text, path, st, depth);
}

static std::vector<Block> parse_impl(const std::string& text, const std::string& name, ParseState& st, int depth) {
  constexpr int kMaxIncludeDepth = 16;
  std::vector<Block> blocks;
  if (depth == 0) st.master_dir = directory_of(name);
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    SourceLocation where{name, line_no};
    std::string t = trim(raw);
    if (t.empty()) {
      if (st.blank_cards && !blocks.empty()) blocks.back().cards.push_back(Card{where, std::string(), {}, false});
      continue;
    }
    if (is_block_header(t)) {
      Block b;
      b.where = where;
      const size_t end = std::min(t.size(), t.find_first_of(" \t,"));
      b.keyword = to_upper(t.substr(0, end));
      b.options = trim(t.substr(end));
      // *END ends the file it stands in, as in LS-DYNA: the rest of that file
      // is not read. An included file's *END ends only that file (it once
      // dropped every keyword after the *INCLUDE); the master deck's is kept
      // for its reader.
      if (b.keyword == "*END") {
        if (depth == 0) blocks.push_back(std::move(b));
        break;
      }
      blocks.push_back(std::move(b));
      continue;
    }
    if (t[0] == '$') continue;  // comment
    if (blocks.empty())
      throw InputError(where, "data line before the first keyword: expected a line starting "
                              "with '*' (e.g. *KEYWORD) or '$FMU_'");
    Card c;
    c.where = where;
    c.text = raw;
    c.comma_separated = raw.find(',') != std::string::npos;
    c.fields = c.comma_separated ? split_commas(raw) : std::vector<std::string>{t};
    blocks.back().cards.push_back(std::move(c));
  }
  if (!st.follow_includes) return blocks;

  std::vector<Block> out;
  for (auto& b : blocks) {
    if (b.keyword == "*INCLUDE_PATH" || b.keyword == "*INCLUDE_PATH_RELATIVE") {
      for (const auto& c : b.cards) {
        std::string dir = trim(c.text);
        if (dir.empty()) continue;
        if (dir.back() != '/') dir += '/';
        st.include_paths.push_back(dir[0] == '/' ? dir : directory_of(name) + dir);
      }
      continue;
    }
    if (b.keyword != "*INCLUDE") {
      out.push_back(std::move(b));
      continue;
    }
    if (depth >= kMaxIncludeDepth) b.fail("*INCLUDE nested deeper than 16 levels (a cycle?)");
    for (const auto& c : b.cards) {
      const std::string file = trim(c.text);
      if (file.empty()) continue;
      // As LS-DYNA looks: the including file's folder, then the master
      // deck's, then each *INCLUDE_PATH in the order given.
      std::string path = file[0] == '/' ? file : directory_of(name) + file;
      std::error_code ec;
      if (file[0] != '/' && !std::filesystem::exists(path, ec)) {
        std::vector<std::string> tried{directory_of(name)};
        if (st.master_dir != directory_of(name)) tried.push_back(st.master_dir);
        for (const std::string& dir : st.include_paths) tried.push_back(dir);
        bool found = false;
        for (const std::string& dir : tried)
          if (std::filesystem::exists(dir + file, ec)) {
            path = dir + file, found = true;
            break;
          }
        if (!found) {
          std::string where;
          for (const std::string& dir : tried) where += std::string(where.empty() ? "" : ", ") + (dir.empty() ? "./" : dir);
          throw InputError(c.where, "*INCLUDE '" + file + "' is in none of the folders looked in: " + where +
                                        " (the including file's, the master deck's, then *INCLUDE_PATH's)");
        }
      }
      auto inc = read_impl(path, st, depth + 1, &c.where);
      for (auto& ib : inc) out.push_back(std::move(ib));
    }
  }
  return out;
}

std::vector<Block> parse_keyword_text(const std::string& text, const std::string& name, bool follow_includes,
                                      bool blank_cards) {
  ParseState st{follow_includes, blank_cards, {}, {}};
  return parse_impl(text, name, st, 0);
}

std::vector<Block> read_keyword_file(const std::string& path, bool follow_includes) {
  ParseState st{follow_includes, false, {}, {}};
  return read_impl(path, st, 0, nullptr);
}

}  // namespace config
