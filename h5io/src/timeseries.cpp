#include "h5io/timeseries.hpp"

#include <chrono>
#include <cstdio>
#include <stdexcept>

namespace h5io {

namespace {
[[noreturn]] void fail(const std::string& what, const std::string& path) {
  throw std::runtime_error("HDF5: " + what + " (" + path + ")");
}
void put_string_attribute(hid_t obj, const std::string& name, const std::string& value,
                          const std::string& path) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.empty() ? 1 : value.size());
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  hid_t space = H5Screate(H5S_SCALAR);
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  hid_t attr = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  herr_t rc = attr < 0 ? -1 : H5Awrite(attr, type, value.empty() ? "" : value.c_str());
  if (attr >= 0) H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  if (rc < 0) fail("cannot write attribute " + name, path);
}
}  // namespace

namespace {
int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

TimeSeriesWriter::TimeSeriesWriter(const std::string& path, size_t rows_per_chunk, double flush_interval, bool resume)
    : path_(path), flush_interval_(flush_interval), resume_(resume), chunk_(rows_per_chunk ? rows_per_chunk : 1) {
  // SWMR needs the file format of HDF5 1.10 or later.
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
  // Rows are appended in order, so a series needs only the chunk being
  // filled in HDF5's chunk cache. Its default (1 MiB per dataset) kept up
  // to 32 finished chunks of every series: fe_server and tlm_host grew by
  // up to 1 MB per series over a run (issue 39: 19 → 39 MB and 26 → 63 MB
  // in 0.6 s; the monolithic rig model 66 MB at 0.4 s, 147 MB at 1.2 s).
  // Two chunks, finished ones evicted first (w0 = 1), hold it flat. Set on
  // the file: the same setting on each dataset's access list left the
  // growth as it was (measured; H5Fstart_swmr_write refreshes the open
  // datasets, which seems to drop it).
  H5Pset_cache(fapl, 0, 7, 2 * chunk_ * sizeof(double), 1.0);
  if (resume) {
    H5E_BEGIN_TRY { file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl); }
    H5E_END_TRY;
    // A writer that died without closing (kill -9, a lost node: the very
    // case a restart is for) leaves the file marked as being written, and
    // HDF5 refuses to open it for writing. Clearing the mark is what
    // `h5clear -s` does, through the file-access property
    // "clear_status_flags" (HDF5 1.10 tools/src/h5clear); safe here, since
    // SWMR kept the file consistent up to its last flush and the rows after
    // the checkpoint, flushed before it was written, are cut off anyway.
    if (file_ < 0) {
      hbool_t clear = 1;
      if (H5Pset(fapl, "clear_status_flags", &clear) >= 0) {
        H5E_BEGIN_TRY { file_ = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl); }
        H5E_END_TRY;
      }
    }
    H5Pclose(fapl);
    if (file_ < 0)
      fail("cannot open the results file to continue it (is it there, and yours?)", path);
  } else {
    file_ = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
  }
  if (file_ < 0) fail("cannot create file", path);
  last_flush_ns_ = now_ns();
}

void TimeSeriesWriter::start_writing() {
  if (live_) return;
  for (Stream& st : streams_) st.buffer.assign(st.series.size() * chunk_, 0.0);
  // SWMR from here on: no new datasets or attributes. Switching writes the
  // metadata and flushes; the flush below makes it durable on every path.
  if (H5Fstart_swmr_write(file_) < 0) fail("cannot switch to SWMR writing", path_);
  live_ = true;
  flush();
}

TimeSeriesWriter::~TimeSeriesWriter() {
  try {
    flush();
  } catch (...) {
    // A destructor must not throw; flush() already reported nothing else can be done.
  }
  for (const Stream& st : streams_)
    for (hid_t d : st.series) H5Dclose(d);
  if (file_ >= 0) H5Fclose(file_);
}

size_t TimeSeriesWriter::add_stream() {
  if (live_) fail("stream declared after the first row", path_);
  streams_.emplace_back();
  return streams_.size() - 1;
}

