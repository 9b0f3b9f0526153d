#include "compare/measure.hpp"

#include <algorithm>
#include <cmath>

#include "compare/peak_speed.hpp"

namespace slipfront::compare {

double tip_position(std::span<const double> x, std::span<const double> area, double threshold) {
  for (std::size_t i = area.size(); i-- > 0;) {
    if (area[i] < threshold) {
      if (i + 1 == area.size()) return x[i];
      const double a0 = area[i], a1 = area[i + 1];
      return x[i] + (threshold - a0) / (a1 - a0) * (x[i + 1] - x[i]);
    }
  }
  return nan;
}

double ls_slope(std::span<const double> t, std::span<const double> y) {
  const std::size_t n = t.size();
  if (n < 2) return nan;
  double mt = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) { mt += t[i]; my += y[i]; }
  mt /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double stt = 0, sty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    sty += (t[i] - mt) * (y[i] - my);
  }
  return stt > 0 ? sty / stt : nan;
}

PeakSpeed peak_tip_speed(std::span<const double> t, std::span<const double> x, double span) {
  PeakSpeed p{nan, nan, nan};
  const std::size_t n = std::min(t.size(), x.size());
  std::size_t j = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (j < n && t[j] < t[i] + span - 1e-12) ++j;
    if (j == n) break;
    const double s = (x[j] - x[i]) / (t[j] - t[i]);
    if (!(s <= p.c)) p = {s, x[i], t[i]};
  }
  return p;
}

SettledSpeed settled_speed(std::span<const double> t, std::span<const double> x, double x_end, double window, double band) {
  SettledSpeed r;
  const std::size_t n = std::min(t.size(), x.size());
  // the first sample at or after `from` whose tip lies beyond `top` (n if none)
  auto passes = [&](std::size_t from, double top) {
    while (from < n && !(x[from] > top)) ++from;
    return from;
  };
  std::vector<std::size_t> first;  // each window's first sample
  for (std::size_t i = 0; i < n; ++i) {
    const double top = x[i] + window;
    if (top > x_end) continue;
    const std::size_t j = passes(i, top);
    if (j == n) continue;  // the samples end before the tip passed the window's end
    first.push_back(i);
    r.window_x.push_back(x[i]);
    r.window_c.push_back(ls_slope(t.subspan(i, j - i), x.subspan(i, j - i)));
  }
  const std::size_t m = r.window_c.size();
  if (m < 2) return r;
  // the largest and smallest windowed speed from window k on, scanned from the last window back
  std::vector<double> hi(m), lo(m);
  for (std::size_t k = m; k-- > 0;) {
    hi[k] = k + 1 < m ? std::max(hi[k + 1], r.window_c[k]) : r.window_c[k];
    lo[k] = k + 1 < m ? std::min(lo[k + 1], r.window_c[k]) : r.window_c[k];
  }
  std::size_t k = 0;
  while (k < m && !(lo[k] > 0.0 && hi[k] <= (1.0 + band) * lo[k])) ++k;
  const double last = r.window_c.back();
  if (k < m && x_end - r.window_x[k] >= 2.0 * window) {
    r.settled = true;
    r.x_settled = r.window_x[k];
    const std::size_t i = first[k], j = passes(i, x_end);
    r.c = ls_slope(t.subspan(i, j - i), x.subspan(i, j - i));
    r.drift = (last - r.window_c[k]) / last;
  } else {
    r.drift = (last - r.window_c.front()) / last;
  }
  return r;
}

FrontTracker::FrontTracker(const core::MeasureParams& p, std::vector<double> x)
    : p_(p), x_(std::move(x)), samples_(p.sample_dt) {}

void FrontTracker::observe_step(double t0, double t1, bool yielded, double max_v) {
  if (yielded && std::isnan(ev_.t_star)) ev_.t_star = t0;
  const double t_mid = 0.5 * (t0 + t1);  // v^{n+1/2} lives at the midpoint
  if (std::isnan(ev_.t_hat) && max_v > p_.v_event) {
    const double f = (p_.v_event - prev_max_v_) / (max_v - prev_max_v_);
    ev_.t_hat = prev_max_v_ <= p_.v_event && f >= 0 && f <= 1 ? prev_t_mid_ + f * (t_mid - prev_t_mid_) : t_mid;
    in_transient_ = true;
  } else if (in_transient_ && max_v < p_.v_event * p_.arrest_fraction) {
    in_transient_ = false;
    ev_.t_arrest = t_mid;
  } else if (!in_transient_ && !std::isnan(ev_.t_arrest) && std::isnan(t_next_) && max_v > p_.v_event) {
    t_next_ = t_mid;  // the next instability: phase 4 (docs/model.md §7.2)
  }
  prev_max_v_ = max_v;
  prev_t_mid_ = t_mid;
}

