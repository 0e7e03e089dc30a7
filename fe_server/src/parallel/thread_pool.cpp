#include "parallel/thread_pool.hpp"

namespace fe {

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& w : workers_) w.join();
}

// Take tasks of the current job until none are left.
void ThreadPool::drain() {
  for (size_t t = next_.fetch_add(1); t < tasks_; t = next_.fetch_add(1)) (*job_)(t);
}

void ThreadPool::work() {
  unsigned long seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (!job_) continue;  // woke after that job was finished
      ++busy_;
    }
    drain();
    std::lock_guard<std::mutex> lock(mutex_);
    if (--busy_ == 0) finished_.notify_all();
  }
}

void ThreadPool::run(size_t tasks, const std::function<void(size_t)>& f) {
  if (tasks == 0) return;
  if (workers_.empty() || tasks == 1) {
    for (size_t t = 0; t < tasks; ++t) f(t);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &f;
    tasks_ = tasks;
    next_.store(0);
    ++generation_;
  }
  start_.notify_all();
  drain();
  // Every task has been taken; wait for the workers still running theirs.
  std::unique_lock<std::mutex> lock(mutex_);
  finished_.wait(lock, [&] { return busy_ == 0; });
  job_ = nullptr;
}

}  // namespace fe
