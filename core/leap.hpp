#pragma once
// Accuracy-chosen steps for the stochastic and mean-field interface laws (issue 22, docs/numerics.md §9):
// the implicit step of core/implicit.hpp (trapezoidal body, the law's stress linearised on the interface,
// the law's own exact or sampled update with the slip rates frozen over the step) with a step size chosen
// for each step by three tests, made on the trial solution before the law advances (so a rejected trial
// costs one solve and no random draw):
//   1. defect   the linearisation defect of the trial (ImplicitSimulation): the stress the law will give at
//               the step's own slip rates against the one the body was solved with. Above
//               time.implicit_tolerance the trial is first solved again with the law linearised at its own
//               rates (at most twice: a site at its threshold then has the yield state in the solve that the
//               law's own test will give it), and only then halved
//   2. leap     the leap condition (Cao, Gillespie & Petzold, J. Chem. Phys. 124, 044109, 2006): over a step the
//               rates of every site's two-state chain (attach 1, detach κ|v| for an overloaded contact) are
//               frozen, so the step keeps, with ε = time.leap_epsilon,
//                   κ |dv_i/dt| h ≤ ε (1 + κ|v_i|)     the detachment rate changes by a fraction ε at most
//                   h ≤ ε (τ_i ≤ s_0), h (1 + κ|v_i|) ≤ ε (τ_i > s_0), ε/4 at a sliding site that a count
//                                                      fluctuation can take below s_0 (kSlidingShare, kNoiseReach)
//                                                      unless the law watches it (its yield test at every count
//                                                      event: discrete::CountLaw::advance_watched)
//                                                      at a site whose contacts move (A < 1, or τ_i > s_0) and
//                                                      whose contact stress τ_i is within 20 % of the range of
//                                                      thresholds [s_0, s_1] (yield_onset, yield_saturation;
//                                                      one value at w = 0): the step is a fraction ε of the time in
//                                                      which its counts relax, so that a fluctuation that takes τ
//                                                      across the threshold and back (a site that re-sticks) is
//                                                      seen by the law's yield test
//               (dv/dt from the trial's W and the previous step's). A trial that breaks it by more than twice
//               is shortened; the next step is sized from it (and from the defect, which scales as h²)
//   3. onset    a site with no overloaded contact whose contact stress |σ̄ + ηW|/A' (the linearised σ̄' and
//               the attach-only A' at the step's end) passes the weakest threshold (core::LawHooks::
//               yield_onset) inside the trial ends the step there (linear interpolation of the stress over
//               the step, then re-solved; at least 1 % of the trial, so that a site hovering at its threshold
//               cannot stall the run), so that the law's own yield test sees the onset at the next step
// The tests are made in the order 2, 3, 1 (the cheap ones first: a trial they shorten does not pay for the
// defect's re-solves), and 2–3 again after a re-solve.
// Within a step the sampled counts are exact for the frozen rates (the two-state chain's transition
// probabilities; a law with a watched step — the count law at one threshold, fresh renewal — takes the accepted
// step of a site near its threshold event by event with the yield test after every event, docs/numerics.md §9.7),
// so the step error is that of freezing the rates (tests 2 and 3) and of the body's
// trapezoidal rule (test 1 and 2 on v); quiet stretches (no site moves its rates) grow the step by ×2 per
// step up to time.dt_max.
//
// Dense output (for the runner's measurements at exact times, compare/dynamic_run.hpp): over the last step
// u is linear (u = u^n + (t − t^n) W, the trapezoidal rule's own), v is the step's frozen W, and A, σ̄ are
// linear between the step's ends.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <concepts>
#include <vector>

#include "core/adaptive.hpp"
#include "core/implicit.hpp"

namespace slipfront::core {

/// Work counters of the step-controlled integrator.
struct LeapStats {
  std::int64_t accepted = 0;       ///< accepted steps (== steps())
  std::int64_t defect_halvings = 0;  ///< trials halved by the linearisation defect (test 1)
  std::int64_t leap_rejected = 0;  ///< trials shortened by the leap condition (test 2)
  std::int64_t located = 0;        ///< trials shortened to end at an onset of yield (test 3)
  std::int64_t relinearised = 0;   ///< trials solved again at their own rates (test 1)
  std::int64_t solves = 0;         ///< trial solves
  std::int64_t forced = 0;         ///< steps taken after kMaxTrials trials without passing every test
  template <class Ar>
  void serialize(Ar& ar) {
    ar(accepted, defect_halvings, leap_rejected, located, relinearised, solves, forced);
  }
};

template <InterfaceLaw Law, Body B = Bulk>
class LeapSimulation : public ImplicitSimulation<Law, B> {
  using Base = ImplicitSimulation<Law, B>;

