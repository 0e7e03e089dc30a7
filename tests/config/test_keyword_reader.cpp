#include <gtest/gtest.h>

#include "config/keyword_reader.hpp"

using config::InputError;
using config::parse_keyword_text;

TEST(KeywordReader, BlocksCardsAndComments) {
  auto blocks = parse_keyword_text(
      "$ a comment\n*KEYWORD\n*NODE\n$ nid, x\n1, 0.5, 2\n       2       1.0\n$FMU_SETTINGS\nmodel, x\n", "deck.k");
  ASSERT_EQ(blocks.size(), 3u);
  EXPECT_EQ(blocks[1].keyword, "*NODE");
  ASSERT_EQ(blocks[1].cards.size(), 2u);
  EXPECT_TRUE(blocks[1].cards[0].comma_separated);
  EXPECT_EQ(blocks[1].cards[0].fields.size(), 3u);
  EXPECT_EQ(blocks[1].cards[0].where.line, 5);
  EXPECT_FALSE(blocks[1].cards[1].comma_separated);
  EXPECT_EQ(blocks[2].keyword, "$FMU_SETTINGS");
}

TEST(KeywordReader, FixedWidthSplit) {
  auto f = config::split_fixed("       1     2.5       -3e-2", {8, 8, 12});
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0], "1");
  EXPECT_EQ(f[1], "2.5");
  EXPECT_EQ(f[2], "-3e-2");
}

TEST(KeywordReader, ErrorsNameFileAndLine) {
  try {
    parse_keyword_text("\n\n1, 2\n", "model.tlm");
    FAIL() << "a data line before any keyword must be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 3);
    EXPECT_NE(std::string(e.what()).find("model.tlm:3:"), std::string::npos);
  }
  auto blocks = parse_keyword_text("*X\n1, abc\n", "f.k");
  try {
    blocks[0].cards[0].real(1, "mass");
    FAIL() << "'abc' is not a number";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("f.k:2: field 2 (mass): expected a number, got 'abc'"), std::string::npos);
  }
  EXPECT_THROW(blocks[0].cards[0].real(5, "k"), InputError);  // missing field
}

TEST(KeywordReader, NumbersAcceptFortranExponents) {
  EXPECT_DOUBLE_EQ(config::parse_real("1.5d-3", {"x", 1}, "v"), 1.5e-3);
  EXPECT_THROW(config::parse_real("1.5.3", {"x", 1}, "v"), InputError);
  EXPECT_THROW(config::parse_integer("2.5", {"x", 1}, "v"), InputError);
}

// LS-DYNA's fixed-width decks drop the exponent's letter to save a column.
TEST(KeywordReader, NumbersAcceptExponentsWithoutTheirLetter) {
  EXPECT_DOUBLE_EQ(config::parse_real("2.00000-3", {"x", 1}, "v"), 2e-3);
  EXPECT_DOUBLE_EQ(config::parse_real("-1.5+2", {"x", 1}, "v"), -150.0);
  EXPECT_DOUBLE_EQ(config::parse_real("7-1", {"x", 1}, "v"), 0.7);
  EXPECT_DOUBLE_EQ(config::parse_real("-3", {"x", 1}, "v"), -3.0);
  EXPECT_THROW(config::parse_real("1-2-3", {"x", 1}, "v"), InputError);
  EXPECT_THROW(config::parse_real("1.0e-3-2", {"x", 1}, "v"), InputError);
  EXPECT_THROW(config::parse_real("a-3", {"x", 1}, "v"), InputError);
}

// A keyword's header keeps what follows the name (LS-DYNA's "+" long-format
// switch, "LONG=Y"); with blank cards on, a blank line in a block is a card
// of defaults (no fields), before the first keyword it is nothing.
TEST(KeywordReader, HeaderOptionsAndBlankCards) {
  const std::string text = "\n*KEYWORD LONG=Y\n*PART +\n\n1, 2, 3\n\n*END\n";
  auto plain = parse_keyword_text(text, "d.k");
  ASSERT_EQ(plain.size(), 3u);
  EXPECT_EQ(plain[0].options, "LONG=Y");
  EXPECT_EQ(plain[1].keyword, "*PART");
  EXPECT_EQ(plain[1].options, "+");
  EXPECT_EQ(plain[1].cards.size(), 1u);
  auto blanks = parse_keyword_text(text, "d.k", false, true);
  ASSERT_EQ(blanks[1].cards.size(), 3u);
  EXPECT_TRUE(blanks[1].cards[0].fields.empty());
  EXPECT_EQ(blanks[1].cards[0].where.line, 4);
  EXPECT_EQ(blanks[1].cards[1].fields.size(), 3u);
}
