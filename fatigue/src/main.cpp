// fatigue_cycles: the rainflow cycle table and the Miner damage of a stress
// history, for checking against one's own fatigue tools.
//
//   fatigue_cycles HISTORY.csv --sn SA_REF,N_REF,M[,ENDURANCE] [--haibach]
//                  [--mean none|goodman|gerber|swt] [--su SU] [--gate G] [--column K]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "config/cli.hpp"
#include "config/keyword_reader.hpp"
#include "config/version.hpp"
#include "fatigue/damage.hpp"
#include "fatigue/rainflow.hpp"

namespace {

int usage(std::ostream& os, int rc) {
  os << "usage: fatigue_cycles HISTORY.csv --sn SA_REF,N_REF,M[,ENDURANCE] [--haibach]\n"
        "                      [--mean none|goodman|gerber|swt] [--su SU] [--gate G] [--column K]\n"
        "Counts the cycles of a stress history (ASTM E1049-85 rainflow) and sums their damage\n"
        "(Palmgren-Miner) on a Basquin S-N curve: N = N_REF * (SA_REF / Sa)^M above the endurance\n"
        "limit (amplitudes, in the history's stress unit), none below it (--haibach: slope 2M-1 there).\n"
        "  HISTORY.csv   rows of time,stress (a header line and # comments are skipped)\n"
        "  --column K    the stress is column K (1-based; default 2, or 1 when a row has one column)\n"
        "  --mean        mean-stress correction (default none); goodman and gerber need --su, the\n"
        "                ultimate strength; compressive means get no credit\n"
        "  --gate G      ignore reversals smaller than G (default 0)\n"
        "  -h, --help, --version\n"
        "Prints the cycles (range, mean, count; half cycles count 0.5), the damage of one pass of the\n"
        "history, and how many passes, and how long, to crack initiation (damage 1).\n"
        "Exit codes: 0 done, 2 usage, 3 the history or a value is wrong.\n";
  return rc;
}

fatigue::SnCurve parse_sn(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    size_t used = 0;
    double d = 0.0;
    try {
      d = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty())
      throw std::invalid_argument("--sn " + text + ": '" + item + "' is not a number");
    v.push_back(d);
  }
  if (v.size() < 3 || v.size() > 4)
    throw std::invalid_argument("--sn " + text + ": expected SA_REF,N_REF,M or SA_REF,N_REF,M,ENDURANCE");
  fatigue::SnCurve c{v[0], v[1], v[2], v.size() == 4 ? v[3] : 0.0, false};
  if (const std::string why = c.check(); !why.empty()) throw std::invalid_argument("--sn " + text + ": " + why);
  return c;
}

