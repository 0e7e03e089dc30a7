// LS-DYNA's ASCII files (output/ascii_output.hpp), read back as a user's
// script would read LS-DYNA's: their values are the HDF5 history's at the
// same times, to the 5 significant digits of the %E fields (%12.4E: 5e-5
// relative, %14.5E: 5e-6), and they obey the physics the files report on:
// a free impact conserves momentum, contact forces are equal and opposite,
// the parts' energies add up to the global ones.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "h5io/timeseries.hpp"
#include "impact_decks.hpp"
#include "input/deck_reader.hpp"
#include "output/history.hpp"
#include "solver/solver.hpp"

namespace {

namespace fs = std::filesystem;

struct Run {
  fs::path dir;
  fe::Model model;
  double dt = 0.0, v0 = 8.0, piston_mass = 0.0;
  ~Run() { fs::remove_all(dir); }
};

// The coaxial impact with every ASCII file asked for at 20 FE steps, and a
// history node and a solid in the tool; run for 600 steps (the pulse passes
// the gauge).
std::unique_ptr<Run> run_impact() {
  auto r = std::make_unique<Run>();
  r->dir = fs::temp_directory_path() / ("pcs_ascii_" + std::to_string(::getpid()));
  fs::create_directories(r->dir);
  std::ostringstream d;
  d << fe_test::bar_impact_deck(0.1, 0.2, 0.01, 0.005, r->v0, fe_test::kE);
  r->model = fe::parse_deck(d.str(), "impact.k");
  r->dt = 0.9 * fe::Solver::stable_dt(r->model).dt;
  const double every = 20 * r->dt;
  std::ostringstream cards;
  for (const char* kw : {"GLSTAT", "MATSUM", "RCFORC", "NODOUT", "ELOUT"}) cards << "*DATABASE_" << kw << "\n" << every << ",\n";  // a comma card: no 10-column limit
  // A node and a solid of the tool, 40 mm below its top face (z = -0.04).
  int node = 0, solid = 0;
  for (size_t i = 0; i < r->model.x0.size() && !node; ++i)
    if (std::fabs(r->model.x0[i].z() + 0.04) < 1e-9) node = r->model.node_ids[i];
  for (const auto& e : r->model.solids)
    if (e.part == 2 && std::fabs(r->model.x0[static_cast<size_t>(e.n[0])].z() + 0.04) < 1e-9) solid = e.id;
  cards << "*DATABASE_HISTORY_NODE\n" << node << "\n*DATABASE_HISTORY_SOLID\n" << solid << "\n";
  r->model = fe::parse_deck(d.str() + cards.str(), "impact.k");
  for (size_t i = 0; i < r->model.x0.size(); ++i)
    if (r->model.v0[i].z() < 0.0) r->piston_mass += r->model.mass[i];
  fe::Solver s(r->model, r->dt);
  fe::History h((r->dir / "fe.h5").string(), r->model, nullptr, r->dt, every);
  for (int k = 0; k < 600; ++k) {
    s.step();
    h.record(s, {}, {});
  }
  h.flush();
  return r;
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

// glstat: every labelled value, by its label without the dots.
std::map<std::string, std::vector<double>> read_glstat(const fs::path& p) {
  std::map<std::string, std::vector<double>> out;
  for (const std::string& l : lines_of(p)) {
    const size_t dots = l.find("..");
    if (l.size() < 33 || dots == std::string::npos || l.rfind(" ", 0) != 0) continue;
    std::string label = l.substr(1, dots - 1);
    while (!label.empty() && label.back() == ' ') label.pop_back();
    out[label].push_back(std::stod(l.substr(32)));
  }
  return out;
}

// The value after "key=" in a matsum line.
double after(const std::string& line, const std::string& key) {
  const size_t at = line.find(key + "=");
  return at == std::string::npos ? NAN : std::stod(line.substr(at + key.size() + 1, 13));
}

// The integer right-aligned in the first `width` columns, or -1 (a header).
int leading_int(const std::string& l, size_t width) {
  if (l.size() < width) return -1;
  const std::string f = l.substr(0, width);
  const size_t first = f.find_first_not_of(' ');
  if (first == std::string::npos || f.find_first_not_of("0123456789", first) != std::string::npos) return -1;
  return std::stoi(f);
}

// Index of the HDF5 row at time t (the files and the HDF5 share their times).
size_t row_at(const std::vector<double>& times, double t) {
  size_t best = 0;
  for (size_t i = 0; i < times.size(); ++i)
    if (std::fabs(times[i] - t) < std::fabs(times[best] - t)) best = i;
  return best;
}

}  // namespace

TEST(AsciiOutput, GlstatCarriesTheHistorysEnergiesAtItsTimes) {
  auto r = run_impact();
  const auto g = read_glstat(r->dir / "glstat");
  const std::string h5 = (r->dir / "fe.h5").string();
  const auto t = h5io::read_series(h5, "time");
  const auto ke = h5io::read_series(h5, "energy/kinetic"), ie = h5io::read_series(h5, "energy/internal");
  ASSERT_EQ(g.at("time").size(), t.size()) << "a block per history row";
  ASSERT_EQ(g.at("time").size(), 30u) << "600 steps at 20 per block";
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(g.at("time")[i], t[i], 5e-6 * t[i]);
    EXPECT_NEAR(g.at("kinetic energy")[i], ke[i], 5e-6 * ke[0]);
    EXPECT_NEAR(g.at("internal energy")[i], ie[i], 5e-6 * ke[0]);
    // Nothing is lost in a free elastic impact but what hourglass and bulk
    // viscosity take (1 % here): total / (initial + work) stays near 1.
    EXPECT_NEAR(g.at("total energy / initial energy")[i], 1.0, 0.01);
    // The momentum of a free impact is the piston's: global z velocity = −m_p·v0 / m.
    EXPECT_NEAR(g.at("global z velocity")[i], -r->piston_mass * r->v0 / r->model.total_mass(), 1e-5 * r->v0);
  }
  EXPECT_GT(ie.back(), 0.1 * ke[0]) << "the pulse is in the tool: the comparison covers the impact";
}

