// The FE server's time histories: port values, history nodes and energies,
// one row per coupling step, through the HDF5 time-series writer.
#pragma once

#include <memory>
#include <string>

#include "cavity_load.hpp"
#include "config/port_table.hpp"
#include "h5io/timeseries.hpp"
#include "solver.hpp"

namespace fe {

class History {
 public:
  History(const std::string& path, const Model& model, const config::PortTable* table);
  // inputs/outputs: the values of the table's to_fe/to_host variables, wire units.
  void record(const Solver& s, const std::vector<double>& inputs, const std::vector<double>& outputs);
  void flush() { writer_.flush(); }
  size_t rows() const { return writer_.rows(); }

 private:
  h5io::TimeSeriesWriter writer_;
  const Model& model_;
  std::vector<double> row_;
};

}  // namespace fe
