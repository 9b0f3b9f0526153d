#pragma once
// Runs one model on one scene: the loop that drives Simulation<Law> (1D, spring block) or the law
// alone (imposed slip rate), feeds the shared measurements and records what the scene asks for.
// Templated on the interface law so the continuum and discrete models share every line of it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "compare/measure.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "continuum/adaptive.hpp"
#include "continuum/bulk.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/implicit.hpp"
#include "continuum/stepper.hpp"

namespace slipfront::compare {

/// Hooks of the caller (CLI): a stop request (Ctrl-C) polled between steps, and progress.
struct RunControl {
  std::function<bool()> stop = [] { return false; };
  std::function<void(const std::string& model, double t, double t_end)> progress =
      [](const std::string&, double, double) {};
};

/// The time step a dynamic scene will use: time.dt, or time.cfl × the explicit limit, shortened so
/// that t_end is a whole number of steps.
double dynamic_time_step(const Scene& s);

/// Slip-rate grid of an imposed-rate sweep (log spaced, MODEL §4 friction_law).
std::vector<double> sweep_rates(const continuum::DriveParams& d);

namespace detail {

// Cadence helper: due(t) is true at the first step at or after each multiple of `every`.
class Cadence {
 public:
  explicit Cadence(double every) : every_(every) {}
  bool due(double t) {
    if (every_ < 0) return false;
    if (t + 1e-9 * every_ < next_) return false;
    next_ = every_ > 0 ? (std::floor(t / every_ + 1e-9) + 1.0) * every_ : t;
    return true;
  }
 private:
  double every_, next_ = 0.0;
};

inline void push(Columns& c, const char* name, double v) { c[name].push_back(v); }
inline void append(Columns& c, const char* name, std::span<const double> v) {
  auto& col = c[name];
  col.insert(col.end(), v.begin(), v.end());
}

// Stick–slip cycles of the spring block: a cycle's slip event starts when v > v_event and ends
// when v < v_event/5; F_peak is the largest F since the previous event, F_residual the smallest F
// during the event.
class CycleDetector {
 public:
  explicit CycleDetector(double v_event) : v_event_(v_event) {}
  void observe(double t, double force, double v, Columns& out) {
    if (!slipping_) {
      peak_ = std::max(peak_, force);
      if (v > v_event_) { slipping_ = true; t_start_ = t; low_ = force; }
    } else {
      low_ = std::min(low_, force);
      if (v < v_event_ / 5.0) {
        push(out, "t_start", t_start_);
        push(out, "F_peak", peak_);
        push(out, "F_residual", low_);
        slipping_ = false;
        peak_ = -HUGE_VAL;
      }
    }
  }
 private:
  double v_event_, peak_ = -HUGE_VAL, low_ = HUGE_VAL, t_start_ = 0.0;
  bool slipping_ = false;
};

// Laws that record contact statistics (the agent representation, MODEL §5 /discrete/contacts): the
// runner snapshots them at the snapshot cadence and stores their tables; other laws compile without
// a trace of it (no virtual call, nothing at run time).
template <class Law>
concept RecordsContacts = requires(Law& law, const Law& cl, double t) {
  law.record_contacts(t);
  cl.contact_tables();
};
template <class Law>
void store_contacts(const Law& law, ModelResult& r) {
  auto tables = law.contact_tables();
  for (auto& [name, col] : tables.columns) r.contacts[name] = std::move(col);
  for (auto& [name, tab] : tables.tables) r.contacts_2d[name] = Table2D{tab.cols, std::move(tab.data)};
}

template <class Stepper>
void set_initial_conditions(const Scene& s, Stepper& sim) {
  using continuum::Loading;
  if (s.drive.loading != Loading::homogeneous) return;  // edge, spring block: u = v = 0, A = 1, σ̄ = 0
  // MODEL §1 homogeneous loading: stuck state, and a nucleation patch in steady sliding at σ_d.
  const auto& ip = s.interface;
  const double sd = s.drive.sigma_d;
  const double vs = continuum::strengthening_branch_velocity(ip, sd);
  const auto& x = sim.bulk().x();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const bool patch = std::isfinite(vs) && x[i] < s.drive.nucleation_length;
    if (patch) {
      const auto ss = continuum::steady_sliding(ip, vs);
      sim.law().set_site(i, ss.area, ss.sigma_bar);
      sim.set_initial(i, sd / ip.alpha, vs);
    } else {
      sim.law().set_site(i, 1.0, sd);
      sim.set_initial(i, sd / ip.alpha, 0.0);
    }
  }
}

}  // namespace detail