double FrontTracker::sample_tip(double t, std::span<const double> area) {
  return record_tips(t, tip_position(x_, area, p_.A_tip), tip_position(x_, area, p_.A_tip_alt));
}

double FrontTracker::record_tips(double t, double tip, double tip_alt) {
  last_tip_alt_ = tip_alt;
  ts_.push_back(t);
  tips_.push_back(tip);
  tips_alt_.push_back(last_tip_alt_);
  samples_.passed(t);
  return tip;
}

namespace {
// Samples (t, tip) with t in [a, b]; false if the tip is undefined (no front) at any of them.
bool window(const std::vector<double>& ts, const std::vector<double>& tips, double a, double b,
            std::vector<double>& wt, std::vector<double>& wy) {
  wt.clear();
  wy.clear();
  bool complete = true;
  for (std::size_t i = 0; i < ts.size(); ++i)
    if (ts[i] >= a && ts[i] <= b) {
      if (!std::isfinite(tips[i])) { complete = false; continue; }
      wt.push_back(ts[i]);
      wy.push_back(tips[i]);
    }
  return complete;
}

// LS slope over the samples whose tip lies in the middle half of [x0, x1] (distance run).
double slope_middle_distance(const std::vector<double>& t, const std::vector<double>& y, double x0, double x1) {
  std::vector<double> ft, fy;
  const double lo = x0 + 0.25 * (x1 - x0), hi = x0 + 0.75 * (x1 - x0);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (y[i] >= lo && y[i] <= hi) { ft.push_back(t[i]); fy.push_back(y[i]); }
  return ls_slope(ft, fy);
}

// `field` not measured: NaN, with the reason.
void drop(Events& ev, double Events::*field, const char* name, const std::string& why) {
  ev.reasons[name] = why;
  ev.*field = nan;
}

// The events a run does not have: under homogeneous loading no first yield, instability or arrest to time
// (docs/model.md §1.3: the nucleation patch slides from t = 0; the front is measured by c_front); max v above
// v_event before any site yielded is elastic motion (a fast drive), not an instability.
void drop_untimed(Events& ev, bool homogeneous) {
  if (homogeneous) {
    const std::string why = "homogeneous loading: the interface slides from t = 0 (no first-yield or instability "
                            "event; the front's speed is c_front)";
    drop(ev, &Events::t_star, "t_star", why);
    drop(ev, &Events::t_hat, "t_hat", why);
    drop(ev, &Events::t_arrest, "t_arrest", why);
  } else if (std::isfinite(ev.t_hat) && !(std::isfinite(ev.t_star) && ev.t_hat > ev.t_star)) {
    drop(ev, &Events::t_hat, "t_hat",
         "max v exceeded v_event at t = " + core::format_number(ev.t_hat, 6) +
             (std::isfinite(ev.t_star) ? ", before first yield (t* = " + core::format_number(ev.t_star, 6) + ")"
                                       : ", with no yield at all") +
             ": elastic motion, not an instability");
    drop(ev, &Events::t_arrest, "t_arrest", "no instability (t_hat)");
  }
}

// c_slow: the tip's slope over the middle half of [t*, t^].
void measure_slow(Events& ev, const std::vector<double>& ts, const std::vector<double>& tips) {
  if (!(std::isfinite(ev.t_star) && std::isfinite(ev.t_hat) && ev.t_hat > ev.t_star)) return;
  std::vector<double> wt, wy;
  const double d = ev.t_hat - ev.t_star;
  if (window(ts, tips, ev.t_star + 0.25 * d, ev.t_hat - 0.25 * d, wt, wy)) ev.c_slow = ls_slope(wt, wy);
}

// The transient from t^ to the arrest (or the end): c_transient over the middle half of the distance it runs, from
// its position at t^ to the farthest tip reached; its peak over windows of 0.5 time units; x_arrest.
void measure_transient(Events& ev, const std::vector<double>& ts, const std::vector<double>& tips) {
  if (!std::isfinite(ev.t_hat)) return;
  std::vector<double> wt, wy;
  const double t_end = std::isfinite(ev.t_arrest) ? ev.t_arrest : (ts.empty() ? ev.t_hat : ts.back());
  window(ts, tips, ev.t_hat, t_end, wt, wy);
  if (wy.empty()) return;
  const double x0 = wy.front();
  const double x1 = *std::max_element(wy.begin(), wy.end());
  if (std::isfinite(ev.t_arrest)) ev.x_arrest = x1;
  if (!(x1 > x0)) return;
  ev.c_transient = slope_middle_distance(wt, wy, x0, x1);
  ev.c_transient_peak = peak_tip_speed(wt, wy, 0.5).c;
}

// Homogeneous loading: the front from the patch, c_front (docs/model.md §3.1), and no transient.
void measure_homogeneous_front(Events& ev, const std::vector<double>& ts, const std::vector<double>& tips,
                               const std::vector<double>& x, const core::MeasureParams& p) {
  std::vector<double> wt, wy;
  window(ts, tips, -1.0, ts.empty() ? 0.0 : ts.back(), wt, wy);
  if (!wy.empty()) {
    const double x_last = x.back();
    const double x1 = *std::max_element(wy.begin(), wy.end());
    // A front is steady only if it runs at least half of what lies ahead of it; a patch that
    // creeps and re-sticks has no front speed.
    if (x1 - wy.front() >= 0.5 * (x_last - wy.front())) {
      ev.c_front_middle = slope_middle_distance(wt, wy, wy.front(), x1);
      // docs/model.md §3.1: the tip's speed over windows of fixed travel, the end zone left
      // out (the tip speeds up over the last ~40 length units as it reaches the free end).
      const double x_end = std::min(x1, x_last - p.settle_end_zone);
      const SettledSpeed s = settled_speed(wt, wy, x_end, p.settle_window, p.settle_band);
      ev.c_front_drift = s.drift;
      ev.front_settled = s.settled ? 1.0 : 0.0;
      ev.c_front = s.settled ? s.c : ev.c_front_middle;
      ev.x_settled = s.x_settled;
      if (!s.settled)
        ev.reasons["x_settled"] =
            "the windowed tip speed (windows of " + core::format_number(p.settle_window, 6) +
            " length units) did not stay within a relative band of " + core::format_number(p.settle_band, 6) +
            " over at least two windows before x = " + core::format_number(x_end, 6) +
            ": not settled (front_settled = 0); c_front is c_front_middle, c_front_drift the drift seen over every window";
    } else {
      ev.reasons["c_front"] = "the front ran less than half of the length ahead of it (re-stuck or too short a run)";
    }
  }
  drop(ev, &Events::c_transient, "c_transient", "homogeneous loading: the front's speed is c_front");
  drop(ev, &Events::c_transient_peak, "c_transient_peak", "homogeneous loading: the front's speed is c_front");
  drop(ev, &Events::x_arrest, "x_arrest", "homogeneous loading: no transient to arrest");
}

// A front speed is the slope of an advancing tip: a negative value is a receding tip (healing), not a front.
void drop_receding(Events& ev) {
  for (const auto& [field, name] : {std::pair{&Events::c_slow, "c_slow"}, std::pair{&Events::c_transient, "c_transient"},
                                    std::pair{&Events::c_transient_peak, "c_transient_peak"}, std::pair{&Events::c_front, "c_front"},
                                    std::pair{&Events::c_front_middle, "c_front_middle"}})
    if (ev.*field < 0.0) drop(ev, field, name, "negative (" + core::format_number(ev.*field, 6) + "): the tip receded, no advancing front");
}

}  // namespace

