// LS-DYNA's keyword grammar around the keywords fe_server reads, applied to
// the parsed blocks before any keyword is interpreted (deck_reader.cpp):
//
//  - long format: "*KEYWORD LONG=Y" (every field 20 columns, the whole deck;
//    LONG=S back to standard), a keyword's own "+" (long) or "-" (standard);
//    "*KEYWORD I10=Y" (node and element ids 10 columns wide);
//  - the _TITLE and _ID options: their title / ID card is taken off and the
//    keyword read as its base (only for keywords whose card layout is known);
//  - blank cards: LS-DYNA reads a blank line as a card of defaults. Inside a
//    keyword with a fixed card layout (*PART's heading, *SECTION_SHELL's card
//    2, *INITIAL_VELOCITY_GENERATION's card 2, the *CONTROL_ cards) it stays
//    a card with no fields; in lists of records (nodes, elements, set
//    members) it says nothing and is dropped, as are blank lines after a
//    keyword's last card;
//  - order: LS-DYNA resolves every id after the whole deck is read, so the
//    blocks are put in definition order (*NODE, then the other definitions,
//    then everything that refers to them), each group in deck order.
#pragma once

#include <vector>

#include "config/keyword_reader.hpp"

namespace fe {

// The deck's blocks, normalised as above; an InputError names file:line of
// an option fe_server cannot honour.
std::vector<config::Block> normalise_blocks(std::vector<config::Block> blocks);

}  // namespace fe
