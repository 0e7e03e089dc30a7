// The LS-DYNA deck corpus (tests/fe_server/lsdyna/): decks in the card styles
// LS-DYNA reads, each with a physical result or a twin to compare with.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "config/keyword_reader.hpp"
#include "input/deck_reader.hpp"
#include "solver/solver.hpp"

namespace {

const std::string kCorpus = PCS_LSDYNA_CORPUS_DIR;

// Node index by deck id, so two models are compared id for id.
int idx(const fe::Model& m, int id) { return m.node_index.at(id); }

}  // namespace

// Every card style of the messy twin (see its header) must give the model
// of the clean one: compared field by field, not through the log, then run.
TEST(DeckCorpus, TheMessyTwinReadsTheSameModelAsTheCleanOne) {
  fe::DeckWarnings w;
  const fe::Model a = fe::read_deck(kCorpus + "/column_clean.k");
  const fe::Model b = fe::read_deck(kCorpus + "/column_messy.k", &w);
  ASSERT_EQ(a.node_ids.size(), 20u);
  ASSERT_EQ(b.node_ids.size(), a.node_ids.size());
  for (int id : a.node_ids) {
    const size_t i = static_cast<size_t>(idx(a, id)), j = static_cast<size_t>(idx(b, id));
    EXPECT_EQ(a.x0[i], b.x0[j]) << "node " << id;
    EXPECT_EQ(a.v0[i], b.v0[j]) << "node " << id;
    EXPECT_EQ(a.mass[i], b.mass[j]) << "node " << id;
    EXPECT_EQ(a.fixed[i], b.fixed[j]) << "node " << id;
  }
  EXPECT_EQ(a.v0[static_cast<size_t>(idx(a, 17))].z(), -0.1);
  EXPECT_TRUE(a.fixed[static_cast<size_t>(idx(a, 3))].all());
  ASSERT_EQ(b.solids.size(), 4u);
  for (size_t e = 0; e < a.solids.size(); ++e) {
    EXPECT_EQ(a.solids[e].id, b.solids[e].id);
    EXPECT_EQ(a.solids[e].part, b.solids[e].part);
    for (int k = 0; k < 8; ++k)
      EXPECT_EQ(a.node_ids[static_cast<size_t>(a.solids[e].n[k])], b.node_ids[static_cast<size_t>(b.solids[e].n[k])]);
  }
  const fe::Material& ma = a.materials.at(1);
  const fe::Material& mb = b.materials.at(1);
  EXPECT_EQ(ma.rho, mb.rho);
  EXPECT_EQ(ma.E, mb.E);
  EXPECT_EQ(ma.nu, mb.nu);
  EXPECT_EQ(b.parts.at(1).title, "") << "a blank heading card is a blank title";
  ASSERT_EQ(b.segment_pressures.size(), 1u);
  EXPECT_EQ(b.segment_pressures[0].sf, 1e6);
  EXPECT_EQ(b.segment_pressures[0].segments.size(), 1u);
  EXPECT_EQ(b.curves.at(1).a, a.curves.at(1).a);
  EXPECT_EQ(b.curves.at(1).o, a.curves.at(1).o);
  ASSERT_EQ(b.history_nodes.size(), 2u);
  for (size_t k = 0; k < 2; ++k)
    EXPECT_EQ(a.node_ids[static_cast<size_t>(a.history_nodes[k])], b.node_ids[static_cast<size_t>(b.history_nodes[k])]);
  EXPECT_EQ(a.end_time, b.end_time);
  EXPECT_EQ(a.history_dt_global, b.history_dt_global);
  // The output-only keyword and the defaults-only control card are warnings.
  ASSERT_EQ(w.messages.size(), 2u);
  EXPECT_NE(w.messages[0].find("*CONTROL_SOLID"), std::string::npos) << w.messages[0];
  EXPECT_NE(w.messages[1].find("*DATABASE_MATSUM"), std::string::npos) << w.messages[1];

  // Same model, same motion: bit for bit.
  fe::Solver sa(a, 2e-7), sb(b, 2e-7);
  for (int k = 0; k < 200; ++k) {
    sa.step();
    sb.step();
  }
  for (int id : a.node_ids)
    EXPECT_EQ(sa.x()[static_cast<size_t>(idx(a, id))], sb.x()[static_cast<size_t>(idx(b, id))]) << "node " << id;
}

// *LOAD_SEGMENT on a curve, after its arrival time: the cube on rollers is
// in uniaxial stress. Dynamic: the ramp (1 ms) is 125 of the cube's
// periods (4·L/c ≈ 8 µs) long, so the ringing it leaves is ~p·T/(π·t_ramp)
// ≈ 0.3 % of p; 1 % bounds it. Nothing acts before AT.
TEST(DeckCorpus, ACurveDrivenSegmentPressureGivesTheUniaxialStress) {
  const fe::Model m = fe::read_deck(kCorpus + "/cube_pressure.k");
  const double p = 5e7, E = 2.1e11;
  fe::Solver s(m, 1e-7);
  const size_t top = static_cast<size_t>(idx(m, 7));
  while (s.time() < 4.9e-4) s.step();
  EXPECT_EQ(s.x()[top].z(), m.x0[top].z()) << "no load before AT";
  double worst_lateral = 0.0;
  while (s.time() < 2.5e-3) {
    s.step();
    if (s.time() > 1.6e-3) {
      EXPECT_NEAR(s.stress(0)(2), -p, 0.01 * p) << "sigma_zz at t = " << s.time();
      worst_lateral = std::max({worst_lateral, std::fabs(s.stress(0)(0)), std::fabs(s.stress(0)(1))});
    }
  }
  EXPECT_LT(worst_lateral, 0.01 * p) << "the rollers leave the sides free";
  const double strain = (s.x()[top].z() - m.x0[top].z()) / 0.01;
  EXPECT_NEAR(strain, -p / E, 0.01 * p / E);
  const double lateral = (s.x()[top].x() - m.x0[top].x()) / 0.01;
  EXPECT_NEAR(lateral, 0.3 * p / E, 0.01 * 0.3 * p / E) << "Poisson's expansion";
}

// A contact stiffness factor above the stable cap is said at start-up, with
// its line, not capped silently (contact.hpp explains the cap).
TEST(DeckCorpus, AContactStiffnessAboveTheCapIsSaid) {
  std::string deck = config::read_text_file(kCorpus + "/column_clean.k");
  deck.insert(deck.find("*END"), "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n2, 2, 0, 0\n0.0, 0.0, 0.0, 0.0, 20.0\n10.0\n");
  fe::DeckWarnings w;
  fe::parse_deck(deck, "sfs.k", &w);
  ASSERT_EQ(w.messages.size(), 1u);
  EXPECT_NE(w.messages[0].find("sfs.k:66: warning: SFS 10 asks for a stiffer contact"), std::string::npos)
      << w.messages[0];
  EXPECT_NE(w.messages[0].find("capped at SFS 2"), std::string::npos);
  deck.replace(deck.find("\n10.0\n"), 6, "\n2.0\n");
  fe::DeckWarnings quiet;
  fe::parse_deck(deck, "sfs.k", &quiet);
  EXPECT_TRUE(quiet.messages.empty());
}
