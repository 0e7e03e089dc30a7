// Reads the LS-DYNA keyword subset that fe_server understands. Cards may be
// comma-separated or fixed-width (10 characters; *NODE 8/16/16/16/8/8;
// *ELEMENT_MASS 8/8/16/8). Unknown keywords are warnings with file:line.
#pragma once

#include <string>
#include <vector>

#include "model/model.hpp"

namespace fe {

struct DeckWarnings {
  std::vector<std::string> messages;
};

Model read_deck(const std::string& path, DeckWarnings* warnings = nullptr);
Model parse_deck(const std::string& text, const std::string& name, DeckWarnings* warnings = nullptr);

}  // namespace fe
