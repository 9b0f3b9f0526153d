#pragma once
// Measurements of docs/model.md §3, written once and applied to every model (continuum and discrete)
// and every stepper. FrontTracker is fed online by the runner: observe_step() every step (or every
// sub-interval of a dense step), sample_tip() at a cadence; CycleDetector (the spring block's stick–slip
// cycles) and BehindRate (homogeneous loading) likewise. Their constants are MeasureParams.
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "compare/cadence.hpp"
#include "core/params.hpp"

namespace slipfront::compare {

inline constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// Event times and front speeds (NaN where the run had no such event).
struct Events {
  double t_star = nan;            ///< first yield: first step at whose start some site has Θ = 1
  double t_hat = nan;             ///< instability: first time max_x v > v_event (interpolated)
  double c_slow = nan;            ///< LS slope of x_tip(t) over the middle half of [t*, t^]
  double c_transient = nan;       ///< LS slope of x_tip over the middle half of the transient's run
  double c_transient_peak = nan;  ///< peak tip speed over 0.5 time units during the transient
  double x_arrest = nan;          ///< largest x_tip reached before max v < v_event/5 after t^
  double t_arrest = nan;          ///< time at which max v fell back below v_event/5
  /// Homogeneous loading (docs/model.md §3.1): the LS slope of x_tip over its settled part
  /// when the front settled (front_settled = 1), else c_front_middle; NaN if it runs less than half the length
  /// ahead of it (re-stuck).
  double c_front = nan;
  double v_behind = nan;          ///< homogeneous loading: mean v over [ℓ_n, x_tip − 10] when x_tip passes 3L/4
  double c_front_middle = nan;    ///< homogeneous loading: LS slope of x_tip over the middle half of its run
  double c_front_drift = nan;     ///< relative change of the windowed tip speed over the settled part (or every window)
  double x_settled = nan;         ///< where the settled part starts (NaN unless front_settled = 1)
  double front_settled = nan;     ///< 1 settled, 0 not (c_front is then c_front_middle), NaN without a front speed
  /// Why an event is NaN where a reader could expect a value (event name → reason), e.g. t_hat before
  /// first yield (elastic motion, not an instability) or a receding tip (a negative speed).
  std::map<std::string, std::string> reasons;
  template <class Ar>
  void serialize(Ar& ar) {
    ar(t_star, t_hat, c_slow, c_transient, c_transient_peak, x_arrest, t_arrest, c_front, v_behind, c_front_middle,
       c_front_drift, x_settled, front_settled, reasons);
  }
};

/// Every event of Events with its name (the HDF5 attribute, the comparison metric, the summary line):
/// the one list of them.
struct EventField {
  const char* name;
  double Events::*member;
};
inline constexpr EventField event_fields[] = {
    {"t_star", &Events::t_star},         {"t_hat", &Events::t_hat},       {"c_slow", &Events::c_slow},
    {"c_transient", &Events::c_transient}, {"c_transient_peak", &Events::c_transient_peak},
    {"x_arrest", &Events::x_arrest},     {"t_arrest", &Events::t_arrest}, {"c_front", &Events::c_front},
    {"v_behind", &Events::v_behind},     {"c_front_middle", &Events::c_front_middle},
    {"c_front_drift", &Events::c_front_drift}, {"x_settled", &Events::x_settled},
    {"front_settled", &Events::front_settled},
};

/// Largest x with A < threshold, interpolated linearly between nodes; NaN if A ≥ threshold everywhere.
double tip_position(std::span<const double> x, std::span<const double> area, double threshold);

/// tip_position over the nodes [0, m) with A evaluated on demand, from node m − 1 down (area(i)), for
/// callers that know every node from m on stays at or above the threshold: the same result as
/// tip_position on the first m values, usually after a few evaluations.
template <class Area>
double tip_position_lazy(std::span<const double> x, std::size_t m, double threshold, Area&& area) {
  double above = 0.0;  // area(i + 1)
  for (std::size_t i = m; i-- > 0;) {
    const double a0 = area(i);
    if (a0 < threshold) {
      if (i + 1 == m) return x[i];
      return x[i] + (threshold - a0) / (above - a0) * (x[i + 1] - x[i]);
    }
    above = a0;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// Least-squares slope of y(t); NaN with fewer than 2 distinct points.
double ls_slope(std::span<const double> t, std::span<const double> y);

/// Where a front's speed has settled (docs/model.md §3.1).
struct SettledSpeed {
  double c = nan;          ///< LS slope of x over the samples from x_settled until x first passes x_end (NaN unless settled)
  double x_settled = nan;  ///< start of the first window from which every windowed speed stays in the band (NaN unless settled)
  /// (last − first windowed speed)/last windowed speed, the first being the window at x_settled when settled, the
  /// first window otherwise; NaN with fewer than two windows.
  double drift = nan;
  bool settled = false;
  std::vector<double> window_x, window_c;  ///< each window's start and its speed
};

/// Tip samples (t, x) in time order (finite tips): a window starts at every sample i and holds the samples from i
/// until the tip first passes x_i + window; its speed is their LS slope. Windows whose end lies beyond x_end, or that
/// the samples do not close (the tip never passed x_i + window), are not formed. The front settled at the first window
/// k from which every later windowed speed lies in a band of relative width `band` (max/min − 1 ≤ band), provided
/// that settled part spans at least two windows (x_end − x_k ≥ 2 window); then c is the LS slope over it.
SettledSpeed settled_speed(std::span<const double> t, std::span<const double> x, double x_end, double window, double band);

class FrontTracker {
 public:
  FrontTracker(const core::MeasureParams& p, std::vector<double> x);

  /// Every step [t0, t1]: whether some site yielded at t0, and max |v| over the step.
  void observe_step(double t0, double t1, bool yielded, double max_v);
  /// Whether a tip sample is due at time t: the first step at or after each multiple of measure.sample_dt.
  bool sample_due(double t) const { return samples_.is_due(t); }
  /// Record the tip positions (both thresholds) at time t; returns the A_tip position. `area` may be
  /// a prefix of the nodes when every node beyond it is known to be above both thresholds.
  double sample_tip(double t, std::span<const double> area);
  /// Record tip positions found by the caller (tip_position or tip_position_lazy) at time t.
  double record_tips(double t, double tip, double tip_alt);
  /// Between t^ and the arrest (max v has not yet fallen back below v_event/5).
  bool in_transient() const { return in_transient_; }
  /// Phase of the run so far (docs/model.md §7.2): 0 before first yield, 1 slow front (t* ≤ t < t^),
  /// 2 transient (t^ to the arrest), 3 after the arrest (to the next instability), 4 next event (from the
  /// next instability after the arrest on: max v > v_event again).
  std::size_t phase() const {
    if (!std::isnan(t_next_)) return 4;
    if (in_transient_) return 2;
    if (!std::isnan(ev_.t_arrest)) return 3;
    return std::isnan(ev_.t_star) ? 0 : 1;
  }

  const std::vector<double>& sample_times() const { return ts_; }
  const std::vector<double>& tips() const { return tips_; }
  double last_tip() const { return tips_.empty() ? nan : tips_.back(); }
  double last_tip_alt() const { return last_tip_alt_; }

  /// Speeds and arrest from the recorded samples of the A_tip front (alt: the A_tip_alt front).
  /// `homogeneous` adds c_front. A speed needs the tip defined at every sample of its window.
  Events finish(bool homogeneous, bool alt = false) const;
  template <class Ar>
  void serialize(Ar& ar) {
    ar(ts_, tips_, tips_alt_, samples_, last_tip_alt_, ev_, prev_max_v_, prev_t_mid_, in_transient_, t_next_);
  }

 private:
  core::MeasureParams p_;
  std::vector<double> x_;
  std::vector<double> ts_, tips_, tips_alt_;
  Cadence samples_;  ///< tip samples: multiples of measure.sample_dt
  double last_tip_alt_ = nan;
  Events ev_;
  double prev_max_v_ = 0.0, prev_t_mid_ = 0.0;
  bool in_transient_ = false;
  double t_next_ = nan;  ///< the next instability after the arrest (phase 4), NaN until then
};

/// The sequence of slip events of an edge-loaded run (output.sequence; docs/model.md §3.2), from its series (t, max_v,
/// tip_x): an event starts when max v rises above v_event and ends when it falls below arrest_fraction · v_event (the
/// t^ and arrest of Events, every time they recur). Columns, one entry per event: t_start, t_end (NaN: still
/// running at the end of the run), peak_v (largest max v), x_arrest (largest tip position during it; NaN: no tip),
/// c_event (LS slope of the tip over the middle half of its run from its position at t_start to x_arrest) and spanning
/// (1 when the tip reached the far end x_end: the whole interface slid).
std::map<std::string, std::vector<double>> slip_sequence(std::span<const double> t, std::span<const double> max_v,
                                                         std::span<const double> tip, const core::MeasureParams& p,
                                                         double x_end);

/// Stick–slip cycles of the spring block: a cycle's slip event starts when v > v_event and ends when
/// v < arrest_fraction · v_event; F_peak is the largest F since the previous event, F_residual the
/// smallest F during the event. Each finished cycle appends t_start, F_peak, F_residual to `out`.
class CycleDetector {
 public:
  explicit CycleDetector(const core::MeasureParams& p) : v_event_(p.v_event), v_end_(p.v_event * p.arrest_fraction) {}
  void observe(double t, double force, double v, std::map<std::string, std::vector<double>>& out);
  template <class Ar>
  void serialize(Ar& ar) {
    ar(peak_, low_, t_start_, slipping_);
  }

 private:
  double v_event_, v_end_, peak_ = -std::numeric_limits<double>::infinity();
  double low_ = std::numeric_limits<double>::infinity(), t_start_ = 0.0;
  bool slipping_ = false;
};

/// Homogeneous loading: the slip rate where the interface slides steadily far behind the front, v_behind
/// (docs/model.md §3): the mean slip rate over [x_tip − behind_far, x_tip − behind_near] (past the tip's
/// transition zone, which decays over ~ 1/0.08 ≈ 12 length units for the paper's parameters, and
/// clear of the rear edge), taken once, when the tip first passes behind_tip_fraction · L.
class BehindRate {
 public:
  explicit BehindRate(const core::MeasureParams& p) : p_(p) {}
  /// At a tip sample: the tip and the slip rates of every node at that time.
  void observe(double tip, std::span<const double> x, std::span<const double> v);
  double value() const { return v_behind_; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar(v_behind_);
  }

 private:
  core::MeasureParams p_;
  double v_behind_ = nan;
};

/// Steady friction law measurement (docs/model.md §3): time average of σ over [t_from, t_end] with its
/// standard error from `batches` batch means of equal duration.
class BatchMeans {
 public:
  BatchMeans(double t_from, double t_end, int batches);
  /// Add the value y held over [t0, t1] (time-weighted).
  void add(double t0, double t1, double y);
  double mean() const;
  double stderr_of_mean() const;

 private:
  double t_from_, t_end_;
  std::vector<double> sum_, weight_;
};

}  // namespace slipfront::compare
