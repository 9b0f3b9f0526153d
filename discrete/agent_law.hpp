#pragma once
// The microcontact ensemble of docs/model.md §2 in the AGENT representation: every contact explicit (state,
// threshold s_j, time of last attachment), with the step contract core::InterfaceLaw (size,
// contact_area, sigma_bar, set_site, advance, params), so the bulk stepper and the scene runner
// take it unchanged. It samples the same process as the count representation (CountLaw) and can
// record contact statistics (discrete/contact_stats.hpp, docs/model.md §2 item 5).
//
// One step [t0, t1 = t0 + Δt] with v_i frozen, at every site (the rates are frozen at their
// start-of-step values, docs/model.md §2):
//   1. load      τ_i = |σ̄_i + η v_i| / A_i; an attached contact is overloaded ("a member") when
//                τ_i > s_j; Y_i = members / attached (1 when none attached)
//   2. idle?     no member that slips and no detached contact: nothing to do (O(1), no draw)
//   3. contacts  the continuous-time two-state chain of every contact with the frozen rates
//                (attach 1, detach d = κ|v_i| for members), simulated event by event (Gillespie):
//                the members of a site detach as a Poisson process of intensity K(t)·d (K the
//                current member count) and its detached contacts attach as one of intensity
//                D(t)·1 (D the detached count); each process has a per-site mark E ~ Exp(1) of its
//                integrated intensity, carried over steps (memoryless), and when a mark is reached
//                the contact that moves is chosen uniformly among the members / the detached.
//                A contact may detach and re-attach within the step (and so on), so the end-of-step
//                state of every contact has exactly the two_state_transition() probabilities.
//   4. stress    σ̄_i' = relax(σ̄_i, α Ā_i v_i, Y_i |v_i|, Δt), Ā = (A + A')/2 (as FrictionLaw)
//
// Cost per site and step: O(1 + number of state changes) for w = 0 (all attached contacts are
// members or none are): a step without an event compares the two marks, draws no random number and
// touches no contact; an event moves one contact between two unordered arrays (swap-remove).
// For w > 0 the attached contacts of a site are kept in B ≈ 4√N quantile bins of g (unordered inside
// a bin) with a Fenwick tree of the bin counts: bins entirely below τ are members, bins entirely
// above are not, and only the one bin that straddles τ is scanned (partitioned so its members come
// first): O(log B + N/B) per site and step plus O(log B) per state change; O(log B) when τ is below
// every threshold (a stuck site).
//
// Thresholds: s is drawn from g when a contact attaches (renewal = fresh; the same law as a fresh
// draw at detachment, since a detached contact's threshold plays no role until it attaches) or
// kept for the whole run (quenched). As in the count representation, a contact that detaches and
// re-attaches within one step keeps its threshold (the step-level transition att → att): about a
// fraction Δt/2 of the renewals (attach rate 1 over the rest of the step), no effect for w = 0.
//
// Randomness: only from the site's own stream site_engine(seed, i), consumed in an order fixed by
// the site's own history: results do not depend on the order in which sites are visited.
// DiscreteParams::threads is not used (one thread; results would not depend on it).
// noise = false is refused (an agent has whole contacts; use the count representation).
//
// Contact aging (interface.aging_b > 0, docs/model.md §11.2): a contact of age a has area 1 + b ln(1 + a/τ_a);
// A_i = Σ areas / N at the end of each step (O(attached) per site and step, a step without events too: the areas
// grow), and with w > 0 Y_i is the overloaded contacts' share of that area (each carries τ_i × its area).
// Attachment and detachment rates are per contact, whatever its area. aging_b = 0 takes none of these branches.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "discrete/contact_stats.hpp"
#include "discrete/params.hpp"
#include "discrete/streams.hpp"
#include "discrete/thresholds.hpp"