// The history's stress column and its first and last time; throws naming file:line.
std::vector<double> read_history(const std::string& path, int column, double& t0, double& t1) {
  const std::string text = config::read_text_file(path, "stress history");
  std::vector<double> out;
  std::stringstream lines(text);
  std::string line;
  int n = 0;
  bool timed = false;
  while (std::getline(lines, line)) {
    ++n;
    line = config::trim(line);
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream f(line);
    std::string field;
    while (std::getline(f, field, ',')) fields.push_back(config::trim(field));
    auto number = [](const std::string& t, double& d) {
      size_t used = 0;
      try {
        d = std::stod(t, &used);
      } catch (const std::exception&) {
        return false;
      }
      return used == t.size() && std::isfinite(d);
    };
    const int k = column > 0 ? column : (fields.size() == 1 ? 1 : 2);
    double value = 0.0;
    if (static_cast<int>(fields.size()) < k || !number(fields[static_cast<size_t>(k - 1)], value)) {
      if (out.empty() && n == 1) continue;  // a header
      throw std::invalid_argument(path + ":" + std::to_string(n) + ": column " + std::to_string(k) +
                                  " is not a finite number: '" + line + "'");
    }
    double t = 0.0;
    if (k != 1 && number(fields[0], t)) {
      if (!timed) t0 = t;
      timed = true;
      t1 = t;
    }
    out.push_back(value);
  }
  if (out.empty()) throw std::invalid_argument(path + ": no stress values");
  if (!timed) t0 = t1 = 0.0;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path, sn_text, mean_name = "none";
  double su = 0.0, gate = 0.0;
  int column = 0;
  bool haibach = false, have_su = false;
  fatigue::SnCurve curve;
  fatigue::MeanStress mean = fatigue::MeanStress::None;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("--sn")) sn_text = args.value();
      else if (args.is("--haibach")) haibach = true;
      else if (args.is("--mean")) mean_name = args.value();
      else if (args.is("--su")) su = args.real(1e-300, 1e300), have_su = true;
      else if (args.is("--gate")) gate = args.real(0.0, 1e300);
      else if (args.is("--column")) {
        column = args.integer();
        if (column < 1) throw std::invalid_argument("--column counts from 1");
      } else if (args.is("-h") || args.is("--help")) return usage(std::cout, 0);
      else if (args.is("--version")) return std::cout << config::version_line("fatigue_cycles") << "\n", 0;
      else if (args.is_option()) args.unknown();
      else if (path.empty()) path = args.current();
      else throw std::invalid_argument("unexpected argument '" + args.current() + "'");
    }
    if (path.empty()) throw std::invalid_argument("no stress history given");
    if (sn_text.empty()) throw std::invalid_argument("no S-N curve given (--sn SA_REF,N_REF,M[,ENDURANCE])");
    curve = parse_sn(sn_text);
    curve.haibach = haibach;
    mean = fatigue::mean_stress_from_name(mean_name);
    if ((mean == fatigue::MeanStress::Goodman || mean == fatigue::MeanStress::Gerber) && !have_su)
      throw std::invalid_argument("--mean " + mean_name + " needs --su, the ultimate strength");
  } catch (const std::exception& e) {
    std::cerr << "fatigue_cycles: " << e.what() << "\n(fatigue_cycles --help lists the options)\n";
    return 2;
  }
  std::vector<double> history;
  double t0 = 0.0, t1 = 0.0;
  try {
    history = read_history(path, column, t0, t1);
  } catch (const std::exception& e) {
    std::cerr << "fatigue_cycles: " << e.what() << "\n";
    return 3;
  }
  // Count (streaming, as fe_server would per element), merging equal cycles for the table.
  std::map<std::pair<double, double>, double> table;  // (range, mean) -> count
  fatigue::Damage damage{curve, mean, su, 0.0, 0.0};
  fatigue::RainflowCounter counter(gate);
  auto sink = [&](const fatigue::Cycle& c) {
    table[{c.range, c.mean}] += c.count;
    damage.add(c);
  };
  for (double x : history) counter.add(x, sink);
  counter.finish(sink);
  std::vector<std::pair<std::pair<double, double>, double>> rows(table.begin(), table.end());
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return a.first.first != b.first.first ? a.first.first > b.first.first : a.first.second < b.first.second;
  });
  std::printf("# %s: %zu samples, rainflow (ASTM E1049-85), gate %g\n", path.c_str(), history.size(), gate);
  std::printf("%16s %16s %8s %16s %14s\n", "range", "mean", "count", "N to failure", "damage");
  for (const auto& [key, count] : rows) {
    const double sa = fatigue::equivalent_amplitude(0.5 * key.first, key.second, mean, su);
    const double n = curve.cycles_to_failure(sa);
    std::printf("%16.8g %16.8g %8.1f %16.6g %14.6g\n", key.first, key.second, count, n,
                std::isinf(n) ? 0.0 : count / n);
  }
  std::printf("cycles %.1f, Miner damage of one pass %.6g (S-N %g at %g cycles, m %g, endurance %g%s; mean "
              "correction %s%s)\n",
              damage.cycles, damage.damage, curve.sa_ref, curve.n_ref, curve.m, curve.endurance,
              haibach ? ", Haibach below it" : "", fatigue::to_string(mean),
              have_su ? (", Su " + std::to_string(su)).c_str() : "");
  if (damage.damage > 0.0) {
    std::printf("passes to crack initiation %.6g", 1.0 / damage.damage);
    if (t1 > t0) std::printf(", %.6g s (%.6g h) at this history's %.6g s per pass", (t1 - t0) / damage.damage,
                             (t1 - t0) / damage.damage / 3600.0, t1 - t0);
    std::printf("\n");
  } else {
    std::printf("no damage: every cycle is below the endurance limit\n");
  }
  return 0;
}