/// Steppers with dense output (the adaptive integrator): the runner records at exact times.
template <class S>
concept DenseStepper = requires(const S& sim, double t, std::span<double> out) {
  sim.previous_time();
  sim.dense_state(t, continuum::Field::slip_rate, out);
};

/// Dense steppers, after a step [t0, t1]: how many leading nodes the tip samples of that step need
/// for `threshold` (MODEL §3 tip: the largest x with A < threshold). Nodes beyond the last one whose
/// A may fall below the threshold during the step stay above it throughout. The bound on |1 − A_i(t)|
/// over the step is the stepper's dense_deviation_bound when it has one, else 1.25 × the largest of
/// |1 − A_i| at the start, middle and end (a quadratic interpolant: the Lebesgue constant of three
/// equispaced points). Returns that node + 2 (one more for the tip's interpolation; at most the node
/// count), or 1 when every node stays above.
template <class S>
  requires requires(const S& sim, double t, std::size_t i) { sim.dense_value(t, continuum::Field::contact_area, i); }
std::size_t tip_nodes(const S& sim, std::size_t nodes, double threshold) {
  using continuum::Field;
  const double t0 = sim.previous_time(), t1 = sim.time(), margin = 1.0 - threshold;
  for (std::size_t i = nodes; i-- > 0;) {
    double bound;
    if constexpr (requires { sim.dense_deviation_bound(Field::contact_area, i, 1.0); }) {
      bound = sim.dense_deviation_bound(Field::contact_area, i, 1.0);
    } else {
      bound = 1.25 * std::max({std::abs(1.0 - sim.dense_value(t0, Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(0.5 * (t0 + t1), Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(t1, Field::contact_area, i))});
    }
    if (!(bound < margin)) return std::min(nodes, i + 2);
  }
  return 1;
}

/// Dense steppers: record the tips at time t inside the last step, each searched lazily over the
/// nodes tip_nodes() left for its threshold (m_tip, m_alt). Returns the A_tip position.
template <class S>
double sample_tips_dense(const S& sim, FrontTracker& tracker, std::span<const double> x, const continuum::MeasureParams& p,
                         double t, std::size_t m_tip, std::size_t m_alt) {
  auto area = [&](std::size_t i) { return sim.dense_value(t, continuum::Field::contact_area, i); };
  return tracker.record_tips(t, tip_position_lazy(x, m_tip, p.A_tip, area), tip_position_lazy(x, m_alt, p.A_tip_alt, area));
}

namespace detail {
template <class Stepper, class Law>
Stepper make_stepper(const Scene& s, Law law) {
  continuum::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  if constexpr (DenseStepper<Stepper>) {
    continuum::AdaptiveOptions o;
    o.rtol = s.time.rtol;
    o.atol = s.time.atol;
    o.dt_max = s.time.dt_max;
    Stepper sim(std::move(bulk), std::move(law), s.interface.eta, o);
    sim.set_stop_time(s.time.t_end);
    return sim;
  } else {
    return Stepper(std::move(bulk), std::move(law), s.interface.eta, dynamic_time_step(s));
  }
}
}  // namespace detail

/// One model on a bulk scene (edge and homogeneous loading, spring block), advanced one step at a
/// time so that several runs can go in lockstep (run_scene_alongside). Each step feeds the shared
/// measurements and records what the scene asks for; finish() hands over the result. The stepper is
/// the explicit Simulation<Law>, or (continuum, time.integrator = "adaptive") AdaptiveSimulation,
/// whose dense output lets every measurement and record be taken at its exact time.
template <class Law, class Stepper = continuum::Simulation<Law>>
class DynamicRun {
 public:
  DynamicRun(const Scene& s, Law law, std::string model)
      : s_(s), wall0_(std::chrono::steady_clock::now()),
        sim_(detail::make_stepper<Stepper>(s, std::move(law))),
        one_d_(continuum::is_one_dimensional(s.drive.loading)),
        tracker_(s.measure, sim_.bulk().x()),
        series_due_(s.output.series_dt),
        snap_due_(s.output.snapshot_dt > 0 ? s.output.snapshot_dt : -1),
        contacts_due_(s.output.snapshot_dt > 0 ? s.output.snapshot_dt : -1),
        cycles_(s.measure.v_event) {
    r_.model = std::move(model);
    r_.x = sim_.bulk().x();
    r_.scalars["stable_dt"] = sim_.bulk().stable_dt();
    if constexpr (DenseStepper<Stepper>) {
      r_.labels["integrator"] = "adaptive";
      r_.scalars["rtol"] = s.time.rtol;
      for (auto* b : {&A_, &sb_, &v_, &u_}) b->resize(r_.x.size());
    } else {
      nsteps_ = static_cast<std::int64_t>(std::llround(s.time.t_end / sim_.dt()));
      r_.scalars["dt"] = sim_.dt();
      r_.labels["integrator"] = Stepper::integrator_name;
      sim_.track_energy(s.output.energy);
    }
    detail::set_initial_conditions(s, sim_);
    record();
  }

  bool done() const {
    if (r_.status != "complete") return true;
    if constexpr (DenseStepper<Stepper>) return sim_.time() >= s_.time.t_end * (1.0 - 1e-12);
    else return n_ >= nsteps_;
  }
  const Stepper& sim() const { return sim_; }
  const std::string& model() const { return r_.model; }
  double time() const { return sim_.time(); }

  /// One step with its measurements; a non-finite state ends the run with status "failed".
  void step() {
    try {
      const double t0 = sim_.time();
      sim_.step();
      ++n_;
      if constexpr (DenseStepper<Stepper>) {
        record_dense(t0, sim_.time());
      } else {
        tracker_.observe_step(t0, sim_.time(), sim_.yielded(), sim_.max_slip_rate());
        if (!one_d_) cycles_.observe(sim_.time(), sim_.drive_force(), sim_.slip_rate()[0], r_.cycles);
        record();
      }
    } catch (const continuum::NumericalError& e) {
      r_.status = "failed";
      r_.message = e.what();
    }
  }

  void interrupt() {
    r_.status = "interrupted";
    r_.message = "stopped at t = " + std::to_string(sim_.time());
  }

  ModelResult finish() {
    using continuum::Loading;
    if constexpr (detail::RecordsContacts<Law>) detail::store_contacts(sim_.law(), r_);
    r_.events = tracker_.finish(s_.drive.loading == Loading::homogeneous);
    r_.events_alt = tracker_.finish(s_.drive.loading == Loading::homogeneous, true);
    r_.events.v_behind = r_.events_alt.v_behind = v_behind_;
    r_.scalars["steps"] = static_cast<double>(sim_.steps());
    r_.scalars["t_reached"] = sim_.time();
    r_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    return std::move(r_);
  }

 private:
  void record() {
    const double t = sim_.time();
    auto& r = r_;
    auto& sim = sim_;
    if constexpr (detail::RecordsContacts<Law>)
      if (contacts_due_.due(t)) sim.law().record_contacts(t);
    const auto area = sim.law().contact_area();
    if (one_d_ && tracker_.sample_due(t)) {
      const double tip = tracker_.sample_tip(t, area);
      if (s_.drive.loading == continuum::Loading::homogeneous) observe_behind(tip, sim.slip_rate());
    }
    if (series_due_.due(t)) {
      detail::push(r.series, "t", t);
      detail::push(r.series, "drive_force", sim.drive_force());
      detail::push(r.series, "max_v", sim.max_slip_rate());
      if (one_d_) {
        detail::push(r.series, "tip_x", tracker_.last_tip());
        detail::push(r.series, "tip_x_alt", tracker_.last_tip_alt());
      } else {
        const double sb = sim.law().sigma_bar()[0], v = sim.slip_rate()[0];
        detail::push(r.series, "A", area[0]);
        detail::push(r.series, "sigma_bar", sb);
        detail::push(r.series, "sigma", sb + s_.interface.eta * v);
        detail::push(r.series, "slip_rate", v);
        detail::push(r.series, "slip", sim.slip()[0]);
      }
      if (const auto& e = sim.energy()) {  // the budget at t^n (one step behind t); all 0 at t = 0
        const bool started = !std::isnan(e->mechanical0);
        detail::push(r.series, "energy_drive_work", started ? e->drive_work : 0.0);
        detail::push(r.series, "energy_mechanical", started ? e->mechanical() - e->mechanical0 : 0.0);
        detail::push(r.series, "energy_viscous", started ? e->viscous : 0.0);
        detail::push(r.series, "energy_interfacial", started ? e->interfacial : 0.0);
        detail::push(r.series, "energy_residual", started ? e->residual() : 0.0);
        detail::push(r.series, "energy_time", started ? e->time : 0.0);
      }
    }
    if (one_d_ && snap_due_.due(t)) {
      r.snapshot_t.push_back(t);
      detail::append(r.snapshots, "A", area);
      detail::append(r.snapshots, "sigma_bar", sim.law().sigma_bar());
      detail::append(r.snapshots, "v", sim.slip_rate());
      detail::append(r.snapshots, "u", sim.slip());
    }
  }

  // Homogeneous loading (MODEL §4 front spectrum): the mean slip rate over [ℓ_n, x_tip − 10] when
  // the tip first passes 3/4 of the system.
  void observe_behind(double tip, std::span<const double> v) {
    const double L = r_.x.back();
    if (!std::isnan(v_behind_) || !(tip >= 0.75 * L)) return;
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < r_.x.size(); ++i)
      if (r_.x[i] >= s_.drive.nucleation_length && r_.x[i] <= tip - 10.0) { sum += v[i]; ++n; }
    v_behind_ = n ? sum / n : nan;
  }

  // Dense stepper: over the accepted step [t0, t1] the tracker sees max|v| on sub-intervals of at
  // most sample_dt/2 (so t^ is interpolated as finely as with small steps), tip samples, series and
  // snapshots are taken at their exact cadence times from the integrator's interpolant.
  // The interpolant is quadratic in time at every node, so over the step |v_i| ≤ 1.25 × the largest of
  // |v_i| at its start, middle and end (the Lebesgue constant of three equispaced points), and likewise
  // for 1 − A_i. That bound spares the work nobody would see: a step whose bound stays ≤ v_event outside
  // a transient cannot move an event, and gets one observation instead of sub-intervals; a node whose
  // A stays above both tip thresholds over the whole step is not interpolated for the tip samples.
  void record_dense(double t0, double t1) {
    using continuum::Field;
    const std::size_t n = r_.x.size();
    sim_.dense_state(t0, Field::slip_rate, v_);
    const double v_start = max_abs(v_);
    sim_.dense_state(0.5 * (t0 + t1), Field::slip_rate, v_);
    const double bound = 1.25 * std::max({v_start, max_abs(v_), max_abs(sim_.slip_rate())});
    if (!tracker_.in_transient() && bound <= s_.measure.v_event) {
      tracker_.observe_step(t0, t1, sim_.yielded(), bound);
      quiet_ = true;
    } else {
      if (quiet_) tracker_.observe_step(t0, t0, false, v_start);  // exact base for interpolating t^
      quiet_ = false;
      const auto m = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((t1 - t0) / (0.5 * s_.measure.sample_dt) - 1e-9)));
      for (std::int64_t j = 0; j < m; ++j) {
        const double a = t0 + (t1 - t0) * static_cast<double>(j) / static_cast<double>(m);
        const double b = j + 1 == m ? t1 : t0 + (t1 - t0) * static_cast<double>(j + 1) / static_cast<double>(m);
        sim_.dense_state(0.5 * (a + b), Field::slip_rate, v_);
        tracker_.observe_step(a, b, sim_.yielded(), max_abs(v_));
      }
    }
    if (!one_d_) cycles_.observe(t1, sim_.drive_force(), sim_.slip_rate()[0], r_.cycles);
    auto times = [t0, t1](double every, auto&& f) {  // multiples of `every` in (t0, t1]
      if (every <= 0) return;
      for (auto k = static_cast<std::int64_t>(std::floor(t0 / every + 1e-9)) + 1;; ++k) {
        const double t = std::min(static_cast<double>(k) * every, t1);
        if (static_cast<double>(k) * every > t1 * (1.0 + 1e-12)) break;
        f(t);
      }
    };
    auto load = [&](double t) {
      sim_.dense_state(t, Field::contact_area, A_);
      sim_.dense_state(t, Field::sigma_bar, sb_);
      sim_.dense_state(t, Field::slip_rate, v_);
      sim_.dense_state(t, Field::slip, u_);
    };
    if (one_d_) {
      // Per threshold, the nodes whose A can be below it during the step; beyond them A stays above.
      const std::size_t m_tip = tip_nodes(sim_, n, s_.measure.A_tip), m_alt = tip_nodes(sim_, n, s_.measure.A_tip_alt);
      times(s_.measure.sample_dt, [&](double t) {
        const double tip = sample_tips_dense(sim_, tracker_, r_.x, s_.measure, t, m_tip, m_alt);
        if (s_.drive.loading == continuum::Loading::homogeneous) {
          sim_.dense_state(t, Field::slip_rate, v_);
          observe_behind(tip, v_);
        }
      });
    }
    times(s_.output.series_dt, [&](double t) {
      if (one_d_) {  // a 1D series row needs u_0 and max |v| only
        sim_.dense_state(t, Field::slip_rate, v_);
        u_[0] = sim_.dense_value(t, Field::slip, 0);
      } else {
        load(t);
      }
      detail::push(r_.series, "t", t);
      detail::push(r_.series, "drive_force", sim_.bulk().drive_force(t, u_[0]));
      detail::push(r_.series, "max_v", max_abs(v_));
      if (one_d_) {
        detail::push(r_.series, "tip_x", tracker_.last_tip());
        detail::push(r_.series, "tip_x_alt", tracker_.last_tip_alt());
      } else {
        detail::push(r_.series, "A", A_[0]);
        detail::push(r_.series, "sigma_bar", sb_[0]);
        detail::push(r_.series, "sigma", sb_[0] + s_.interface.eta * v_[0]);
        detail::push(r_.series, "slip_rate", v_[0]);
        detail::push(r_.series, "slip", u_[0]);
      }
    });
    if (one_d_)
      times(s_.output.snapshot_dt, [&](double t) {
        load(t);
        r_.snapshot_t.push_back(t);
        detail::append(r_.snapshots, "A", A_);
        detail::append(r_.snapshots, "sigma_bar", sb_);
        detail::append(r_.snapshots, "v", v_);
        detail::append(r_.snapshots, "u", u_);
      });
  }

  static double max_abs(std::span<const double> v) {
    double m = 0.0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
  }

  const Scene& s_;
  std::chrono::steady_clock::time_point wall0_;
  ModelResult r_;
  Stepper sim_;
  bool one_d_;
  FrontTracker tracker_;
  detail::Cadence series_due_, snap_due_, contacts_due_;
  detail::CycleDetector cycles_;
  std::int64_t n_ = 0, nsteps_ = 0;
  double v_behind_ = nan;
  bool quiet_ = false;                  // dense stepper: the last step got one max|v| observation
  std::vector<double> A_, sb_, v_, u_;  // dense-output buffers
};

