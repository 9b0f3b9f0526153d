// The shared measurements of docs/model.md §3 (compare/measure) on synthetic data with known answers:
// tip_position, ls_slope, the FrontTracker's events and speeds, and BatchMeans.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "compare/alongside.hpp"
#include "compare/measure.hpp"
#include "scenes.hpp"
#include "core/params.hpp"

namespace compare = slipfront::compare;
namespace continuum = slipfront::continuum;
namespace core = slipfront::core;

namespace {

std::vector<double> grid(double dx, double L) {
  std::vector<double> x;
  for (std::size_t i = 0; static_cast<double>(i) * dx <= L + 1e-12; ++i) x.push_back(static_cast<double>(i) * dx);
  return x;
}

// Synthetic front: A = 0.5 + (x − X)/w clamped to [0, 1] — linear across the nodes around the tip, so
// linear interpolation recovers the A = 0.5 crossing X and the A = 0.9 crossing X + 0.4 w exactly,
// provided the node after X + 0.4 w is still on the ramp: 0.4 w + dx ≤ 0.5 w, i.e. w ≥ 10 dx.
std::vector<double> ramp_profile(const std::vector<double>& x, double X, double w) {
  std::vector<double> A(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) A[i] = std::clamp(0.5 + (x[i] - X) / w, 0.0, 1.0);
  return A;
}

}  // namespace

TEST_CASE("measure: tip_position: largest x with A < threshold, linearly interpolated, NaN without a front", "[measure]") {
  // docs/model.md §3: x_tip = largest x with A < A_tip, interpolated between nodes. Tolerance 1e-12 (exact
  // linear interpolation on linear data).
  const auto x = grid(0.5, 10.0);
  std::vector<double> A(x.size(), 1.0);
  CHECK(std::isnan(compare::tip_position(x, A, 0.5)));  // no front
  std::fill(A.begin(), A.end(), 0.5);
  CHECK(std::isnan(compare::tip_position(x, A, 0.5)));  // A == threshold is not below it
  // front at the last node: the last node itself
  std::fill(A.begin(), A.end(), 1.0);
  A.back() = 0.2;
  CHECK(compare::tip_position(x, A, 0.5) == x.back());
  // exact interpolation of a linear ramp, for tips at, between and near nodes
  for (double X : {3.0, 3.1, 3.49, 7.25, 0.01}) {
    const auto R = ramp_profile(x, X, 6.0);
    CHECK(compare::tip_position(x, R, 0.5) == Approx(X).margin(1e-12));
    CHECK(compare::tip_position(x, R, 0.9) == Approx(X + 2.4).margin(1e-12));
  }
  // several dips: the largest x wins (a healed region behind, a second front ahead)
  std::fill(A.begin(), A.end(), 1.0);
  A[2] = 0.1;                     // x = 1.0
  A[12] = 0.3;                    // x = 6.0, neighbours at 1: crossing at 6 + 0.2/0.7·0.5 ahead
  CHECK(compare::tip_position(x, A, 0.5) == Approx(6.0 + (0.5 - 0.3) / (1.0 - 0.3) * 0.5).margin(1e-12));
}

TEST_CASE("measure: ls_slope: exact on lines, NaN when undefined", "[measure]") {
  // Least squares on exact data y = a + b t returns b to round-off (1e-12 relative), whatever the
  // (unequal) spacing; fewer than 2 points or a single repeated t have no slope.
  const std::vector<double> t = {0.0, 0.1, 0.35, 0.36, 1.0, 2.7, 2.71};
  for (double b : {-3.0, 0.0, 0.77, 1e4}) {
    std::vector<double> y;
    for (double ti : t) y.push_back(5.0 + b * ti);
    CHECK(compare::ls_slope(t, y) == Approx(b).epsilon(1e-12).margin(1e-12));
  }
  CHECK(std::isnan(compare::ls_slope(std::vector<double>{}, std::vector<double>{})));
  CHECK(std::isnan(compare::ls_slope(std::vector<double>{1.0}, std::vector<double>{2.0})));
  CHECK(std::isnan(compare::ls_slope(std::vector<double>{1.0, 1.0}, std::vector<double>{2.0, 3.0})));
}

