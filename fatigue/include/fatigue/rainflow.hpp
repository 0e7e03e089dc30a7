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

// The turning points of a sampled signal: the hot part of a counter (two
// numbers and a direction per signal), apart from the reversals it holds.
// gate >= 0: a turning point counts only once the signal has come back from
// it by more than the gate, so noise below the gate makes none.
struct TurningPoints {
  double extreme = 0.0;       // the current run's extremum: the next reversal when it turns
  double first = 0.0;         // the first sample, until the signal leaves it
  signed char direction = 0;  // +1 rising to extreme, -1 falling to it, 0 not yet left the first sample
  bool started = false;

  // One sample; true when it makes a reversal, written to *r (the first
  // sample is one).
  bool next(double x, double gate, double* r) {
    if (direction != 0) {  // the common case, one branch that is almost always taken the same way
      const double d = x - extreme;
      if (d * direction >= 0.0) {
        extreme = x;  // still going the same way: the candidate moves
        return false;
      }
      if (std::fabs(d) <= gate) return false;
      *r = extreme;  // it turned back by more than the gate
      direction = static_cast<signed char>(-direction);
      extreme = x;
      return true;
    }
    if (!started) {
      started = true;
      first = extreme = *r = x;
      return true;
    }
    // Which way the history leaves its first point.
    if (x - first > gate) direction = 1, extreme = x;
    else if (first - x > gate) direction = -1, extreme = x;
    return false;
  }
  // At the end of the history: the last extremum, if the signal ever moved.
  bool last(double* r) const {
    if (direction == 0) return false;
    *r = extreme;
    return true;
  }
};

// ASTM E1049-85's three-point rule with the starting point (5.4.4 steps
// 2-5) on each reversal as it comes, and the residue as half cycles at the
// end (step 6). Each cycle goes to the sink, a callable taking a Cycle, as
// soon as it closes.
class ReversalCounter {
 public:
  template <class Sink>
  void push(double r, Sink& sink) {
    stack_.push_back(r);
    // stack_[0] is the starting point S; X is the newest range, Y the one before it.
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
  template <class Sink>
  void finish(Sink& sink) {
    for (size_t i = 1; i < stack_.size(); ++i) emit(stack_[i - 1], stack_[i], 0.5, sink);
    stack_.clear();
  }
  const std::vector<double>& held() const { return stack_; }
  void restore(std::vector<double> held) { stack_ = std::move(held); }

 private:
  template <class Sink>
  static void emit(double a, double b, double count, Sink& sink) {
    const double hi = a > b ? a : b, lo = a > b ? b : a;
    sink(Cycle{hi - lo, 0.5 * (hi + lo), count});
  }
  std::vector<double> stack_;
};

// Rainflow counting of one signal, streaming (ASTM E1049-85, 5.4.4): its
// turning points, and the three-point rule on them.
class RainflowCounter {
 public:
  explicit RainflowCounter(double gate = 0.0) : gate_(gate) {}

  template <class Sink>
  void add(double x, Sink&& sink) {
    double r;
    if (points_.next(x, gate_, &r)) reversals_.push(r, sink);
  }
  // The end of the history: the last extremum is a reversal, and every range
  // left is half a cycle. The counter is then empty, ready for a new history.
  template <class Sink>
  void finish(Sink&& sink) {
    double r;
    if (points_.last(&r)) reversals_.push(r, sink);
    reversals_.finish(sink);
    points_ = TurningPoints{};
  }
  // Reversals held, not yet closed into cycles: the counter's memory.
  size_t held() const { return reversals_.held().size(); }

 private:
  double gate_;
  TurningPoints points_;
  ReversalCounter reversals_;
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
