// The FE server's time histories: port values, history nodes and energies,
// one row per coupling step, through the HDF5 time-series writer.
#pragma once

#include <memory>
#include <string>

#include "loads/cavity_load.hpp"
#include "config/port_table.hpp"
#include "h5io/timeseries.hpp"
#include "solver/solver.hpp"

namespace fe {

// All of a run's output behind one interface: time histories at the rates
// the deck asks for, field snapshots (HDF5 + XDMF) every
// *DATABASE_BINARY_D3PLOT interval, and the energy balance check at the end.
//
// Three streams of rows, each with its own time series and interval:
//   time,  ports/*, contact/*, energy/*   *DATABASE_GLSTAT / RCFORC DT
//   time_nodes,    nodes/*                *DATABASE_NODOUT DT
//   time_elements, solids/* (plastic_strain too on plastic parts),
//                  bars/* (stress and axial velocity),
//                  axisymmetric/*, sections/<id>/{fx,fy,fz,vx,vy,vz}
//                  (2D: fy, vy)           *DATABASE_ELOUT / SECFORC DT
// time_elements is the time of the state the row's stresses belong to: a
// step computes them from x_n, so after the step to t_{n+1} the row says
// t_n, with the velocities of t_n (½(v_{n−1/2} + v_{n+1/2})).
// A row every round(DT/Δt) FE steps (at least every step): a decimated
// history holds exactly the values an every-step history has at its times.
// Without a DT the stream uses the default interval given to the
// constructor (fe_server: the coupling step in a co-simulation, 1/10000 of
// the run standalone); node and element streams default to the first's.
// On the ranks other than 0 (fe_server across ranks, parallel/domain.hpp):
// no files; takes part in what History on rank 0 gathers, a field snapshot
// at the same steps. Called after every FE step, as History::record.
class FollowerHistory {
 public:
  FollowerHistory(const Model& model, double fe_dt);
  void record(const Solver& s);

 private:
  const Model& model_;
  double fe_dt_;
  double next_snapshot_ = 0.0;
};

class History {
 public:
  // resume: continue the file of a run restarted from a checkpoint (state()
  // then cuts it back to the checkpoint's rows) instead of creating it.
  History(const std::string& path, const Model& model, const config::PortTable* table, double fe_dt,
          double default_interval, bool resume = false);
  ~History();
  // Called after every FE step; writes the rows that are due.
  // inputs/outputs: the values of the table's to_fe/to_host variables, wire units.
  void record(const Solver& s, const std::vector<double>& inputs, const std::vector<double>& outputs);
  void flush();
  // The rows written so far and the energy scale (checkpoints; flush first).
  // Restoring cuts the resumed file back to the saved rows.
  void state(config::StateIO& io);
  size_t rows() const { return writer_.rows(); }
  // FE steps between two rows of each stream (global, nodes, elements).
  long every_global() const { return every_[0]; }
  long every_nodes() const { return every_[1]; }
  long every_elements() const { return every_[2]; }
  size_t snapshots() const;
  // *PCS_FATIGUE_PART: the hot spots so far ("" without fatigue counting),
  // and every counted element's table as CSV.
  std::string fatigue_report(double time) const;
  void write_fatigue_table(const std::string& path, double time) const;
  // The XDMF index of the field snapshots ("" when the deck asks for none).
  std::string fields_path() const;
  // "energy balance error X J (Y % of Z J)"; *exceeded is set when the error
  // is above its bound, 1 % of the largest energy the run held (kinetic +
  // internal, or the work done on it), *failed when it is 100 times above
  // (the results are not to be trusted: the run fails).
  std::string energy_summary(const Solver& s, bool* exceeded, bool* failed = nullptr) const;
  static constexpr double kEnergyFailFactor = 100.0;
  // The rule itself: bound 1 % of the largest energy the run held (scale);
  // exceeded above it, failed above kEnergyFailFactor times it.
  static void judge_energy(double error, double scale, bool* exceeded, bool* failed);

 private:
  static bool plastic_part(const Model& m, int part);
  std::vector<char> solid_plastic_, axis_plastic_;  // per history element: it has a plastic_strain series
  h5io::TimeSeriesWriter writer_;
  const Model& model_;
  std::vector<double> row_;
  std::vector<int> section_components_;                // the components a section writes (2D: y only)
  std::vector<std::vector<double>> section_weights_;  // per cross section: its nodes' mass shares
  long every_[3] = {1, 1, 1};
  size_t stream_[3] = {0, 0, 0};
  std::unique_ptr<class FieldWriter> fields_;
  std::unique_ptr<class AsciiOutput> ascii_;  // LS-DYNA's ASCII files, when the deck asks for them
  std::unique_ptr<class FatigueTracker> fatigue_;  // *PCS_FATIGUE_PART
  double next_snapshot_ = 0.0;
  double energy_scale_ = 0.0;
};

}  // namespace fe
