#pragma once
// The microcontact ensemble of docs/model.md §2 in the COUNT representation, as an interface law with the
// step contract core::InterfaceLaw (size, contact_area, sigma_bar, set_site, advance,
// params): the bulk stepper and the scene runner take it unchanged (docs/discrete.md).
//
// State of site i: the attached counts n_{i,b} per threshold bin b (B quantile bins of g with
// probability 1/B each, bin b represented by its conditional mean threshold s_b, ascending; B = 1
// when g is degenerate), and the detached count (one pool per site with renewal = fresh, since a
// detached contact gets a fresh threshold; per bin with renewal = quenched). A_i = n_i / N.
//
// One step [t, t + Δt] with v_i frozen (docs/model.md §2), at every site:
//   1. load        τ_i = |σ̄_i + η v_i| / A_i;  bin b is overloaded when τ_i > s_b (a prefix of bins)
//   2. idle?       no overloaded attached contact that slips and no detached contact: nothing moves,
//                  no random draw, no exponential (the stuck majority of a front costs a few flops)
//   3. contacts    exact two-state transition per bin (a = 1, d = κ|v_i| if overloaded else 0):
//                  binomial draws from the site's own stream; noise off: their expectations, as
//                  fractions of the site, evaluated with relax() at every site (no idle skip). Fresh
//                  renewal, B > 1, noise on: at k = 0 or k = B the attaching contacts stay unspread (one
//                  count per site, one class), spread over the bins at the first step with 0 < k < B
//                  (exact: docs/discrete.md, "Unspread arrivals")
//   4. stress      σ̄_i' = relax(σ̄_i, α Ā_i v_i, Y_i |v_i|, Δt),  Ā = (A + A')/2,
//                  Y_i = overloaded fraction of the attached contacts at t (1 when none attached)
// The step-controlled integrator (core/leap.hpp) takes its accepted steps by advance_watched: at one threshold, fresh
// renewal, noise on and no normal load, a site whose τ is within a count fluctuation of s_0 takes stages 2–4 event by
// event instead (Gillespie's direct method, the yield test after every event, docs/discrete.md "The watched step",
// docs/numerics.md §9.7); every other site, and every site under advance(), takes the step above.
// With w = 0 and noise off this is, operation for operation, FrictionLaw::advance (docs/model.md §2 item 1):
// the two laws agree bit for bit (tests/test_discrete_identity.cpp).
//
// Under a prescribed normal load (docs/model.md §12, set_normal_load) with resting area a_i = (p_i/p_0)^m:
//   re-attachment channel  a detached contact attaches at rate a_i, an attached one detaches at rate 1 − a_i (+ κ|v|
//                          when overloaded): the mean relaxes towards a_i at unit rate; needs a_i ≤ 1 (p ≤ p_0)
//   instantaneous channel  the chain is today's; every contact of site i has area a_i: A_i = a_i n_i/N
// A law never given a load takes neither branch (today's bits).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "discrete/binomial.hpp"
#include "discrete/params.hpp"
#include "discrete/streams.hpp"
#include "discrete/thresholds.hpp"

namespace slipfront::discrete {

namespace detail {
class SitePool;  // worker threads over sites (DiscreteParams::threads > 1)
/// Owns the workers; a copy starts without them (they are made at the copy's first step).
struct PoolHandle {
  std::unique_ptr<SitePool> p;
  PoolHandle();
  ~PoolHandle();
  PoolHandle(const PoolHandle&);
  PoolHandle& operator=(const PoolHandle&);
  PoolHandle(PoolHandle&&) noexcept;
  PoolHandle& operator=(PoolHandle&&) noexcept;
};
}  // namespace detail

// core::LawHooks::steady_state: its mean-field steady state with every threshold overloaded (docs/model.md §2.2), the
// closed form of core/steady_sliding.hpp: exact at w = 0 and while the thresholds lie below the steady contact stress.
class CountLaw : public core::OverloadedSteadyState<CountLaw> {
 public:
  static constexpr core::LawHooks hooks{.checkpoints = true, .yield_onset = true, .count_noise = true,
                                        .steady_state = true, .steady_front = true, .normal_load = true};
  /// Validates `dp` (ParamError naming the key). All sites start stuck: A = 1, σ̄ = 0, the N
  /// attached contacts spread over the bins by expectation rounding (a stratified sample of g).
  CountLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites);
  ~CountLaw();
  CountLaw(CountLaw&&) noexcept;
  CountLaw& operator=(CountLaw&&) noexcept;
  CountLaw(const CountLaw&);  ///< copies the state and the engines; the copy starts its own threads
  CountLaw& operator=(const CountLaw&);

