#include "output/field_output.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace fe {

namespace {
void put_unit(hid_t d, const std::string& unit) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, unit.empty() ? 1 : unit.size());
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(d, "unit", type, space, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    H5Awrite(a, type, unit.c_str());
    H5Aclose(a);
  }
  H5Sclose(space);
  H5Tclose(type);
}
}  // namespace

double von_mises(const Eigen::Matrix<double, 6, 1>& t) {
  return std::sqrt(0.5 * ((t(0) - t(1)) * (t(0) - t(1)) + (t(1) - t(2)) * (t(1) - t(2)) + (t(2) - t(0)) * (t(2) - t(0))) +
                   3.0 * (t(3) * t(3) + t(4) * t(4) + t(5) * t(5)));
}

FieldWriter::FieldWriter(const std::string& path, const Model& model, bool resume) : m_(model), path_(path) {
  xdmf_ = path.substr(0, path.rfind('.')) + ".xdmf";
  for (const auto& [id, mat] : model.materials) plastic_ = plastic_ || mat.plastic;
  fatigue_ = !model.fatigue.empty();
  if (resume && std::filesystem::exists(path)) {
    H5E_BEGIN_TRY { file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT); }
    H5E_END_TRY;
    if (file_ < 0)
      throw std::runtime_error("HDF5: cannot open the field snapshots " + path +
                               " to continue them (a run killed while writing a snapshot leaves them unreadable: "
                               "move the file away, and the restart writes the later snapshots to a new one)");
    return;
  }
  // A restart without the file starts a new one with the later snapshots.
  fresh_ = resume;
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("HDF5: cannot create " + path);
  std::vector<double> xyz;
  for (const auto& p : model.x0) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  write_dataset("mesh/coordinates", xyz.data(), model.x0.size(), 3, "m");
  std::vector<int> conn, part, eid;
  const hsize_t corners = axisymmetric() ? 4 : 8;
  if (axisymmetric()) {
    for (const auto& e : model.axis) conn.insert(conn.end(), e.n, e.n + 4), part.push_back(e.part), eid.push_back(e.id);
  } else {
    for (const auto& e : model.solids) conn.insert(conn.end(), e.n, e.n + 8), part.push_back(e.part), eid.push_back(e.id);
  }
  write_int_dataset("mesh/topology", conn, cells(), corners);
  write_int_dataset("mesh/part", part, cells(), 1);
  write_int_dataset("mesh/element_id", eid, cells(), 1);
  write_int_dataset("mesh/node_id", model.node_ids, model.x0.size(), 1);
  if (fresh_) return;
  // The state at t = 0: undeformed, initial velocities, no stress.
  write_snapshot(0.0, model.x0, model.v0, std::vector<Eigen::Matrix<double, 6, 1>>(cells(), Eigen::Matrix<double, 6, 1>::Zero()),
                 std::vector<double>(cells(), 0.0), std::vector<double>(cells(), 0.0));
}

std::vector<FieldWriter::Field> FieldWriter::field_list() const {
  std::vector<Field> f{{"displacement", "Node", "m"}, {"velocity", "Node", "m/s"}};
  static const char* k3d[6] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_zx"};
  static const char* kAxi[4] = {"stress_radial", "stress_axial", "stress_hoop", "stress_shear_ry"};
  for (int c = 0; c < (axisymmetric() ? 4 : 6); ++c) f.push_back({axisymmetric() ? kAxi[c] : k3d[c], "Cell", "Pa"});
  f.push_back({"von_mises", "Cell", "Pa"});
  if (plastic_) f.push_back({"plastic_strain", "Cell", "1"});
  if (fatigue_) f.push_back({"fatigue_damage", "Cell", "1"});
  return f;
}

void FieldWriter::state(config::StateIO& io) {
  io.list("field times", times_);
  if (io.saving()) return;
  if (fresh_) {  // a new file: the earlier snapshots are not in it
    times_.clear();
    return;
  }
  // Snapshots taken after the checkpoint (the run went on before it stopped) go.
  for (size_t k = times_.size();; ++k) {
    char group[32];
    std::snprintf(group, sizeof group, "fields/%06zu", k);
    htri_t exists = 0;
    H5E_BEGIN_TRY { exists = H5Lexists(file_, group, H5P_DEFAULT); }
    H5E_END_TRY;
    if (exists <= 0) break;
    if (H5Ldelete(file_, group, H5P_DEFAULT) < 0) throw std::runtime_error("HDF5: cannot remove " + std::string(group) + " from " + path_);
  }
  fields_ = field_list();
  write_index();
}

FieldWriter::~FieldWriter() {
  if (file_ >= 0) H5Fclose(file_);
}

void FieldWriter::write_dataset(const std::string& name, const double* data, hsize_t rows, hsize_t cols,
                                const std::string& unit) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  herr_t rc = d < 0 ? -1 : (rows ? H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0);
  if (d >= 0) {
    put_unit(d, unit);
    H5Dclose(d);
  }
  H5Pclose(lcpl);
  H5Sclose(space);
  if (rc < 0) throw std::runtime_error("HDF5: cannot write " + name + " to " + path_);
}

void FieldWriter::write_int_dataset(const std::string& name, const std::vector<int>& data, hsize_t rows, hsize_t cols) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_INT, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  herr_t rc = d < 0 ? -1 : (rows ? H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) : 0);
  if (d >= 0) H5Dclose(d);
  H5Pclose(lcpl);
  H5Sclose(space);
  if (rc < 0) throw std::runtime_error("HDF5: cannot write " + name + " to " + path_);
}