 public:
  static constexpr const char* integrator_name = "leap";
  static constexpr bool error_control = true;
  /// The law advances in steps with frozen rates, one per accepted step (as the fixed-step integrators): what
  /// a contact prediction along the fields needs (compare/dynamic_run.hpp).
  static constexpr bool frozen_rate_steps = true;
  /// A trial is shortened when it breaks the leap condition by more than this factor.
  static constexpr double kLeapReject = 2.0;
  /// Growth and shrink limits of the proposed next step, and the safety factor.
  static constexpr double kGrowMax = 2.0, kShrinkMin = 0.2, kSafety = 0.9;
  /// At most this many trials per step (then the last one is taken and counted in LeapStats::forced).
  static constexpr int kMaxTrials = 40;
  /// The band of contact stress about the range of thresholds, relative to its ends, in which a site whose contacts move
  /// keeps the step a fraction ε of its relaxation time (leap_ratio).
  static constexpr double kBand = 0.2;
  /// A sliding site in that band (τ > s_0) keeps the step this share of ε of its relaxation time where the law tests
  /// its yield state only at a step's start: the re-sticking of a sliding site (a count fluctuation taking τ below s_0,
  /// random, so not located) is then seen only at the next step's, its contacts detaching until then. At ε (share 1)
  /// that made fig1's late-mode t^ at N = 10³ late by 3.5 ± 0.7 against the explicit reference (288 runs); at ε/4 by
  /// 0.3 ± 0.5 and 1.3 ± 0.6 on two sets of 288 seeds (docs/numerics.md §9.4). A site the law watches (watched(): the
  /// count law at one threshold with fresh renewal, within the noise reach and its event cap, discrete::CountLaw::
  /// watches) keeps share 1: its yield test is made at every count event of the step, which removes that delay and
  /// the early-transient excess the share left (docs/numerics.md §9.6, §9.7; tests/test_slow_leap.cpp). Binned or
  /// quenched thresholds, the agent law, a normal load and a site past the event cap keep this share.
  static constexpr double kSlidingShare = 0.25;
  /// ... only where a count fluctuation can reach the threshold (core::LawHooks::count_noise): τ_i − s_0 ≤ kNoiseReach
  /// τ_i / √(N A_i), a site's stress fluctuating by ~τ/√(N A) over its relaxation time (N A attached contacts), of
  /// which a step is at most a fraction ε. A deterministic law (the continuum, mean-field, the count law with the noise
  /// off) has no such crossing and keeps ε at its sliding sites; so does a law with no threshold (no yield_onset).
  static constexpr double kNoiseReach = 4.0;
  /// A located step is at least this fraction of the step the leap condition and the defect allow (not of a
  /// trial already shortened by a location, which would let the floor shrink with it): a site whose contact stress hovers at the threshold
  /// (its rise in σ̄ balanced by a fall of η W) cannot shrink the steps without end; its onset is then late by
  /// at most this fraction of a step.
  static constexpr double kLocateFloor = 0.01;
  /// Before a trial with too large a defect is halved, it is solved again up to this many times with the law
  /// linearised at the trial's own slip rates: where a site's yield state differs between the previous step's
  /// rate and the trial's (a site at its threshold), the yield state of the solve then agrees with the law's.
  static constexpr int kRelinearise = 2;

  LeapSimulation(B bulk, Law law, const AdaptiveOptions& opt)
      : Base(std::move(bulk), std::move(law), opt.dt_initial), opt_(opt), h_next_(opt.dt_initial),
        u0_(this->n_), a0_(this->sites_), s0_(this->sites_), w_prev_(this->sites_), w_lin_(this->sites_) {
    this->set_error_control(opt.defect_tolerance, 0);
  }

  /// No step crosses t (a scene's t_end): the step that would is shortened to end on it.
  void set_stop_time(double t) { t_stop_ = t; }
  double previous_time() const { return t_prev_; }
  double dt() const { return h_last_ > 0.0 ? h_last_ : h_next_; }  ///< the last accepted step
  const LeapStats& stats() const { return stats_; }