  // --- the step contract (core::InterfaceLaw) -------------------------------------------
  std::size_t size() const { return area_.size(); }
  const core::InterfaceParams& params() const { return ip_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }

  /// Initial state of site i: n = round(A N) attached contacts (noise off: A N, a real count),
  /// spread over the bins by expectation rounding (no random draw); the rest detached. A ∈ [0, 1].
  void set_site(std::size_t i, double area, double sigma_bar);

  /// The resting area a_i = (p_i/p_0)^m of every site (docs/model.md §12; the channel from interface.load_channel).
  /// Re-attachment: the rates above (ParamError naming interface.load_p where a_i > 1: the site's N contacts are
  /// its capacity at p_0); instantaneous: each contact's area becomes a_i, so A and σ̄ scale by a_new/a_old at once.
  void set_normal_load(std::span<const double> factor);
  /// a_i (1 without a normal load).
  double resting_area(std::size_t i) const { return rest_.empty() ? 1.0 : rest_[i]; }

  /// docs/model.md §2 over [t, t + dt] with the slip rates v frozen; any_yield: some site had an
  /// overloaded attached contact (or no attached contact at all, τ = ∞: Θ = 1 of docs/model.md §1) and
  /// v_i ≠ 0 at the start of the step.
  core::LawStepInfo advance(double dt, std::span<const double> v);

