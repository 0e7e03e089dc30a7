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
