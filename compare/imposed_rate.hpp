#pragma once
// Imposed slip rate (0D, docs/model.md §1 "0D scenes"): the law alone, no bulk. Two kinds of run, both
// driven by run_loop (compare/run_loop.hpp) like every other run:
//   ImposedSweep    the steady friction law over a log grid of v (docs/model.md §3 steady friction
//                   law), one point per step, then its minimum
//   ImposedHistory  one piecewise-constant history v(t) (velocity steps), steps aligned with the
//                   switch times, measured and recorded as a 1-site interface
// Neither is checkpointed (a 0D run takes seconds).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "compare/cadence.hpp"
#include "compare/dynamic_run.hpp"
#include "compare/fit.hpp"
#include "compare/measure.hpp"
#include "compare/record.hpp"
#include "compare/result.hpp"
#include "compare/run_loop.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "core/law.hpp"

namespace slipfront::compare {

/// Steady friction at imposed v (docs/model.md §3): run one site for t_end + slip_end/|v| in `steps`
/// exact steps and average σ = σ̄ + ηv over the last (1 − average_from) of the run by batch means.
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

/// The steady friction law: one steady_point per step over sweep_rates; finish() adds its minimum.
template <class Law, class MakeLaw>
class ImposedSweep {
 public:
  static constexpr std::int64_t progress_every = 1;
  static constexpr bool checkpointable = false;
  ImposedSweep(const Scene& s, MakeLaw make_law, std::string model)
      : s_(s), make_law_(std::move(make_law)), rates_(sweep_rates(s.drive)), wall0_(std::chrono::steady_clock::now()) {
    r_.model = std::move(model);
    r_.x = {0.0};
  }
  bool done() const { return r_.status != RunStatus::complete || k_ >= rates_.size(); }
  double time() const { return static_cast<double>(k_); }
  double end() const { return static_cast<double>(rates_.size()); }
  void step() {
    const SteadyPoint p = steady_point<Law>(s_, make_law_(std::size_t{1}), rates_[k_++]);
    detail::push(r_.friction_law, "v", p.v);
    detail::push(r_.friction_law, "sigma", p.sigma);
    detail::push(r_.friction_law, "sigma_stderr", p.sigma_stderr);
    detail::push(r_.friction_law, "A", p.area);
    detail::push(r_.friction_law, "sigma_closed_form", continuum::steady_sliding(s_.interface, p.v).sigma);
  }
  void interrupt() {
    r_.status = RunStatus::interrupted;
    r_.message = "stopped during the sweep";
  }

  /// The minimum of the steady law: a parabola in log v through the smallest tabulated σ and its
  /// neighbours; for a deterministic rate law, golden-section search on the computed steady friction
  /// between those neighbours (to 1e-7 in log v).
  ModelResult finish() {
    const auto& vv = r_.friction_law["v"];
    const auto& sv = r_.friction_law["sigma"];
    if (const TabulatedMinimum m = parabola_minimum_log(vv, sv); sv.size() >= 3) {
      if (m.found) {
        r_.scalars["v_m_fit"] = m.x;
        r_.scalars["sigma_c_fit"] = m.y;
      }
      if constexpr (core::SmoothLaw<Law>) {
        auto f = [&](double lx) { return steady_point<Law>(s_, make_law_(std::size_t{1}), std::exp(lx)).sigma; };
        const double lx = golden_section_minimum(f, std::log(vv[m.index - 1]), std::log(vv[m.index + 1]), 1e-7);
        r_.scalars["v_m_numeric"] = std::exp(lx);
        r_.scalars["sigma_c_numeric"] = f(lx);
      }
    }
    r_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    return std::move(r_);
  }

