#include "field_output.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace fe {

FieldWriter::FieldWriter(const std::string& path, const Model& model) : m_(model), path_(path) {
  xdmf_ = path.substr(0, path.rfind('.')) + ".xdmf";
  file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file_ < 0) throw std::runtime_error("HDF5: cannot create " + path);
  std::vector<double> xyz;
  for (const auto& p : model.x0) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  write_dataset("mesh/coordinates", xyz.data(), model.x0.size(), 3);
  std::vector<int> conn;
  for (const auto& e : model.solids) conn.insert(conn.end(), e.n, e.n + 8);
  hsize_t dims[2] = {model.solids.size(), 8};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, "mesh/topology", H5T_NATIVE_INT, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  if (d >= 0 && !conn.empty()) H5Dwrite(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, conn.data());
  if (d >= 0) H5Dclose(d);
  H5Pclose(lcpl);
  H5Sclose(space);
}

FieldWriter::~FieldWriter() {
  if (file_ >= 0) H5Fclose(file_);
}

void FieldWriter::write_dataset(const std::string& name, const double* data, hsize_t rows, hsize_t cols) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
  herr_t rc = d < 0 ? -1 : (rows ? H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0);
  if (d >= 0) H5Dclose(d);
  H5Pclose(lcpl);
  H5Sclose(space);
  if (rc < 0) throw std::runtime_error("HDF5: cannot write " + name + " to " + path_);
}

void FieldWriter::write(const Solver& s) {
  char group[32];
  std::snprintf(group, sizeof group, "fields/%06zu/", times_.size());
  std::vector<double> u, v, sig, mises;
  for (size_t i = 0; i < m_.x0.size(); ++i) {
    const Vec3 d = s.x()[i] - m_.x0[i];
    u.insert(u.end(), {d.x(), d.y(), d.z()});
    v.insert(v.end(), {s.v()[i].x(), s.v()[i].y(), s.v()[i].z()});
  }
  for (size_t e = 0; e < m_.solids.size(); ++e) {
    const auto& t = s.stress(e);
    for (int k = 0; k < 6; ++k) sig.push_back(t(k));
    const double vm = std::sqrt(0.5 * ((t(0) - t(1)) * (t(0) - t(1)) + (t(1) - t(2)) * (t(1) - t(2)) +
                                       (t(2) - t(0)) * (t(2) - t(0))) +
                                3.0 * (t(3) * t(3) + t(4) * t(4) + t(5) * t(5)));
    mises.push_back(vm);
  }
  write_dataset(std::string(group) + "displacement", u.data(), m_.x0.size(), 3);
  write_dataset(std::string(group) + "velocity", v.data(), m_.x0.size(), 3);
  write_dataset(std::string(group) + "stress", sig.data(), m_.solids.size(), 6);
  write_dataset(std::string(group) + "von_mises", mises.data(), m_.solids.size(), 1);
  H5Fflush(file_, H5F_SCOPE_GLOBAL);
  times_.push_back(s.time());
  write_index();
}

void FieldWriter::write_index() const {
  const std::string h5 = path_.substr(path_.rfind('/') == std::string::npos ? 0 : path_.rfind('/') + 1);
  const size_t nn = m_.x0.size(), ne = m_.solids.size();
  std::ofstream x(xdmf_ + ".tmp");
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
    << "<Grid Name=\"fe_server\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (size_t k = 0; k < times_.size(); ++k) {
    char g[32];
    std::snprintf(g, sizeof g, "fields/%06zu/", k);
    x << "<Grid Name=\"step" << k << "\" GridType=\"Uniform\">\n<Time Value=\"" << times_[k] << "\"/>\n"
      << "<Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << ne << "\">\n"
      << "<DataItem Dimensions=\"" << ne << " 8\" NumberType=\"Int\" Format=\"HDF\">" << h5 << ":/mesh/topology</DataItem>\n"
      << "</Topology>\n<Geometry GeometryType=\"XYZ\">\n"
      << "<DataItem Dimensions=\"" << nn << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5
      << ":/mesh/coordinates</DataItem>\n</Geometry>\n";
    auto attr = [&](const char* name, const char* center, const char* type, size_t n, int cols) {
      x << "<Attribute Name=\"" << name << "\" AttributeType=\"" << type << "\" Center=\"" << center << "\">\n"
        << "<DataItem Dimensions=\"" << n;
      if (cols > 1) x << " " << cols;
      x << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5 << ":/" << g << name << "</DataItem>\n</Attribute>\n";
    };
    attr("displacement", "Node", "Vector", nn, 3);
    attr("velocity", "Node", "Vector", nn, 3);
    attr("stress", "Cell", "Tensor6", ne, 6);
    attr("von_mises", "Cell", "Scalar", ne, 1);
    x << "</Grid>\n";
  }
  x << "</Grid>\n</Domain>\n</Xdmf>\n";
  x.close();
  std::rename((xdmf_ + ".tmp").c_str(), xdmf_.c_str());
}

}  // namespace fe
