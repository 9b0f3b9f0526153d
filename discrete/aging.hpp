#pragma once
// Contact aging in the mean-field limit (docs/model.md §11): the age cohorts of one threshold class, and the closed
// forms of the age-structured balance with w = 0 that the tests and the scene check against.
//
// A contact of age a has area 1 + b ln(1 + a/τ_a) (core::InterfaceParams::aged_area). In the N → ∞ limit a class's
// attached contacts are an age density n(a, t) transported at unit speed in age and removed at the class's
// detachment rate d, fed at age 0 by the attachments (docs/model.md §11.3):
//     ∂t n + ∂a n = −d n,    n(0, t) = the attachment flux.
// With d and the flux frozen over a step (as the mean-field law freezes them) this is solved exactly along its
// characteristics: every cohort ages by Δt and keeps the fraction e^{−dΔt}; the contacts attached during the step
// that survive it (the step's exact count increment, n' − n e^{−dΔt}) form a new cohort at the mid-step age Δt/2.
// Cohorts are merged while the ages a merged cohort spans stay within a relative width ε of τ_a + a (the scale on
// which ln(1 + a/τ_a) bends), so a class holds O(ln(1 + t/τ_a)/ε) cohorts; merging keeps the mass and the mean age
// exactly and changes the area by at most b ε²/8 per unit mass (the curvature of ln(τ_a + a) over the span).
//
// The cost (docs/model.md §11.3): a class holds hundreds of cohorts, and the area needs ln(1 + a/τ_a) of each at every
// step. Each cohort keeps that logarithm, advanced over a step by ln(1 + Δt/(τ_a + a)) (exact: the ages only shift)
// evaluated as its Taylor polynomial x − x²/2 + x³/3 − x⁴/4 while x = Δt/(τ_a + a) ≤ cached_log_series_max (error
// ≤ x⁵/5 a step, ≤ x⁵/5 + x⁴/20 over a cohort's life), with std::log1p above; a new or merged cohort's logarithm is
// computed afresh. One std::log1p per new or merged cohort instead of one per cohort.
#include <cstddef>
#include <vector>

#include "core/params.hpp"

namespace slipfront::discrete {

/// The relative age span ε within which cohorts merge (docs/model.md §11.3: area error ≤ b ε²/8).
inline constexpr double cohort_merge_width = 0.01;
/// The largest Δt/(τ_a + a) whose step of a cohort's logarithm is the Taylor polynomial (above: std::log1p); a
/// cohort's logarithm is then within (1/64)⁵/5 + (1/64)⁴/20 = 3.2e-9 of ln(1 + a/τ_a) over its life, plus the
/// rounding of its steps (docs/model.md §11.3).
inline constexpr double cached_log_series_max = 1.0 / 64.0;

/// The attached contacts of one threshold class of one site, by age.
class AgeCohorts {
 public:
  struct Cohort {
    double mass;    ///< attached fraction of the site's contacts
    double age;     ///< mean age (mass-weighted)
    double lo, hi;  ///< the ages the cohort spans
    double log;     ///< ln(1 + age/τ_a), kept by step() (header comment)
  };
  /// All attached contacts new (age 0).
  void reset(double mass) {
    cohorts_.clear();
    if (mass > 0.0) cohorts_.push_back({mass, 0.0, 0.0, 0.0, 0.0});
  }
  /// One step of length dt: every cohort keeps `survive` of its mass and ages by dt; `fresh` (the contacts attached
  /// during the step that survive it) joins at age dt/2; then merge. Keeps each cohort's logarithm.
  void step(double dt, double survive, double fresh, double tau) { advance<true>(dt, survive, fresh, tau); }
  /// Σ mass (1 + b ln(1 + age/τ_a)), from the cohorts' kept logarithms (τ_a the one step() was given).
  double area(const core::InterfaceParams& p) const;

  /// The path before the kept logarithms (bench/bench_aging.cpp, tests/test_aging.cpp): step_recomputing() moves the
  /// same masses and ages as step() but keeps no logarithm, area_recomputed() takes std::log1p of every cohort's age.
  /// A set of cohorts is stepped by one of the two only.
  void step_recomputing(double dt, double survive, double fresh, double tau) {
    advance<false>(dt, survive, fresh, tau);
  }
  double area_recomputed(const core::InterfaceParams& p) const;
  double mass() const;
  std::size_t size() const { return cohorts_.size(); }
  const std::vector<Cohort>& cohorts() const { return cohorts_; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar(cohorts_);
  }

 private:
  template <bool keep_logs>
  void advance(double dt, double survive, double fresh, double tau);

  std::vector<Cohort> cohorts_;  ///< oldest first
};

/// E[ln(1 + a/τ)] for a ~ Exp(λ): e^{λτ} E_1(λτ) (docs/model.md §11.1).
double mean_log_age_exponential(double lambda, double tau);
/// The age-structured balance's steady area at slip rate v (w = 0, sliding): attached fraction 1/(1 + κ|v|), ages
/// ~ Exp(κ|v|): A_ss = (1 + b e^{x} E_1(x)) / (1 + κ|v|), x = κ|v|τ_a (docs/model.md §11.1).
double aged_steady_area(const core::InterfaceParams& p, double v);
/// Its steady friction σ_ss = α A_ss + η v (the contact-level stress α + ηv/A_ss > 1: sliding).
double aged_steady_sigma(const core::InterfaceParams& p, double v);
/// At rest (no detachment) from an attached fraction φ0 of age 0 at t = 0, detached contacts attaching at unit rate:
/// the expected area at t (docs/model.md §11.1),
///   φ0 (1 + b ln(1 + t/τ)) + (1 − φ0) [1 − e^{−t} + b (ln(1 + t/τ) − e^{−(t+τ)} (Ei(t + τ) − Ei(τ)))].
double aged_rest_area(const core::InterfaceParams& p, double phi0, double t);
/// At rest for t after steady sliding at v (w = 0): the survivors φ0 = 1/(1 + κ|v|) keep their Exp(κ|v|) ages shifted
/// by t, E[ln(1 + (a + t)/τ)] = ln(1 + t/τ) + e^{y} E_1(y), y = κ|v|(τ + t); the detached attach as in aged_rest_area
/// (docs/model.md §11.1): the area at the end of a hold of a slide-hold-slide.
double aged_hold_area(const core::InterfaceParams& p, double v, double t);

}  // namespace slipfront::discrete
