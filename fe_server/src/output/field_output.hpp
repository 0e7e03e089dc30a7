// Field snapshots for ParaView: displacements and velocities per node,
// stress components and von Mises stress per element, the part, element and
// node ids of the deck, written to an HDF5 file with an XDMF index beside it
// (a temporal collection of grids over one shared mesh: hexahedra in a 3D
// deck, quadrilaterals in the x–y plane in a 2D axisymmetric deck). The XDMF
// file is rewritten after every snapshot, so a run that stops early still
// leaves a readable index.
//
// What a ParaView user needs and meets (ParaView 5.11): the initial state is
// a snapshot at t = 0 (a colour scale does not start from an all-zero first
// frame); times are written to full precision; every stress component is a
// scalar of its own with its name (stress_xx ... or stress_radial ...), since
// readers disagree on the slot order of XDMF's Tensor6; units are in each
// attribute's Information and on each HDF5 dataset.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

#include "model/model.hpp"
#include "solver/solver.hpp"

namespace fe {

// Von Mises stress of a Voigt stress (xx, yy, zz, xy, yz, zx; for an
// axisymmetric element rr, yy, θθ, ry, 0, 0).
double von_mises(const Eigen::Matrix<double, 6, 1>& s);

class FieldWriter {
 public:
  // `path` is the HDF5 file; the XDMF index goes to the same name with .xdmf.
  // Writes the mesh and the snapshot at t = 0 (the model's initial state).
  // resume: opens the file of a run restarted from a checkpoint instead;
  // state() then drops the snapshots taken after the checkpoint.
  FieldWriter(const std::string& path, const Model& model, bool resume = false);
  ~FieldWriter();
  FieldWriter(const FieldWriter&) = delete;
  FieldWriter& operator=(const FieldWriter&) = delete;
  // damage: the fatigue damage per cell (FatigueTracker::damage_field), for
  // a model with *PCS_FATIGUE_PART; empty: zeros.
  void write(const Solver& s, const std::vector<double>& damage = {});
  size_t snapshots() const { return times_.size(); }
  // The snapshots' times (checkpoints); restoring removes later snapshots
  // from the file and rewrites the index.
  void state(config::StateIO& io);
  const std::string& xdmf_path() const { return xdmf_; }

 private:
  struct Field {
    std::string name, center, unit;  // center: Node or Cell
  };
  bool axisymmetric() const { return m_.solids.empty() && !m_.axis.empty(); }
  size_t cells() const { return axisymmetric() ? m_.axis.size() : m_.solids.size(); }
  // One snapshot from nodal displacements, velocities and element stresses
  // (Voigt per element, the solver's layout).
  void write_snapshot(double time, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& stress, const std::vector<double>& plastic_strain,
                      const std::vector<double>& damage);
  bool plastic_ = false;  // a plastic material: snapshots carry plastic_strain
  bool fatigue_ = false;  // *PCS_FATIGUE_PART: snapshots carry fatigue_damage
  bool fresh_ = false;    // a restart began a new file: the earlier snapshots are elsewhere
  // The fields of every snapshot, in the order written.
  std::vector<Field> field_list() const;
  void write_dataset(const std::string& name, const double* data, hsize_t rows, hsize_t cols, const std::string& unit);
  void write_int_dataset(const std::string& name, const std::vector<int>& data, hsize_t rows, hsize_t cols);
  void write_index() const;
  const Model& m_;
  std::string path_, xdmf_;
  hid_t file_ = -1;
  std::vector<double> times_;
  std::vector<Field> fields_;  // per snapshot, in the order written
};

}  // namespace fe
