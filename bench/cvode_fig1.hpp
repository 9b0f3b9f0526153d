#pragma once
// Work-precision runs of one dynamic scene (fig1 by default) with three integrators of the same
// method-of-lines ODE (core/bulk.hpp grid, docs/model.md §1), all measured by the one implementation of
// docs/model.md §3 (compare::FrontTracker):
//   explicit  the reference scheme, run through compare::run_model exactly as `slipfront run` does;
//   adaptive  core::AdaptiveSimulation (core/adaptive.hpp);
//   cvode     the peer: SUNDIALS CVODE (BDF 1–5, banded difference-quotient Jacobian, band LU) on the
//             same ODE, Θ either evaluated inside the right-hand side (discontinuous) or frozen and
//             switched at CVODE's located roots of |σ|/A − 1 (`roots`).  Defined in cvode_fig1.cpp.
// The variable-step integrators are observed through their dense output (DenseObserver): tip samples
// at the exact multiples of measure.sample_dt, max_x v at sub-intervals of ≤ sample_dt/5 wherever a
// threshold (v_event, v_event/5) can be crossed, fields at the requested times. So every integrator
// feeds the tracker the same functional of its solution; the explicit scheme, sampled at its step
// ends, is what the runner records today.
//
// Header-only except run_cvode(); tests may include it without linking SUNDIALS.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "compare/measure.hpp"
#include "compare/result.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/adaptive.hpp"
#include "core/bulk.hpp"
#include "continuum/friction_law.hpp"
#include "core/stepper.hpp"
#include "tests/scenes.hpp"

namespace slipfront::bench {

/// fig1 (docs/model.md §4): edge loading, ρ = 0.01, μ = 300, κ = 8, α = 1.05, η = 0.1, K = 2.5, v_d = 0.3,
/// L = 300, dx = 0.5, t_end = 140, cfl 0.5.
inline compare::Scene fig1_scene() {
  compare::Scene s = testing::fig1_scene();  // the paper's fig1 (tests/scenes.hpp)
  s.output.series_dt = 1.0;
  s.output.snapshot_dt = 10.0;
  return s;
}

/// homogeneous_front (docs/model.md §4): uniform σ_d = 0.5, nucleation patch ℓ_n = 150, L = 1000, t_end = 15.
inline compare::Scene homogeneous_front_scene() {
  compare::Scene s = testing::homogeneous_scene(0.5, 150.0, 15.0);  // tests/scenes.hpp
  s.bulk.length = 1000.0;
  s.output.series_dt = 1.0;
  s.output.snapshot_dt = 5.0;
  return s;
}

/// One run: what it measured, its fields at fixed times, and what it cost.
struct RunRecord {
  std::string integrator;  ///< explicit, adaptive, cvode, cvode_roots
  double setting = 0.0;    ///< cfl (explicit) or rtol
  std::string status = "complete", message;
  compare::Events events;
  double wall = 0.0;           ///< seconds for the whole run: integration + the shared measurements
  double wall_observer = 0.0;  ///< of which the measurements (tracker feeding, dense output for it)
  double integrator_wall() const { return wall - wall_observer; }
  std::int64_t steps = 0, rejected = 0, rhs = 0, switchings = 0;
  std::vector<double> snap_t;
  std::vector<std::vector<double>> snap_A, snap_sb;  ///< [snap][node]
};

/// Initial state of a dynamic scene (docs/model.md §1): at rest (edge loading), or the stuck state with a
/// nucleation patch in steady sliding at σ_d (homogeneous loading; the runner does the same).
struct InitialState {
  std::vector<double> u, v, A, sb;
};
inline InitialState initial_state(const compare::Scene& s, const core::Bulk& bulk) {
  const std::size_t n = bulk.nodes();
  InitialState st{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), std::vector<double>(n, 1.0),
                  std::vector<double>(n, 0.0)};
  if (s.drive.loading != core::Loading::homogeneous) return st;
  const auto& ip = s.interface;
  const double sd = s.drive.sigma_d, vs = continuum::strengthening_branch_velocity(ip, sd);
  for (std::size_t i = 0; i < n; ++i) {
    st.u[i] = sd / ip.alpha;
    st.sb[i] = sd;
    if (std::isfinite(vs) && bulk.x()[i] < s.drive.nucleation_length) {
      const auto ss = continuum::steady_sliding(ip, vs);
      st.A[i] = ss.area;
      st.sb[i] = ss.sigma_bar;
      st.v[i] = vs;
    }
  }
  return st;
}

