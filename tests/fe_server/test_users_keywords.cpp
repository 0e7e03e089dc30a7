// Keywords as users' decks write them (LS-PrePost's output, public example
// decks): the _TITLE and _ID forms, cards that spell out LS-DYNA's
// defaults, run controls that change no result, and the refusals that say
// why. Each form is read against its plain twin, field by field.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "config/keyword_reader.hpp"
#include "deck_errors.hpp"
#include "input/deck_reader.hpp"
#include "process.hpp"

namespace {

// One hex8 cube (nodes 1-8), its part, and what the caller adds.
std::string cube(const std::string& rest) {
  return "*KEYWORD\n*NODE\n1,0,0,0\n2,0.01,0,0\n3,0.01,0.01,0\n4,0,0.01,0\n"
         "5,0,0,0.01\n6,0.01,0,0.01\n7,0.01,0.01,0.01\n8,0,0.01,0.01\n"
         "*PART\ncube\n1,1,1\n*SECTION_SOLID\n1,1\n*ELEMENT_SOLID\n1,1,1,2,3,4,5,6,7,8\n" +
         rest + "*END\n";
}

using fe_test::deck_error;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

bool warned(const fe::DeckWarnings& w, const std::string& part) {
  for (const std::string& m : w.messages)
    if (has(m, part)) return true;
  return false;
}

}  // namespace

// LS-PrePost writes *MAT_024's EPS/ES cards as zeros when the curve is
// SIGY/ETAN (or LCSS): LS-DYNA then takes SIGY and ETAN, and so must we.
// Strains without stresses are a mistake and stop at the ES card's line.
TEST(UsersKeywords, ZeroCurveCardsOfMat024MeanSigyAndEtan) {
  const std::string zeros = "0.0,0.0,0.0,0.0,0.0,0.0,0.0,0.0\n";
  const fe::Model m = fe::parse_deck(
      cube("*MAT_PIECEWISE_LINEAR_PLASTICITY\n1,7850,200e9,0.3,250e6,2e9\n0,0,0,0,0\n" + zeros + zeros), "deck.k");
  const fe::Material& mat = m.materials.at(1);
  EXPECT_TRUE(mat.hardening_strain.empty());
  EXPECT_EQ(mat.yield, 250e6);
  EXPECT_DOUBLE_EQ(mat.plastic_modulus, 200e9 * 2e9 / (200e9 - 2e9));
  double slope = 0.0;
  EXPECT_DOUBLE_EQ(mat.yield_stress(0.01, &slope), 250e6 + 0.01 * mat.plastic_modulus);
  // A real curve on the same cards is still read as a curve.
  const fe::Model c = fe::parse_deck(
      cube("*MAT_PIECEWISE_LINEAR_PLASTICITY\n1,7850,200e9,0.3,999e6,0\n0,0,0,0,0\n0,0.002,0.01\n250e6,260e6,270e6\n"),
      "deck.k");
  EXPECT_EQ(c.materials.at(1).hardening_stress.size(), 3u);
  EXPECT_EQ(c.materials.at(1).yield_stress(0.0, &slope), 250e6);
  const std::string e = deck_error(
      cube("*MAT_PIECEWISE_LINEAR_PLASTICITY\n1,7850,200e9,0.3,250e6,2e9\n0,0,0,0,0\n0,0.002,0.01\n" + zeros));
  EXPECT_TRUE(has(e, "deck.k:22: EPS are given but every ES is 0")) << e;
}

