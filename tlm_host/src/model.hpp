// The TLM host's model file (keyword style, the same reader as the port
// configuration) and the system built from it.
//
//   *SIMULATION   key, value          timestep, stoptime, log_every
//   *COMPONENT    name, Type, key=value, key=value, ...
//   *CONNECT      comp.port, comp.port   (one C-type and one Q-type port)
//
// Every parameter can be overridden from the command line (--set comp.key=value).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "component.hpp"
#include "h5io/timeseries.hpp"
#include "peer_group.hpp"

namespace tlm {

struct ComponentSpec {
  std::string name, type;
  ParameterSet params;
  config::SourceLocation where;
  // Step once at t = 0, after initialize() and before the first row: what
  // Hopsan's sources, turbulent orifices, steps and gains do in their
  // initialize(), so a Hopsan model's series line up with Hopsan's step for step.
  bool initial_step = false;
};

struct ConnectionSpec {
  std::string a, b;
  config::SourceLocation where;
};

struct ModelSpec {
  std::string source;
  double dt = 0.0;
  double stop_time = 0.0;
  // The clock at the first row: 0 but for Hopsan models, whose GUI often
  // writes a negative start (the run goes from start_time to stop_time).
  double start_time = 0.0;
  int log_every = 1;
  std::vector<ComponentSpec> components;
  std::vector<ConnectionSpec> connections;
  // *REPORT: key, value rows (piston, inlet_p, inlet_q, peak, settle, lowpass); empty: no report
  std::vector<config::Card> report;
  // Where the simulation settings were last set (the *SIMULATION block, or
  // the --set that changed one): the place check_simulation names.
  config::SourceLocation simulation_where;
  // A model read from a Hopsan file: every port's results also under
  // Hopsan's names, results/<component>/<port>/<variable> in the HDF5 file
  // (links to ours) and component#port#variable in Hopsan's CSV layout.
  bool hopsan_results = false;
  std::map<std::string, std::string> result_ports;  // "component.our port" → Hopsan's port name, where they differ
  std::set<std::string> unlogged_ports;             // "component.port": a Hopsan multiport's, which Hopsan does not log
  // *LOG (or tlm_host --log): the series written to the results, each a
  // series ("nodes/cavA.P2/p") or a group of them ("components/mech"); the
  // time and what the *REPORT reads are always written. Empty: every series.
  std::vector<std::pair<std::string, config::SourceLocation>> log_only;

  ComponentSpec* find(const std::string& name);
  const ComponentSpec* find(const std::string& name) const;
  // "comp.key=value" (or "simulation.timestep=…"); throws on an unknown component.
  void apply_override(const std::string& assignment);
  // timestep and stoptime positive, a finite number of steps, log_every ≥ 1;
  // checked by System once every override is in, so the order of several
  // --set options does not matter.
  void check_simulation() const;
};

ModelSpec parse_model(const std::string& text, const std::string& name);
ModelSpec read_model(const std::string& path);

// The run stopped after both sides checkpointed because fe_server asked
// (it got a stop signal: a cluster's wall-time limit); tlm_host exits 10.
class CheckpointStop : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class System {
 public:
  // Creates, configures and connects the components; checks that every port
  // is connected and every node joins one C and one Q port.
  explicit System(ModelSpec spec);
  ~System();
  // Run to the stop time, writing the HDF5 time series to out_path (flushed
  // on every error, so what was computed is kept). Progress goes to stderr.
  void run(const std::string& out_path, bool progress);
  // Also write every logged series as CSV (same rows as the HDF5 file).
  void set_csv(const std::string& path) { csv_path_ = path; }
  // Checkpoint and restart. With a path, run() writes a checkpoint every
  // `every_s` seconds of wall time (0: never on a clock) and when a stop
  // signal arrives, each time after asking every FMU's fe_server for its own
  // checkpoint of the same step (fe_server writes its file first). With
  // `restart`, run() continues from that checkpoint: the FMUs resume their
  // sessions at its step (fe_server must be restarted from its checkpoint of
  // the same step), and the results file (and CSV) continue after its row.
  struct Checkpointing {
    std::string path, restart;
    double every_s = 0.0;
  };
  void set_checkpointing(const Checkpointing& c) { checkpointing_ = c; }
  // How several FMUs (peers) are stepped: in parallel (the default), or one
  // after the other as a sequential importer would (peer_group.hpp).
  void set_peer_stepping(PeerGroup::Stepping how) { peer_stepping_ = how; }
  Component* find(const std::string& name);
  // Stability advisor: one message per component whose largest stable step
  // (explicit springs, stops, contacts) is below dt.
  std::vector<std::string> stability_warnings(double dt) const;
  const ModelSpec& spec() const { return spec_; }
  long steps_done() const { return steps_done_; }