 private:
  const Scene& s_;
  MakeLaw make_law_;
  std::vector<double> rates_;
  std::size_t k_ = 0;
  ModelResult r_;
  std::chrono::steady_clock::time_point wall0_;
};

/// One history: piecewise-constant v (drive.v from drive.v_times), steps of about time.dt (or
/// t_end/time.steps) aligned with the switch times; measured (t*, t^) and recorded like a 1-site bulk.
template <class Law>
class ImposedHistory {
 public:
  static constexpr std::int64_t progress_every = 1024;
  static constexpr bool checkpointable = false;
  ImposedHistory(const Scene& s, Law law, std::string model)
      : s_(s), law_(std::move(law)), tracker_(s.measure, {0.0}), recorder_(s, r_),
        contacts_due_(s.output.contact_every()), wall0_(std::chrono::steady_clock::now()) {
    r_.model = std::move(model);
    r_.x = {0.0};
    if constexpr (Law::hooks.ages) law_.track_ages(s.output.ages);
    record(s.drive.v[0]);
    start_segment();
  }
  bool done() const { return r_.status != RunStatus::complete || k_ >= s_.drive.v.size(); }
  double time() const { return t_; }
  const Law& law() const { return law_; }  ///< the site's state (the Python module's views, docs/python.md)
  double end() const { return s_.time.t_end; }
  void step() {
    const double v[1] = {s_.drive.v[k_]};
    const double t0 = t_;
    const bool yielded = law_.advance(dt_, v).any_yield;
    t_ = s_.drive.v_times[k_] + static_cast<double>(++j_) * dt_;
    tracker_.observe_step(t0, t_, yielded, std::abs(v[0]));
    record(v[0]);
    ++steps_;
    if (j_ == n_) {
      ++k_;
      start_segment();
    }
  }
  void interrupt() {
    r_.status = RunStatus::interrupted;
    r_.message = "stopped at t = " + std::to_string(t_);
  }
  ModelResult finish() {
    if constexpr (Law::hooks.contact_statistics) detail::store_contacts(law_, r_);
    r_.events = tracker_.finish(false);
    r_.scalars["steps"] = static_cast<double>(steps_);
    r_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    return std::move(r_);
  }

 private:
  // Segment k_: n_ steps of dt_ from its switch time to the next (or t_end); an empty segment ends the
  // history.
  void start_segment() {
    const auto& vs = s_.drive.v;
    const auto& ts = s_.drive.v_times;
    for (; k_ < vs.size(); ++k_) {
      const double t_seg_end = k_ + 1 < vs.size() ? std::min(ts[k_ + 1], s_.time.t_end) : s_.time.t_end;
      if (t_seg_end <= ts[k_]) {
        k_ = vs.size();
        return;
      }
      const double dt_target = s_.time.dt > 0 ? s_.time.dt : s_.time.t_end / s_.time.steps;
      const double segment_steps = std::ceil((t_seg_end - ts[k_]) / dt_target - 1e-9);
      if (!(segment_steps < 9.0e18))
        throw core::ParamError("time.dt", "gives more than 9e18 steps in one segment of drive.v");
      n_ = static_cast<std::int64_t>(segment_steps);
      dt_ = (t_seg_end - ts[k_]) / static_cast<double>(n_);
      j_ = 0;
      if (n_ > 0) return;
    }
  }
  void record(double v) {
    if constexpr (Law::hooks.contact_statistics)
      if (contacts_due_.due(t_)) law_.record_contacts(t_);
    const ImposedRateState<Law> now{law_, t_, v};
    recorder_.after_step(t_, t_, false, [&](double) { return now; }, tracker_, no_energy_);
  }

  const Scene& s_;
  Law law_;
  ModelResult r_;
  FrontTracker tracker_;
  Recorder recorder_;
  Cadence contacts_due_;
  std::chrono::steady_clock::time_point wall0_;
  const std::optional<core::EnergyBudget> no_energy_;
  std::size_t k_ = 0;  // segment
  std::int64_t j_ = 0, n_ = 0, steps_ = 0;
  double t_ = 0.0, dt_ = 0.0;
};

/// Imposed slip rate (0D): a sweep over v (friction law) or one piecewise-constant history v(t).
template <class Law, class MakeLaw>
ModelResult run_imposed_rate(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl) {
  if (s.drive.sweep_points > 0) {
    ImposedSweep<Law, MakeLaw> sweep(s, std::move(make_law), model);
    run_loop(sweep, ctl, model);
    return sweep.finish();
  }
  ImposedHistory<Law> history(s, make_law(std::size_t{1}), model);
  run_loop(history, ctl, model);
  return history.finish();
}

}  // namespace slipfront::compare