/// Bulk scenes run alone: step to t_end, polling the stop request every 64 steps.
template <class Law, class Stepper = continuum::Simulation<Law>>
ModelResult run_dynamic(const Scene& s, Law law, const std::string& model, const RunControl& ctl) {
  DynamicRun<Law, Stepper> run(s, std::move(law), model);
  for (std::int64_t n = 1; !run.done(); ++n) {
    run.step();
    if ((n & 63) == 0) {
      if ((n & 1023) == 0) ctl.progress(model, run.time(), s.time.t_end);
      if (ctl.stop()) run.interrupt();
    }
  }
  return run.finish();
}

/// Steady friction at imposed v (MODEL §3): run one site for t_end + slip_end/|v| in `steps` exact
/// steps and average σ = σ̄ + ηv over the last (1 − average_from) of the run by batch means.
struct SteadyPoint {
  double v, sigma, sigma_stderr, area;
};
template <class Law>
SteadyPoint steady_point(const Scene& s, Law law, double v) {
  const double T = s.time.t_end + s.time.slip_end / std::abs(v);
  const double dt = T / s.time.steps;
  BatchMeans sig(s.measure.average_from * T, T, s.measure.batches), area(s.measure.average_from * T, T, 2);
  const double vv[1] = {v};
  for (int n = 0; n < s.time.steps; ++n) {
    law.advance(dt, vv);
    const double t0 = n * dt, t1 = (n + 1) * dt;
    sig.add(t0, t1, law.sigma_bar()[0] + s.interface.eta * v);
    area.add(t0, t1, law.contact_area()[0]);
  }
  return {v, sig.mean(), sig.stderr_of_mean(), area.mean()};
}

