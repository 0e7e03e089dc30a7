// Field snapshots for ParaView: displacements and velocities per node,
// stress and von Mises stress per solid element, written to an HDF5 file
// with an XDMF index beside it (a temporal collection of hexahedral grids
// over one shared mesh). The XDMF file is rewritten after every snapshot,
// so a run that stops early still leaves a readable index.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

#include "model.hpp"
#include "solver.hpp"

namespace fe {

class FieldWriter {
 public:
  // `path` is the HDF5 file; the XDMF index goes to the same name with .xdmf.
  FieldWriter(const std::string& path, const Model& model);
  ~FieldWriter();
  FieldWriter(const FieldWriter&) = delete;
  FieldWriter& operator=(const FieldWriter&) = delete;
  void write(const Solver& s);
  size_t snapshots() const { return times_.size(); }
  const std::string& xdmf_path() const { return xdmf_; }

 private:
  void write_dataset(const std::string& name, const double* data, hsize_t rows, hsize_t cols);
  void write_index() const;
  const Model& m_;
  std::string path_, xdmf_;
  hid_t file_ = -1;
  std::vector<double> times_;
};

}  // namespace fe