  /// Dense output of one field at t ∈ [previous_time(), time()] (see the header).
  void dense_state(double t, Field f, std::span<double> out) const {
    const std::size_t n = std::min(out.size(), f == Field::slip || f == Field::slip_rate ? this->n_ : this->sites_);
    for (std::size_t i = 0; i < n; ++i) out[i] = dense_value(t, f, i);
  }
  double dense_value(double t, Field f, std::size_t i) const {
    switch (f) {
      case Field::slip:
        return stats_.accepted == 0 ? this->u_[i] : u0_[i] + std::clamp(t - t_prev_, 0.0, h_last_) * this->v_[i];
      case Field::slip_rate: return this->v_[i];
      case Field::contact_area: return lerp(a0_[i], this->law_.contact_area()[i], t);
      case Field::sigma_bar: return lerp(s0_[i], this->law_.sigma_bar()[i], t);
    }
    return 0.0;
  }

  /// Bound on |target − y_i(t)| over the whole last step: every field's dense output is linear in t (slip:
  /// u0 + (t − t_prev) v; A and σ̄: lerp), so its distance from target is largest at an end of the step; the
  /// margin covers the rounding of the interpolation (a few ulps of the larger end). Cheaper and tighter than
  /// sampling the output three times (compare::tip_nodes scans every node ahead of the front at every step).
  double dense_deviation_bound(Field f, std::size_t i, double target) const {
    const double y0 = dense_value(t_prev_, f, i), y1 = dense_value(this->t_, f, i);
    constexpr double eps = std::numeric_limits<double>::epsilon();
    return std::max(std::abs(target - y0), std::abs(target - y1)) +
           4.0 * eps * (std::abs(target) + std::max(std::abs(y0), std::abs(y1)));
  }

  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("leap");
    Base::serialize(ar);
    ar(t_prev_, h_next_, h_last_, t_stop_, u0_, a0_, s0_, w_prev_, stats_);
  }

  // One accepted step: trials from the proposed size through tests 1–3 (the header), then the step is taken
  // as an implicit step (u, V from W, the law's own update) and the next size is proposed from the leap ratio.
  // The cheap tests (2, 3: one pass over the sites each) are made on every trial before the defect's re-solves
  // (test 1), which a trial that is shortened anyway would waste, and again after a re-solve (its W differs).
  void step() {
    this->start_energy();
    const double t = this->t_;
    double h = std::min(h_next_, opt_.dt_max);
    if (t_stop_ > t && h >= t_stop_ - t) h = t_stop_ - t;
    double h_wanted = h, ratio = 0.0, defect = 0.0;
    std::copy(this->v_.begin(), this->v_.begin() + static_cast<std::ptrdiff_t>(this->sites_), w_prev_.begin());
    // Tests 2 and 3 on the trial in trial_: false (and h shortened) when it fails one of them.
    const auto leap_and_onset = [&] {
      ratio = leap_ratio(h);  // 2. leap
      if (ratio > kLeapReject) {
        ++stats_.leap_rejected;
        h *= std::max(kShrinkMin, kSafety / ratio);
        h_wanted = h;
        return false;
      }
      if constexpr (Law::hooks.yield_onset) {  // 3. onset
        const double frac = first_onset(h);
        const double h_loc = std::max(kLocateFloor * h_wanted, h * frac * (1.0 + 1e-6));
        if (frac < 1.0 && h_loc < h * (1.0 - 1e-3)) {
          ++stats_.located;
          h = h_loc;
          return false;
        }
      }
      return true;
    };
    for (int trial = 1;; ++trial) {
      if (h < opt_.dt_min)  // as the adaptive integrator: a failure, not a step taken on a test it failed
        throw NumericalError(stats_.accepted, t, 0, "leap step below dt_min (" + format_number(h) + ")");
      this->solve_trial(t, h);
      ++stats_.solves;
      if (trial == kMaxTrials) {
        ++stats_.forced;
        break;
      }
      if (!leap_and_onset()) continue;
      if (this->tol_ > 0.0) {  // 1. defect
        defect = this->linearisation_defect(h);
        int resolved = 0;
        for (; resolved < kRelinearise && defect > this->tol_; ++resolved) {  // linearised again at the trial's own W
          resolve_at_trial(t, h);
          defect = this->linearisation_defect(h);
        }
        if (defect > this->tol_) {
          ++stats_.defect_halvings;
          h *= 0.5;
          h_wanted = h;
          continue;
        }
        if (resolved > 0 && !leap_and_onset()) continue;
        this->max_defect_ = std::max(this->max_defect_, defect);
      }
      break;
    }
    take(t, h);
    // the next size: the leap ratio scales as h, the defect as h² (a change of the rates over the step, times h)
    double grow = ratio > 0.0 ? kSafety / ratio : kGrowMax;
    if (defect > 0.0) grow = std::min(grow, kSafety * std::sqrt(this->tol_ / defect));
    h_next_ = h_wanted * std::clamp(grow, kShrinkMin, kGrowMax);
  }