/// Imposed slip rate (0D): a sweep over v (friction law) or one piecewise-constant history v(t).
template <class Law, class MakeLaw>
ModelResult run_imposed_rate(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl) {
  using namespace continuum;
  const auto wall0 = std::chrono::steady_clock::now();
  ModelResult r;
  r.model = model;
  r.x = {0.0};
  if (s.drive.sweep_points > 0) {
    const auto rates = sweep_rates(s.drive);
    for (std::size_t k = 0; k < rates.size(); ++k) {
      const SteadyPoint p = steady_point<Law>(s, make_law(std::size_t{1}), rates[k]);
      detail::push(r.friction_law, "v", p.v);
      detail::push(r.friction_law, "sigma", p.sigma);
      detail::push(r.friction_law, "sigma_stderr", p.sigma_stderr);
      detail::push(r.friction_law, "A", p.area);
      detail::push(r.friction_law, "sigma_closed_form", steady_sliding(s.interface, p.v).sigma);
      ctl.progress(model, static_cast<double>(k + 1), static_cast<double>(rates.size()));
      if (ctl.stop()) { r.status = "interrupted"; r.message = "stopped during the sweep"; break; }
    }
    // Numerical minimum: parabola in log v through the smallest tabulated σ and its neighbours.
    const auto& sv = r.friction_law["sigma"];
    const auto& vv = r.friction_law["v"];
    if (sv.size() >= 3) {
      auto k = static_cast<std::size_t>(std::min_element(sv.begin(), sv.end()) - sv.begin());
      k = std::clamp<std::size_t>(k, 1, sv.size() - 2);
      const double x0 = std::log(vv[k - 1]), x1 = std::log(vv[k]), x2 = std::log(vv[k + 1]);
      const double y0 = sv[k - 1], y1 = sv[k], y2 = sv[k + 1];
      const double d = (x0 - x1) * (x0 - x2) * (x1 - x2);
      const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
      const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
      const double c = (x1 * x2 * (x1 - x2) * y0 + x2 * x0 * (x2 - x0) * y1 + x0 * x1 * (x0 - x1) * y2) / d;
      if (a > 0) {
        const double xm = -b / (2 * a);
        r.scalars["v_m_fit"] = std::exp(xm);
        r.scalars["sigma_c_fit"] = c - b * b / (4 * a);
      }
      // The deterministic continuum law: locate the minimum by golden-section search on the computed
      // steady friction between the neighbours of the tabulated minimum (to 1e-7 in log v).
      if constexpr (std::is_same_v<Law, continuum::FrictionLaw>) {
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        double lo = x0, hi = x2;
        auto f = [&](double lx) { return steady_point<Law>(s, make_law(std::size_t{1}), std::exp(lx)).sigma; };
        double p1 = hi - g * (hi - lo), p2 = lo + g * (hi - lo), f1 = f(p1), f2 = f(p2);
        while (hi - lo > 1e-7) {
          if (f1 < f2) { hi = p2; p2 = p1; f2 = f1; p1 = hi - g * (hi - lo); f1 = f(p1); }
          else { lo = p1; p1 = p2; f1 = f2; p2 = lo + g * (hi - lo); f2 = f(p2); }
        }
        r.scalars["v_m_numeric"] = std::exp(0.5 * (lo + hi));
        r.scalars["sigma_c_numeric"] = f(0.5 * (lo + hi));
      }
    }
  } else {
    // One history: piecewise-constant v, steps aligned with the switch times.
    Law law = make_law(std::size_t{1});
    const auto& vs = s.drive.v;
    const auto& ts = s.drive.v_times;
    const double dt_target = s.time.dt > 0 ? s.time.dt : s.time.t_end / s.time.steps;
    FrontTracker tracker(s.measure, r.x);
    detail::Cadence series_due(s.output.series_dt);
    [[maybe_unused]] detail::Cadence contacts_due(s.output.snapshot_dt > 0 ? s.output.snapshot_dt : -1);
    double t = 0.0;
    auto record = [&](double v) {
      if constexpr (detail::RecordsContacts<Law>)
        if (contacts_due.due(t)) law.record_contacts(t);
      if (!series_due.due(t)) return;
      const double sb = law.sigma_bar()[0];
      detail::push(r.series, "t", t);
      detail::push(r.series, "slip_rate", v);
      detail::push(r.series, "A", law.contact_area()[0]);
      detail::push(r.series, "sigma_bar", sb);
      detail::push(r.series, "sigma", sb + s.interface.eta * v);
      detail::push(r.series, "drive_force", sb + s.interface.eta * v);
      detail::push(r.series, "max_v", std::abs(v));
    };
    record(vs[0]);
    std::int64_t steps = 0;
    for (std::size_t k = 0; k < vs.size() && r.status == "complete"; ++k) {
      const double t_seg_end = k + 1 < vs.size() ? std::min(ts[k + 1], s.time.t_end) : s.time.t_end;
      if (t_seg_end <= ts[k]) break;
      const auto n = static_cast<std::int64_t>(std::ceil((t_seg_end - ts[k]) / dt_target - 1e-9));
      const double dt = (t_seg_end - ts[k]) / static_cast<double>(n);
      const double v[1] = {vs[k]};
      for (std::int64_t j = 0; j < n; ++j) {
        const double t0 = t;
        const bool yielded = law.advance(dt, v).any_yield;
        t = ts[k] + static_cast<double>(j + 1) * dt;
        tracker.observe_step(t0, t, yielded, std::abs(v[0]));
        record(v[0]);
        if ((++steps & 1023) == 0) {
          ctl.progress(model, t, s.time.t_end);
          if (ctl.stop()) { r.status = "interrupted"; r.message = "stopped at t = " + std::to_string(t); break; }
        }
      }
    }
    if constexpr (detail::RecordsContacts<Law>) detail::store_contacts(law, r);
    r.events = tracker.finish(false);
    r.scalars["steps"] = static_cast<double>(steps);
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

/// Run one model on a scene, whichever loading it has. make_law(n_sites) builds the law.
template <class Law, class MakeLaw>
ModelResult run_model(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl) {
  if (s.drive.loading == continuum::Loading::imposed_rate) return run_imposed_rate<Law>(s, make_law, model, ctl);
  const continuum::Bulk probe(s.bulk, s.drive, s.interface, s.grid.dx);
  if (s.time.integrator == continuum::Integrator::implicit_trapezoidal)
    return run_dynamic<Law, continuum::ImplicitSimulation<Law>>(s, make_law(probe.nodes()), model, ctl);
  return run_dynamic<Law>(s, make_law(probe.nodes()), model, ctl);
}

/// Every model the scene lists, in order (continuum; discrete from issue 3 on).
std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl);

}  // namespace slipfront::compare
