// tlm_host: the TLM system simulator of the hydraulic circuit.
//
//   tlm_host MODEL [--fmu FILE.fmu] [--server HOST:PORT] [--token-file F]
//            [--out results.h5] [--set comp.param=value ...] [--quiet]
#include <csignal>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "config/cli.hpp"
#include "config/stop_signal.hpp"
#include "socketlib/socketlib.h"
#include "config/token.hpp"
#include "config/version.hpp"
#include "hopsan_loader.hpp"
#include "model.hpp"

namespace {

int usage(std::ostream& os, int rc) {
  os << "usage: tlm_host MODEL [options]\n"
        "  MODEL               our model file (model.tlm), or a Hopsan model file (.hmf)\n"
        "  --fmu FILE          FMU for every FmuQ component that names none\n"
        "  --server HOST:PORT  fe_server address for every FmuQ component\n"
        "  --token-file FILE   session token for fe_server, first line of FILE (mode 600, yours);\n"
        "                      else the FMU takes $PCS_TOKEN or the file named by $PCS_TOKEN_FILE\n"
        "  --out FILE          HDF5 results (default results.h5)\n"
        "  --set C.P=VALUE     override parameter P of component C (repeatable);\n"
        "                      simulation.timestep / stoptime / log_every too\n"
        "  --csv FILE          also write every logged series as CSV\n"
        "  --log A,B,...       write only these series or groups (nodes/cavA.P2/p, components/mech),\n"
        "                      the time and what the *REPORT reads; replaces the model's *LOG\n"
        "  --report FILE       write the percussion report (model's *REPORT block) to FILE\n"
        "                      (JSON in SI units when FILE ends in .json)\n"
        "  --no-report         do not evaluate the model's *REPORT (a run too short for its blows)\n"
        "  --checkpoint FILE   checkpoint here (default: the results file with .ckpt for .h5) at a stop\n"
        "                      signal (SIGTERM, SIGINT, SIGHUP) and every --checkpoint-every minutes;\n"
        "                      each FMU's fe_server writes its own checkpoint of the same step first\n"
        "  --checkpoint-every M  a checkpoint every M minutes of wall time\n"
        "  --restart FILE      continue from a checkpoint (fe_server restarted with --restart and its\n"
        "                      checkpoint of the same step); the results file continues after its row\n"
        "  --peers HOW         several FMUs: parallel (default: each steps on its own thread), sequential\n"
        "                      (one thread: every FMU's inputs set, then each stepped), or one-by-one (each\n"
        "                      set and stepped in turn, which fe_server refuses): how other importers step\n"
        "  --quiet             no progress line\n"
        "  --hopsan-types      the Hopsan component types read from .hmf files, as Markdown\n"
        "  -h, --help, --version  this text; the version\n"
        "Exit codes: 0 ok, 2 usage, 3 model rejected (or a checkpoint that does not fit it), 4 simulation\n"
        "            failed, 10 stopped after a checkpoint fe_server asked for (it got a stop signal),\n"
        "            128 + N stopped by signal N (130 Ctrl-C, 143 SIGTERM) with results flushed.\n";
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGPIPE, SIG_IGN);
  config::install_stop_handlers();
  std::string model_path, fmu, server, token, out = "results.h5", report_path, csv_path, log_list;
  bool no_report = false;
  std::vector<std::string> overrides;
  bool quiet = false;
  tlm::PeerGroup::Stepping peers = tlm::PeerGroup::Stepping::Parallel;
  tlm::System::Checkpointing ck;
  try {
    config::Args args(argc, argv);
    while (args.next()) {
      if (args.is("--fmu")) fmu = args.value();
      else if (args.is("--server")) server = args.value();
      else if (args.is("--token")) throw std::invalid_argument(config::token_on_command_line_refused("tlm_host"));
      else if (args.is("--token-file")) token = config::read_token_file(args.value());
      else if (args.is("--out")) out = args.value();
      else if (args.is("--set")) {
        overrides.push_back(args.value());
        const std::string& o = overrides.back();
        if (o.find(".token=") != std::string::npos) throw std::invalid_argument(config::token_on_command_line_refused("tlm_host"));
      }
      else if (args.is("--quiet")) quiet = true;
      else if (args.is("--peers")) {
        const std::string how = args.value();
        if (how == "parallel") peers = tlm::PeerGroup::Stepping::Parallel;
        else if (how == "sequential") peers = tlm::PeerGroup::Stepping::Sequential;
        else if (how == "one-by-one") peers = tlm::PeerGroup::Stepping::OneByOne;
        else throw std::invalid_argument("--peers " + how + ": parallel, sequential or one-by-one");
      }
      else if (args.is("--report")) report_path = args.value();
      else if (args.is("--no-report")) no_report = true;
      else if (args.is("--csv")) csv_path = args.value();
      else if (args.is("--log")) log_list = args.value();
      else if (args.is("--checkpoint")) ck.path = args.value();
      else if (args.is("--checkpoint-every")) ck.every_s = 60.0 * args.real(1e-3, 1e6);
      else if (args.is("--restart")) ck.restart = args.value();
      else if (args.is("-h") || args.is("--help")) return usage(std::cout, 0);
      else if (args.is("--version")) return std::cout << config::version_line("tlm_host") << "\n", 0;
      else if (args.is("--hopsan-types")) return std::cout << tlm::hopsan_mapping_markdown(), 0;
      else if (args.is_option()) args.unknown();
      else if (model_path.empty()) model_path = args.current();
      else throw std::invalid_argument("more than one model given");
    }
    if (model_path.empty()) throw std::invalid_argument("no model file given");
    if (ck.path.empty() && (ck.every_s > 0.0 || !ck.restart.empty())) {
      const bool h5 = out.size() > 3 && out.compare(out.size() - 3, 3, ".h5") == 0;
      ck.path = (h5 ? out.substr(0, out.size() - 3) : out) + ".ckpt";
    }
  } catch (const std::exception& e) {
    // The error alone, so that it does not scroll away behind the usage.
    std::cerr << "tlm_host: " << e.what() << "\n(tlm_host --help lists the options)\n";
    return 2;
  }