 private:
  double lerp(double a, double b, double t) const {
    if (stats_.accepted == 0 || !(h_last_ > 0.0)) return b;
    const double th = std::clamp((t - t_prev_) / h_last_, 0.0, 1.0);
    return a + th * (b - a);
  }

  // The leap condition's ratio for the trial W (in trial_), the largest over the sites of two ratios to ε:
  //   rates   κ |dv_i/dt| h / (1 + κ|W_i|), dv/dt from W and the previous step's rate over the mean of the two
  //           steps' lengths: the change of the detachment rate over the step, relative to the site's rates
  //   state   h (1 + κ|W_i| [τ_i > s_0]) (over kSlidingShare where a count fluctuation can take a sliding site's τ_i
  //           below s_0 and the law does not watch the site) at a site whose contacts move (A_i < 1, or τ_i > s_0)
  //           and whose contact stress τ_i = |σ̄_i + ηW_i|/A_i lies in the threshold range widened by kBand, (1 − kBand) s_0 ≤ τ_i ≤
  //           (1 + kBand) s_1 (s_0, s_1 the weakest and strongest thresholds): the step is a small
  //           part of the time in which the site's counts relax, so that a fluctuation that takes τ across a
  //           threshold and back (a site that re-sticks, or yields again) is seen by the law's yield test, as it
  //           is at the small steps of the reference scheme
  double leap_ratio(double h) const {
    const double kappa = this->law_.params().kappa, eta = this->law_.params().eta;
    const double span = h_last_ > 0.0 ? 0.5 * (h + h_last_) : h, scale = kappa * h / span;
    double s0 = 0.0, s1 = std::numeric_limits<double>::infinity();
    if constexpr (Law::hooks.yield_onset) {
      s0 = this->law_.yield_onset();
      s1 = this->law_.yield_saturation();
    }
    const double reach = noise_reach();
    const auto area = this->law_.contact_area(), sb = this->law_.sigma_bar();
    double r = 0.0;
    for (std::size_t i = 0; i < this->sites_; ++i) {
      const double w = this->trial_[i], speed = kappa * std::abs(w);
      r = std::max(r, scale * std::abs(w - w_prev_[i]) / (1.0 + speed));
      const double tau = contact_stress(sb[i] + eta * w, area[i]);
      if ((area[i] < 1.0 || tau > s0) && tau >= (1.0 - kBand) * s0 && tau <= (1.0 + kBand) * s1) {
        // false for reach = 0 (τ > s_0 here); a site the law watches (its yield test at every count event) needs no share
        const bool shared = tau - s0 <= reach * tau / std::sqrt(area[i]) && !watched(i, w, h);
        r = std::max(r, tau > s0 ? h * (1.0 + speed) / (shared ? kSlidingShare : 1.0) : h);
      }
    }
    return std::isfinite(r) ? r / opt_.leap_epsilon : std::numeric_limits<double>::infinity();
  }

  // A law with a watched step (discrete::CountLaw::advance_watched: the yield test at every count event of a site near
  // its threshold) takes its accepted steps by it; watched(i, w, h) says whether it watches site i over a step of h
  // at the rate w (then the site keeps ε unshared: its re-sticking is seen when it happens, not at the next step).
  static constexpr bool kWatchedLaw = requires(Law& law, std::span<const double> v) {
    { law.advance_watched(1.0, v, 1.0) } -> std::same_as<LawStepInfo>;
    { std::as_const(law).watches(std::size_t{0}, 1.0, 1.0, 1.0) } -> std::same_as<bool>;
  };
  bool watched(std::size_t i, double w, double h) const {
    if constexpr (kWatchedLaw) return this->law_.watches(i, w, h, kNoiseReach);
    else return false;
  }

  // kNoiseReach / √N of a law with count noise (τ_i − s_0 ≤ this τ_i / √A_i is within reach of a fluctuation); 0 for a
  // deterministic law or instance; +∞ for a noisy law with no threshold range (every sliding site counts as near).
  double noise_reach() const {
    if constexpr (Law::hooks.count_noise) {
      const double n = this->law_.noise_contacts();
      if (!(n > 0.0)) return 0.0;
      if constexpr (!Law::hooks.yield_onset) return std::numeric_limits<double>::infinity();
      return kNoiseReach / std::sqrt(n);
    } else {
      return 0.0;
    }
  }

