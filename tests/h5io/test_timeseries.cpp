// The HDF5 time-series writer (h5io/timeseries.hpp) shared by fe_server and
// tlm_host.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "h5io/timeseries.hpp"
#include "process.hpp"

namespace {

long rss_kb() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

}  // namespace

// Memory stays flat however long a run writes. HDF5's default chunk cache
// (1 MiB per dataset) kept up to 32 finished chunks of every series, so a
// process grew by up to 1 MB per series over a run: the monolithic rig model
// (145 series) reached 66 MB at 0.4 s and 147 MB at 1.2 s of simulated time.
// 64 series × 36 chunks of 4096 rows (75 MB of rows): the old cache grows by
// 64 MB; the writer's (two chunks per series) by at most 64 × 64 KB = 4 MB,
// plus HDF5's chunk index. 16 MB leaves room for that and the allocator.
TEST(TimeSeriesWriter, MemoryStaysFlatWhileASeriesGrows) {
#ifdef PCS_SANITIZED
  GTEST_SKIP() << "the sanitizers' quarantine holds freed memory: RSS does not measure the writer there";
#endif
  testing_support::TempDir dir;
  constexpr size_t kSeries = 64, kRows = 36 * 4096;
  h5io::TimeSeriesWriter w(dir.file("long.h5"));
  for (size_t i = 0; i < kSeries; ++i) w.add_series("s/" + std::to_string(i), "m");
  std::vector<double> row(kSeries);
  long after_first_chunk = 0;
  for (size_t r = 0; r < kRows; ++r) {
    for (size_t i = 0; i < kSeries; ++i) row[i] = 1e-3 * static_cast<double>(r) + static_cast<double>(i);
    w.append(row);
    if (r == 2 * 4096) after_first_chunk = rss_kb();
  }
  w.flush();
  const long grown = rss_kb() - after_first_chunk;
  std::printf("RSS grew by %ld kB while 34 more chunks per series were written\n", grown);
  EXPECT_LT(grown, 16 * 1024);
  EXPECT_EQ(w.rows(), kRows);
  const std::vector<double> back = h5io::read_series(dir.file("long.h5"), "s/63");
  ASSERT_EQ(back.size(), kRows);
  EXPECT_EQ(back.back(), 1e-3 * static_cast<double>(kRows - 1) + 63.0);
}

// Each series names its own time axis. fe_server writes three streams at
// three rates (ports and energies, history nodes, sections); their lengths
// can be equal (time and time_nodes both every 100 us in the rig deck), so a
// reader that paired series with axes by length would pair them wrongly.
// Here two streams of the same length: each series must name its own.
TEST(TimeSeriesWriter, EverySeriesNamesTheTimeAxisOfItsStream) {
  testing_support::TempDir dir;
  const std::string path = dir.file("axes.h5");
  {
    h5io::TimeSeriesWriter w(path);
    w.add_series("time", "s");
    w.add_series("ports/a.p", "Pa");
    const size_t s1 = w.add_stream();
    w.add_series("time_elements", "s", s1);
    w.add_series("sections/1/fy", "N", s1);
    for (int i = 0; i < 3; ++i) {
      w.append({1e-3 * i, 1e5}, 0);
      w.append({2e-3 * i, 10.0}, s1);
    }
  }
  EXPECT_EQ(h5io::read_attribute(path, "time", "/ports/a.p"), "/time");
  EXPECT_EQ(h5io::read_attribute(path, "time", "/sections/1/fy"), "/time_elements");
  EXPECT_EQ(h5io::read_attribute(path, "unit", "/sections/1/fy"), "N");
  EXPECT_EQ(h5io::read_attribute(path, "time", "/time_elements"), "") << "an axis names no axis";
  EXPECT_EQ(h5io::read_attribute(path, "time", "/no/such"), "");
}