  // With checkpoints a stop signal asks for one of both sides, which needs
  // the link: the FMU's waits (they watch this process's flag, see
  // FmuArchive) then end at a second signal, not at the first.
  if (!ck.path.empty()) sl_set_stop_flag(config::second_stop_flag());

  std::unique_ptr<tlm::System> system;
  tlm::ReportSettings report;
  bool want_report = false;
  try {
    // A Hopsan model file (.hmf) or ours (model.tlm).
    const bool hmf = model_path.size() > 4 && model_path.compare(model_path.size() - 4, 4, ".hmf") == 0;
    tlm::ModelSpec spec;
    if (hmf) {
      tlm::HmfModel h = tlm::read_hmf(model_path);
      for (const auto& note : h.notes) std::cerr << "tlm_host: note: " << note << "\n";
      spec = std::move(h.spec);
    } else {
      spec = tlm::read_model(model_path);
    }
    for (auto& c : spec.components) {
      if (c.type != "FmuQ") continue;
      config::SourceLocation cli{"command line", 0};
      if (!fmu.empty() && !c.params.has("fmu")) c.params.set("fmu", fmu, cli);
      if (!server.empty()) c.params.set("server", server, cli);
      if (!token.empty()) c.params.set("token", token, cli);
    }
    for (const auto& o : overrides) spec.apply_override(o);
    if (!log_list.empty()) {
      if (hmf) throw std::invalid_argument("--log: a Hopsan model's results keep Hopsan's layout; --log is for model files");
      spec.log_only.clear();
      std::stringstream list(log_list);
      for (std::string f; std::getline(list, f, ',');)
        if (!config::trim(f).empty()) spec.log_only.emplace_back(config::trim(f), config::SourceLocation{"--log", 0});
      // An empty list would write every series: not what a --log asks for.
      if (spec.log_only.empty()) throw config::InputError({"--log", 0}, "names no series: '" + log_list + "'");
    }
    want_report = !spec.report.empty() && !no_report;
    if (no_report && !report_path.empty()) throw config::InputError({"--report", 0}, "--report and --no-report together");
    if (want_report) report = tlm::report_settings(spec);
    system = std::make_unique<tlm::System>(std::move(spec));
    if (!csv_path.empty()) system->set_csv(csv_path);
    system->set_checkpointing(ck);
    system->set_peer_stepping(peers);
  } catch (const std::exception& e) {
    std::cerr << "tlm_host: " << e.what() << "\n";
    return 3;
  }
  try {
    system->run(out, !quiet);
  } catch (const tlm::CheckpointStop& e) {
    std::cerr << "tlm_host: " << e.what() << "\n";
    system.reset();
    return 10;
  } catch (const config::CheckpointError& e) {
    std::cerr << "tlm_host: " << e.what() << "\n";
    system.reset();
    return 3;
  } catch (const config::StopRequested& e) {
    std::cerr << "tlm_host: " << e.what() << "\n";
    system.reset();  // frees the FMUs now: fe_server is told, their folders removed
    return config::stop_exit_code(e.signo());
  } catch (const std::exception& e) {
    std::cerr << "tlm_host: " << e.what() << "\n";
    system.reset();  // frees the FMUs now: fe_server is told, their folders removed
    // A wait ended by a stop signal (the FMU's connect or handshake, before
    // the step loop) is a stop, whatever error it surfaced as.
    if (const int signo = config::stop_signal()) return config::stop_exit_code(signo);
    return 4;
  }
  if (want_report) {
    try {
      const tlm::PercussionFigures figures = tlm::evaluate_percussion(out, report);
      const std::string text = tlm::format_figures(figures);
      std::cout << "percussion report (" << out << "):\n" << text;
      if (!report_path.empty()) {
        const bool json = report_path.size() > 5 && report_path.compare(report_path.size() - 5, 5, ".json") == 0;
        std::ofstream f(report_path);
        f << (json ? tlm::figures_json(figures) : text);
        if (!f) throw std::runtime_error("cannot write " + report_path);
      }
    } catch (const std::exception& e) {
      std::cerr << "tlm_host: report: " << e.what() << "\n";
      return 4;
    }
  }
  if (!quiet)
    std::cout << "tlm_host: " << system->steps_done() << " steps of " << system->spec().dt << " s done; results in "
              << out << "\n";
  return 0;
}