TEST(AsciiOutput, MatsumPartsAddUpToTheGlobalValuesAndConserveMomentum) {
  auto r = run_impact();
  const auto g = read_glstat(r->dir / "glstat");
  double ie = 0.0, hg = 0.0, zmom = 0.0;
  size_t block = 0, parts = 0;
  auto close_block = [&] {
    if (parts == 0) return;
    ASSERT_LT(block, g.at("internal energy").size());
    const double scale = g.at("kinetic energy")[0];
    EXPECT_NEAR(ie, g.at("internal energy")[block], 1e-4 * scale) << "block " << block;
    EXPECT_NEAR(hg, g.at("hourglass energy")[block], 1e-4 * scale) << "block " << block;
    EXPECT_NEAR(zmom, -r->piston_mass * r->v0, 1e-4 * r->piston_mass * r->v0) << "block " << block;
    ++block;
  };
  for (const std::string& l : lines_of(r->dir / "matsum")) {
    if (l.rfind(" time =", 0) == 0) {
      close_block();
      ie = hg = zmom = 0.0;
      parts = 0;
    } else if (l.find("mat.#=") != std::string::npos) {
      ie += after(l, "inten");
      ++parts;
    } else if (l.find("z-mom=") != std::string::npos) {
      zmom += after(l, "z-mom");
    } else if (l.find("hgeng=") != std::string::npos) {
      hg += after(l, "hgeng");
    }
  }
  close_block();
  EXPECT_EQ(block, 30u);
  EXPECT_EQ(parts, 2u) << "piston and tool";
}