TEST_CASE("measure: FrontTracker: recovers t*, t^, c_slow, c_transient, its peak, x_arrest of a synthetic front", "[measure]") {
  // Synthetic history, stepped with h = 0.004 (not commensurate with the event times):
  //  - yield from t_y = 10 on (observe_step's flag), a front X(t) = 1 + c1 (t − t_y) (slow, c1 = 0.8);
  //  - max_v = 0.1 until t_a = 30, then rising linearly to 1.1 at t_a + 1: it crosses v_event = 0.5
  //    at t_a + 0.4 exactly; the tracker interpolates linearly between step midpoints, exact here;
  //  - from t^ the tip runs at c2 = 20 until t_stop = t^ + 3, then stops (x_arrest = X(t_stop));
  //  - max_v falls linearly from 1.1 at t_stop to 0 at t_stop + 1.1: below v_event/5 = 0.1 at
  //    t_stop + 1.0; t_arrest is the first step midpoint after that (within one step h).
  // Expected (docs/model.md §3): t* = the start of the first yielding step = t_y (h divides 10 to round-off),
  // t^ = t_a + 0.4 (1e-9), c_slow = c1 (LS on an exact line, 1e-9), c_transient = c2 (middle half of
  // the run, all on the fast line, 1e-9), peak = c2 (1e-9), x_arrest = X(t_stop) (1e-9),
  // t_arrest within h of t_stop + 1. The A_tip_alt = 0.9 front is X + 0.4 w: same speeds.
  core::MeasureParams mp;  // A_tip 0.5, A_tip_alt 0.9, v_event 0.5, sample_dt 0.01
  const auto x = grid(0.5, 300.0);
  const double w = 8.0, h = 0.004, t_y = 10.0, c1 = 0.8, t_a = 30.0, c2 = 20.0;
  const double t_hat = t_a + 0.4, t_stop = t_hat + 3.0, T = 40.0;
  auto front = [&](double t) {
    if (t < t_y) return -1e9;  // no front
    const double xh = 1.0 + c1 * (t_hat - t_y);
    if (t < t_hat) return 1.0 + c1 * (t - t_y);
    return xh + c2 * (std::min(t, t_stop) - t_hat);
  };
  auto max_v = [&](double t) {
    if (t < t_a) return 0.1;
    if (t < t_a + 1.0) return 0.1 + (t - t_a);
    if (t < t_stop) return 1.1;
    return std::max(0.0, 1.1 - (t - t_stop));
  };
  compare::FrontTracker tr(mp, x);
  const std::vector<double> healed(x.size(), 1.0);
  const auto n = static_cast<int>(std::lround(T / h));
  for (int k = 0; k < n; ++k) {
    const double t0 = k * h, t1 = (k + 1) * h;
    tr.observe_step(t0, t1, t0 >= t_y - 1e-9, max_v(0.5 * (t0 + t1)));
    if (tr.sample_due(t1)) {
      const double X = front(t1);
      tr.sample_tip(t1, X < 0 ? healed : ramp_profile(x, X, w));
    }
  }
  const auto ev = tr.finish(false);
  CHECK(ev.t_star == Approx(t_y).margin(1e-9));
  CHECK(ev.t_hat == Approx(t_hat).margin(1e-9));
  CHECK(ev.c_slow == Approx(c1).epsilon(1e-9));
  CHECK(ev.c_transient == Approx(c2).epsilon(1e-9));
  CHECK(ev.c_transient_peak == Approx(c2).epsilon(1e-9));
  CHECK(ev.x_arrest == Approx(front(t_stop)).epsilon(1e-9));
  CHECK(ev.t_arrest >= t_stop + 1.0);
  CHECK(ev.t_arrest <= t_stop + 1.0 + h + 1e-9);
  CHECK(std::isnan(ev.c_front));  // not homogeneous
  const auto alt = tr.finish(false, true);
  CHECK(alt.c_slow == Approx(c1).epsilon(1e-9));
  CHECK(alt.c_transient == Approx(c2).epsilon(1e-9));
  CHECK(alt.x_arrest == Approx(front(t_stop) + 0.4 * w).epsilon(1e-9));
  // The tip samples: one at the first step end at or after each multiple m·sample_dt (so they do
  // not drift: sample k lies in [m_k·sample_dt, m_k·sample_dt + h) with m_k strictly increasing),
  // NaN before the front exists.
  REQUIRE(tr.sample_times().size() == tr.tips().size());
  const auto& st = tr.sample_times();
  long prev_m = -1;
  for (std::size_t k = 0; k < st.size(); ++k) {
    const long m = static_cast<long>(std::floor(st[k] / mp.sample_dt + 1e-9));
    REQUIRE(st[k] - static_cast<double>(m) * mp.sample_dt < h + 1e-12);
    REQUIRE(m > prev_m);
    prev_m = m;
  }
  REQUIRE(st.size() >= static_cast<std::size_t>(T / mp.sample_dt * 0.99));
  CHECK(std::isnan(tr.tips().front()));
  CHECK(tr.tips().back() == Approx(front(t_stop)).epsilon(1e-12));
  // Homogeneous mode: c_front is the LS slope over the samples whose tip lies in the middle half of
  // the distance run, [x0 + (x1 − x0)/4, x0 + 3(x1 − x0)/4] with x0 the first tip, x1 the farthest.
  // Here x0 ≈ 1, x1 = X(t_stop) ≈ 77.3: the middle half starts beyond the slow part (X(t^) ≈ 17.3), so
  // c_front = c2 (1e-9).
  // But this front stops at x1 ≈ 77 of the 299 ahead of it: less than half, so it counts as a patch
  // that re-stuck and has no steady front speed (NaN).
  const double x0 = 1.0, x1 = front(t_stop);
  REQUIRE(x0 + 0.25 * (x1 - x0) > front(t_hat) + 0.1);
  REQUIRE(x1 - x0 < 0.5 * (x.back() - x0));
  const auto hom = tr.finish(true);
  CHECK(std::isnan(hom.c_front));
}