size_t TimeSeriesWriter::add_series(const std::string& name, const std::string& unit, size_t stream) {
  if (live_) fail("series '" + name + "' declared after the first row", path_);
  if (stream >= streams_.size()) fail("series '" + name + "' names an undeclared stream", path_);
  if (resume_) {
    hid_t d = -1;
    H5E_BEGIN_TRY { d = H5Dopen2(file_, name.c_str(), H5P_DEFAULT); }
    H5E_END_TRY;
    if (d < 0) fail("the file to continue has no series '" + name + "' (written by another model?)", path_);
    streams_[stream].series.push_back(d);
    return streams_[stream].series.size() - 1;
  }
  hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {chunk_};
  hid_t space = H5Screate_simple(1, dims, maxdims);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(dcpl, 1, chunk);
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, lcpl, dcpl, H5P_DEFAULT);
  H5Pclose(lcpl);
  H5Pclose(dcpl);
  H5Sclose(space);
  if (d < 0) fail("cannot create dataset '" + name + "'", path_);
  put_string_attribute(d, "unit", unit, path_);
  // A stream's first series is its time; every other series names it, so a
  // reader pairs each series with its own time axis without guessing by length.
  Stream& s = streams_[stream];
  if (s.series.empty())
    s.time_name = "/" + name;
  else
    put_string_attribute(d, "time", s.time_name, path_);
  s.series.push_back(d);
  return streams_[stream].series.size() - 1;
}