/// Feeds compare::FrontTracker from a variable-step integrator with dense output. The stepper needs
/// previous_time(), time(), yielded() and dense_state(t, Field, span) on [previous_time(), time()].
class DenseObserver {
 public:
  DenseObserver(const compare::Scene& s, std::vector<double> x, std::vector<double> snap_times)
      : p_(s.measure), x_(x), tracker_(s.measure, x), snap_times_(std::move(snap_times)), n_(x.size()),
        area_(n_), rate_(n_), sb_(n_) {}

  /// The state at t = 0 (the runner records it before the first step).
  void start(std::span<const double> area, std::span<const double> rate) {
    tracker_.sample_tip(0.0, area);
    next_k_ = 1;
    last_mv_ = max_abs(rate);
  }

  template <class Stepper>
  void after_step(const Stepper& sim) {
    const auto clock0 = std::chrono::steady_clock::now();
    observe(sim);
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
  }
  double seconds() const { return seconds_; }  ///< time spent in after_step

  compare::Events finish(bool homogeneous) const { return tracker_.finish(homogeneous); }
  const compare::FrontTracker& tracker() const { return tracker_; }

  std::vector<double> snap_t;
  std::vector<std::vector<double>> snap_A, snap_sb;

 private:
  template <class Stepper>
  void observe(const Stepper& sim) {
    using core::Field;
    const double t0 = sim.previous_time(), t1 = sim.time();
    // max_x |v|: at the midpoint of the step (or of each sub-interval), where the tracker puts it.
    sim.dense_state(t1, Field::slip_rate, rate_);
    const double mv1 = max_abs(rate_);
    const double lo = std::min(last_mv_, mv1), hi = std::max(last_mv_, mv1);
    const bool near_hat = !hat_seen_ && 1.5 * hi >= p_.v_event;
    const bool near_arrest = hat_seen_ && !arrest_seen_ && lo / 1.5 <= p_.v_event / 5.0;
    const double dt_obs = p_.sample_dt / 5.0;
    const int m = (near_hat || near_arrest) ? std::max(1, static_cast<int>(std::ceil((t1 - t0) / dt_obs - 1e-9))) : 1;
    for (int j = 0; j < m; ++j) {
      const double a = t0 + (t1 - t0) * j / m, b = j + 1 == m ? t1 : t0 + (t1 - t0) * (j + 1) / m;
      sim.dense_state(0.5 * (a + b), Field::slip_rate, rate_);
      const double mv = max_abs(rate_);
      tracker_.observe_step(a, b, sim.yielded(), mv);
      if (mv > p_.v_event) hat_seen_ = true;
      else if (hat_seen_ && mv < p_.v_event / 5.0) arrest_seen_ = true;
    }
    last_mv_ = mv1;
    // Tip samples at the exact multiples of sample_dt, over the nodes that can be below a threshold.
    constexpr bool lazy = requires { sim.dense_value(t1, Field::contact_area, std::size_t{0}); };
    std::size_t m_tip = n_, m_alt = n_;
    if constexpr (lazy) {
      std::tie(m_tip, m_alt) = compare::tip_nodes(sim, n_, p_.A_tip, p_.A_tip_alt);
    }
    for (;;) {
      const double tk = static_cast<double>(next_k_) * p_.sample_dt;
      if (tk > t1 * (1.0 + 1e-14)) break;
      ++next_k_;
      if (tk < t0 || !tracker_.sample_due(tk)) continue;
      if constexpr (lazy) {
        compare::sample_tips_dense(sim, tracker_, x_, p_, tk, m_tip, m_alt);
      } else {
        sim.dense_state(tk, Field::contact_area, area_);
        tracker_.sample_tip(tk, area_);
      }
    }
    // Fields at the requested times.
    while (next_snap_ < snap_times_.size() && snap_times_[next_snap_] <= t1 * (1.0 + 1e-14)) {
      const double ts = snap_times_[next_snap_++];
      sim.dense_state(ts, Field::contact_area, area_);
      sim.dense_state(ts, Field::sigma_bar, sb_);
      snap_t.push_back(ts);
      snap_A.push_back(area_);
      snap_sb.push_back(sb_);
    }
  }

