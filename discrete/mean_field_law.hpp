#pragma once
// The mean-field limit N → ∞ of the microcontact ensemble (docs/model.md §2.2), the model `mean_field`: a
// deterministic population balance over yield thresholds, as an interface law (core::InterfaceLaw).
//
// State of site i: the attached fraction n_{i,b} of the site's contacts in each threshold class b (B quantile
// bins of g with probability 1/B each, bin b represented by its conditional mean threshold s_b, ascending;
// B = 1 when g is degenerate: w = 0 or delta), and σ̄_i. A_i = Σ_b n_{i,b}. The detached fractions are not
// state: 1 − A_i in one pool (renewal = fresh: a junction that forms draws its threshold from g afresh, so the
// pool feeds every class by 1/B) or 1/B − n_{i,b} per class (quenched: each class keeps its threshold).
//
// The population balance (docs/model.md §2.2), with τ_i = |σ̄_i + η v_i| / A_i, d_b = κ|v_i| if τ_i > s_b
// else 0, and the total T_{i,b} a class relaxes towards (fresh: n_b + (1 − A)/B; quenched: 1/B):
//   dn_b/dt = (T_b − n_b) − d_b n_b,     dσ̄/dt = α A v − |v| Y σ̄,   Y = Σ_{b: τ > s_b} n_b / A (1 when A = 0).
// One step [t, t + Δt] with v_i frozen, as the count representation's step with the noise off
// (discrete/count_law.hpp, docs/discrete.md), so that the two agree bit for bit at the same binning:
//   1. load        τ_i at the start of the step; classes b < k overloaded (τ_i > s_b: a prefix)
//   2. contacts    n_b' = relax(n_b, T_b, 1 + d_b, Δt)   (T_b, d_b frozen: the exact expected two-state step)
//   3. stress      σ̄' = relax(σ̄, α Ā v, Y |v|, Δt), Ā = (A + A')/2, Y at the start of the step
// Reads discrete.threshold, width, renewal and bins; not contacts_per_site, seed, representation, noise or
// threads. With w = 0 it is the continuum law bit for bit (docs/model.md §2.2: one class, T = 1 exactly — fresh
// renewal's T = A + (1 − A) rounds to 1 for every A in [0, 1] — and otherwise FrictionLaw's operations).
//
// Contact aging (interface.aging_b > 0, docs/model.md §11.3): every class carries its attached contacts by age
// (discrete::AgeCohorts, exact along the characteristics with the step's frozen rates); A_i is the area
// Σ_b Σ_cohorts mass (1 + b ln(1 + age/τ_a)), the detached pool is 1 − Σ_b n_b (counts, not area), and Y_i the
// overloaded classes' share of the area. aging_b = 0 takes none of these branches (advance_site_aging).
//
// Under a prescribed normal load (docs/model.md §12, set_normal_load) with resting area a_i = (p_i/p_0)^m, as the
// count representation with the noise off: re-attachment n_b' = relax(n_b, a_i T_b, 1 + d_b, Δt); instantaneous:
// the classes as today, A_i = a_i Σ_b n_b (contacts of area a_i). Not with aging (the scene refuses the pair).
//
// The adaptive integrator does not apply: its state is [A | σ̄] per site (core::SmoothLaw), this law's is the
// B attached fractions and σ̄, and Y is piecewise constant in τ with B jumps (docs/model.md §2.2).
#include <cstddef>
#include <span>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "discrete/aging.hpp"
#include "discrete/params.hpp"
#include "discrete/thresholds.hpp"

namespace slipfront::discrete {

// core::LawHooks::steady_state: its mean-field steady state with every threshold overloaded (docs/model.md §2.2), the
// closed form of core/steady_sliding.hpp: exact at w = 0 and while the thresholds lie below the steady contact stress.
class MeanFieldLaw : public core::OverloadedSteadyState<MeanFieldLaw> {
 public:
  static constexpr core::LawHooks hooks{.class_hazards = true, .checkpoints = true, .yield_onset = true,
                                        .steady_state = true, .steady_front = true, .normal_load = true};
  /// Validates the threshold keys of `dp` (DiscreteParams::validate_threshold_law: ParamError naming the
  /// key). All sites start stuck: A = 1 (1/B in every class), σ̄ = 0.
  MeanFieldLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites);

  // --- the step contract (core::InterfaceLaw) -------------------------------------------
  std::size_t size() const { return area_.size(); }
  const core::InterfaceParams& params() const { return ip_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }

  /// Initial state of site i: A/B attached in every class (the attached contacts are a sample of g). A ∈ [0, 1].
  void set_site(std::size_t i, double area, double sigma_bar);

  /// The resting area a_i = (p_i/p_0)^m of every site (docs/model.md §12; as CountLaw::set_normal_load, a_i ≤ 1
  /// under re-attachment).
  void set_normal_load(std::span<const double> factor);
  /// a_i (1 without a normal load).
  double resting_area(std::size_t i) const { return rest_.empty() ? 1.0 : rest_[i]; }

  /// The population balance over [t, t + dt] with the slip rates v frozen (header comment); any_yield: some
  /// site with v_i ≠ 0 had an overloaded attached class (or A_i = 0) at the start of the step.
  core::LawStepInfo advance(double dt, std::span<const double> v);