  // The trial again, the law linearised at the trial's W (in trial_), which is also the iteration's first guess.
  void resolve_at_trial(double t, double h) {
    std::copy(this->trial_.begin(), this->trial_.begin() + static_cast<std::ptrdiff_t>(this->sites_), w_lin_.begin());
    this->bulk_.implicit_solve(this->law_.linearisation(h), std::span<const double>(w_lin_), this->c0_, this->c1_, t, h,
                               this->law_.params().eta, this->displacement(), this->V_, this->law_.sigma_bar(),
                               this->trial_);
    ++stats_.solves;
    ++stats_.relinearised;
  }

  // Test 3: the earliest fraction of the trial at which a site with no overloaded contact reaches the
  // weakest threshold s_0 (1: none). Its contact stress at the step's start, |σ̄ + ηW|/A, and at its end,
  // |c0 + c1 W + ηW|/A' with A' = relax(A, a, 1, h) (attach only; a the site's resting area under a normal load,
  // docs/model.md §12.2, either channel; 1 without, today's bits: 1 · w = w), interpolated linearly.
  double first_onset(double h) const {
    const double s0 = this->law_.yield_onset(), eta = this->law_.params().eta;
    const auto area = this->law_.contact_area(), sb = this->law_.sigma_bar();
    const double e = std::exp(-h), w1 = relax_weight(1.0, h);
    double frac = 1.0;
    for (std::size_t i = 0; i < this->sites_; ++i) {
      const double w = this->trial_[i], a = area[i];
      const double start = contact_stress(sb[i] + eta * w, a);
      if (!(start <= s0)) continue;  // already overloaded (or no contact attached)
      const double end = contact_stress(this->c0_[i] + this->c1_[i] * w + eta * w, a * e + resting(i) * w1);
      if (end > s0) frac = std::min(frac, (s0 - start) / (end - start));
    }
    return frac;
  }

  // The resting area of site i (docs/model.md §12: a normal load's (p/p_0)^m; 1 without one).
  double resting(std::size_t i) const {
    if constexpr (Law::hooks.normal_load) return this->law_.resting_area(i);
    else return 1.0;
  }

  // The step [t, t + h] with the trial's W: remember the start for the dense output, then taken as an implicit
  // (sub)step (ImplicitSimulation::accept_trial).
  void take(double t, double h) {
    t_prev_ = t;
    std::copy(this->u_.begin(), this->u_.end(), u0_.begin());
    const auto area = this->law_.contact_area(), sb = this->law_.sigma_bar();
    std::copy(area.begin(), area.end(), a0_.begin());
    std::copy(sb.begin(), sb.end(), s0_.begin());
    this->yielded_any_ = false;
    this->vmax_step_ = 0.0;
    const double t_end = (t_stop_ > t && h == t_stop_ - t) ? t_stop_ : t + h;
    if constexpr (kWatchedLaw) {  // ImplicitSimulation::accept_trial with the law's watched step
      ++this->substeps_;
      const double edge0 = this->bulk_.edge_slip(this->displacement());
      this->commit(h);
      if (this->energy_) this->work_over_step(t, h, edge0);
      this->yielded_any_ |= this->law_.advance_watched(h, this->slip_rate(), kNoiseReach).any_yield;
      if (this->energy_) this->mechanical_now(t_end);
    } else {
      this->accept_trial(t, h, t_end);
    }
    this->t_ = t_end;
    ++this->steps_;
    ++stats_.accepted;
    h_last_ = h;
    this->yielded_ = this->yielded_any_;
    this->max_v_ = this->vmax_step_;
    if (!std::isfinite(this->max_v_)) this->report_non_finite();
  }

  AdaptiveOptions opt_;
  double t_prev_ = 0.0, h_next_, h_last_ = 0.0, t_stop_ = -1.0;
  std::vector<double> u0_, a0_, s0_;  ///< u, A, σ̄ at the last step's start (dense output)
  std::vector<double> w_prev_;        ///< the slip rates of the previous step (leap condition)
  std::vector<double> w_lin_;         ///< the rates a re-solved trial is linearised at
  LeapStats stats_;
};

}  // namespace slipfront::core