TEST_CASE("measure: FrontTracker: c_front of a front that crosses the system", "[measure]") {
  // Homogeneous mode: a front from x = 10 running at c = 25 up to the end x = 100 (more than half of
  // what lies ahead): c_front is the LS slope over the middle half of its run, exact to 1e-9.
  core::MeasureParams mp;
  const auto x = grid(0.5, 100.0);
  const double w = 4.0, h = 0.004, c = 25.0;
  compare::FrontTracker tr(mp, x);
  for (int k = 0; k < 1500; ++k) {
    const double t0 = k * h, t1 = (k + 1) * h;
    tr.observe_step(t0, t1, true, 5.0);
    if (tr.sample_due(t1)) tr.sample_tip(t1, ramp_profile(x, std::min(10.0 + c * t1, 100.0 + w), w));
  }
  CHECK(tr.finish(true).c_front == Approx(c).epsilon(1e-9));
}

TEST_CASE("measure: FrontTracker: no yield, no instability -> every event NaN", "[measure]") {
  // A run that never yields (elastic stage only) has no event: NaN everywhere (docs/model.md §5).
  core::MeasureParams mp;
  const auto x = grid(1.0, 50.0);
  compare::FrontTracker tr(mp, x);
  const std::vector<double> healed(x.size(), 1.0);
  for (int k = 0; k < 1000; ++k) {
    tr.observe_step(k * 0.01, (k + 1) * 0.01, false, 0.05);
    if (tr.sample_due((k + 1) * 0.01)) tr.sample_tip((k + 1) * 0.01, healed);
  }
  const auto ev = tr.finish(false);
  for (double e : {ev.t_star, ev.t_hat, ev.c_slow, ev.c_transient, ev.c_transient_peak, ev.x_arrest, ev.t_arrest})
    CHECK(std::isnan(e));
}

