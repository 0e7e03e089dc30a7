// tlm_fit: fit named parameters of a monolithic model to named targets of
// its percussion report, over one or more running conditions (calibration.hpp).
//
//   tlm_fit MODEL --fit C.P[=START][:LO..HI],... --condition NAME:C.P=V,... --target NAME:FIGURE=VALUE ...
#include <csignal>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "calibration.hpp"
#include "config/cli.hpp"
#include "config/stop_signal.hpp"
#include "config/version.hpp"

namespace {

int usage(std::ostream& os, int rc) {
  os << "usage: tlm_fit MODEL --fit C.P[=START][,C.P...] --target [COND:]FIGURE=VALUE ... [options]\n"
        "  MODEL                  a model file with a *REPORT block (model.tlm), run without an FMU\n"
        "  --fit C.P[=START][:LO..HI],...\n"
        "                         parameters to fit (positive numbers); the start is the model's value\n"
        "                         unless given; bounds keep every trial inside (valve.Cd:0.5..0.9)\n"
        "  --condition NAME:C.P=V[,C.P=V...]\n"
        "                         a running condition: these --set values on top of the common ones\n"
        "                         (repeatable; without any, one condition named 'model')\n"
        "  --target [COND:]FIGURE=VALUE\n"
        "                         a figure of COND's report to meet (repeatable); VALUE in SI or with\n"
        "                         a unit: 80l/min, 151bar (absolute, as the report), 20Hz, 78mm, 12kW\n"
        "                         figures: frequency v_impact stroke p_in q_in P_in W P_out efficiency\n"
        "                         and peak_LABEL for each peak row of the model's *REPORT\n"
        "  --set C.P=VALUE        an override for every run (repeatable), e.g. simulation.stoptime=1.0\n"
        "  --tolerance R          every relative residual at most R for success (default 0.01)\n"
        "  --max-iterations N     (default 30)\n"
        "  --report FILE          also write the fit's table to FILE\n"
        "  --quiet                no line per iteration\n"
        "Each evaluation runs every condition once; the Jacobian costs one run per parameter more.\n"
        "  -h, --help, --version  this text; the version\n"
        "Exit codes: 0 every target met, 2 usage, 3 model or problem rejected, 4 a run at the start\n"
        "            values failed, 5 the fit ended without meeting every target (the table says\n"
        "            which), or the targets do not determine every parameter, 128 + N stopped by\n"
        "            signal N.\n";
  return rc;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);
  config::install_stop_handlers();
  tlm::FitProblem problem;
  std::vector<std::string> fit_args, target_args;
  std::string report_path;
  bool quiet = false;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("--fit")) fit_args.push_back(args.value());
      else if (args.is("--condition")) {
        const std::string v = args.value();
        const size_t colon = v.find(':');
        if (colon == std::string::npos || colon == 0)
          throw std::invalid_argument("--condition '" + v + "': expected NAME:C.P=V[,C.P=V...]");
        tlm::FitCondition c{v.substr(0, colon), split(v.substr(colon + 1), ',')};
        for (const auto& other : problem.conditions)
          if (other.name == c.name) throw std::invalid_argument("--condition: '" + c.name + "' is given twice");
        problem.conditions.push_back(std::move(c));
      } else if (args.is("--target")) target_args.push_back(args.value());
      else if (args.is("--set")) problem.common_overrides.push_back(args.value());
      else if (args.is("--tolerance")) problem.tolerance = args.real(1e-9, 1.0);
      else if (args.is("--max-iterations")) problem.max_iterations = args.integer();
      else if (args.is("--report")) report_path = args.value();
      else if (args.is("--quiet")) quiet = true;
      else if (args.is("-h") || args.is("--help")) return usage(std::cout, 0);
      else if (args.is("--version")) return std::cout << config::version_line("tlm_fit") << "\n", 0;
      else if (args.is_option()) args.unknown();
      else if (problem.model_path.empty()) problem.model_path = args.current();
      else throw std::invalid_argument("more than one model given");
    }
    if (problem.model_path.empty()) throw std::invalid_argument("no model file given");
    if (fit_args.empty()) throw std::invalid_argument("--fit: name the parameters to fit");
  } catch (const std::exception& e) {
    std::cerr << "tlm_fit: " << e.what() << " (tlm_fit --help)\n";
    return 2;
  }

  try {
    const tlm::ModelSpec model = tlm::read_model(problem.model_path);
    if (model.report.empty()) throw std::invalid_argument(problem.model_path + " has no *REPORT block: nothing to fit to");
    for (const auto& a : fit_args)
      for (const auto& name : split(a, ',')) problem.parameters.push_back(tlm::parse_fit_parameter(name, model));
    if (problem.conditions.empty()) problem.conditions.push_back({"model", {}});
    for (const auto& t : target_args) {
      const size_t eq = t.find('=');
      if (eq == std::string::npos) throw std::invalid_argument("--target '" + t + "': expected [COND:]FIGURE=VALUE");
      const std::string lhs = t.substr(0, eq);
      const size_t colon = lhs.find(':');
      tlm::FitTarget target;
      if (colon == std::string::npos) {
        if (problem.conditions.size() != 1)
          throw std::invalid_argument("--target '" + t + "': say which condition (COND:FIGURE=VALUE)");
        target.condition = problem.conditions.front().name;
        target.figure = lhs;
      } else {
        target.condition = lhs.substr(0, colon);
        target.figure = lhs.substr(colon + 1);
      }
      try {
        target.value = tlm::parse_fit_value(t.substr(eq + 1));
      } catch (const std::exception& e) {
        throw std::invalid_argument("--target " + lhs + ": " + e.what());
      }
      problem.targets.push_back(target);
    }
    tlm::check_fit_problem(problem);
  } catch (const std::exception& e) {
    std::cerr << "tlm_fit: " << e.what() << "\n";
    return 3;
  }

  tlm::FitResult result;
  try {
    result = tlm::run_fit(problem, quiet ? std::function<void(const std::string&)>()
                                         : [](const std::string& line) { std::cout << line << std::endl; });
  } catch (const config::StopRequested& e) {
    std::cerr << "tlm_fit: " << e.what() << "\n";
    return config::stop_exit_code(e.signo());
  } catch (const std::exception& e) {
    std::cerr << "tlm_fit: " << e.what() << "\n";
    return 4;
  }
  const std::string table = tlm::format_fit(problem, result);
  std::cout << table;
  if (!report_path.empty()) {
    std::ofstream f(report_path);
    f << table;
    if (!f) {
      std::cerr << "tlm_fit: cannot write " << report_path << "\n";
      return 4;
    }
  }
  return result.succeeded() ? 0 : 5;
}
