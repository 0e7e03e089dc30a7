#include "config/keyword_reader.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

std::string read_text_file(const std::string& path, const std::string& what) {
  // Only regular files: a device (/dev/zero) or a FIFO would never end.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error("cannot open " + what + " '" + path + "': not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + what + " '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

double parse_real(const std::string& text, const SourceLocation& where, const std::string& what) {
  std::string t = trim(text);
  // Fortran-style exponents ("1.0d-6") appear in decks written by older tools.
  for (char& c : t)
    if (c == 'd' || c == 'D') c = 'e';
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

static std::vector<Block> parse_impl(const std::string& text, const std::string& name,
                                     bool follow_includes, int depth);

static std::vector<Block> read_impl(const std::string& path, bool follow_includes, int depth,
                                    const SourceLocation* from) {
  std::string text;
  try {
    text = read_text_file(path, "include file");
  } catch (const std::runtime_error& e) {
    if (from) throw InputError(*from, e.what());
    throw;
  }
  return parse_impl(text, path, follow_includes, depth);
}

static std::vector<Block> parse_impl(const std::string& text, const std::string& name,
                                     bool follow_includes, int depth) {
  constexpr int kMaxIncludeDepth = 16;
  std::vector<Block> blocks;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    SourceLocation where{name, line_no};
    std::string t = trim(raw);
    if (t.empty()) continue;
    if (is_block_header(t)) {
      Block b;
      b.where = where;
      std::string kw = t.substr(0, t.find_first_of(" \t,"));
      b.keyword = to_upper(kw);
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
  if (!follow_includes) return blocks;

  std::vector<Block> out;
  for (auto& b : blocks) {
    if (b.keyword != "*INCLUDE") {
      out.push_back(std::move(b));
      continue;
    }
    if (depth >= kMaxIncludeDepth) b.fail("*INCLUDE nested deeper than 16 levels (a cycle?)");
    for (const auto& c : b.cards) {
      std::string file = trim(c.text);
      std::string path = (!file.empty() && file[0] == '/') ? file : directory_of(name) + file;
      auto inc = read_impl(path, true, depth + 1, &c.where);
      for (auto& ib : inc) out.push_back(std::move(ib));
    }
  }
  return out;
}

std::vector<Block> parse_keyword_text(const std::string& text, const std::string& name,
                                      bool follow_includes) {
  return parse_impl(text, name, follow_includes, 0);
}

std::vector<Block> read_keyword_file(const std::string& path, bool follow_includes) {
  return read_impl(path, follow_includes, 0, nullptr);
}

}  // namespace config