// Every material, node set and SPC of the titled deck must be the plain
// deck's: the heading cards are taken off, not read as data.
TEST(UsersKeywords, TitledAndIdFormsReadAsTheirPlainTwins) {
  const std::string plain = cube(
      "*MAT_PLASTIC_KINEMATIC\n1,7850,200e9,0.3,250e6,2e9,0.5\n"
      "*MAT_PIECEWISE_LINEAR_PLASTICITY\n2,7800,210e9,0.29,300e6,1e9\n"
      "*SET_NODE_LIST_GENERATE\n7\n1,2,5,6\n"
      "*SET_NODE_LIST\n8\n3,4\n"
      "*BOUNDARY_SPC_SET\n7,0,1,1,1\n*BOUNDARY_SPC_SET\n8,0,0,0,1\n");
  const std::string titled = cube(
      "*MAT_PLASTIC_KINEMATIC_TITLE\nsteel 003\n1,7850,200e9,0.3,250e6,2e9,0.5\n"
      "*MAT_PIECEWISE_LINEAR_PLASTICITY_TITLE\nsteel 024\n2,7800,210e9,0.29,300e6,1e9\n"
      "*SET_NODE_LIST_GENERATE_TITLE\nbottom and front\n7,0.0,0.0,0.0,0.0\n1,2,5,6\n"
      "*SET_NODE_LIST_TITLE\nback\n8\n3,4\n"
      // Two definitions in one block, an ID card before each.
      "*BOUNDARY_SPC_SET_ID\n1,clamp\n7,0,1,1,1\n2,slide\n8,0,0,0,1\n");
  const fe::Model a = fe::parse_deck(plain, "plain.k"), b = fe::parse_deck(titled, "titled.k");
  for (int id : {1, 2}) {
    const fe::Material &ma = a.materials.at(id), &mb = b.materials.at(id);
    EXPECT_EQ(ma.rho, mb.rho) << id;
    EXPECT_EQ(ma.E, mb.E) << id;
    EXPECT_EQ(ma.yield, mb.yield) << id;
    EXPECT_EQ(ma.plastic_modulus, mb.plastic_modulus) << id;
    EXPECT_EQ(ma.beta, mb.beta) << id;
  }
  EXPECT_EQ(b.materials.at(1).beta, 0.5);
  ASSERT_EQ(b.node_sets.at(7), (std::vector<int>{1, 2, 5, 6})) << "the ranges 1-2 and 5-6";
  EXPECT_EQ(b.node_sets.at(7), a.node_sets.at(7));
  for (size_t i = 0; i < a.fixed.size(); ++i) EXPECT_EQ(a.fixed[i], b.fixed[i]) << "node " << a.node_ids[i];
  EXPECT_TRUE(b.fixed[0].all()) << "node 1: set 7, x y z";
  EXPECT_TRUE(b.fixed[2].z() && !b.fixed[2].x()) << "node 3: set 8, z only (the second definition)";
  // An ID block whose cards do not pair up says so instead of misreading one.
  EXPECT_TRUE(has(deck_error(cube("*SET_NODE_LIST\n8\n3,4\n*BOUNDARY_SPC_SET_ID\n1,a\n8,0,0,0,1\n8,0,1,0,0\n")),
                  "expected a ID card and 1 card(s) per definition, got 3 cards"));
}

// A contact's _ID or _TITLE puts one heading card before its cards.
TEST(UsersKeywords, ContactHeadingsAreTakenOff) {
  const std::string sets = "*SET_NODE_LIST\n1\n5,6,7,8\n*SET_SEGMENT\n2\n1,2,3,4\n*MAT_ELASTIC\n1,7850,2e11,0.3\n";
  const std::string cards = "1,2,4,0\n0.0,0.0\n";
  const fe::Model a = fe::parse_deck(cube(sets + "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n" + cards), "a.k");
  for (const char* form : {"_ID\n7,contact seven\n", "_TITLE\n7,contact seven\n"}) {
    const fe::Model b = fe::parse_deck(cube(sets + "*CONTACT_AUTOMATIC_NODES_TO_SURFACE" + form + cards), "b.k");
    ASSERT_EQ(b.contacts.size(), a.contacts.size()) << form;
  }
  ASSERT_EQ(a.contacts.size(), 1u);
}

// Run controls set how LS-DYNA runs, not what it computes: noted, and the
// model is the one without them. Defaults written out are defaults; a
// value that is not one still stops at its line.
TEST(UsersKeywords, RunControlsAndWrittenOutDefaultsChangeNothing) {
  const std::string mat = "*MAT_ELASTIC\n1,7850,2e11,0.3\n";
  fe::DeckWarnings w;
  const fe::Model m = fe::parse_deck(
      cube(mat + "*KEYWORD_ID\nproject,1,stage\n*CONTROL_PARALLEL\n4,0,1,0\n*CONTROL_MPP_IO_NODUMP\n"
                 "*CONTROL_CONTACT\n0.1,0.0,1,0,1,0,1,0\n0,0,0,0,4.0,0,0,0\n0.0,0.0,0.0,0.0\n0,0,0,0\n"
                 "0,0,1,0.0,1.0\n"
                 "*CONTROL_SHELL\n20.0,0,-1,0,2,2,1,0\n"),
      "deck.k", &w);
  EXPECT_EQ(m.solids.size(), 1u);
  EXPECT_TRUE(warned(w, "*CONTROL_PARALLEL sets LS-DYNA's CPU count")) << "noted, not silent";
  EXPECT_TRUE(warned(w, "*CONTROL_MPP_IO_NODUMP"));
  EXPECT_TRUE(warned(w, "*CONTROL_CONTACT is not supported; its cards hold only LS-DYNA's defaults"));
  EXPECT_TRUE(warned(w, "*CONTROL_SHELL is not supported; its cards hold only LS-DYNA's defaults"));
  const std::string e = deck_error(cube(mat + "*CONTROL_CONTACT\n0.2\n"));
  EXPECT_TRUE(has(e, "deck.k:21: *CONTROL_CONTACT is not supported by this fe_server version and field 1 ('0.2')")) << e;
  EXPECT_TRUE(has(deck_error(cube(mat + "*CONTROL_CONTACT\n0.1\n0,0,0,0,3.0\n")), "field 5 ('3.0')"))
      << "XPENE 4 is the default, 3 is not";
}