  /// The implicit step's linearisation (core/law.hpp), one site at a time: y = Y_i, the overloaded
  /// fraction of the attached contacts at the previous step's rate (0 below the weakest threshold: no
  /// call there).
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(ip_, dt), s_min = thresholds_.front()](
               std::size_t i, double wp, double& c0, double& c1) {
      const double a = area_[i], sb = sigma_bar_[i];
      double y = 0.0;
      if (wp != 0.0 && core::contact_stress(sb + ip_.eta * wp, a) > s_min) y = overloaded_fraction(i, wp);
      core::linearise_stress(a, sb, y, wp, k, c0, c1, resting_area(i));
    };
  }

  // --- the watched step (core/leap.hpp; docs/numerics.md §9.7) ------------------------------------
  /// The count events a watched site's step may take at most: a site is watched only while N (1 + κ|v|) dt, a bound
  /// on its expected events over the step (attach ≤ N, detach ≤ κ|v| N), stays within it. At the leap's default
  /// ε = 0.2 a sliding site's step keeps (1 + κ|v|) dt ≤ ε, so every site near s_0 is watched up to N ≈ 2·10⁴; at
  /// N = 10⁵ a watched site would draw ~2·10⁴ events a step (~10⁵ per unit time, each an exponential and a uniform),
  /// where the binomial step at the leap's ε/4 share costs a few draws a step: there the site keeps the binomial step.
  static constexpr double kWatchCap = 4096.0;
  /// Whether advance_watched(dt, v, reach) watches site i at slip rate v (the leap integrator's share, core/leap.hpp):
  /// a law with one threshold s_0 (w = 0 or bins = 1), fresh renewal, the noise on and no normal load; some contact
  /// attached, its contact stress τ within a count fluctuation of s_0, |τ − s_0| ≤ reach τ/√(N A) (reach: the leap's
  /// kNoiseReach), and N (1 + κ|v|) dt ≤ kWatchCap. From the state at the step's start: the same answer before and
  /// during advance_watched.
  bool watches(std::size_t i, double v, double dt, double reach) const;
  /// advance(dt, v) with the sites that watches(i, v[i], dt, reach) names stepped event by event (Gillespie's direct
  /// method: waiting times at the total rate (N − n) + κ|v| n [τ > s_0], the yield test after every event, σ̄ relaxed
  /// exactly between events with A fixed, v frozen): the two-state chain of docs/model.md §2 with its yield state
  /// watched continuously, not only at the step's start. Every other site takes advance()'s step. any_yield: some
  /// site had an overloaded attached contact (or none attached) with v ≠ 0 at the step's start, or, at a watched
  /// site, at some event of the step.
  core::LawStepInfo advance_watched(double dt, std::span<const double> v, double reach);

  /// The weakest threshold s_0: below it no contact is overloaded (core::LawHooks::yield_onset).
  double yield_onset() const { return thresholds_.front(); }
  /// The strongest threshold s_{B−1}: above it every contact is overloaded.
  double yield_saturation() const { return thresholds_.back(); }
  /// N, whose random draws move the state; 0 with the noise off (every draw its expectation: a deterministic law;
  /// core::LawHooks::count_noise).
  double noise_contacts() const { return noise_ ? n_contacts_ : 0.0; }

  // --- inspection ------------------------------------------------------------------------------
  const DiscreteParams& discrete_params() const { return dp_; }
  const ThresholdDistribution& distribution() const { return g_; }
  std::size_t bins() const { return thresholds_.size(); }
  /// Representative threshold s_b of each bin (conditional mean of g on its quantile interval).
  std::span<const double> thresholds() const { return thresholds_; }
  double contacts_per_site() const { return n_contacts_; }
  /// Attached counts of site i per bin [B] (noise off: expected counts as fractions of the site's N). With noise
  /// on and fresh renewal this first settles the site's unspread arrivals (settle below): a read draws from the
  /// site's stream, so reading per-bin counts mid-run changes the run's random stream (not its law).
  std::span<const double> attached(std::size_t i) const;
  /// Attached contacts of site i not yet spread over the bins (noise on, fresh renewal, B > 1; else 0): they joined
  /// while every bin shared one fate (none overloaded, or all), so their bins did not matter yet.
  double unspread(std::size_t i) const { return unspread_.empty() ? 0.0 : unspread_[i]; }
  /// Whether a law with these parameters and `bins` threshold bins keeps unspread arrivals: noise on, fresh renewal,
  /// more than one bin (the memory estimate counts them by this too).
  static bool keeps_unspread(const DiscreteParams& dp, std::size_t bins) {
    return dp.noise && dp.renewal != "quenched" && bins > 1;
  }
  /// Whether a law with these parameters, `bins` threshold bins and a normal load or not watches any site at all
  /// (watches below; the estimate prices the leap's steps by this too, compare/estimate.cpp): the noise on, fresh
  /// renewal, one threshold, no normal load.
  static bool may_watch(const DiscreteParams& dp, std::size_t bins, bool normal_load) {
    return dp.noise && dp.renewal != "quenched" && bins == 1 && !normal_load;
  }
  /// Detached counts of site i: [1] (fresh renewal) or per bin [B] (quenched); units as attached().
  std::span<const double> detached(std::size_t i) const;
  double attached_total(std::size_t i) const { return n_att_[i]; }  ///< Σ_b attached(i)
  /// Y_i: the overloaded fraction of the attached contacts of site i at slip rate v, now.
  double overloaded_fraction(std::size_t i, double v) const;
  /// The random stream of site i (site_engine(seed, i) advanced by the draws so far).
  const Engine& engine(std::size_t i) const { return engine_at(i); }

  /// Whole state (counts, σ̄, engines) as text; load_state() restores it bit for bit into a law
  /// built with the same parameters and size (throws std::invalid_argument otherwise).
  std::string save_state() const;
  void load_state(const std::string& text);
  /// Checkpoints (core::Archive): save_state / load_state.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("count law");
    std::string s = ar.loading() ? std::string() : save_state();
    ar(s);
    if (ar.loading()) load_state(s);
  }

 private:
  friend class detail::SitePool;
  /// Advance sites [lo, hi); returns whether one of them yielded.
  bool advance_sites(std::size_t lo, std::size_t hi, double dt, const double* v);
  /// Stages 2–3 of the step at site i with k overloaded bins and detach rate κ|v|; return A'.
  double step_contacts_sampled(std::size_t i, std::size_t k, double n_over, double detach, double dt);
  double step_contacts_mean(std::size_t i, std::size_t k, double detach, double dt);
  /// The watched step of site i (advance_watched): counts and σ̄ over [t, t + dt] event by event; returns whether the
  /// site was overloaded with v ≠ 0 at some event (or at the start).
  bool step_watched(std::size_t i, double v, double dt);
  /// Noise on, re-attachment channel of a normal load (docs/model.md §12.2): attach a_i, detach 1 − a_i (+ detach in
  /// the overloaded bins); return A'.
  double step_contacts_reattaching(std::size_t i, std::size_t k, double detach, double dt);
  std::size_t overloaded_bins(double tau) const;
  /// Attached contacts of site i in the overloaded bins [0, k), the unspread ones included (settled first when
  /// 0 < k < B).
  double overloaded_count(std::size_t i, std::size_t k) const;
  /// Spread site i's unspread arrivals over the bins (a uniform multinomial from the site's stream; exact: each of
  /// them fell in a uniform bin independently of what it went through since). Logically const (docs/discrete.md).
  void settle(std::size_t i) const;
  int pool_threads() const;
  double area_of(std::size_t i, double attached_total) const;
  double* att(std::size_t i) { return att_.data() + i * nbins_; }
  double* det(std::size_t i) { return det_.data() + i * det_stride_; }

  core::InterfaceParams ip_;
  DiscreteParams dp_;
  ThresholdDistribution g_;
  std::vector<double> thresholds_;  ///< s_b, ascending [B]
  std::size_t nbins_ = 1, det_stride_ = 1;
  double n_contacts_ = 1.0;
  bool quenched_ = false, noise_ = true;
  std::vector<double> rest_;  ///< [sites] resting area a_i under a normal load (docs/model.md §12); empty: none
  bool reattach_ = false;     ///< a load through re-attachment: the rates a_i, 1 − a_i
  bool scaled_ = false;       ///< a load at once: contact area a_i, A = a_i n/N
  double watch_reach_ = 0.0;  ///< inside advance_watched: its reach (> 0); else 0 (advance(): no site watched)

  // Counts are whole numbers held in doubles (noise on), or real fractions of the site (noise off).
  // att_ and unspread_ are mutable for settle(), which a const reader of the bins calls.
  mutable std::vector<double> att_;   ///< [sites × B] attached counts, the unspread ones (unspread_) excepted
  /// [sites] (noise on, fresh renewal, B > 1; else empty) attached contacts that joined while every bin shared one
  /// fate, each in a uniform bin not drawn yet: a step with k = 0 or k = B costs two or three draws instead of
  /// one per bin (docs/discrete.md, "Unspread arrivals").
  mutable std::vector<double> unspread_;
  std::vector<double> det_;        ///< [sites × (1 | B)] detached counts
  std::vector<double> n_att_;      ///< [sites] Σ_b att + unspread
  std::vector<double> area_;       ///< [sites] A = n_att / N
  std::vector<double> sigma_bar_;  ///< [sites]
  /// [sites] site_engine(seed, i), seeded at the site's first draw (engine_at): a site that never draws — stuck ahead
  /// of a front, or noise off — costs no seeding (~5 µs each: 6 % of a validity_fig1 run, docs/performance.md §17).
  /// The same stream either way: the engine is a function of (seed, i) until it draws.
  mutable std::vector<std::optional<Engine>> engines_;
  Engine& engine_at(std::size_t i) const {  // (only site i's own step touches engines_[i]: threads over sites are safe)
    auto& e = engines_[i];
    if (!e) e.emplace(site_engine(dp_.seed, i));
    return *e;
  }
  std::vector<detail::BinomialRate> share_;  ///< [B + 1]: share_[m] = 1/m, the uniform spread's successive rates

  double cached_dt_ = -1.0;        ///< two-state transition of a non-overloaded bin for cached_dt_
  core::TwoStateTransition attach_only_{1.0, 0.0};
  double cached_free_exp_ = 1.0;   ///< e^{−cached_dt_}

  detail::PoolHandle pool_;
};

}  // namespace slipfront::discrete
