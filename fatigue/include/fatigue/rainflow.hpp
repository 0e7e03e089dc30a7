// Rainflow cycle counting of a stress history (ASTM E1049-85, 5.4.4),
// streaming: a counter takes one sample at a time and keeps only the
// reversals not yet closed into cycles (a handful for a repeated load
// history, never the history), so one counter per element of a long run
// costs memory per element, not per step.
#pragma once

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace fatigue {

// One counted cycle: its range (max - min), its mean, and its count: 1 for a
// full cycle, 0.5 for a half cycle (a range holding the starting point, and
// the residue at the end).
struct Cycle {
  double range = 0.0;
  double mean = 0.0;
  double count = 0.0;
};

// ASTM E1049-85 rainflow counting: the three-point rule with the starting
// point (5.4.4 steps 1-5) on each reversal as it is found, and the residue
// counted as half cycles at the end (step 6). Each cycle goes to the sink,
// a callable taking a Cycle, as soon as it closes.
class RainflowCounter {
 public:
  // gate >= 0: a turning point counts only once the signal has come back
  // from it by more than the gate, so noise below the gate makes no cycles
  // (0: every turning point of the samples).
  explicit RainflowCounter(double gate = 0.0) : gate_(gate) {}

  template <class Sink>
  void add(double x, Sink&& sink) {
    if (!started_) {  // the first sample is the first reversal
      started_ = true;
      reversal(x, sink);
      extreme_ = x;
      return;
    }
    if (direction_ == 0) {  // which way the history leaves its first point
      if (x - stack_.back() > gate_) direction_ = 1, extreme_ = x;
      else if (stack_.back() - x > gate_) direction_ = -1, extreme_ = x;
      return;
    }
    if ((direction_ > 0 && x >= extreme_) || (direction_ < 0 && x <= extreme_)) {
      extreme_ = x;  // still going the same way: the candidate moves
    } else if (std::fabs(x - extreme_) > gate_) {
      reversal(extreme_, sink);  // it turned back by more than the gate
      direction_ = -direction_;
      extreme_ = x;
    }
  }

  // The end of the history: the last extremum is a reversal, and every range
  // left is half a cycle. The counter is then empty, ready for a new history.
  template <class Sink>
  void finish(Sink&& sink) {
    if (direction_ != 0) reversal(extreme_, sink);
    for (size_t i = 1; i < stack_.size(); ++i) emit(stack_[i - 1], stack_[i], 0.5, sink);
    stack_.clear();
    direction_ = 0;
    started_ = false;
  }

  // Reversals held, not yet closed into cycles: the counter's memory.
  size_t held() const { return stack_.size(); }

  // The counter's whole state, for a checkpoint, and its restoration.
  const std::vector<double>& held_reversals() const { return stack_; }
  int direction() const { return direction_; }
  double extreme() const { return extreme_; }
  bool started() const { return started_; }
  void restore(std::vector<double> held, int direction, double extreme, bool started) {
    stack_ = std::move(held), direction_ = direction, extreme_ = extreme, started_ = started;
  }

 private:
  template <class Sink>
  static void emit(double a, double b, double count, Sink& sink) {
    const double hi = a > b ? a : b, lo = a > b ? b : a;
    sink(Cycle{hi - lo, 0.5 * (hi + lo), count});
  }

  // ASTM 5.4.4 steps 2-5 for the reversal just read. stack_[0] is the
  // starting point S; X is the newest range, Y the one before it.
  template <class Sink>
  void reversal(double r, Sink& sink) {
    stack_.push_back(r);
    while (stack_.size() >= 3) {
      const size_t n = stack_.size();
      const double x = std::fabs(stack_[n - 1] - stack_[n - 2]);
      const double y = std::fabs(stack_[n - 2] - stack_[n - 3]);
      if (x < y) return;
      if (n == 3) {  // Y holds S: half a cycle; S moves to Y's second point
        emit(stack_[0], stack_[1], 0.5, sink);
        stack_.erase(stack_.begin());
      } else {  // a whole cycle; its two points go
        emit(stack_[n - 3], stack_[n - 2], 1.0, sink);
        stack_.erase(stack_.begin() + static_cast<long>(n - 3), stack_.begin() + static_cast<long>(n - 1));
      }
    }
  }

  double gate_;
  std::vector<double> stack_;
  int direction_ = 0;     // +1 rising to extreme_, -1 falling to it, 0 not yet left the start
  double extreme_ = 0.0;  // the extremum of the current run: the next reversal when it turns
  bool started_ = false;
};

// The reversals (turning points) of a whole history, for counting it at
// once (rainflow_whole); the same gate as the streaming counter.
std::vector<double> reversals(const std::vector<double>& history, double gate = 0.0);

// An independent count of a whole history, for checking the streaming one:
// the four-point rule on the reversals (a range between two ranges at least
// as large is a full cycle), the residue's ranges half cycles. ASTM's
// starting-point rule and this one give the same cycles.
std::vector<Cycle> rainflow_whole(const std::vector<double>& history, double gate = 0.0);

// The streaming counter on a whole history (add, then finish).
std::vector<Cycle> rainflow(const std::vector<double>& history, double gate = 0.0);

}  // namespace fatigue