  static double max_abs(std::span<const double> v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
  }
  core::MeasureParams p_;
  std::vector<double> x_;
  compare::FrontTracker tracker_;
  std::vector<double> snap_times_;
  std::size_t n_, next_snap_ = 0;
  std::int64_t next_k_ = 1;
  double last_mv_ = 0.0, seconds_ = 0.0;
  bool hat_seen_ = false, arrest_seen_ = false;
  std::vector<double> area_, rate_, sb_;
};

/// Time step of the explicit scheme at `cfl`, shortened so that every multiple of 10 (the snapshot
/// times must be multiples of 10) and t_end are step ends.
inline double explicit_time_step(const compare::Scene& s, double cfl) {
  const core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const double quantum = 10.0;
  return quantum / std::ceil(quantum / (cfl * bulk.stable_dt()) - 1e-9);
}

/// The explicit reference scheme at time.cfl = cfl, measured exactly as compare::run_dynamic does
/// (tracker fed at the step ends: observe_step every step, tip samples at the first step end at or
/// after each multiple of sample_dt), with the measurement time kept apart. `via_runner` runs
/// compare::run_model itself instead (same events; its wall time includes the runner's recording).
inline RunRecord run_explicit(compare::Scene s, double cfl, const std::vector<double>& snap_times,
                              bool via_runner = false) {
  s.time.dt = explicit_time_step(s, cfl);
  s.time.cfl = cfl;
  RunRecord rec;
  rec.integrator = via_runner ? "explicit_runner" : "explicit";
  rec.setting = cfl;
  if (via_runner) {
    s.output.series_dt = 1.0;
    s.output.snapshot_dt = 10.0;
    auto make = [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); };
    const auto r = compare::run_model<continuum::FrictionLaw>(s, make, "continuum", compare::RunControl{});
    rec.status = compare::to_string(r.status);
    rec.message = r.message;
    rec.events = r.events;
    rec.wall = r.wall_seconds;
    rec.steps = rec.rhs = static_cast<std::int64_t>(r.scalars.at("steps"));
    const std::size_t nx = r.x.size();
    for (double ts : snap_times)
      for (std::size_t k = 0; k < r.snapshot_t.size(); ++k)
        if (std::abs(r.snapshot_t[k] - ts) < 1e-9 * ts) {
          const auto& A = r.snapshots.at("A");
          const auto& sb = r.snapshots.at("sigma_bar");
          const auto b = static_cast<std::ptrdiff_t>(k * nx), e = static_cast<std::ptrdiff_t>((k + 1) * nx);
          rec.snap_t.push_back(ts);
          rec.snap_A.emplace_back(A.begin() + b, A.begin() + e);
          rec.snap_sb.emplace_back(sb.begin() + b, sb.begin() + e);
        }
    return rec;
  }
  using clock = std::chrono::steady_clock;
  const auto wall0 = clock::now();
  core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const auto init = initial_state(s, bulk);
  const std::vector<double> x = bulk.x();
  const double dt = s.time.dt;
  const auto nsteps = static_cast<std::int64_t>(std::llround(s.time.t_end / dt));
  core::ExplicitSimulation<continuum::FrictionLaw> sim(std::move(bulk), continuum::FrictionLaw(s.interface, x.size()),
                                                            dt);
  for (std::size_t i = 0; i < x.size(); ++i) {
    sim.law().set_site(i, init.A[i], init.sb[i]);
    sim.set_initial(i, init.u[i], init.v[i]);
  }
  compare::FrontTracker tracker(s.measure, x);
  tracker.sample_tip(0.0, sim.law().contact_area());
  std::size_t next_snap = 0;
  double observer = 0.0;
  try {
    for (std::int64_t n = 0; n < nsteps; ++n) {
      const double t0 = sim.time();
      sim.step();
      const auto c0 = clock::now();
      const double t = sim.time();
      tracker.observe_step(t0, t, sim.yielded(), sim.max_slip_rate());
      if (tracker.sample_due(t)) tracker.sample_tip(t, sim.law().contact_area());
      if (next_snap < snap_times.size() && std::abs(t - snap_times[next_snap]) < 0.5 * dt) {
        const auto A = sim.law().contact_area(), sb = sim.law().sigma_bar();
        rec.snap_t.push_back(snap_times[next_snap++]);
        rec.snap_A.emplace_back(A.begin(), A.end());
        rec.snap_sb.emplace_back(sb.begin(), sb.end());
      }
      observer += std::chrono::duration<double>(clock::now() - c0).count();
    }
  } catch (const core::NumericalError& e) {
    rec.status = "failed";
    rec.message = e.what();
  }
  rec.events = tracker.finish(s.drive.loading == core::Loading::homogeneous);
  rec.wall = std::chrono::duration<double>(clock::now() - wall0).count();
  rec.wall_observer = observer;
  rec.steps = rec.rhs = sim.steps();
  return rec;
}

