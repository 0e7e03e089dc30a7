// Reads the LS-DYNA keyword subset that fe_server understands, with
// LS-DYNA's card grammar (input/deck_grammar.hpp): comma-separated or
// fixed-width cards (10 characters; *NODE 8/16/16/16/8/8; *ELEMENT_MASS
// 8/8/16/8; long format and I10 as the deck asks). A keyword it does not
// read is an error with file:line unless it provably changes no result
// (output requests, *CONTROL_ cards of defaults only): those are warnings.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace fe {

struct DeckWarnings {
  std::vector<std::string> messages;
  // A substitution that changes the physics (another hourglass type,
  // another element formulation) is refused unless
  // `approximate` (fe_server --approximate); then each is listed here too.
  bool approximate = false;
  std::vector<std::string> substitutions;
};

// A deck with errors is refused with all of them, up to this many, each
// with its file:line (the first one's location is the exception's).
constexpr size_t kMaxDeckErrors = 20;

Model read_deck(const std::string& path, DeckWarnings* warnings = nullptr);
Model parse_deck(const std::string& text, const std::string& name, DeckWarnings* warnings = nullptr);

// The keywords the reader reads, and what it makes of each, as Markdown
// (the page docs/lsdyna_keywords.md; fe_server --keywords prints it).
std::string deck_keyword_coverage();

}  // namespace fe