TEST(AsciiOutput, RcforcSidesAreEqualAndOppositeAndCarryTheContactForce) {
  auto r = run_impact();
  const std::string h5 = (r->dir / "fe.h5").string();
  const auto force = h5io::read_series(h5, "contact/force");
  std::vector<double> slave_z, master_z;
  for (const std::string& l : lines_of(r->dir / "rcforc")) {
    if (l.rfind("  slave", 0) != 0 && l.rfind("  master", 0) != 0) continue;  // the header
    const double z = std::stod(l.substr(l.find(" z ") + 3, 13));
    (l.rfind("  slave", 0) == 0 ? slave_z : master_z).push_back(z);
  }
  ASSERT_EQ(slave_z.size(), force.size());
  ASSERT_EQ(master_z.size(), force.size());
  double peak = 0.0;
  for (size_t i = 0; i < force.size(); ++i) {
    EXPECT_NEAR(slave_z[i], -master_z[i], 1e-5 * std::fabs(slave_z[i]) + 1e-9);
    // The piston (slave) is pushed up by the tool: +z, the normal force of the history.
    EXPECT_NEAR(slave_z[i], force[i], 1e-3 * force[i] + 1e-6) << "row " << i;
    peak = std::max(peak, force[i]);
  }
  EXPECT_GT(peak, 1e4) << "the impact happened";
}

TEST(AsciiOutput, NodoutAndEloutCarryTheHistorysNodeAndSolidAtTheirTimes) {
  auto r = run_impact();
  const std::string h5 = (r->dir / "fe.h5").string();
  const int node = r->model.node_ids[static_cast<size_t>(r->model.history_nodes.at(0))];
  const int solid = r->model.solids[static_cast<size_t>(r->model.history_solids.at(0))].id;
  const auto tn = h5io::read_series(h5, "time_nodes");
  const auto vz = h5io::read_series(h5, "nodes/" + std::to_string(node) + "/vz");
  const auto te = h5io::read_series(h5, "time_elements");
  const auto szz = h5io::read_series(h5, "solids/" + std::to_string(solid) + "/szz");
  double time = 0.0;
  size_t nodes = 0, solids = 0;
  double peak = 0.0;
  bool stress_block = false;
  for (const std::string& l : lines_of(r->dir / "nodout")) {
    if (l.find("( at time") != std::string::npos) time = std::stod(l.substr(l.find("( at time") + 9, 12));
    if (leading_int(l, 9) == node) {
      const size_t i = row_at(tn, time);
      EXPECT_NEAR(std::stod(l.substr(9 + 13 + 2 * 12 + 2 * 12, 12)), vz[i], 5e-5 * r->v0) << "z-vel at " << time;
      ++nodes;
    }
  }
  for (const std::string& l : lines_of(r->dir / "elout")) {
    if (l.find("( at time") != std::string::npos) time = std::stod(l.substr(l.find("( at time") + 9, 12));
    if (l.size() == 16 && l[8] == '-') stress_block = leading_int(l, 8) == solid;
    if (stress_block && l.rfind("       1 ", 0) == 0) {
      const size_t i = row_at(te, time);
      const double z = std::stod(l.substr(17 + 2 * 12, 12));
      EXPECT_NEAR(z, szz[i], 5e-5 * 162e6) << "sig-zz at " << time;
      peak = std::max(peak, std::fabs(z));
      ++solids;
      stress_block = false;
    }
  }
  EXPECT_EQ(nodes, 30u);
  EXPECT_EQ(solids, 30u);
  EXPECT_GT(peak, 50e6) << "the pulse passed the solid: the comparison covers it";
}

// 20 steps at half the stable step, every one a history row, into dir/fe.h5
// and the ASCII files the deck asks for; returns the step.
static double run_twenty_steps(const fe::Model& m, const fs::path& dir) {
  const double dt = 0.5 * fe::Solver::stable_dt(m).dt;
  fe::Solver s(m, dt);
  fe::History h((dir / "fe.h5").string(), m, nullptr, dt, dt);
  for (int k = 0; k < 20; ++k) {
    s.step();
    h.record(s, {}, {});
  }
  return dt;
}

