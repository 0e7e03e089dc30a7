// The error a deck's text raises in the reader ("" if it reads), for tests
// that check a refusal's words and line.
#pragma once

#include <string>

#include "config/keyword_reader.hpp"
#include "input/deck_reader.hpp"

namespace fe_test {

inline std::string deck_error(const std::string& text, const std::string& name = "deck.k") {
  try {
    fe::parse_deck(text, name);
  } catch (const config::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace fe_test
