#pragma once
// The interface-law contract (docs/model.md §1, §2): what every interface law provides and every
// stepper uses. The continuum FrictionLaw (continuum/friction_law.hpp) and the microcontact ensembles
// (discrete/: CountLaw, AgentLaw, NaiveAgentLaw) are implementations; the steppers (ExplicitSimulation,
// ImplicitSimulation, AdaptiveSimulation) are templates on the law, so no call is virtual.
//
//   InterfaceLaw   every law: the state per site (A, σ̄), its initial value, the exact or stochastic
//                  step with the slip rates frozen over it, and the linearisation an implicit step needs
//   SmoothLaw      a deterministic law written as rates: the adaptive integrator advances its state
//                  itself with the rates and their Jacobian (no stochastic step to freeze rates for)
//   LawHooks       what a law provides beyond the contract, declared by the law (`hooks`) and checked
//                  against its members at compile time: a declared hook that is missing or misspelt,
//                  or a hook present but not declared, is a compile error (check_hooks)
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/archive.hpp"
#include "core/contacts.hpp"
#include "core/exact_update.hpp"
#include "core/params.hpp"
#include "core/steady_sliding.hpp"

namespace slipfront::core {

/// Optional capabilities of an interface law; every law declares its own as
///   static constexpr core::LawHooks hooks{.ages = true, ...};
/// and the runner and the steppers use a hook only where it is declared (if constexpr on the flag).
struct LawHooks {
  /// Mean contact age (docs/model.md §7, output.ages): track_ages(bool), tracks_ages(), mean_age(out).
  bool ages = false;
  /// Ages on the adaptive integrator's dense output: advance_age(t0, t1, theta, sampler) after each
  /// accepted step, age_mass_at(i, t, sampler) inside it (needs `ages`).
  bool dense_ages = false;
  /// Contact statistics (docs/model.md §7.2): record_contacts(t) at the contact snapshots,
  /// observe_front(FrontClasses) at every tip sample, contact_tables() at the end.
  bool contact_statistics = false;
  /// The detachment hazard of an attached contact at a site state, detachment_hazard(SiteState): what
  /// the contact prediction (compare/contacts.hpp) integrates along the law's own fields.
  bool contact_hazard = false;
  /// The same per threshold class (the mean-field law, docs/model.md §2.2): prediction_classes() classes per
  /// site, attached_classes() their attached fractions [sites × classes], and class_rates(i, v, A, σ̄, n,
  /// hazard, total) the hazard and relaxation total of each class of site i for a step at slip rate v from
  /// the start-of-step state (A, σ̄, n) (compare/contacts.hpp: ContactPrediction with classes).
  bool class_hazards = false;
  /// Checkpoints (core/archive.hpp): serialize(ar) names the whole state, random streams included.
  bool checkpoints = false;
  /// The range of thresholds: yield_onset(), the contact stress below which no contact is overloaded (the
  /// weakest threshold), and yield_saturation(), the one above which every contact is (the strongest; equal at
  /// w = 0). The step-controlled integrator (core/leap.hpp) ends a step where a site that had no overloaded
  /// contact reaches the first (a located onset of yield), and keeps its steps short where the contact stress
  /// of a site whose contacts move is near the range (docs/numerics.md §9).
  bool yield_onset = false;
  /// Count noise: noise_contacts(), the number of contacts per site whose random attachments and detachments move
  /// the law's state (N: a site's contact stress τ then fluctuates by ~τ/√(N A)), or 0 where this instance of the law
  /// draws nothing (the count law with discrete.noise = false). A law without it is deterministic (the continuum,
  /// the mean-field law): the step-controlled integrator (core/leap.hpp) shortens the steps of a sliding site near
  /// its threshold only where a fluctuation can take it across (docs/numerics.md §9.4).
  bool count_noise = false;
  /// Its steady sliding (docs/model.md §1.4; the ensembles': their mean-field steady state, §2.2): steady_sliding(v),
  /// A, σ̄ and σ at slip rate v, and steady_velocity(σ), the slip rate on the strengthening branch at stress σ (NaN:
  /// none). The start of a homogeneous scene puts its nucleation patch in this state (compare/initial.hpp), and the
  /// run checks the rate behind a front against it (sigma_ss_at_v_behind); a law without it cannot start a patch.
  bool steady_state = false;
  /// Its steady front is the continuum's solved front (docs/fronts.md; the ensembles': their mean-field limit's, exact
  /// at w = 0, as steady_state): drive.start = "steady_front" puts each site in the front's A and σ̄
  /// (compare/initial.hpp). A law without it is refused there, naming drive.start, before the front is solved.
  bool steady_front = false;
  /// A prescribed normal load (docs/model.md §12): set_normal_load(factor), the resting area (p/p_0)^m of every site
  /// (the law reads its channel, interface.load_channel, from its parameters), and resting_area(i), the one site i was
  /// given (1 before any): what the adaptive integrators relax A towards (SiteState::rest; core/leap.hpp's onset). The
  /// run layer calls it once before the initial state (compare/initial.hpp) and only when some factor differs from 1; a
  /// law that was never given one is today's law, bit for bit. A scene with a profile refuses a model whose law lacks
  /// it (compare/scene.cpp).
  bool normal_load = false;
};

struct LawStepInfo {
  bool any_yield = false;  ///< some site had Θ = 1 (or an overloaded contact) at the start of the step
};

/// One site's state as the rates see it; `rest` is the site's resting area a = (p/p_0)^m under a normal load (docs/model.md
/// §12.1: the A equation relaxes towards it), 1 without one (the adaptive integrator fills it from the law's
/// resting_area(i), core::LawHooks::normal_load).
struct SiteState {
  double v, area, sigma_bar;
  double rest = 1.0;
};
/// d/dt of (A, σ̄) at one site.
struct SiteRate {
  double area, sigma_bar;
};
/// ∂(dA/dt, dσ̄/dt)/∂(v, A, σ̄) at one site with the yield state fixed; ∂(dA/dt)/∂σ̄ = 0 by the
/// structure of the contract (the area relaxes whatever the stress, once the yield state is known),
/// which is what lets the adaptive integrator eliminate (v, A, σ̄) node by node.
struct SiteJacobian {
  double area_v, area_area;
  double sigma_v, sigma_area, sigma_sigma;
};

/// A stand-in for the adaptive integrator's dense output (AdaptiveSimulation::DenseSampler), to check the
/// dense-age hooks' signatures: A and v of site i at time t inside the last step.
struct DenseSamplerArchetype {
  double area(double t, std::size_t i) const;
  double slip_rate(double t, std::size_t i) const;
};

// The members behind each hook of LawHooks.
template <class L>
concept HasAgeHooks = requires(L& law, const L& cl, std::span<double> out) {
  law.track_ages(true);
  { cl.tracks_ages() } -> std::same_as<bool>;
  cl.mean_age(out);
};
template <class L>
concept HasDenseAgeHooks = requires(L& law, const L& cl, std::span<const std::uint8_t> theta,
                                    const DenseSamplerArchetype& at) {
  law.advance_age(0.0, 0.0, theta, at);
  { cl.age_mass_at(std::size_t{0}, 0.0, at) } -> std::convertible_to<double>;
};
template <class L>
concept HasContactStatisticsHooks = requires(L& law, const L& cl, const FrontClasses& f) {
  law.record_contacts(0.0);
  law.observe_front(f);
  { cl.contact_tables() } -> std::same_as<ContactTables>;
};
template <class L>
concept HasContactHazard = requires(const L& cl, SiteState st) {
  { cl.detachment_hazard(st) } -> std::same_as<double>;
};
template <class L>
concept HasYieldOnset = requires(const L& cl) {
  { cl.yield_onset() } -> std::convertible_to<double>;
  { cl.yield_saturation() } -> std::convertible_to<double>;
};
template <class L>
concept HasCountNoise = requires(const L& cl) {
  { cl.noise_contacts() } -> std::convertible_to<double>;
};
template <class L>
concept HasSteadyState = requires(const L& cl, double v) {
  { cl.steady_sliding(v) } -> std::same_as<SteadyState>;
  { cl.steady_velocity(v) } -> std::convertible_to<double>;
};
template <class L>
concept HasNormalLoad = requires(L& law, const L& cl, std::span<const double> factor) {
  law.set_normal_load(factor);
  { cl.resting_area(std::size_t{0}) } -> std::convertible_to<double>;
};
template <class L>
concept HasClassHazards = requires(const L& cl, std::span<const double> n, std::span<double> out) {
  { cl.prediction_classes() } -> std::convertible_to<std::size_t>;
  { cl.attached_classes() } -> std::convertible_to<std::span<const double>>;
  cl.class_rates(std::size_t{0}, 0.0, 0.0, 0.0, n, out, out);
};

/// The law's declared hooks against its members: each declared hook must be there with its signature,
/// and each hook that is there must be declared (a hook the law has but does not declare would never be
/// called). A law without `hooks` is not an interface law.
template <class L>
consteval bool check_hooks() {
  constexpr LawHooks h = L::hooks;
  static_assert(h.ages == HasAgeHooks<L>,
                "LawHooks::ages must be declared exactly when the law has track_ages(bool), tracks_ages(), mean_age(span)");
  static_assert(h.dense_ages == HasDenseAgeHooks<L>,
                "LawHooks::dense_ages must be declared exactly when the law has advance_age(t0, t1, theta, sampler) and "
                "age_mass_at(i, t, sampler)");
  static_assert(!h.dense_ages || h.ages, "LawHooks::dense_ages needs LawHooks::ages");
  static_assert(h.contact_statistics == HasContactStatisticsHooks<L>,
                "LawHooks::contact_statistics must be declared exactly when the law has record_contacts(t), "
                "observe_front(FrontClasses) and contact_tables()");
  static_assert(h.contact_hazard == HasContactHazard<L>,
                "LawHooks::contact_hazard must be declared exactly when the law has detachment_hazard(SiteState)");
  static_assert(h.class_hazards == HasClassHazards<L>,
                "LawHooks::class_hazards must be declared exactly when the law has prediction_classes(), attached_classes() "
                "and class_rates(i, v, A, sigma_bar, n, hazard, total)");
  static_assert(h.yield_onset == HasYieldOnset<L>,
                "LawHooks::yield_onset must be declared exactly when the law has yield_onset() and yield_saturation()");
  static_assert(h.count_noise == HasCountNoise<L>,
                "LawHooks::count_noise must be declared exactly when the law has noise_contacts()");
  static_assert(h.steady_state == HasSteadyState<L>,
                "LawHooks::steady_state must be declared exactly when the law has steady_sliding(v) and steady_velocity(sigma)");
  static_assert(h.normal_load == HasNormalLoad<L>,
                "LawHooks::normal_load must be declared exactly when the law has set_normal_load(span) and resting_area(i)");
  static_assert(h.checkpoints == requires(L& law, Archive& ar) { law.serialize(ar); },
                "LawHooks::checkpoints must be declared exactly when the law has serialize(ar)");
  return true;
}

/// Every interface law.
///   size()                      number of sites
///   params()                    α, κ, η (η enters the contact-level stress |σ̄ + η v|/A and the bulk)
///   contact_area(), sigma_bar() A and σ̄ per site
///   set_site(i, A, σ̄)           initial state of site i
///   advance(dt, v)              A, σ̄: t → t + dt with the slip rates v frozen over the step (exact
///                               for the continuum law, the exact two-state chain for the ensembles)
///   linearisation(dt)           a function (i, w_i, c0_i&, c1_i&) of one site, for one step dt:
///                               σ̄_i(t + dt) ≈ c0_i + c1_i W_i, the stress the law's own update would
///                               give for a slip rate W_i frozen over the step, linear in W_i, with the
///                               yield state (Θ_i, or the overloaded fraction Y_i) and the relaxation
///                               rate frozen at the rate w_i of the previous step (linearise_stress).
///                               One site at a time, so that the implicit step computes it inside its
///                               elimination loop (the loop's chain of divisions then hides its cost);
///                               linearise() below gives every site at once.
template <class L>
concept InterfaceLaw = requires(L& law, const L& cl, std::size_t i, double a, double s, double dt,
                                std::span<const double> v, double& r) {
  { cl.size() } -> std::convertible_to<std::size_t>;
  { cl.params() } -> std::convertible_to<const InterfaceParams&>;
  { cl.contact_area() } -> std::convertible_to<std::span<const double>>;
  { cl.sigma_bar() } -> std::convertible_to<std::span<const double>>;
  law.set_site(i, a, s);
  { law.advance(dt, v) } -> std::same_as<LawStepInfo>;
  cl.linearisation(dt)(i, a, r, r);
  { L::hooks } -> std::convertible_to<LawHooks>;
} && check_hooks<L>();

/// Every site's linearisation (InterfaceLaw::linearisation) for a step dt at the rates w.
template <class L>
void linearise(const L& law, double dt, std::span<const double> w, std::span<double> c0, std::span<double> c1) {
  const auto lin = law.linearisation(dt);
  for (std::size_t i = 0; i < w.size(); ++i) lin(i, w[i], c0[i], c1[i]);
}

/// A deterministic law given by its rates (the continuum law; a test law with another detachment
/// rate): what the adaptive integrator needs besides InterfaceLaw.
///   fields()                    the state [A_0..A_{n−1} | σ̄_0..σ̄_{n−1}], contiguous and writable:
///                               the integrator advances it in place (no second copy anywhere)
///   sliding(st)                 the yield state Θ of a site (|σ̄ + η v|/A > 1)
///   load(st)                    |σ̄ + η v|: Θ flips where the load crosses the area A
///   rate(st, Θ), jacobian(st, Θ) the right-hand side and its Jacobian with Θ fixed
template <class L>
concept SmoothLaw = InterfaceLaw<L> && requires(L& law, const L& cl, SiteState st, bool sliding) {
  { law.fields() } -> std::same_as<std::span<double>>;
  { cl.sliding(st) } -> std::same_as<bool>;
  { cl.load(st) } -> std::convertible_to<double>;
  { cl.rate(st, sliding) } -> std::same_as<SiteRate>;
  { cl.jacobian(st, sliding) } -> std::same_as<SiteJacobian>;
};

/// The age mass M = A ā of one site (docs/model.md §7) over [t0, t1] with the yield state Θ fixed:
///   dM/dt = A(t) − Θ κ |v(t)| M,
/// A(t) = area(t) and v(t) = slip_rate(t) (the adaptive step's dense output; slip_rate is not called
/// when Θ = 0). The step is cut into s sub-intervals (s = 1 unless Θκ max|v| (t1 − t0) > 1, then s =
/// that rounded up, at most 16); on each, the exact update of the equation with frozen coefficients,
/// relax(M, Ā, r̄, δ), where Ā and r̄ = Θκ⟨|v|⟩ are the Simpson averages of A and Θκ|v| over the
/// sub-interval (samples at its ends and middle). Exact when A and |v| are constant; otherwise the
/// local error is O(δ³) (the frozen-coefficient exponential update of a linear equation with smooth
/// coefficients), so the age mass is second order in the step, the order of the dense output it reads
/// (tests/test_contact_age.cpp measures 2.0).
template <class Area, class SlipRate>
double integrate_age_mass(double m, double t0, double t1, bool theta, double kappa, const Area& area,
                          const SlipRate& slip_rate) {
  const double h = t1 - t0;
  if (!(h > 0.0)) return m;
  if (!theta) return m + h * (area(t0) + 4.0 * area(t0 + 0.5 * h) + area(t1)) / 6.0;  // Simpson: dM/dt = A
  double a_area = area(t0), a_speed = std::abs(slip_rate(t0));
  const double mid_speed = std::abs(slip_rate(t0 + 0.5 * h)), end_speed = std::abs(slip_rate(t1));
  const double r_max = kappa * h * std::max({a_speed, mid_speed, end_speed});
  const int sub = r_max > 1.0 ? static_cast<int>(std::min(16.0, std::ceil(r_max))) : 1;
  for (int j = 0; j < sub; ++j) {
    const double lo = t0 + h * j / sub, hi = j + 1 == sub ? t1 : t0 + h * (j + 1) / sub, c = 0.5 * (lo + hi);
    const double c_area = area(c), c_speed = sub == 1 ? mid_speed : std::abs(slip_rate(c));
    const double b_area = area(hi), b_speed = j + 1 == sub ? end_speed : std::abs(slip_rate(hi));
    const double mean_area = (a_area + 4.0 * c_area + b_area) / 6.0;
    const double rate = kappa * (a_speed + 4.0 * c_speed + b_speed) / 6.0;
    m = relax(m, mean_area, rate, hi - lo);
    a_area = b_area;
    a_speed = b_speed;
  }
  return m;
}

/// Constants of linearise_stress that depend on the step only (computed once per step).
struct StressStepConstants {
  double alpha, kappa, dt;
  double e1, w1;  ///< e^{−Δt} and (1 − e^{−Δt}): A' of a site with no overloaded contact
  StressStepConstants(const InterfaceParams& p, double step)
      : alpha(p.alpha), kappa(p.kappa), dt(step), e1(std::exp(-step)), w1(relax_weight(1.0, step)) {}
};

/// The implicit integrator's view of the stress update of docs/model.md §1–§2 at one site, shared by
/// every law: with the overloaded fraction y (Θ for the continuum law) and the rate |w| of the previous
/// step frozen, A' = relax(A, a_rest, 1 + y κ |w|, Δt) (a_rest: the site's resting area, 1 but under a normal
/// load, docs/model.md §12) and
///   σ̄' = σ̄ e^{−y|w|Δt} + α (A + A')/2 · W · (1 − e^{−y|w|Δt})/(y|w|)     = c0 + c1 W,
/// linear in the step's slip rate W (the source α Ā W is linear in W; y = 0: σ̄' = σ̄ + α Ā W Δt).
inline void linearise_stress(double area, double sigma_bar, double y, double w_prev, const StressStepConstants& k,
                             double& c0, double& c1, double rest = 1.0) {
  if (y == 0.0) {
    c0 = sigma_bar;
    c1 = k.alpha * 0.5 * (area + (area * k.e1 + rest * k.w1)) * k.dt;  // rest = 1: today's bits (1 · w = w)
    return;
  }
  const double speed = std::abs(w_prev), lam = y * speed;
  const double a_new = relax(area, rest, 1.0 + y * k.kappa * speed, k.dt);
  c0 = sigma_bar * std::exp(-lam * k.dt);
  c1 = k.alpha * 0.5 * (area + a_new) * relax_weight(lam, k.dt);
}

}  // namespace slipfront::core
