// Time series in HDF5, written by both fe_server and tlm_host: one extendible
// 1-D dataset per series (unit as attribute), rows buffered in memory and
// written in chunks. flush() makes everything appended so far durable, so a
// run that stops on an error keeps what it had computed.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

namespace h5io {

class TimeSeriesWriter {
 public:
  // Creates (or truncates) the file.
  explicit TimeSeriesWriter(const std::string& path, size_t rows_per_chunk = 4096);
  ~TimeSeriesWriter();
  TimeSeriesWriter(const TimeSeriesWriter&) = delete;
  TimeSeriesWriter& operator=(const TimeSeriesWriter&) = delete;

  // Declare a series before the first append; `name` may contain '/' groups.
  // Returns its column index.
  size_t add_series(const std::string& name, const std::string& unit);
  // A string attribute on the file's root group (scene, model, settings...).
  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, double value);
  // One value for every declared series, in declaration order.
  void append(const double* row);
  void append(const std::vector<double>& row) { append(row.data()); }
  // Write buffered rows and flush the file to disk.
  void flush();
  size_t rows() const { return rows_written_ + buffered_; }
  size_t columns() const { return series_.size(); }
  const std::string& path() const { return path_; }

 private:
  void write_buffer();
  std::string path_;
  hid_t file_ = -1;
  size_t chunk_;
  std::vector<hid_t> series_;
  std::vector<double> buffer_;  // chunk_ rows × columns, column-major
  size_t buffered_ = 0;
  size_t rows_written_ = 0;
};

// Read a whole 1-D dataset of doubles (post-processing and tests).
std::vector<double> read_series(const std::string& file, const std::string& dataset);
// Read a string attribute of the root group; empty if absent.
std::string read_attribute(const std::string& file, const std::string& name);

}  // namespace h5io
