#include "peer_group.hpp"

namespace tlm {

PeerGroup::PeerGroup(std::vector<Component*> members, Stepping how)
    : members_(std::move(members)), how_(how), errors_(members_.size()) {
  if (how_ == Stepping::Parallel)
    for (size_t i = 0; i + 1 < members_.size(); ++i) workers_.emplace_back(&PeerGroup::work, this, i);
}

PeerGroup::~PeerGroup() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  start_.notify_all();
  for (auto& w : workers_) w.join();
}

void PeerGroup::work(size_t index) {
  unsigned long seen = 0;
  for (;;) {
    double t = 0.0;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return quit_ || generation_ != seen; });
      if (quit_) return;
      seen = generation_;
      t = t_;
    }
    std::exception_ptr error;
    try {
      members_[index]->simulate_one_step(t);
    } catch (...) {
      error = std::current_exception();
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      errors_[index] = error;
      --pending_;
    }
    done_.notify_one();
  }
}

void PeerGroup::step(double t) {
  if (how_ != Stepping::Parallel) {
    if (how_ == Stepping::Sequential)
      for (Component* c : members_) c->send_peer_inputs();
    for (Component* c : members_) c->simulate_one_step(t);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    t_ = t;
    pending_ = workers_.size();
    ++generation_;
  }
  start_.notify_all();
  std::exception_ptr error;
  try {
    members_.back()->simulate_one_step(t);
  } catch (...) {
    error = std::current_exception();
  }
  {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [&] { return pending_ == 0; });
  }
  for (size_t i = 0; i < workers_.size(); ++i)
    if (errors_[i]) std::rethrow_exception(errors_[i]);
  if (error) std::rethrow_exception(error);
}

}  // namespace tlm