namespace slipfront::discrete {

namespace detail {

/// Fenwick tree of counts over bins: prefix sums and rank search in O(log B).
class Fenwick {
 public:
  void reset(std::size_t n) { tree_.assign(n + 1, 0); }
  void add(std::size_t i, std::int64_t delta) {
    for (std::size_t k = i + 1; k < tree_.size(); k += k & (~k + 1)) tree_[k] += delta;
  }
  /// Σ counts over bins [0, i).
  std::int64_t prefix(std::size_t i) const {
    std::int64_t s = 0;
    for (std::size_t k = i; k > 0; k -= k & (~k + 1)) s += tree_[k];
    return s;
  }
  /// The bin b holding the element of rank r (0-based) and the rank inside it: smallest b with
  /// prefix(b + 1) > r; r must be < prefix(size).
  template <class Ar>
  void serialize(Ar& ar) {
    ar(tree_);
  }
  std::size_t find(std::int64_t& r) const {
    std::size_t pos = 0, step = 1;
    while (step * 2 < tree_.size()) step *= 2;
    for (; step > 0; step /= 2)
      if (pos + step < tree_.size() && tree_[pos + step] <= r) {
        pos += step;
        r -= tree_[pos];
      }
    return pos;  // 0-based bin index
  }

 private:
  std::vector<std::int64_t> tree_;
};

}  // namespace detail

/// An attached contact: its threshold and the time it attached.
struct AttachedContact {
  double threshold;
  double attached_at;
};
/// A detached contact: when it detached, and its threshold (quenched; or, renewal = fresh, the one it
/// keeps if it re-attaches within the step of its detachment; NaN for a contact detached by set_site).
struct DetachedContact {
  double detached_at;
  double threshold;
};

// core::LawHooks::steady_state: its mean-field steady state with every threshold overloaded (docs/model.md §2.2), the
// closed form of core/steady_sliding.hpp: exact at w = 0 and while the thresholds lie below the steady contact stress.
class AgentLaw : public core::OverloadedSteadyState<AgentLaw> {
 public:
  static constexpr core::LawHooks hooks{
      .ages = true, .contact_statistics = true, .contact_hazard = true, .checkpoints = true, .yield_onset = true,
      .count_noise = true, .steady_state = true, .steady_front = true, .normal_load = true};
  /// Validates `dp` (ParamError naming the key). All sites start stuck: A = 1, σ̄ = 0.
  AgentLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites);

  // --- the step contract (core::InterfaceLaw) -------------------------------------------
  std::size_t size() const { return area_.size(); }
  const core::InterfaceParams& params() const { return ip_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }
  /// The lowest threshold g gives (its first bin edge; 1 when w = 0): below it no contact is overloaded
  /// (core::LawHooks::yield_onset).
  double yield_onset() const { return degenerate_ ? 1.0 : edges_.front(); }
  /// The highest threshold g gives (its last bin edge, +∞ for an unbounded g; 1 when w = 0).
  double yield_saturation() const { return degenerate_ ? 1.0 : edges_.back(); }
  /// N: every contact attaches and detaches by its own draw (core::LawHooks::count_noise).
  double noise_contacts() const { return static_cast<double>(n_contacts_); }

  /// Initial state of site i: n = round(A N) attached contacts with thresholds drawn from g (none
  /// drawn when w = 0) and age 0, the rest detached since now. Restarts the site's random stream, so
  /// the state depends only on (seed, i, A, σ̄). A ∈ [0, 1].
  void set_site(std::size_t i, double area, double sigma_bar);
  /// The resting area a_i = (p_i/p_0)^m of every site (docs/model.md §12.2, as CountLaw::set_normal_load): under
  /// re-attachment each new contact attaches at rate a_i and every attached contact detaches at rate 1 − a_i besides
  /// the overload's κ|v| (a_i ≤ 1, else ParamError naming interface.load_p); instantaneous: contacts of area a_i,
  /// A = a_i n/N, and A, σ̄ scale at once by a_new/a_old.
  void set_normal_load(std::span<const double> factor);
  /// a_i (1 without a normal load).
  double resting_area(std::size_t i) const { return rest_.empty() ? 1.0 : rest_[i]; }

