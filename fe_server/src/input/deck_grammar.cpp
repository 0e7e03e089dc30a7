#include "input/deck_grammar.hpp"

#include <algorithm>
#include <map>
#include <set>

namespace fe {

namespace {

using config::Block;
using config::Card;

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }
bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Keywords with a fixed card layout, where a blank card holds defaults.
bool fixed_layout(const std::string& kw) {
  static const std::set<std::string> kFixed = {
      "*PART", "*SECTION_SHELL", "*SECTION_BEAM", "*INITIAL_VELOCITY", "*INITIAL_VELOCITY_GENERATION", "*MAT_RIGID",
      "*MAT_020", "*PART_INERTIA", "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", "*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE",
      "*CONSTRAINED_NODAL_RIGID_BODY_SPC", "*DEFINE_CURVE", "*LOAD_BODY_X", "*LOAD_BODY_Y", "*LOAD_BODY_Z",
      "*LOAD_BODY_PARTS"};
  return kFixed.count(kw) || starts_with(kw, "*CONTROL_");
}

// _TITLE: cards per definition after the title card (0: one definition per
// block, its cards variable in number: only the first card is the title).
const std::map<std::string, int>& title_layouts() {
  static const std::map<std::string, int> kTitle = {
      {"*MAT_ELASTIC", 1}, {"*MAT_001", 1}, {"*MAT_SPRING_ELASTIC", 1}, {"*MAT_S01", 1},
      {"*MAT_DAMPER_VISCOUS", 1}, {"*MAT_S02", 1}, {"*SECTION_SOLID", 1}, {"*SECTION_SHELL", 2},
      {"*SECTION_BEAM", 2}, {"*SECTION_DISCRETE", 1}, {"*MAT_RIGID", 0}, {"*MAT_020", 0},
      {"*DEFINE_CURVE", 0}, {"*SET_NODE_LIST", 0}, {"*SET_PART_LIST", 0}, {"*SET_PART", 0},
      {"*SET_SEGMENT", 0}, {"*SET_SOLID", 0}, {"*SET_SOLID_LIST", 0}, {"*SET_SHELL", 0},
      {"*SET_SHELL_LIST", 0}, {"*SET_BEAM", 0}, {"*SET_BEAM_LIST", 0}, {"*SET_NODE_GENERATE", 0},
      {"*SET_NODE_ADD", 0}, {"*SET_PART_ADD", 0}, {"*SET_NODE_LIST_GENERATE", 0},
      {"*MAT_PLASTIC_KINEMATIC", 0}, {"*MAT_003", 0}, {"*MAT_PIECEWISE_LINEAR_PLASTICITY", 0}, {"*MAT_024", 0}};
  return kTitle;
}

// Takes the title or ID cards off: one before every `per` cards, or only the
// first card when per = 0.
void drop_heading_cards(Block& b, int per, const char* what) {
  if (b.cards.empty()) b.fail(b.keyword + ": the " + what + " card is missing");
  std::vector<Card> kept;
  const size_t stride = per == 0 ? b.cards.size() : static_cast<size_t>(per) + 1;
  for (size_t i = 0; i < b.cards.size(); ++i)
    if (i % stride != 0) kept.push_back(b.cards[i]);
  if (per != 0 && b.cards.size() % stride != 0)
    b.fail(b.keyword + ": expected a " + what + " card and " + std::to_string(per) + " card(s) per definition, got " +
           std::to_string(b.cards.size()) + " cards");
  b.cards = std::move(kept);
}

// The contacts this reader reads, whose _ID and _TITLE forms put one
// heading card (CID, HEADING) before the contact's own cards.
bool contact_heading(const std::string& kw) {
  static const std::set<std::string> kContacts = {
      "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", "*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE",
      "*CONTACT_NODES_TO_SURFACE",             "*CONTACT_AUTOMATIC_NODES_TO_SURFACE",
      "*CONTACT_AUTOMATIC_SINGLE_SURFACE",     "*CONTACT_TIED_SURFACE_TO_SURFACE",
      "*CONTACT_TIED_NODES_TO_SURFACE",        "*CONTACT_FORCE_TRANSDUCER_PENALTY"};
  for (const char* suffix : {"_ID", "_TITLE"})
    if (ends_with(kw, suffix) && kContacts.count(kw.substr(0, kw.size() - std::string(suffix).size()))) return true;
  return false;
}

bool blank(const Card& c) { return !c.comma_separated && config::trim(c.text).empty(); }

// Definition order: 0 nodes, 1 what nodes make up (parts, sections,
// materials, sets, curves, elements), 2 everything that refers to those.
int tier(const std::string& kw) {
  if (kw == "*NODE") return 0;
  for (const char* p : {"*PART", "*SECTION_", "*MAT_", "*SET_", "*DEFINE_", "*ELEMENT_"})
    if (starts_with(kw, p)) return 1;
  return 2;
}

}  // namespace