  /// The implicit step's linearisation (core/law.hpp): y = Y_i at the previous step's rate.
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(ip_, dt), s_min = thresholds_.front()](
               std::size_t i, double wp, double& c0, double& c1) {
      const double a = area_[i], sb = sigma_bar_[i];
      double y = 0.0;
      if (wp != 0.0 && core::contact_stress(sb + ip_.eta * wp, a) > s_min) y = overloaded_fraction(i, wp);
      core::linearise_stress(a, sb, y, wp, k, c0, c1, resting_area(i));
    };
  }

  /// The weakest class threshold s_0: below it no class is overloaded (core::LawHooks::yield_onset).
  double yield_onset() const { return thresholds_.front(); }
  /// The strongest class threshold: above it every class is overloaded.
  double yield_saturation() const { return thresholds_.back(); }

  // --- inspection ------------------------------------------------------------------------------
  const ThresholdDistribution& distribution() const { return g_; }
  bool quenched() const { return quenched_; }
  std::size_t bins() const { return thresholds_.size(); }
  /// s_b, ascending: the conditional mean of g on the quantile interval [b/B, (b+1)/B).
  std::span<const double> thresholds() const { return thresholds_; }
  /// Attached fraction of site i per class [B] (Σ = A_i).
  std::span<const double> attached(std::size_t i) const { return {att_.data() + i * nbins_, nbins_}; }
  /// Detached fraction of site i in class b: fresh 1 − A_i over the pool (b ignored), quenched 1/B − n_b.
  double detached(std::size_t i, std::size_t b) const;
  /// Y_i: the overloaded fraction of the attached contacts of site i at slip rate v, now.
  double overloaded_fraction(std::size_t i, double v) const;

  // --- the contact prediction by threshold class (core::LawHooks::class_hazards, compare/contacts.hpp) ------
  std::size_t prediction_classes() const { return nbins_; }
  /// Every site's attached fractions per class [sites × B] (class fastest).
  std::span<const double> attached_classes() const { return att_; }
  /// For a step at slip rate v from the start-of-step state (area, sigma_bar, n = the site's B class fractions),
  /// what advance() freezes in each class b: the detachment hazard κ|v| θ(τ − s_b), τ = |σ̄ + ηv|/A, and the total
  /// T_b the class relaxes to (fresh n_b + (1 − A)/B, quenched 1/B).
  void class_rates(std::size_t i, double v, double area, double sigma_bar, std::span<const double> n,
                   std::span<double> hazard, std::span<double> total) const;

  /// Checkpoints (core::Archive): the attached fractions and σ̄; a state of another size or binning is refused.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("mean-field law");
    std::size_t sites = size(), nb = nbins_;
    bool quenched = quenched_;
    ar(sites, nb, quenched);
    if (sites != size() || nb != nbins_ || quenched != quenched_)
      throw core::ArchiveError("checkpoint: the mean-field state has another size, binning or renewal than this scene's");
    ar(att_, sigma_bar_);
    if (aging_) ar(cohorts_, class_area_, area_);  // docs/model.md §11.3 (absent without aging: today's format)
    if (ar.loading()) {
      if (att_.size() != sites * nbins_ || sigma_bar_.size() != sites ||
          (aging_ && (cohorts_.size() != att_.size() || class_area_.size() != att_.size() || area_.size() != sites)))
        throw core::ArchiveError("checkpoint: the mean-field state's arrays do not match its size");
      if (!aging_)
        for (std::size_t i = 0; i < sites; ++i) area_[i] = total(i);
    }
  }

  /// Aging (docs/model.md §11.3): the age cohorts of site i's class b (empty without aging).
  const AgeCohorts& cohorts(std::size_t i, std::size_t b) const { return cohorts_[i * nbins_ + b]; }
  /// Σ_b n_b of site i: the attached fraction by count (= A without aging).
  double attached_fraction(std::size_t i) const { return total(i); }

 private:
  bool advance_site_aging(std::size_t i, double dt, double vi);
  std::size_t overloaded_classes(double tau) const;
  double total(std::size_t i) const;  ///< Σ_b n_{i,b}, summed in class order (as advance() sums it)

  core::InterfaceParams ip_;
  ThresholdDistribution g_;
  std::vector<double> thresholds_;  ///< s_b [B]
  std::size_t nbins_ = 1;
  bool quenched_ = false;
  std::vector<double> att_;        ///< [sites × B] attached fractions
  std::vector<double> area_;       ///< [sites] A = Σ_b n_b
  std::vector<double> sigma_bar_;  ///< [sites]
  double cached_dt_ = -1.0, free_exp_ = 1.0, free_weight_ = 0.0;  ///< e^{−Δt}, (1 − e^{−Δt}): no overloaded class
  bool aging_ = false;                 ///< interface.aging_b > 0 (docs/model.md §11.3)
  std::vector<AgeCohorts> cohorts_;    ///< aging: [sites × B] the attached contacts of each class by age
  std::vector<double> class_area_;     ///< aging: [sites × B] each class's area
  std::vector<double> rest_;  ///< [sites] resting area a_i under a normal load (docs/model.md §12); empty: none
  bool reattach_ = false;     ///< a load through re-attachment: the source a_i T_b
  bool scaled_ = false;       ///< a load at once: A = a_i Σ_b n_b
};

static_assert(core::InterfaceLaw<MeanFieldLaw>);

}  // namespace slipfront::discrete
