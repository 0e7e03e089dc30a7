// The checkpoint file (config/checkpoint.hpp): what is saved comes back
// bit for bit, and a file that does not fit (damaged, truncated, another
// program's records or sizes, records left over) is refused naming why.
#include <gtest/gtest.h>
#include <chrono>
#include <unistd.h>
#include <sys/stat.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "config/checkpoint.hpp"

namespace {

struct Pair {
  double a;
  int b;
};

// A small state with every kind of record the programs write.
struct State {
  double x = 0.0;
  long n = 0;
  bool flag = false;
  std::vector<double> values;
  std::vector<Pair> pairs;
  std::string name;
  void io(config::StateIO& io) {
    io.expect("size", 3, "the size");
    io.value("x", x);
    io.value("n", n);
    io.value("flag", flag);
    io.list("values", values);  // lists: restored to the file's length
    io.list("pairs", pairs);
    io.text("name", name);
  }
};

std::string temp_file(const char* name) { return (std::filesystem::temp_directory_path() / name).string(); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const config::CheckpointError& e) {
    return e.what();
  }
  return "";
}

State sample() {
  State s;
  s.x = std::nextafter(1.0, 2.0);  // a value a decimal round trip could lose
  s.n = -1234567890123L;
  s.flag = true;
  s.values = {0.1, -0.0, std::numeric_limits<double>::denorm_min(), 1e300};
  s.pairs = {{1.5, 7}, {-2.5, -9}};
  s.name = "piston";
  return s;
}

}  // namespace

TEST(Checkpoint, WhatIsSavedComesBackBitForBit) {
  const std::string path = temp_file("pcs_ckpt_roundtrip.ckpt");
  State s = sample();
  config::StateWriter w;
  s.io(w);
  w.write(path);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp")) << "the temporary file is renamed";
  State r;
  config::StateReader reader(path);
  r.io(reader);
  reader.finish();
  EXPECT_EQ(std::memcmp(&r.x, &s.x, sizeof s.x), 0);
  EXPECT_EQ(r.n, s.n);
  EXPECT_EQ(r.flag, s.flag);
  ASSERT_EQ(r.values.size(), s.values.size());
  EXPECT_EQ(std::memcmp(r.values.data(), s.values.data(), s.values.size() * sizeof(double)), 0);  // -0.0 kept
  ASSERT_EQ(r.pairs.size(), 2u);
  EXPECT_EQ(r.pairs[1].a, -2.5);
  EXPECT_EQ(r.pairs[1].b, -9);
  EXPECT_EQ(r.name, "piston");
  std::filesystem::remove(path);
}

TEST(Checkpoint, AFileThatDoesNotFitIsRefusedSayingWhy) {
  const std::string path = temp_file("pcs_ckpt_refused.ckpt");
  State s = sample();
  config::StateWriter w;
  s.io(w);
  w.write(path);
  const auto size = std::filesystem::file_size(path);

  {  // another size where one is expected
    config::StateReader r(path);
    const std::string e = error_of([&] { r.expect("size", 4, "the number of nodes"); });
    EXPECT_NE(e.find("the number of nodes: the checkpoint has 3, this run has 4"), std::string::npos) << e;
  }
  {  // another record where one is expected (another program or version)
    config::StateReader r(path);
    r.expect("size", 3, "the size");
    double y = 0;
    const std::string e = error_of([&] { r.value("y", y); });
    EXPECT_NE(e.find("record 2 ('y' expected): found 'x'"), std::string::npos) << e;
  }
  {  // another element size for the same name
    config::StateReader r(path);
    r.expect("size", 3, "the size");
    float x = 0;
    const std::string e = error_of([&] { r.value("x", x); });
    EXPECT_NE(e.find("record 'x'"), std::string::npos) << e;
  }
  {  // an array whose length the run has fixed refuses another length
    config::StateReader r(path);
    r.expect("size", 3, "the size");
    double x = 0;
    long n = 0;
    bool flag = false;
    r.value("x", x), r.value("n", n), r.value("flag", flag);
    std::vector<double> three(3);
    const std::string e = error_of([&] { r.array("values", three); });
    EXPECT_NE(e.find("record 'values': 4 elements, this run has 3"), std::string::npos) << e;
  }
  {  // records the reader does not take
    config::StateReader r(path);
    r.expect("size", 3, "the size");
    const std::string e = error_of([&] { r.finish(); });
    EXPECT_NE(e.find("holds more state than this run has"), std::string::npos) << e;
  }
  {  // one byte changed
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    const char c = static_cast<char>(f.peek());
    f.put(static_cast<char>(c ^ 1));
    f.close();
    const std::string e = error_of([&] { config::StateReader r(path); });
    EXPECT_NE(e.find("is damaged"), std::string::npos) << e;
  }
  {  // cut short, and not a checkpoint at all
    std::filesystem::resize_file(path, 20);
    EXPECT_NE(error_of([&] { config::StateReader r(path); }).find("is not a checkpoint file"), std::string::npos);
    std::ofstream(path) << "*KEYWORD\n";
    EXPECT_NE(error_of([&] { config::StateReader r(path); }).find("is not a checkpoint file"), std::string::npos);
  }
  std::filesystem::remove(path);
  EXPECT_NE(error_of([&] { config::StateReader r(path); }).find("cannot open checkpoint"), std::string::npos);
}

// A checkpoint is a regular file: a FIFO once blocked --restart forever and
// /dev/zero read until bad_alloc. Both are refused at once, saying why, as
// is a folder. (The FIFO has no writer: opening it for reading without
// O_NONBLOCK would block this test for good.)
TEST(Checkpoint, AFifoADeviceOrAFolderIsRefusedAtOnce) {
  const std::string fifo = std::filesystem::temp_directory_path() / ("pcs_ckpt_fifo_" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {fifo, std::string("/dev/zero"), std::string("/tmp")}) {
    const auto start = std::chrono::steady_clock::now();
    const std::string why = error_of([&] { config::StateReader r(path); });
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0) << path;
    EXPECT_NE(why.find("cannot open checkpoint '" + path + "'"), std::string::npos) << why;
    EXPECT_TRUE(why.find("not a regular file") != std::string::npos || why.find("it is a folder") != std::string::npos)
        << why;
  }
  std::filesystem::remove(fifo);
}

// A crash while a checkpoint is written leaves a partial FILE.tmp, never a
// partial FILE: the name is given only to a whole, flushed file (rename).
// The checkpoint a new one replaces stays as FILE.prev.
TEST(Checkpoint, AWriteCutShortLeavesThePreviousCheckpointWhole) {
  const std::string path = temp_file("pcs_ckpt_atomic.ckpt");
  State s = sample();
  config::StateWriter w;
  s.io(w);
  w.write(path);
  std::ofstream(path + ".tmp") << "PCS-CKPT half a checkpoint";  // what a crash mid-write leaves
  State r;
  config::StateReader reader(path);
  r.io(reader);
  reader.finish();
  EXPECT_EQ(r.name, "piston");
  s.name = "spool";  // the next checkpoint replaces both
  config::StateWriter w2;
  s.io(w2);
  w2.write(path);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  config::StateReader again(path);
  r.io(again);
  EXPECT_EQ(r.name, "spool");
  config::StateReader previous(path + ".prev");  // the one it replaced is kept
  r.io(previous);
  EXPECT_EQ(r.name, "piston");
  std::filesystem::remove(path);
  std::filesystem::remove(path + ".prev");
}
