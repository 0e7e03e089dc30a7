// Time series in HDF5, written by both fe_server and tlm_host: one extendible
// 1-D dataset per series (unit as attribute), rows buffered in memory and
// written in chunks. flush() makes everything appended so far durable, so a
// run that stops on an error keeps what it had computed.
//
// The file is written in HDF5's single-writer/multiple-reader (SWMR) mode
// from the first row on, flushed after its first 64 rows and then at least
// every flush_interval seconds (default 1 s, checked every 64 rows). Then:
//  - a reader may watch the file while it grows (h5py: File(path, "r",
//    swmr=True), dataset.refresh());
//  - after kill -9 or a power loss the file still opens with every row up
//    to the last flush: SWMR's write order keeps the file consistent at all
//    times (HDF5 1.10 "SWMR User's Guide"). Such a file is still marked as
//    being written: open it with swmr=True, or clear the mark with
//    `h5clear -s FILE` (Debian's hdf5-tools). read_series() does the former.
// Datasets and attributes are therefore all declared before the first row.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace h5io {

class TimeSeriesWriter {
 public:
  // Creates (or truncates) the file; with `resume`, opens an existing one
  // written by the same program to continue it (a restart from a
  // checkpoint): add_series then opens the series instead of creating
  // them, and resume_at() cuts each stream back to the checkpoint's rows.
  explicit TimeSeriesWriter(const std::string& path, size_t rows_per_chunk = 4096, double flush_interval = 1.0,
                            bool resume = false);
  ~TimeSeriesWriter();
  TimeSeriesWriter(const TimeSeriesWriter&) = delete;
  TimeSeriesWriter& operator=(const TimeSeriesWriter&) = delete;

  // Declare a series before the first append; `name` may contain '/' groups.
  // A stream's first series is its time axis (unit s); each later series of
  // the stream gets a string attribute `time` with that axis' absolute path
  // ("/time", "/time_elements"), beside its `unit`.
  // Returns its column index within its stream.
  size_t add_series(const std::string& name, const std::string& unit, size_t stream = 0);
  // Another name for a series (an HDF5 soft link: `alias` reads as
  // `target`, both absolute paths); before the first row.
  void add_link(const std::string& alias, const std::string& target);
  // A further stream: series written at their own rate (their own rows and
  // their own time series). Stream 0 exists from the start. Before the first row.
  size_t add_stream();
  // A string attribute on the file's root group (scene, model, settings...);
  // before the first row.
  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, double value);
  // One value for every series of the stream, in declaration order.
  void append(const double* row, size_t stream = 0);
  void append(const std::vector<double>& row, size_t stream = 0) { append(row.data(), stream); }
  // Resume: continue stream `stream` after its first `rows` rows (the rows a
  // checkpoint was taken at; later ones, written after it, are dropped).
  // After the stream's series are declared, before the first row. Throws if
  // a series has fewer rows.
  void resume_at(size_t rows, size_t stream = 0);
  // Everything is declared: switch to SWMR writing and flush, so that the
  // file opens (with its rows so far, or none) even after kill -9 before the
  // first row (it was 48 bytes that did not open). The first append() does
  // this if it has not been done; a resumed file after resume_at().
  void start_writing();
  // Write buffered rows and flush the file to disk.
  void flush();
  size_t rows(size_t stream = 0) const { return streams_[stream].rows_written + streams_[stream].buffered; }
  size_t columns(size_t stream = 0) const { return streams_[stream].series.size(); }
  const std::string& path() const { return path_; }

 private:
  struct Stream {
    std::vector<hid_t> series;
    std::string time_name;  // the first series' absolute path
    std::vector<double> buffer;  // chunk_ rows × columns, column-major
    size_t buffered = 0;
    size_t rows_written = 0;
  };
  void write_buffer(Stream& s);
  std::string path_;
  double flush_interval_;
  int64_t last_flush_ns_ = 0;
  unsigned rows_since_check_ = 0;
  bool first_rows_flushed_ = false;
  bool live_ = false;
  bool resume_ = false;
  hid_t file_ = -1;
  size_t chunk_;
  std::vector<Stream> streams_{1};
};

// Read a whole 1-D dataset of doubles (post-processing and tests).
std::vector<double> read_series(const std::string& file, const std::string& dataset);
// Every 1-D dataset of the file with its length (rows), by path.
std::vector<std::pair<std::string, size_t>> list_series(const std::string& file);
// Read a string attribute of the root group, or of the group or dataset
// `object` (a series' "unit" or "time"); empty if either is absent.
std::string read_attribute(const std::string& file, const std::string& name, const std::string& object = "/");

}  // namespace h5io