TEST_CASE("measure: BatchMeans: time-weighted batch means, mean and standard error on piecewise-constant data", "[measure]") {
  // docs/model.md §3: time average of y over [t_from, t_end] from equal-duration batches, with the standard
  // error sqrt(Σ(m_k − m)²/((n − 1) n)). Synthetic y(t) = 1 on t < 17, 3 on [17, 26), 2 after, fed in
  // irregular chunks (some spanning batch edges, some before t_from or after t_end, to be ignored).
  // Batches of [10, 30] (4 × 5): the expected batch means are the exact time averages of y over each
  // batch, computed below from the breakpoints. Tolerance 1e-12.
  const double t_from = 10.0, t_end = 30.0;
  const int nb = 4;
  auto y = [](double t) { return t < 17.0 ? 1.0 : (t < 26.0 ? 3.0 : 2.0); };
  compare::BatchMeans bm(t_from, t_end, nb);
  std::vector<double> cuts = {0.0, 3.3, 9.7, 10.4, 12.0, 16.2, 17.0, 17.05, 21.9, 26.0, 29.99, 31.5, 35.0};
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    // split each chunk at the breakpoints of y so that y is constant over what is added
    std::vector<double> pts = {cuts[k]};
    for (double b : {17.0, 26.0})
      if (b > cuts[k] && b < cuts[k + 1]) pts.push_back(b);
    pts.push_back(cuts[k + 1]);
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) bm.add(pts[j], pts[j + 1], y(0.5 * (pts[j] + pts[j + 1])));
  }
  // exact batch means: ∫y over [a, b] / (b − a), y piecewise constant with breaks 17, 26
  auto integral = [&](double a, double b) {
    const double br[4] = {-1e9, 17.0, 26.0, 1e9};
    const double val[3] = {1.0, 3.0, 2.0};
    double s = 0.0;
    for (int i = 0; i < 3; ++i) s += val[i] * std::max(0.0, std::min(b, br[i + 1]) - std::max(a, br[i]));
    return s;
  };
  std::vector<double> m;
  const double len = (t_end - t_from) / nb;
  for (int k = 0; k < nb; ++k) m.push_back(integral(t_from + k * len, t_from + (k + 1) * len) / len);
  double mean = 0.0;
  for (double mk : m) mean += mk / nb;
  double ss = 0.0;
  for (double mk : m) ss += (mk - mean) * (mk - mean);
  const double se = std::sqrt(ss / (nb - 1) / nb);
  CHECK(bm.mean() == Approx(mean).epsilon(1e-12));
  CHECK(bm.stderr_of_mean() == Approx(se).epsilon(1e-12));
  CHECK(bm.mean() == Approx(integral(t_from, t_end) / (t_end - t_from)).epsilon(1e-12));  // equal batches

  // Constant data: mean exact, zero standard error; empty: NaN.
  compare::BatchMeans flat(0.0, 1.0, 5);
  for (int k = 0; k < 7; ++k) flat.add(k / 7.0, (k + 1) / 7.0, 0.25);
  CHECK(flat.mean() == Approx(0.25).epsilon(1e-14));
  CHECK(flat.stderr_of_mean() == Approx(0.0).margin(1e-15));
  compare::BatchMeans empty(0.0, 1.0, 3);
  CHECK(std::isnan(empty.mean()));
}

TEST_CASE("measure: events that do not apply are NaN with a reason, not values that contradict them", "[measure]") {
  // Issue 10 "measurements that know when they do not apply", on synthetic histories (docs/model.md §3):
  //  (a) max v above v_event before any site yields (a fast drive moving the bulk elastically): t^ is
  //      not an instability — NaN with a reason, and no transient is measured from it;
  //  (b) a tip that recedes (A healing behind a front that stopped) has a negative least-squares slope:
  //      c_transient NaN with a reason;
  //  (c) homogeneous loading: the patch slides from t = 0, t* and t^ are NaN with a reason, c_front kept.
  core::MeasureParams mp;
  const auto x = grid(0.5, 100.0);
  const double h = 0.01;
  {  // (a)
    compare::FrontTracker tr(mp, x);
    for (int k = 0; k < 1000; ++k) tr.observe_step(k * h, (k + 1) * h, k * h >= 5.0, k * h >= 1.0 ? 0.8 : 0.1);
    const auto ev = tr.finish(false);
    CHECK(ev.t_star == Approx(5.0).margin(1e-9));
    CHECK(std::isnan(ev.t_hat));
    REQUIRE(ev.reasons.count("t_hat"));
    CHECK(ev.reasons.at("t_hat").find("before first yield") != std::string::npos);
    CHECK(std::isnan(ev.c_transient));
  }
  {  // (b) yield at 1, instability at 2: the tip runs from 20 to 60 in one time unit, then recedes to 20
     // over ten (A healing) while max v stays high: the LS slope over the middle half of the distance run
     // is dominated by the long recession, negative
    compare::FrontTracker tr(mp, x);
    for (int k = 0; k < 1300; ++k) {
      const double t0 = k * h, t1 = t0 + h;
      tr.observe_step(t0, t1, t0 >= 1.0, t0 >= 2.0 ? 1.0 : 0.1);
      const double X = t1 < 3.0 ? 20.0 + 40.0 * (t1 - 2.0) : 60.0 - 4.0 * (t1 - 3.0);
      if (tr.sample_due(t1) && t1 >= 2.0) tr.sample_tip(t1, ramp_profile(x, X, 4.0));
    }
    const auto ev = tr.finish(false);
    REQUIRE(std::isfinite(ev.t_hat));
    CHECK(std::isnan(ev.c_transient));
    REQUIRE(ev.reasons.count("c_transient"));
    CHECK(ev.reasons.at("c_transient").find("receded") != std::string::npos);
    CHECK(ev.c_transient_peak == Approx(40.0).epsilon(1e-6));  // the advance itself was real
  }
  {  // (c) a front running at 20 from x = 10 on a homogeneous scene, max v high from the start
    compare::FrontTracker tr(mp, x);
    for (int k = 0; k < 400; ++k) {
      const double t0 = k * h, t1 = t0 + h;
      tr.observe_step(t0, t1, true, 2.0);
      if (tr.sample_due(t1)) tr.sample_tip(t1, ramp_profile(x, 10.0 + 20.0 * t1, 4.0));
    }
    const auto ev = tr.finish(true);
    CHECK(std::isnan(ev.t_star));
    CHECK(std::isnan(ev.t_hat));
    CHECK(ev.reasons.count("t_star") == 1);
    CHECK(ev.reasons.count("t_hat") == 1);
    CHECK(ev.c_front == Approx(20.0).epsilon(1e-6));
  }
}