// elout lists history solids only: a deck whose *DATABASE_ELOUT serves a bar
// history (the hammer scene's stress gauge) would get a header every DT and
// nothing else (15 MB in 0.08 s there). It is not written, the deck reader
// says so at the card's line, and ELOUT's DT still sets the HDF5 element
// history's rate (the bar's stress at every DT).
TEST(AsciiOutput, EloutWithoutHistorySolidsIsNotWrittenAndSaysWhy) {
  const fs::path dir = fs::temp_directory_path() / ("pcs_elout_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string deck =
      "*KEYWORD\n*NODE\n1,0,0,0\n2,0,0,0.1\n*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n"
      "*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*ELEMENT_BEAM\n1,1,1,2\n*INITIAL_VELOCITY_NODE\n2,0,0,1\n"
      "*DATABASE_GLSTAT\n1e-7,\n*DATABASE_ELOUT\n1e-7,\n*DATABASE_HISTORY_BEAM\n1\n";
  fe::DeckWarnings warnings;
  const fe::Model m = fe::parse_deck(deck, "gauge.k", &warnings);
  bool said = false;
  for (const auto& w : warnings.messages) said = said || w.rfind("gauge.k:19: warning: *DATABASE_ELOUT", 0) == 0;
  EXPECT_TRUE(said) << (warnings.messages.empty() ? std::string("no warning") : warnings.messages.front());
  const double dt = run_twenty_steps(m, dir);
  EXPECT_TRUE(fs::exists(dir / "glstat"));
  EXPECT_FALSE(fs::exists(dir / "elout"));
  const auto te = h5io::read_series((dir / "fe.h5").string(), "time_elements");
  EXPECT_GE(te.size(), 10u) << "the bar's history still at ELOUT's DT (1e-7 s, every " << dt << " s step or two)";
  fs::remove_all(dir);
}

// BINARY on a *DATABASE_ card as LS-DYNA reads it: 1 or blank the ASCII
// file, 2 the binary database only (LS-DYNA's binout; here the HDF5 history,
// always written), 3 both. A scene that wants its energies at a fine DT for
// post-processing but not 800 bytes of ASCII per row asks BINARY 2 (the rig
// scene's glstat was 39 MB per simulated second). Any other value is refused
// at its line: a deck meant for another solver's flags must not pass.
TEST(AsciiOutput, BinaryTwoWritesTheHistoryOnlyAndThreeBoth) {
  const fs::path dir = fs::temp_directory_path() / ("pcs_binary_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string bar =
      "*KEYWORD\n*NODE\n1,0,0,0\n2,0,0,0.1\n*PART\nbar\n1,1,1\n*SECTION_BEAM\n1,3\n1e-4\n"
      "*MAT_ELASTIC\n1,7850,2.1e11,0.0\n*ELEMENT_BEAM\n1,1,1,2\n*INITIAL_VELOCITY_NODE\n2,0,0,1\n"
      "*DATABASE_HISTORY_NODE\n2\n";
  const fe::Model m =
      fe::parse_deck(bar + "*DATABASE_GLSTAT\n1e-7,2\n*DATABASE_NODOUT\n1e-7,3\n*DATABASE_RCFORC\n1e-7\n", "binary.k");
  EXPECT_EQ(m.ascii_dt.count("glstat"), 0u) << "BINARY 2: no ASCII glstat";
  EXPECT_EQ(m.ascii_dt.count("nodout"), 1u) << "BINARY 3: the ASCII nodout too";
  EXPECT_EQ(m.ascii_dt.count("rcforc"), 1u) << "BINARY blank: ASCII, LS-DYNA's default";
  EXPECT_DOUBLE_EQ(m.history_dt_global, 1e-7) << "GLSTAT's DT still sets the HDF5 history's rate";
  run_twenty_steps(m, dir);
  EXPECT_FALSE(fs::exists(dir / "glstat"));
  EXPECT_TRUE(fs::exists(dir / "nodout"));
  EXPECT_GE(h5io::read_series((dir / "fe.h5").string(), "energy/kinetic").size(), 10u)
      << "the energies are in the HDF5 at GLSTAT's DT";
  fs::remove_all(dir);
  try {
    fe::parse_deck(bar + "*DATABASE_GLSTAT\n1e-7,4\n", "binary.k");
    ADD_FAILURE() << "BINARY 4 was accepted";
  } catch (const config::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("binary.k:20: BINARY must be 1"), std::string::npos) << e.what();
  }
}