Events FrontTracker::finish(bool homogeneous, bool alt) const {
  Events ev = ev_;
  const std::vector<double>& tips = alt ? tips_alt_ : tips_;
  drop_untimed(ev, homogeneous);
  measure_slow(ev, ts_, tips);
  measure_transient(ev, ts_, tips);
  if (homogeneous) measure_homogeneous_front(ev, ts_, tips, x_, p_);
  drop_receding(ev);
  return ev;
}

namespace {
// One event of slip_sequence: samples [i0, i1) of the series; `ended` when max v fell below the arrest level.
void push_event(std::map<std::string, std::vector<double>>& out, std::span<const double> t, std::span<const double> v,
                std::span<const double> tip, std::size_t i0, std::size_t i1, bool ended, double x_end) {
  double peak = 0.0, x_max = nan, x0 = nan;
  std::vector<double> ts, xs;
  for (std::size_t i = i0; i < i1; ++i) {
    peak = std::max(peak, v[i]);
    if (!std::isfinite(tip[i])) continue;
    if (std::isnan(x0)) x0 = tip[i];
    x_max = std::isnan(x_max) ? tip[i] : std::max(x_max, tip[i]);
    ts.push_back(t[i]);
    xs.push_back(tip[i]);
  }
  out["t_start"].push_back(t[i0]);
  out["t_end"].push_back(ended ? t[i1 - 1] : nan);
  out["peak_v"].push_back(peak);
  out["x_arrest"].push_back(x_max);
  out["c_event"].push_back(std::isfinite(x0) && x_max > x0 ? slope_middle_distance(ts, xs, x0, x_max) : nan);
  out["spanning"].push_back(x_max >= x_end * (1.0 - 1e-12) ? 1.0 : 0.0);
}
}  // namespace

