#pragma once
// When something is due in simulated time: records (series, snapshots, contact snapshots, field
// comparisons), tip samples and checkpoints all keep their rhythm with this one type.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace slipfront::compare {

/// Due at the first time at or after each multiple of `every` (every = 0: at every time; every < 0:
/// never). "At or after" has a tolerance of 1e-9 every, so that a step count times dt that lands a
/// rounding error short of a multiple still counts as on it. A new cadence is due at once (its first
/// multiple is 0); after(every, t) starts one that is next due at the first multiple after t (a
/// checkpoint clock started, or restarted, at t).
class Cadence {
 public:
  explicit Cadence(double every) : every_(every) {}
  static Cadence after(double every, double t) {
    Cadence c(every);
    c.passed(t);
    return c;
  }
  bool is_due(double t) const { return every_ >= 0 && !(t + 1e-9 * every_ < next_); }
  /// Marks a time t as served: the next one due is the first multiple after t.
  void passed(double t) { next_ = every_ > 0 ? (std::floor(t / every_ + 1e-9) + 1.0) * every_ : t; }
  /// is_due(t), and if so passed(t).
  bool due(double t) {
    if (!is_due(t)) return false;
    passed(t);
    return true;
  }
  template <class Ar>
  void serialize(Ar& ar) {
    ar(next_);
  }

 private:
  double every_, next_ = 0.0;
};

/// Calls f(t) at every multiple t of `every` in (t0, t1] (the last one clamped to t1): the exact
/// cadence times inside a step of a stepper with dense output.
template <class F>
void multiples_in(double t0, double t1, double every, F&& f) {
  if (every <= 0) return;
  for (auto k = static_cast<std::int64_t>(std::floor(t0 / every + 1e-9)) + 1;; ++k) {
    if (static_cast<double>(k) * every > t1 * (1.0 + 1e-12)) break;
    f(std::min(static_cast<double>(k) * every, t1));
  }
}

}  // namespace slipfront::compare