std::vector<Block> normalise_blocks(std::vector<Block> blocks) {
  bool long_deck = false, i10 = false;
  for (Block& b : blocks) {
    if (b.keyword == "*KEYWORD_ID") {  // the deck's project, number and stage: a label, no physics
      b.keyword = "*KEYWORD";
      b.cards.clear();
    }
    if (b.keyword == "*KEYWORD") {
      const std::string o = config::to_upper(b.options);
      if (o.find("LONG=Y") != std::string::npos) long_deck = true;
      if (o.find("LONG=S") != std::string::npos) long_deck = false;
      if (o.find("I10=Y") != std::string::npos) i10 = true;
      continue;
    }
    bool long_format = long_deck;
    if (b.options == "+") long_format = true;
    if (b.options == "-") long_format = false;
    // The options.
    if (contact_heading(b.keyword)) {
      // A contact's _ID or _TITLE: one card (CID, HEADING) before its cards.
      const std::string base = b.keyword.substr(0, b.keyword.rfind('_'));
      while (!b.cards.empty() && blank(b.cards.back())) b.cards.pop_back();
      drop_heading_cards(b, 0, ends_with(b.keyword, "_ID") ? "ID" : "title");
      b.keyword = base;
    } else if (ends_with(b.keyword, "_TITLE") && b.keyword != "*TITLE") {
      const std::string base = b.keyword.substr(0, b.keyword.size() - 6);
      // Another keyword's _TITLE stays as it is: the reader refuses it, with
      // its reason (deck_reader.cpp, unsupported).
      const auto it = title_layouts().find(base);
      if (it != title_layouts().end()) {
        while (!b.cards.empty() && blank(b.cards.back())) b.cards.pop_back();
        drop_heading_cards(b, it->second, "title");
        b.keyword = base;
      }
    } else if (ends_with(b.keyword, "_ID")) {
      const std::string base = b.keyword.substr(0, b.keyword.size() - 3);
      while (!b.cards.empty() && blank(b.cards.back())) b.cards.pop_back();
      if (base == "*BOUNDARY_PRESCRIBED_MOTION_NODE" || base == "*BOUNDARY_PRESCRIBED_MOTION_SET" ||
          base == "*BOUNDARY_PRESCRIBED_MOTION_RIGID" || base == "*BOUNDARY_SPC_NODE" || base == "*BOUNDARY_SPC_SET")
        drop_heading_cards(b, 1, "ID");  // an ID card before each definition
      else
        continue;  // as a _TITLE above: the reader refuses it
      b.keyword = base;
    }
    // Blank cards. After the last card they are layout, except where a
    // keyword of two cards per record ends with a blank second card.
    static const std::set<std::string> kPairs = {"*PART", "*SECTION_SHELL", "*SECTION_BEAM", "*INITIAL_VELOCITY",
                                                 "*INITIAL_VELOCITY_GENERATION", "*CONSTRAINED_NODAL_RIGID_BODY_SPC"};
    const size_t period = kPairs.count(b.keyword) ? 2 : 1;
    while (!b.cards.empty() && blank(b.cards.back()) && (period == 1 || b.cards.size() % period != 0)) b.cards.pop_back();
    if (!fixed_layout(b.keyword))
      b.cards.erase(std::remove_if(b.cards.begin(), b.cards.end(), blank), b.cards.end());
    // Column widths other than the standard ones: split here, so the
    // keyword's reader gets the fields as if they had been comma-separated.
    std::vector<int> widths;
    if (long_format) widths = {20};
    else if (i10 && b.keyword == "*NODE") widths = {10, 16, 16, 16, 10, 10};
    else if (i10 && b.keyword == "*ELEMENT_MASS") widths = {10, 10, 16, 10};
    else if (i10 && b.keyword == "*ELEMENT_DISCRETE") widths = {10, 10, 10, 10, 10, 16, 10, 16};
    else if (i10 && starts_with(b.keyword, "*ELEMENT_")) widths = {10};
    if (!widths.empty() && b.keyword != "*TITLE")
      for (Card& c : b.cards)
        if (!c.comma_separated && !blank(c)) {
          c.fields = config::split_fixed(c.text, widths);
          c.comma_separated = true;
        }
  }
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const Block& a, const Block& b) { return tier(a.keyword) < tier(b.keyword); });
  return blocks;
}

}  // namespace fe