// What users' decks carry and fe_server refuses: the message names the
// line, what is not modelled and what to do instead.
TEST(UsersKeywords, RefusalsSayWhyAndWhatToDo) {
  const std::string mat = "*MAT_ELASTIC\n1,7850,2e11,0.3\n";
  struct Case {
    std::string cards, expected;
  };
  const Case cases[] = {
      {"*MAT_NULL\n3,1000,-1e6,0.001\n*EOS_GRUNEISEN\n1,1647,2.48\n", "*MAT_NULL is not supported by this fe_server "
                                                                      "version: fluids with an equation of state"},
      {"*MAT_NULL\n3,1000\n*EOS_GRUNEISEN\n1,1647,2.48\n", "*EOS_GRUNEISEN is not supported"},
      {"*MAT_ADD_EROSION\n1\n", "element erosion is not modelled"},
      {"*CONSTRAINED_JOINT_SCREW_ID\n1,screw\n1,2,3,4\n", "*CONSTRAINED_JOINT_SCREW is not supported by this "
                                                          "fe_server version: joints are not modelled"},
      {"*CONTROL_IMPLICIT_GENERAL\n1,0.1\n", "(fe_server is explicit only"},
      {"*DATABASE_HISTORY_NODE_ID\n1,top\n", "*DATABASE_HISTORY_NODE is read by this fe_server version, but not its _ID "
                                             "form"},
      {"*MAT_NULL_TITLE\nwater\n3,1000\n", "*MAT_NULL is not supported"},
      {"*SECTION_SHELL\n2,2\n0.001\n", "ELFORM 2: 3D shells are not modelled"},
      {"*CONTROL_SOLID\n0,1\n", "*CONTROL_SOLID field 2 ('1') is not read by this fe_server version"},
      {"*CONTROL_SOLID\n2\n", "ESORT 2: 0 or 1"},
  };
  for (const Case& c : cases) {
    const std::string e = deck_error(cube(mat + c.cards));
    EXPECT_TRUE(has(e, "deck.k:2")) << "names its line (the cube takes lines 1-19): " << e;
    EXPECT_TRUE(has(e, c.expected)) << c.cards << "\n" << e;
  }
  // An implicit control of zeros only asks for LS-DYNA's default, explicit.
  fe::DeckWarnings w;
  EXPECT_NO_THROW(fe::parse_deck(cube(mat + "*CONTROL_IMPLICIT_GENERAL\n0,0.0\n"), "deck.k", &w));
  // Frequency-domain outputs are LS-DYNA's own: not "unknown".
  EXPECT_TRUE(has(deck_error(cube(mat + "*DATABASE_FREQUENCY_BINARY_D3PSD\n1\n*FREQUENCY_DOMAIN_SSD\n1\n")),
                  "*FREQUENCY_DOMAIN_SSD is not supported by this fe_server version: frequency-domain"));
}

// fe_server --check reads a deck (and its port tables) as a run would and
// says what it holds, or stops with every error, without a run: 0 for a
// deck that would run, 3 (the input error's code) for one that would not,
// and 3 for a coupling step the model's stable step cannot take.
TEST(FeServerCheck, SaysWhatTheDeckHoldsOrWhyItWouldNotRun) {
  const testing_support::TempDir dir;
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.file(name)) << text;
    return dir.file(name);
  };
  const std::string good = write("good.k", cube("*MAT_ELASTIC\n1,7850,2e11,0.3\n*SET_SEGMENT\n1\n5,6,7,8\n"
                                                "*USER_LOADING_SET\n1,PRESSS,1\n*CONTROL_TERMINATION\n1e-4\n"));
  {
    testing_support::ChildProcess p({PCS_FE_SERVER_EXE, "--model", good, "--check"});
    EXPECT_EQ(p.wait(30.0), 0) << p.output();
    EXPECT_NE(p.output().find("it would run"), std::string::npos) << p.output();
    EXPECT_NE(p.output().find("8 nodes; 1 hexahedra, 0 tetrahedra"), std::string::npos) << p.output();
    EXPECT_NE(p.output().find("steps"), std::string::npos) << p.output();
  }
  {
    const std::string bad = write("bad.k", cube("*MAT_NULL\n1,1000\n"));
    testing_support::ChildProcess p({PCS_FE_SERVER_EXE, "--model", bad, "--check"});
    EXPECT_EQ(p.wait(30.0), 3) << p.output();
    EXPECT_NE(p.output().find("*MAT_NULL is not supported"), std::string::npos) << p.output();
  }
  {
    // A 1 cm steel cube's stable step is about 1e-6 s: a 1e-5 s coupling step
    // in one FE step cannot run.
    const std::string ports = write("ports.cfg", "$FMU_SETTINGS\nmodel, cube\ntimestep, 1e-5\n$FMU_HOPSAN_PORTS\n"
                                                 "1, top, Hydraulic\n$FMU_HOPSAN_SEND\n1, pressure\n"
                                                 "$FMU_HOPSAN_RECEIVE\n1, flow\n");
    testing_support::ChildProcess p({PCS_FE_SERVER_EXE, "--model", good, "--ports", ports, "--check"});
    EXPECT_EQ(p.wait(30.0), 3) << p.output();
    EXPECT_NE(p.output().find("exceeds the stable step"), std::string::npos) << p.output();
  }
}