 private:
  struct LoggedSeries {
    std::string name, unit;
    const double* value;
  };
  std::vector<LoggedSeries> logged_series(const double* time) const;
  ModelSpec spec_;
  std::vector<std::unique_ptr<Component>> components_;
  std::vector<std::unique_ptr<HydraulicNode>> nodes_;
  std::vector<Component*> signal_, c_type_, q_type_;
  void order_signals_as_hopsan(const std::vector<std::pair<Component*, Component*>>& edges);
  // Two or more FMUs: stepped together at the first one's place in q_type_,
  // which then holds only that first one of them.
  std::unique_ptr<PeerGroup> peers_;
  long steps_done_ = 0;
  // The run-quality guard ("" when all is well, else why, naming the node;
  // the FMUs' port nodes after every step, every node before each results
  // row and every kGuardEvery steps):
  //  - every node's values finite;
  //  - a hydraulic node's pressure at most kSourceFactor × the model's
  //    highest source or start pressure, where sources bound it (no flow
  //    source, pump, force or FMU that can drive a node to any pressure);
  //  - at an FMU's port (the coupling's TLM port) at least −1 bar absolute,
  //    less kUndershoot × the highest source pressure: a cavitating chamber
  //    holds p_vap, but the port's p = c + Zc·q undershoots for a step or
  //    two (the main job: −6.1 bar at its 150 bar), while a coupling far
  //    too coarse swings to hundreds of bar below zero.
  static constexpr double kLowestPressure = -1e5;  // Pa absolute
  static constexpr double kSourceFactor = 10.0;
  static constexpr double kUndershoot = 0.1;
  static constexpr long kGuardEvery = 16;  // steps between two node checks
  double highest_pressure_ = 1e300;  // Pa; 1e300 where no source bounds it
  double lowest_port_pressure_ = kLowestPressure;
  // Per node (nodes_ order): the pressure bounds of the guard (mechanical
  // nodes ±inf), so that the check every step is two compares and a sum.
  std::vector<double> node_lo_, node_hi_;
  std::vector<size_t> fmu_node_index_;  // the FMUs' hydraulic port nodes, checked every step
  std::string check_nodes() const;
  std::string check_fmu_nodes() const;
  std::string node_failure(const HydraulicNode& n, double lowest) const;
  std::set<const SignalPort*> bound_;
  std::string csv_path_;
  // A Hopsan model's results under Hopsan's names (ModelSpec::hopsan_results).
  void hopsan_names(h5io::TimeSeriesWriter& out,
                    const std::function<void(const std::string&, const std::string&, const double*)>& add,
                    std::vector<const double*>& csv_sources, std::vector<std::string>& csv_header, const double* time);
  Checkpointing checkpointing_;
  PeerGroup::Stepping peer_stepping_ = PeerGroup::Stepping::Parallel;
  // The state that is not a component's: the nodes' p, q, c, Zc and every
  // component's state(), in file order.
  void exchange_state(config::StateIO& io);
};

}  // namespace tlm

#include "percussion_report.hpp"

namespace tlm {
// The report settings from the model's *REPORT block (piston mass taken from
// the piston component's parameter m). Throws config::InputError for a bad row.
ReportSettings report_settings(ModelSpec& spec);
}  // namespace tlm
