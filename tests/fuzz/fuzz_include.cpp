// Fuzz target: *INCLUDE in the FE keyword deck. The input is a main deck and
// an included file, split at the first line "#FILE"; both are written into
// a private folder where the main deck may include "inc.k" (which may
// include itself, or the main deck: a cycle must be refused, not followed).
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_folder.hpp"

#include "input/deck_reader.hpp"

namespace {
const std::string& folder() { return fuzz_support::private_folder("pcs_fuzz_include"); }
void write(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t cut = text.find("\n#FILE\n");
  const std::string main_deck = text.substr(0, cut);
  const std::string included = cut == std::string::npos ? "" : text.substr(cut + 7);
  write(folder() + "/main.k", main_deck);
  write(folder() + "/inc.k", included);
  try {
    fe::DeckWarnings warnings;
    (void)fe::read_deck(folder() + "/main.k", &warnings);
  } catch (const std::exception&) {
  }
  return 0;
}