void FieldWriter::write(const Solver& s, const std::vector<double>& damage) {
  // Across ranks the other ranks take part in gathering it (History's
  // follower: history.hpp).
  std::vector<Vec3> x, v;
  std::vector<Eigen::Matrix<double, 6, 1>> stress;
  std::vector<double> plastic;
  s.gather_fields(x, v, stress, plastic, axisymmetric());
  write_snapshot(s.time(), x, v, stress, plastic, damage.empty() ? std::vector<double>(cells(), 0.0) : damage);
}

void FieldWriter::write_snapshot(double time, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                 const std::vector<Eigen::Matrix<double, 6, 1>>& stress,
                                 const std::vector<double>& plastic_strain, const std::vector<double>& damage) {
  char group[32];
  std::snprintf(group, sizeof group, "fields/%06zu/", times_.size());
  const std::string g = group;
  std::vector<double> u, vel;
  for (size_t i = 0; i < m_.x0.size(); ++i) {
    const Vec3 d = x[i] - m_.x0[i];
    u.insert(u.end(), {d.x(), d.y(), d.z()});
    vel.insert(vel.end(), {v[i].x(), v[i].y(), v[i].z()});
  }
  fields_ = field_list();
  write_dataset(g + "displacement", u.data(), m_.x0.size(), 3, "m");
  write_dataset(g + "velocity", vel.data(), m_.x0.size(), 3, "m/s");
  // Stress components as named scalars: 3D Voigt xx, yy, zz, xy, yz, zx;
  // axisymmetric radial (x), axial (y), hoop, shear in the r–y plane.
  static const char* k3d[6] = {"stress_xx", "stress_yy", "stress_zz", "stress_xy", "stress_yz", "stress_zx"};
  static const char* kAxi[4] = {"stress_radial", "stress_axial", "stress_hoop", "stress_shear_ry"};
  const int n = axisymmetric() ? 4 : 6;
  std::vector<double> column(stress.size());
  for (int c = 0; c < n; ++c) {
    for (size_t e = 0; e < stress.size(); ++e) column[e] = stress[e](c);
    const std::string name = axisymmetric() ? kAxi[c] : k3d[c];
    write_dataset(g + name, column.data(), stress.size(), 1, "Pa");
  }
  for (size_t e = 0; e < stress.size(); ++e) column[e] = von_mises(stress[e]);
  write_dataset(g + "von_mises", column.data(), stress.size(), 1, "Pa");
  if (plastic_)  // effective plastic strain (0 in elastic parts)
    write_dataset(g + "plastic_strain", plastic_strain.data(), plastic_strain.size(), 1, "1");
  if (fatigue_)  // Miner damage so far (*PCS_FATIGUE_PART; 0 in parts without one)
    write_dataset(g + "fatigue_damage", damage.data(), damage.size(), 1, "1");
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
  times_.push_back(time);
  write_index();
}

void FieldWriter::write_index() const {
  const std::string h5 = path_.substr(path_.rfind('/') == std::string::npos ? 0 : path_.rfind('/') + 1);
  const size_t nn = m_.x0.size(), ne = cells();
  const bool axi = axisymmetric();
  std::ofstream x(xdmf_ + ".tmp");
  x << std::setprecision(17);
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"fe_server\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < times_.size(); ++k) {
    char g[32];
    std::snprintf(g, sizeof g, "fields/%06zu/", k);
    x << "<Grid Name=\"step" << k << "\" GridType=\"Uniform\">\n<Time Value=\"" << times_[k] << "\"/>\n"
      << "<Topology TopologyType=\"" << (axi ? "Quadrilateral" : "Hexahedron") << "\" NumberOfElements=\"" << ne
      << "\">\n"
      << "<DataItem Dimensions=\"" << ne << " " << (axi ? 4 : 8) << "\" NumberType=\"Int\" Format=\"HDF\">" << h5
      << ":/mesh/topology</DataItem>\n"
      << "</Topology>\n<Geometry GeometryType=\"XYZ\">\n"
      << "<DataItem Dimensions=\"" << nn << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
      << ":/mesh/coordinates</DataItem>\n</Geometry>\n";
    auto attr = [&](const std::string& name, const std::string& center, const std::string& path, size_t n, int cols,
                    const char* number, const std::string& unit) {
      x << "<Attribute Name=\"" << name << "\" AttributeType=\"" << (cols == 3 ? "Vector" : "Scalar") << "\" Center=\""
        << center << "\">\n";
      if (!unit.empty()) x << "<Information Name=\"unit\" Value=\"" << unit << "\"/>\n";
      x << "<DataItem Dimensions=\"" << n;
      if (cols > 1) x << " " << cols;
      x << "\" NumberType=\"" << number << "\"" << (number[0] == 'F' ? " Precision=\"8\"" : "") << " Format=\"HDF\">"
        << h5 << ":/" << path << "</DataItem>\n</Attribute>\n";
    };
    for (const Field& f : fields_)
      attr(f.name, f.center, g + f.name, f.center == "Node" ? nn : ne, f.name == "displacement" || f.name == "velocity" ? 3 : 1,
           "Float", f.unit);
    attr("part", "Cell", "mesh/part", ne, 1, "Int", "");
    attr("element_id", "Cell", "mesh/element_id", ne, 1, "Int", "");
    attr("node_id", "Node", "mesh/node_id", nn, 1, "Int", "");
    x << "</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  x.close();
  std::rename((xdmf_ + ".tmp").c_str(), xdmf_.c_str());
}

}  // namespace fe