TEST_CASE("compare: relative differences are defined where the continuum value is 0", "[measure][compare]") {
  // Issue 10: /compare relative differences were ±inf where the continuum value was 0. Now: 0 when both
  // vanish, NaN (with the absolute difference beside it) when only the continuum does.
  compare::ModelResult c, d;
  c.events.x_arrest = 0.0;
  d.events.x_arrest = 0.0;
  c.events.c_slow = 0.0;
  d.events.c_slow = 0.5;
  c.events.t_hat = 100.0;
  d.events.t_hat = 101.0;
  compare::Scene s = slipfront::testing::fig1_scene();
  const auto cmp = compare::compare_results(s, c, d);
  CHECK(cmp.metrics.at("x_arrest_rel_diff") == 0.0);
  CHECK(std::isnan(cmp.metrics.at("c_slow_rel_diff")));
  CHECK(cmp.metrics.at("c_slow_abs_diff") == 0.5);
  CHECK(cmp.metrics.at("t_hat_rel_diff") == Approx(0.01).epsilon(1e-12));
  for (const auto& [k, v] : cmp.metrics) CHECK_FALSE(std::isinf(v));
}

TEST_CASE("measure: FrontTracker: phases, and the after-arrest phase ends at the next instability", "[measure]") {
  // docs/model.md §7.2: 0 before yield, 1 slow front, 2 transient (t^ to the arrest), 3 after arrest, 4 from the
  // next instability on (max v > v_event again after the arrest); the events of the first cycle are kept.
  core::MeasureParams mp;
  const auto x = grid(1.0, 50.0);
  compare::FrontTracker tr(mp, x);
  auto step = [&](double t, bool yielded, double max_v) { tr.observe_step(t, t + 0.01, yielded, max_v); };
  CHECK(tr.phase() == 0);
  step(1.0, true, 0.1);
  CHECK(tr.phase() == 1);
  step(2.0, true, 2.0 * mp.v_event);
  CHECK(tr.phase() == 2);
  step(3.0, true, 0.5 * mp.v_event);  // still above the arrest level v_event/5
  CHECK(tr.phase() == 2);
  step(4.0, false, 0.1 * mp.v_event);
  CHECK(tr.phase() == 3);
  step(5.0, true, 0.9 * mp.v_event);  // a new slow front, below v_event: still after arrest
  CHECK(tr.phase() == 3);
  step(6.0, true, 1.5 * mp.v_event);
  CHECK(tr.phase() == 4);
  step(7.0, false, 0.01);  // and it stays: one cycle per run of the statistics
  CHECK(tr.phase() == 4);
  const auto ev = tr.finish(false);
  CHECK(ev.t_arrest == Approx(4.005));
  CHECK(ev.t_hat > 1.005);  // interpolated between the midpoints of the steps before and at the crossing
  CHECK(ev.t_hat <= 2.005);
}