std::map<std::string, std::vector<double>> slip_sequence(std::span<const double> t, std::span<const double> max_v,
                                                         std::span<const double> tip, const core::MeasureParams& p,
                                                         double x_end) {
  std::map<std::string, std::vector<double>> out;
  for (const char* c : {"t_start", "t_end", "peak_v", "x_arrest", "c_event", "spanning"}) out[c];
  const std::size_t n = std::min({t.size(), max_v.size(), tip.size()});
  std::size_t start = n;  // the running event's first sample (n: none running)
  for (std::size_t i = 0; i < n; ++i) {
    if (start == n && max_v[i] > p.v_event) start = i;
    else if (start != n && max_v[i] < p.v_event * p.arrest_fraction) {
      push_event(out, t, max_v, tip, start, i + 1, true, x_end);
      start = n;
    }
  }
  if (start != n) push_event(out, t, max_v, tip, start, n, false, x_end);
  return out;
}

void CycleDetector::observe(double t, double force, double v, std::map<std::string, std::vector<double>>& out) {
  if (!slipping_) {
    peak_ = std::max(peak_, force);
    if (v > v_event_) {
      slipping_ = true;
      t_start_ = t;
      low_ = force;
    }
    return;
  }
  low_ = std::min(low_, force);
  if (v < v_end_) {
    out["t_start"].push_back(t_start_);
    out["F_peak"].push_back(peak_);
    out["F_residual"].push_back(low_);
    slipping_ = false;
    peak_ = -std::numeric_limits<double>::infinity();
  }
}

void BehindRate::observe(double tip, std::span<const double> x, std::span<const double> v) {
  if (!std::isnan(v_behind_) || !(tip >= p_.behind_tip_fraction * x.back())) return;
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= tip - p_.behind_far && x[i] <= tip - p_.behind_near) {
      sum += v[i];
      ++n;
    }
  v_behind_ = n ? sum / n : nan;
}

BatchMeans::BatchMeans(double t_from, double t_end, int batches)
    : t_from_(t_from), t_end_(t_end), sum_(static_cast<std::size_t>(batches), 0.0),
      weight_(static_cast<std::size_t>(batches), 0.0) {}

void BatchMeans::add(double t0, double t1, double y) {
  if (t1 <= t_from_ || t0 >= t_end_) return;
  const double nb = static_cast<double>(sum_.size()), len = (t_end_ - t_from_) / nb;
  double a = std::max(t0, t_from_);
  const double b = std::min(t1, t_end_);
  while (a < b) {  // split [a, b] over the batches it covers
    auto k = static_cast<std::size_t>(std::min(nb - 1.0, std::floor((a - t_from_) / len)));
    const double edge = std::min(b, t_from_ + static_cast<double>(k + 1) * len);
    const double w = edge - a;
    if (w <= 0) { a = std::nextafter(a, b); continue; }
    sum_[k] += w * y;
    weight_[k] += w;
    a = edge;
  }
}

double BatchMeans::mean() const {
  double s = 0;
  int n = 0;
  for (std::size_t k = 0; k < sum_.size(); ++k)
    if (weight_[k] > 0) { s += sum_[k] / weight_[k]; ++n; }
  return n ? s / n : nan;
}

double BatchMeans::stderr_of_mean() const {
  const double m = mean();
  double s = 0;
  int n = 0;
  for (std::size_t k = 0; k < sum_.size(); ++k)
    if (weight_[k] > 0) { const double d = sum_[k] / weight_[k] - m; s += d * d; ++n; }
  return n > 1 ? std::sqrt(s / (n - 1) / n) : nan;
}

}  // namespace slipfront::compare