  /// docs/model.md §2 over [t, t + dt] with the slip rates v frozen. any_yield: some site had an
  /// overloaded attached contact (or none attached, τ = ∞) and v_i ≠ 0 at the start of the step
  /// (the definition of CountLaw).
  core::LawStepInfo advance(double dt, std::span<const double> v);

  /// Y_i: the overloaded fraction of the attached contacts of site i at slip rate v, now (1 when none
  /// is attached: τ = ∞).
  double overloaded_fraction(std::size_t i, double v) const;
  /// The implicit step's linearisation (core/law.hpp), one site at a time, with y = Y_i at the
  /// previous step's rate.
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(ip_, dt), s_min = degenerate_ ? 1.0 : edges_.front()](
               std::size_t i, double wp, double& c0, double& c1) {
      const double a = area_[i], sb = sigma_bar_[i];
      double y = 0.0;
      if (wp != 0.0 && core::contact_stress(sb + ip_.eta * wp, a) > s_min) y = overloaded_fraction(i, wp);
      core::linearise_stress(a, sb, y, wp, k, c0, c1);
    };
  }

  // --- contact age (docs/model.md §7) ------------------------------------------------------------
  /// Report the mean age of the attached contacts (output.ages). The sums behind it are always kept
  /// (Σ t_attach per site, one addition per event), so this only says whether to report it.
  void track_ages(bool on) { ages_ = on; }
  bool tracks_ages() const { return ages_; }
  /// ā_i = t − Σ t_attach / n_i over the attached contacts of site i, exactly (NaN when none attached).
  void mean_age(std::span<double> out) const;

  // --- contact statistics (the runner calls these when the law has them) ---------------------
  /// Snapshot of the attached contacts (ages, thresholds) and the per-site event counts since the
  /// previous snapshot; a no-op unless DiscreteParams::contact_statistics.
  void record_contacts(double t);
  /// Where the sites are relative to the front and the phase of the run (the runner, at every tip
  /// sample): the class of each event and snapshot (docs/model.md §7.2).
  void observe_front(const core::FrontClasses& f) { stats_.set_front(f); }
  core::ContactTables contact_tables() const { return stats_.tables(); }
  const ContactStats& contact_stats() const { return stats_; }
  /// The hazard of an attached contact at the state s if its threshold were drawn afresh from g:
  /// κ|v| P(threshold < τ), τ = |σ̄ + ηv|/A; with w = 0 the continuum law's Θκ|v| (docs/model.md §7.2:
  /// the contact prediction from this law's own fields, exact for w = 0; with w > 0 it ignores the
  /// selection of strong contacts by the front).
  double detachment_hazard(core::SiteState s) const {
    const double rate = ip_.kappa * std::abs(s.v);
    if (degenerate_) return core::slides(s.sigma_bar, s.v, s.area, ip_.eta) ? rate : 0.0;
    return rate * g_.cdf(core::contact_stress(s.sigma_bar + ip_.eta * s.v, s.area));
  }

  /// Checkpoints (core::Archive): every contact in its order, the marks, the streams, the statistics.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("agent law");
    for (auto& st : sites_) {
      ar(st.bins, st.counts, st.detached, st.n_att, st.detach_mark, st.attach_mark);
      serialize_engine(ar, st.engine);
    }
    ar(area_, sigma_bar_, t_, changes_, stats_, ages_);
    for (auto& st : sites_) ar(st.attach_time_sum, st.pristine, st.set_at);  // ages (docs/model.md §7)
  }

  // --- inspection ------------------------------------------------------------------------------
  const DiscreteParams& discrete_params() const { return dp_; }
  const ThresholdDistribution& distribution() const { return g_; }
  double time() const { return t_; }  ///< Σ dt since construction
  std::size_t contacts_per_site() const { return n_contacts_; }
  std::size_t attached_count(std::size_t i) const { return sites_[i].n_att; }
  std::size_t threshold_bins() const { return nbins_; }
  /// The random stream of site i (site_engine(seed, i) advanced by the draws since set_site).
  const Engine& engine(std::size_t i) const { return sites_[i].engine; }
  /// Contact state changes (attachments + detachments) simulated so far, all sites.
  std::uint64_t state_changes() const { return changes_; }
  /// f(const AttachedContact&) for every attached contact of site i (between steps).
  template <class F>
  void for_each_attached(std::size_t i, F&& f) const {
    for (const auto& bin : sites_[i].bins)
      for (const auto& c : bin) f(c);
  }
  /// f(const DetachedContact&) for every detached contact of site i.
  template <class F>
  void for_each_detached(std::size_t i, F&& f) const {
    for (const auto& c : sites_[i].detached) f(c);
  }

 private:
  struct Site {
    std::vector<std::vector<AttachedContact>> bins;  ///< attached contacts by threshold bin
    detail::Fenwick counts;                          ///< attached counts per bin (B > 1)
    std::vector<DetachedContact> detached;           ///< unordered
    std::size_t n_att = 0;
    double attach_time_sum = 0.0;  ///< Σ t_attach over the attached contacts (docs/model.md §7)
    bool pristine = true;          ///< no event since set_site: every attached contact attached at set_at
    double set_at = 0.0;           ///< the time of set_site
    double detach_mark = -1.0;  ///< residual Exp(1) of ∫ K d dt until the next detachment (< 0: not drawn)
    double attach_mark = -1.0;  ///< residual Exp(1) of ∫ D dt until the next attachment (< 0: not drawn)
    Engine engine;
  };
  /// The members of a site at the start of a step (frozen τ).
  struct Load {
    std::size_t full_bins = 0;              ///< bins [0, full_bins) are all members
    std::size_t partial = static_cast<std::size_t>(-1);  ///< bin straddling τ (members first) or npos
    std::size_t partial_members = 0;
    std::size_t members = 0;
  };

  Load classify(Site& st, double tau) const;
  double aged_area_sum(const Site& st, double t) const;
  double aged_overloaded_fraction(const Site& st, double tau, double t) const;
  bool is_member(const Load& ld, std::size_t bin, double s, double tau) const;
  std::size_t bin_of(double s) const;
  double draw_threshold(Engine& e) const;
  void add_attached(Site& st, Load& ld, AttachedContact c, double tau);
  AttachedContact remove_member(Site& st, Load& ld, std::uint64_t rank);
  /// Remove the attached non-member of rank `rank` (the straddling bin's non-members, then the bins above it).
  AttachedContact remove_non_member(Site& st, const Load& ld, std::uint64_t rank);
  /// Step 3 at site i over [t0, t1]: the event-driven chain.
  void run_events(std::size_t i, Site& st, Load& ld, double tau, double detach, double t0, double t1);

  core::InterfaceParams ip_;
  DiscreteParams dp_;
  ThresholdDistribution g_;
  std::size_t n_contacts_ = 1, nbins_ = 1;
  bool degenerate_ = true, quenched_ = false;
  std::vector<double> edges_;  ///< bin edges e_0..e_B (quantiles b/B of g), non-degenerate only
  double t_ = 0.0;
  std::uint64_t changes_ = 0;
  bool ages_ = false;
  bool aging_ = false;  ///< interface.aging_b > 0: contacts' areas grow with their age (docs/model.md §11.2)
  std::vector<double> rest_;  ///< [sites] resting area a_i under a normal load (docs/model.md §12); empty: none
  bool reattach_ = false;     ///< a load through re-attachment: attach a_i, spontaneous detachment 1 − a_i
  bool scaled_ = false;       ///< a load at once: contacts of area a_i

  std::vector<Site> sites_;
  std::vector<double> area_, sigma_bar_;
  ContactStats stats_;
};

}  // namespace slipfront::discrete