void TimeSeriesWriter::add_link(const std::string& alias, const std::string& target) {
  if (live_) fail("link '" + alias + "' declared after the first row", path_);
  if (resume_) return;  // the file to continue has it
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  const herr_t e = H5Lcreate_soft(target.c_str(), file_, alias.c_str(), lcpl, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (e < 0) fail("cannot create link '" + alias + "' to '" + target + "'", path_);
}

void TimeSeriesWriter::resume_at(size_t rows, size_t stream) {
  if (!resume_ || live_) fail("resume_at() on a new file or after the first row", path_);
  Stream& st = streams_.at(stream);
  const hsize_t size[1] = {rows};
  for (hid_t d : st.series) {
    hid_t space = H5Dget_space(d);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    H5Sclose(space);
    if (n < 0 || static_cast<size_t>(n) < rows)
      fail("a series has " + std::to_string(n) + " rows, the checkpoint was taken after " + std::to_string(rows), path_);
    if (H5Dset_extent(d, size) < 0) fail("cannot cut a series back to the checkpoint's rows", path_);
  }
  st.rows_written = rows;
  st.buffered = 0;
}

void TimeSeriesWriter::set_attribute(const std::string& name, const std::string& value) {
  if (live_) fail("attribute '" + name + "' set after the first row", path_);
  put_string_attribute(file_, name, value, path_);
}

void TimeSeriesWriter::set_attribute(const std::string& name, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", value);
  put_string_attribute(file_, name, buf, path_);
}

void TimeSeriesWriter::append(const double* row, size_t stream) {
  if (!live_) start_writing();  // the first row: everything is declared
  Stream& st = streams_[stream];
  for (size_t c = 0; c < st.series.size(); ++c) st.buffer[c * chunk_ + st.buffered] = row[c];
  if (++st.buffered == chunk_) write_buffer(st);
  if (++rows_since_check_ >= 64) {  // the clock is read every 64 rows only
    rows_since_check_ = 0;
    // The first 64 rows at once: a reader watching the file (or a test
    // waiting for a run to be under way) sees rows within a fraction of a
    // second, not only after the first interval; a short co-simulation had
    // ended before its first flush.
    if (!first_rows_flushed_ || static_cast<double>(now_ns() - last_flush_ns_) >= flush_interval_ * 1e9) {
      flush();
      first_rows_flushed_ = true;
    }
  }
}

void TimeSeriesWriter::write_buffer(Stream& st) {
  if (st.buffered == 0) return;
  hsize_t start[1] = {st.rows_written}, count[1] = {st.buffered};
  hsize_t new_size[1] = {st.rows_written + st.buffered};
  for (size_t c = 0; c < st.series.size(); ++c) {
    hid_t d = st.series[c];
    if (H5Dset_extent(d, new_size) < 0) fail("cannot extend a dataset", path_);
    hid_t file_space = H5Dget_space(d);
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    hid_t mem_space = H5Screate_simple(1, count, nullptr);
    herr_t rc = H5Dwrite(d, H5T_NATIVE_DOUBLE, mem_space, file_space, H5P_DEFAULT,
                         st.buffer.data() + c * chunk_);
    H5Sclose(mem_space);
    H5Sclose(file_space);
    if (rc < 0) fail("cannot write rows", path_);
  }
  st.rows_written += st.buffered;
  st.buffered = 0;
}

void TimeSeriesWriter::flush() {
  if (file_ < 0) return;
  for (Stream& st : streams_) write_buffer(st);
  if (H5Fflush(file_, H5F_SCOPE_GLOBAL) < 0) fail("cannot flush", path_);
  last_flush_ns_ = now_ns();
}

namespace {
// Opens for reading; a file still marked as being written (its writer was
// killed, or is running) is opened as an SWMR reader.
hid_t open_for_reading(const std::string& file) {
  hid_t f = -1;
  H5E_BEGIN_TRY { f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
  H5E_END_TRY;
  if (f < 0) f = H5Fopen(file.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, H5P_DEFAULT);
  return f;
}
}  // namespace

std::vector<double> read_series(const std::string& file, const std::string& dataset) {
  hid_t f = open_for_reading(file);
  if (f < 0) fail("cannot open file", file);
  hid_t d = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
  if (d < 0) {
    H5Fclose(f);
    fail("no dataset '" + dataset + "'", file);
  }
  hid_t space = H5Dget_space(d);
  hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<double> out(static_cast<size_t>(n > 0 ? n : 0));
  herr_t rc = out.empty() ? 0 : H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
  if (rc < 0) fail("cannot read '" + dataset + "'", file);
  return out;
}

namespace {
herr_t collect_dataset(hid_t obj, const char* name, const H5O_info_t* info, void* out) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  hid_t d = H5Dopen2(obj, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t space = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  H5Sclose(space);
  H5Dclose(d);
  static_cast<std::vector<std::pair<std::string, size_t>>*>(out)->emplace_back(name, static_cast<size_t>(n > 0 ? n : 0));
  return 0;
}
}  // namespace

std::vector<std::pair<std::string, size_t>> list_series(const std::string& file) {
  hid_t f = open_for_reading(file);
  if (f < 0) fail("cannot open file", file);
  std::vector<std::pair<std::string, size_t>> out;
  const herr_t rc = H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_NATIVE, collect_dataset, &out, H5O_INFO_BASIC);
  H5Fclose(f);
  if (rc < 0) fail("cannot list the datasets", file);
  return out;
}

std::string read_attribute(const std::string& file, const std::string& name, const std::string& object) {
  hid_t f = open_for_reading(file);
  if (f < 0) fail("cannot open file", file);
  std::string out;
  hid_t o = -1;
  H5E_BEGIN_TRY { o = H5Oopen(f, object.c_str(), H5P_DEFAULT); }
  H5E_END_TRY;
  if (o >= 0 && H5Aexists(o, name.c_str()) > 0) {
    hid_t a = H5Aopen(o, name.c_str(), H5P_DEFAULT);
    hid_t type = H5Aget_type(a);
    size_t size = H5Tget_size(type);
    std::string buf(size + 1, '\0');
    hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, size + 1);
    if (H5Aread(a, mem, &buf[0]) >= 0) out = buf.c_str();
    H5Tclose(mem);
    H5Tclose(type);
    H5Aclose(a);
  }
  if (o >= 0) H5Oclose(o);
  H5Fclose(f);
  return out;
}

}  // namespace h5io
