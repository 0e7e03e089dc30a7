// Keyword-style text input shared by the port configuration, the FE keyword
// deck and the TLM host model: `$` comment lines, blocks opened by `*KEYWORD`
// (LS-DYNA style) or `$FMU_...` (the thesis' port-file style), and cards of
// comma-separated or fixed-width fields. Every error names file:line.
#pragma once

#include <stdexcept>
#include <cstdint>
#include <string>
#include <vector>

namespace config {

struct SourceLocation {
  std::string file;
  int line = 0;
  // file:line, or the bare name for a place without lines (an option: "--set a.b=1").
  std::string str() const { return line > 0 ? file + ":" + std::to_string(line) : file; }
};

// A user-facing input error: "file:line: message".
class InputError : public std::runtime_error {
 public:
  InputError(const SourceLocation& where, const std::string& message)
      : std::runtime_error(where.str() + ": " + message), where_(where) {}
  const SourceLocation& where() const { return where_; }

 private:
  SourceLocation where_;
};

// One data line of a block. If the line has a comma, `fields` holds the
// comma-separated fields, trimmed; otherwise the card is fixed-width and the
// reader of that keyword splits `text` with split_fixed().
struct Card {
  SourceLocation where;
  std::string text;
  std::vector<std::string> fields;
  bool comma_separated = false;

  size_t size() const { return fields.size(); }
  // Field i; `name` is used in the error message ("field 2 (mass)").
  const std::string& field(size_t i, const char* name) const;
  double real(size_t i, const char* name) const;
  // Field i as a number, or `fallback` when the field is absent or blank.
  double real_or(size_t i, const char* name, double fallback) const;
  long integer(size_t i, const char* name) const;
  long integer_or(size_t i, const char* name, long fallback) const;
  [[noreturn]] void fail(const std::string& message) const { throw InputError(where, message); }
};

struct Block {
  SourceLocation where;
  std::string keyword;  // upper case, with its leading '*' or '$'
  std::string options;  // the rest of the header line, trimmed (LS-DYNA: "+", "-", "LONG=Y")
  std::vector<Card> cards;
  [[noreturn]] void fail(const std::string& message) const { throw InputError(where, message); }
};

// Parse text that came from `name` (used in messages). If `follow_includes`
// is set, `*INCLUDE` blocks are replaced by the blocks of the named files,
// resolved relative to the including file, else in the directories of the
// `*INCLUDE_PATH` blocks read so far (LS-DYNA's search order). With
// `blank_cards` a blank line inside a block is a card (LS-DYNA reads it as a
// card of defaults: its text is empty and it has no fields); otherwise blank
// lines are skipped.
std::vector<Block> parse_keyword_text(const std::string& text, const std::string& name,
                                      bool follow_includes = false, bool blank_cards = false);
std::vector<Block> read_keyword_file(const std::string& path, bool follow_includes = false);

// Split a fixed-width card into fields of the given widths, trimmed; the last
// width repeats until the line ends.
std::vector<std::string> split_fixed(const std::string& line, const std::vector<int>& widths);

// Number parsing with a message that names what was expected. Reals take
// Fortran's forms too: "1.5d-3", and the exponent without its letter that
// fixed-width decks use to save a column ("2.00000-3" = 2e-3, "1.5+2" = 150).
double parse_real(const std::string& text, const SourceLocation& where, const std::string& what);
long parse_integer(const std::string& text, const SourceLocation& where, const std::string& what);

// Input files are regular files of bounded size: a FIFO would block the
// reader forever and /dev/zero would fill the memory (both were seen with
// --restart). Larger than any deck or checkpoint this tool is sized for
// (a 10-million-element deck is about 2 GB of text).
inline constexpr uint64_t kMaxInputFileBytes = 4ull << 30;  // 4 GiB

// The whole file as a string; throws std::runtime_error "cannot open <what>
// '<path>': <why>" for a missing file, one that is not a regular file (it is
// opened without blocking, then checked), or one larger than max_bytes.
std::string read_text_file(const std::string& path, const std::string& what = "file",
                           uint64_t max_bytes = kMaxInputFileBytes);
// The same, as bytes.
std::vector<uint8_t> read_binary_file(const std::string& path, const std::string& what = "file",
                                      uint64_t max_bytes = kMaxInputFileBytes);

std::string trim(const std::string& s);
std::string to_upper(std::string s);
std::string to_lower(std::string s);

}  // namespace config
