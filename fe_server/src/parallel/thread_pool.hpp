// A small pool of worker threads for the solver's loops. run(n, f) calls
// f(0) … f(n−1), each exactly once, spread over the workers and the calling
// thread, and returns when all are done. Which thread runs which task is
// not fixed; the solver makes its results independent of that by giving
// each task its own output (a block of elements writes its own forces and
// its own energy partials, reduced afterwards in block order), so results
// are bit-identical for any thread count.
//
// Waiting is passive (condition variables, no spinning): in a co-simulation
// the host process shares the cores.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace fe {

class ThreadPool {
 public:
  explicit ThreadPool(int threads);  // threads ≥ 1; threads − 1 workers are started
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }
  void run(size_t tasks, const std::function<void(size_t)>& f);

 private:
  void work();
  void drain();
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, finished_;
  // Set under the lock by run(); a worker drains only while it is counted
  // in busy_, and run() returns only when busy_ is back to zero, so no
  // worker ever meets a job that has returned.
  const std::function<void(size_t)>* job_ = nullptr;
  size_t tasks_ = 0;
  std::atomic<size_t> next_{0};
  int busy_ = 0;
  unsigned long generation_ = 0;
  bool stop_ = false;
};

}  // namespace fe
