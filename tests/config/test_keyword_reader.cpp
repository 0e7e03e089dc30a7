#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "config/cli.hpp"
#include "config/keyword_reader.hpp"
#include "config/nearest.hpp"

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

// An include tree is bounded as a whole: a file that includes the next ten
// times, eight levels deep, names the last one 10^8 times (it once took
// 3.3 GB and 51 s before bad_alloc). It is refused at the 10 000th file read,
// at the *INCLUDE card that went past, in well under a second.
TEST(KeywordReader, AnIncludeTreeThatFansOutIsRefusedAtItsBound) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("pcs_fanout_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (int level = 0; level < 8; ++level) {
    std::ofstream f(dir / ("level" + std::to_string(level) + ".k"));
    f << "*KEYWORD\n*INCLUDE\n";
    for (int i = 0; i < 10; ++i) f << "level" << level + 1 << ".k\n";
  }
  std::ofstream(dir / "level8.k") << "*KEYWORD\n*PART\npart\n1,1,1\n";
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  try {
    config::read_keyword_file((dir / "level0.k").string(), true);
  } catch (const InputError& e) {
    why = e.what();
  }
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(why.find("more than 10000 files read in one include tree"), std::string::npos) << why;
  EXPECT_NE(why.find(".k:"), std::string::npos) << "at the card's file and line: " << why;
  EXPECT_LT(took, 5.0) << "the bound stops it early";
  // One file larger than what the tree may read (sparse: no disk used) is
  // refused before it is read; a master deck past the 4 GiB of any input too.
  {
    std::ofstream(dir / "big.k");
    fs::resize_file(dir / "big.k", 3ull << 30);
    std::ofstream(dir / "takes_big.k") << "*KEYWORD\n*INCLUDE\nbig.k\n";
    const auto t0 = std::chrono::steady_clock::now();
    std::string big_why;
    try {
      config::read_keyword_file((dir / "takes_big.k").string(), true);
    } catch (const InputError& e) {
      big_why = e.what();
    }
    EXPECT_NE(big_why.find("takes_big.k:3"), std::string::npos) << big_why;
    EXPECT_NE(big_why.find("would take the include tree past the 2147483648 bytes"), std::string::npos) << big_why;
    fs::resize_file(dir / "big.k", 5ull << 30);
    std::string master_why;
    try {
      config::read_keyword_file((dir / "big.k").string(), true);
    } catch (const std::runtime_error& e) {
      master_why = e.what();
    }
    EXPECT_NE(master_why.find("more than the 4294967296 this reader accepts"), std::string::npos) << master_why;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0) << "nothing read";
    fs::remove(dir / "big.k");
  }
  // A tree that only fans out a little reads as before.
  std::ofstream(dir / "small.k") << "*KEYWORD\n*INCLUDE\nlevel7.k\nlevel7.k\n";
  EXPECT_EQ(config::read_keyword_file((dir / "small.k").string(), true).size(), 1u + 2u * (1u + 10u * 2u))
      << "*KEYWORD, then twice level7: its *KEYWORD and ten times level8 (*KEYWORD, *PART)";
  fs::remove_all(dir);
}

// An include that is not a regular file (a FIFO would block, /dev/zero
// would never end) is refused at its card.
TEST(KeywordReader, AnIncludeThatIsNotARegularFileIsRefusedAtItsCard) {
  const std::string deck = "*KEYWORD\n*INCLUDE\n/dev/zero\n";
  try {
    config::parse_keyword_text(deck, "deck.k", true);
    FAIL() << "/dev/zero must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("deck.k:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

// *END ends the file it stands in: in an included file only that file (it
// once ended the whole deck, every keyword after the *INCLUDE dropped with
// exit 0); in the master deck the deck. Lines after it are not read at all.
TEST(KeywordReader, EndInAnIncludedFileEndsOnlyThatFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("pcs_end_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "part.k") << "*KEYWORD\n*PART\nincluded\n*END\n*MAT_ELASTIC\nnot read\n";
  std::ofstream(dir / "main.k") << "*KEYWORD\n*INCLUDE\npart.k\n*NODE\n1,0,0,0\n*END\nanything at all\n";
  const auto blocks = config::read_keyword_file((dir / "main.k").string(), true);
  std::vector<std::string> keywords;
  for (const auto& b : blocks) keywords.push_back(b.keyword);
  EXPECT_EQ(keywords, (std::vector<std::string>{"*KEYWORD", "*KEYWORD", "*PART", "*NODE", "*END"}));
  fs::remove_all(dir);
}

// Include paths as LS-DYNA resolves them: from the including file's folder,
// then from the master deck's, then *INCLUDE_PATH. A file in sub/ that
// includes "mat.k" kept beside the master deck was not found.
TEST(KeywordReader, AnIncludeIsLookedForBesideTheIncludingFileThenBesideTheMasterDeck) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("pcs_inc_" + std::to_string(::getpid()));
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "mat.k") << "*MAT_ELASTIC\nmaster's\n";
  std::ofstream(dir / "sub" / "local.k") << "*SECTION_SOLID\nlocal\n";
  std::ofstream(dir / "sub" / "parts.k") << "*PART\nin sub\n*INCLUDE\nlocal.k\nmat.k\n";
  std::ofstream(dir / "main.k") << "*KEYWORD\n*INCLUDE\nsub/parts.k\n*END\n";
  const auto blocks = config::read_keyword_file((dir / "main.k").string(), true);
  std::vector<std::string> keywords;
  for (const auto& b : blocks) keywords.push_back(b.keyword + ":" + (b.cards.empty() ? "" : b.cards.front().text));
  EXPECT_EQ(keywords, (std::vector<std::string>{"*KEYWORD:", "*PART:in sub", "*SECTION_SOLID:local",
                                                "*MAT_ELASTIC:master's", "*END:"}));
  // Beside neither: refused at its card, naming where it looked.
  std::ofstream(dir / "sub" / "parts.k") << "*PART\nin sub\n*INCLUDE\nnowhere.k\n";
  try {
    config::read_keyword_file((dir / "main.k").string(), true);
    ADD_FAILURE() << "a missing include was not refused";
  } catch (const config::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("parts.k:4: *INCLUDE 'nowhere.k' is in none of the folders looked in: " + (dir / "sub").string() +
                     "/, " + dir.string() + "/"),
              std::string::npos)
        << m;
  }
  fs::remove_all(dir);
}

// "Did you mean": the nearest candidate within a third of the word's edits,
// and an unknown option told the nearest of the options the program tested
// for (it tests them all before it calls unknown()).
TEST(Nearest, ACloseMisspellingIsNamedAndAFarOneIsNot) {
  EXPECT_EQ(config::edit_distance("--modle", "--model"), 2u);
  EXPECT_EQ(config::nearest("--modle", {"--out", "--model", "--ports"}), "--model");
  EXPECT_EQ(config::nearest("HydraulicVolumC", {"HydraulicVolumeC", "PressureSourceC"}), "HydraulicVolumeC");
  EXPECT_EQ(config::nearest("--xyz", {"--out", "--model"}), "") << "3 edits of 5 letters is not a misspelling";
  std::vector<std::string> words{"prog", "--ouT"};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  config::Args args(static_cast<int>(argv.size()), argv.data());
  try {
    while (args.next()) {
      if (args.is("--out")) continue;
      if (args.is("--model")) continue;
      if (args.is_option()) args.unknown();
    }
    ADD_FAILURE() << "--ouT was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown argument --ouT (did you mean --out?)");
  }
}