TEST_CASE("measure: slip_sequence: every slip event of a synthetic series, with its run and arrest", "[measure]") {
  // Three events on a 300-long interface (v_event = 0.5, arrest below 0.1): a precursor whose tip runs 10 -> 40 at
  // speed 6, a spanning event whose tip runs 0 -> 300 at speed 20, and one still running at the end. Between events
  // max v is 0.05 and there is no tip.
  core::MeasureParams p;
  std::vector<double> t, v, tip;
  const auto quiet = [&](double t0, double t1) {
    for (double s = t0; s < t1 - 1e-9; s += 0.05) { t.push_back(s); v.push_back(0.05); tip.push_back(compare::nan); }
  };
  const auto event = [&](double t0, double x0, double c, double x1, double peak) {
    const double dur = (x1 - x0) / c;
    for (double s = 0.0; s <= dur + 1e-9; s += 0.05) {
      t.push_back(t0 + s);
      v.push_back(0.6 + (peak - 0.6) * std::sin(M_PI * s / dur));
      tip.push_back(x0 + c * s);
    }
  };
  quiet(0.0, 10.0);
  event(10.0, 10.0, 6.0, 40.0, 2.0);
  quiet(15.05, 30.0);
  event(30.0, 0.0, 20.0, 300.0, 3.0);
  quiet(45.05, 60.0);
  event(60.0, 0.0, 5.0, 20.0, 1.0);
  const auto seq = compare::slip_sequence(t, v, tip, p, 300.0);
  REQUIRE(seq.at("t_start").size() == 3);
  CHECK(seq.at("t_start")[0] == Approx(10.0));
  CHECK(seq.at("t_start")[1] == Approx(30.0));
  CHECK(seq.at("t_end")[0] == Approx(15.05));  // the first quiet sample after it
  CHECK(std::isnan(seq.at("t_end")[2]));        // still running at the end
  CHECK(seq.at("x_arrest")[0] == Approx(40.0));
  CHECK(seq.at("x_arrest")[1] == Approx(300.0));
  CHECK(seq.at("c_event")[0] == Approx(6.0));
  CHECK(seq.at("c_event")[1] == Approx(20.0));
  CHECK(seq.at("peak_v")[1] == Approx(3.0).epsilon(1e-3));
  CHECK(seq.at("spanning") == std::vector<double>{0.0, 1.0, 0.0});
  // no event: every column present and empty
  const std::vector<double> tq{0.0, 1.0}, vq{0.1, 0.2}, xq{compare::nan, compare::nan};
  const auto none = compare::slip_sequence(tq, vq, xq, p, 300.0);
  CHECK(none.size() == 6);
  CHECK(none.at("t_start").empty());
}

TEST_CASE("measure: output.sequence on fig1: the first slip event is the run's t^ and arrest, and more follow",
          "[measure][sequence]") {
  // fig1 (continuum) driven to t = 400: the first event of the sequence starts at the first series sample after t^ and
  // reaches the run's x_arrest (within the tip's sampling: the series and the tracker sample it at different times);
  // later events follow as the drive reloads the edge (docs/model.md §3.2).
  compare::Scene s = slipfront::testing::fig1_scene();
  s.models = {"continuum"};
  s.time.t_end = 400.0;
  s.output.snapshot_dt = 0.0;
  s.output.sequence = true;
  const compare::ModelResult r = slipfront::testing::run_continuum(s);
  const auto& seq = r.sequence;
  REQUIRE(seq.at("t_start").size() >= 3);
  const double series_dt = s.output.series_dt;
  INFO("t^ " << r.events.t_hat << ", first event at " << seq.at("t_start")[0]);
  CHECK(seq.at("t_start")[0] >= r.events.t_hat - 1e-9);
  CHECK(seq.at("t_start")[0] <= r.events.t_hat + series_dt + 1e-9);
  CHECK(seq.at("t_end")[0] == Approx(r.events.t_arrest).margin(series_dt + 1e-9));
  CHECK(seq.at("x_arrest")[0] == Approx(r.events.x_arrest).epsilon(0.01));
  CHECK(seq.at("spanning")[0] == 0.0);
  for (std::size_t k = 1; k < seq.at("t_start").size(); ++k) CHECK(seq.at("t_start")[k] > seq.at("t_end")[k - 1]);
  // not stored unless asked for
  s.output.sequence = false;
  s.time.t_end = 120.0;
  CHECK(slipfront::testing::run_continuum(s).sequence.empty());
}