/// The adaptive integrator on a dynamic scene, observed through its dense output.
inline RunRecord run_adaptive(const compare::Scene& s, const core::AdaptiveOptions& opt,
                              const std::vector<double>& snap_times) {
  const auto wall0 = std::chrono::steady_clock::now();
  core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const auto init = initial_state(s, bulk);
  const std::vector<double> x = bulk.x();
  core::AdaptiveSimulation sim(std::move(bulk), continuum::FrictionLaw(s.interface, x.size()), opt);
  for (std::size_t i = 0; i < x.size(); ++i) {
    sim.law().set_site(i, init.A[i], init.sb[i]);
    sim.set_initial(i, init.u[i], init.v[i]);
  }
  sim.set_stop_time(s.time.t_end);
  DenseObserver obs(s, x, snap_times);
  obs.start(sim.law().contact_area(), sim.slip_rate());
  RunRecord rec;
  rec.integrator = "adaptive";
  rec.setting = opt.rtol;
  try {
    while (sim.time() < s.time.t_end) {
      sim.step();
      obs.after_step(sim);
    }
  } catch (const core::NumericalError& e) {
    rec.status = "failed";
    rec.message = e.what();
  }
  rec.events = obs.finish(s.drive.loading == core::Loading::homogeneous);
  rec.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  rec.wall_observer = obs.seconds();
  const auto& st = sim.stats();
  rec.steps = st.accepted;
  rec.rejected = st.rejected;
  rec.rhs = st.rhs;
  rec.switchings = st.switchings;
  rec.snap_t = obs.snap_t;
  rec.snap_A = obs.snap_A;
  rec.snap_sb = obs.snap_sb;
  return rec;
}

/// The peer: SUNDIALS CVODE (BDF, banded DQ Jacobian, band LU) on the same ODE.
struct CvodeOptions {
  double rtol = 1e-6;
  double atol = 1e-8;
  bool roots = false;          ///< Θ frozen, switched at located roots (CVODE rootfinding + ReInit)
  int max_order = 5;           ///< BDF order limit (2: A-stable)
  bool stability_detection = false;  ///< CVodeSetStabLimDet (BDF order reduction near the stability limit)
  double dt_max = 1.0;
  long max_steps = 50'000'000;
};
RunRecord run_cvode(const compare::Scene& s, const CvodeOptions& opt, const std::vector<double>& snap_times);

/// Discrete L2 distance over the interface, sqrt(Σ w_i (a_i − b_i)²) with the lumped node weights.
inline double l2_distance(const core::Bulk& bulk, std::span<const double> a, std::span<const double> b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += bulk.node_weight(i) * (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

}  // namespace slipfront::bench
