#pragma once
// Contact statistics predicted from the continuum fields, and their goodness of fit against the agent's
// measured ones (docs/model.md §7.2, docs/contacts.md §3–§4).
//
// The prediction. In the mean-field (continuum) model a contact-slot of site i attaches at unit rate
// when free, and an attached contact detaches with the hazard h_i(t) = Θ_i κ |v_i| whatever its age:
// a contact attached at s survives to t with probability exp(−∫_s^t h_i). The expected contacts of
// site i attached at times in [s, s + ds] and still attached at t are therefore
// N (1 − A_i(s)) ds · exp(−∫_s^t h_i): ContactPrediction carries them as **cohorts** (attachment-time
// interval, expected mass as a fraction of N), fed by the continuum run step by step with the law's own
// frozen rates (A at the step's start, h over the step: the exact solution of dA/dt = (1 − A) − hA is
// what the law integrates). Every step, at each site with h > 0, every cohort decays by e^{−hΔt} and
// its loss is added to the lifetime histogram of the site's current class (region × phase), with
// lifetimes spread over the step with the exponential density of the frozen hazard; the cohort born
// in the step is added with the mass that survives it (its own losses, lifetimes in [0, Δt], with
// their exact density for a constant attachment rate). At each contact snapshot the cohorts' masses
// are added to the age histogram of the site's class (uniform over each cohort's age interval).
// Adjacent cohorts are merged while the merged attachment interval stays within cohort_width × its
// youngest age (or past age_cap; a merged cohort is uniform with its mean attachment time kept exactly),
// and cohorts below 1e-14 of a site are dropped: at most
// ln(age_cap/Δt)/ln(1 + cohort_width/2) + 2 cohorts per site (≈ 270 for Δt = 0.02, the defaults),
// whatever t_end. With hazard_scale ≠ 1 the survival uses s·h (a deliberately wrong prediction for
// tests: the births still follow the run's A).
//
// Threshold classes (the mean-field law, docs/model.md §2.2): with `classes` = B > 1 every site holds B
// sub-populations, one per threshold class b, each with its own hazard h_b = κ|v| θ(τ − s_b) and the total
// T_b its attached fraction n_b relaxes to (dn_b/dt = (T_b − n_b) − h_b n_b: fresh T_b = n_b + (1 − A)/B,
// quenched 1/B; the continuum is B = 1, T = 1). Its attachments over a step are then ∫(T_b − n_b) with the
// law's own n_b(u); everything else is per sub-population as above, and the classes of a site share its
// region and phase, so the tables are those of the site's contacts whatever their threshold.
//
// Thresholds (set_thresholds): a class b of the mean-field law stands for the thresholds of g in its quantile
// interval [b/B, (b + 1)/B), drawn from g restricted to it (both renewals: a contact that forms in class b has a
// threshold of that interval with g's density, and the law treats the class as one). At each contact snapshot the
// attached mass of each (site, class) is spread over the agent's threshold edges with those weights
// (threshold_spread), into the site's region and phase: the expected thresholds of the attached contacts
// (class_threshold_counts, region_threshold_counts). Within a class the agent removes the contacts below τ first,
// the law all at once at τ > s_b: the prediction's resolution is the class width (1/B of g's mass).
//
// The goodness of fit (contact_fit): per class, the measured histogram against the predicted one on the
// class edges (docs/contacts.md §4): bins merged from the small end until each predicted probability is
// at least 5/m (the rest joins the last group); the measured population thinned to a uniform subsample
// of m contacts (a multinomial draw from the measured proportions with a fixed seed; no thinning when
// there are at most m), and Pearson's X² of the subsample against the predicted proportions with
// K − 1 degrees of freedom (p-value from Boost.Math's chi-squared distribution): false-alarm rate α
// when the measured population has the predicted distribution, resolution ~ 1/sqrt(m). Beside it the
// distances of the whole population: the binned Kolmogorov distance max |F_measured − F_predicted| and
// the totals. Written here by hand: the bin merging, the thinning and the X² sum (a few lines each).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "discrete/contact_stats.hpp"
#include "discrete/thresholds.hpp"

namespace slipfront::compare {

class ContactPrediction {
 public:
  /// `contacts_per_site` N scales the expected counts; every site starts with one cohort of age 0
  /// and the mass given by initial_areas (call start() before the first step).
  /// `classes` threshold classes per site (1: the continuum).
  ContactPrediction(std::size_t sites, double contacts_per_site, double hazard_scale = 1.0,
                    double cohort_width = 0.1, double age_cap = 1e4, std::size_t classes = 1);
  /// The state at t = 0: every attached contact has age 0. `areas` [sites × classes]: the attached fraction
  /// of each class of each site (class fastest).
  void start(std::span<const double> areas);
  /// The threshold prediction: `edges` the agent's threshold edges [nt + 1], `spread` [classes × nt] the
  /// fraction of class b's contacts in each threshold bin (threshold_spread; each row sums to 1). Without it
  /// tables() has no threshold tables.
  void set_thresholds(std::vector<double> edges, std::vector<double> spread);
  /// Where the sites are relative to the continuum's front, and its phase (docs/model.md §7.2).
  void set_front(const core::FrontClasses& f) { front_ = f; }
  /// One step of length dt of the continuum run: A at its start and the hazard Θκ|v| frozen over it
  /// (per class, [sites × classes], with the totals T of the header comment; empty totals: T = 1).
  /// Times are kept on the prediction's own clock Σ dt, accumulated as the agent accumulates its time
  /// (AgentLaw::time), so that ages that fall exactly on a bin edge (before first yield every age is t)
  /// land in the same bin in both.
  void step(double dt, std::span<const double> area0, std::span<const double> hazard,
            std::span<const double> totals = {});
  /// A contact snapshot at the end of the last step: the expected ages of the attached contacts.
  void snapshot();
  double time() const { return clock_; }
  /// Expected mean age of the attached contacts of site i now, and their expected attached fraction
  /// Σ cohort masses (= A_i of the run, hazard_scale = 1).
  double mean_age(std::size_t i) const;
  double attached_mass(std::size_t i) const;
  /// The expected counts under the agent's table names (class_time_edges, class_lifetime_counts,
  /// class_age_counts, region_age_counts, snapshot_t, contact_snapshot_phase, with set_thresholds
  /// threshold_hist_edges, class_threshold_counts and region_threshold_counts,
  /// contact_snapshots_per_phase, detachments_total_per_site, attachments_total_per_site,
  /// lifetime_total).
  core::ContactTables tables() const;
  std::size_t max_cohorts() const { return max_cohorts_; }  ///< the most cohorts any site (class) held
  std::size_t cohorts(std::size_t i) const;                 ///< cohorts of site i, all its classes
  std::size_t classes() const { return classes_; }

  /// Checkpoints (core::Archive).
  template <class Ar>
  void serialize(Ar& ar) {
    ar(n_contacts_, scale_, width_, age_cap_, clock_, front_, edges_, bins_, cohorts_, compacted_size_, lifetime_, age_,
       detach_total_, attach_total_, snapshots_per_phase_, snapshot_t_, snapshot_phase_, region_age_rows_, max_cohorts_,
       classes_, tail_);
    ar(threshold_edges_, spread_, class_threshold_, region_threshold_rows_);
  }

 private:
  // Expected contacts attached at times s in [start, end] with density ∝ e^{tilt (s − end)}: a cohort
  // born in one step with the hazard h has tilt h (the later-born survive the step more often); every
  // later step multiplies the whole cohort by the same e^{−hΔt}, so the shape stays; merged cohorts
  // (old, narrow against their age) are taken as uniform.
  struct Cohort {
    double start, end;  ///< attachment times [start, end]
    double mass;        ///< expected attached contacts as a fraction of N
    double tilt;        ///< density ∝ e^{tilt (s − end)} on [start, end]
    double mean;        ///< mean attachment time (kept exactly through merges: the mean age)
  };
  // Mean of end − s for the density ∝ e^{−tilt (end − s)} on [0, w].
  static double mean_back(double tilt, double w);
  // P(attached at s ≤ x) within cohort c.
  static double share_before(const Cohort& c, double x);
  // Lifetimes of `mass` lost over [t0, t0 + dt] from cohort c, by class bin: loss times with the
  // frozen hazard's density ∝ e^{−rate (t' − t0)}, attachment times with the cohort's density (Gauss
  // quadrature where the lifetime range straddles a bin edge).
  // `b` is bin(t0 − c.end), the bin of its shortest lifetime (step() walks it down the age-ordered cohorts).
  void add_losses(std::size_t cls, const Cohort& c, double mass, double t0, double dt, double rate, std::size_t b);
  // What a step's loss computations depend on besides the masses, shared by the sub-populations of one
  // step: the classes of a site see at most two hazards (κ|v| for the overloaded ones, 0 for the others)
  // and their cohorts born in the same steps under the same hazard have the same attachment interval and
  // tilt, so each quantity below is computed once per site and step and reused bit for bit (the same
  // function of the same arguments; only the masses differ). Cleared at every site.
  struct RateTerms {   // the factors of one hazard hs (rate r = 1 + h) over the step
    double h = -1.0, hs = -1.0, decay = 0.0, loss = 0.0, birth_weight = 0.0, surv_weight = 0.0, surv_exp = 0.0,
           surv_cross = 0.0, back = 0.0;  ///< back: mean_back(hs, dt), the new cohort's mean age
    std::size_t young_begin = 0, young_end = 0;  ///< the young-loss fractions in split_values_
  };
  struct LossSplit {  // add_losses' cumulative fractions at the class edges of one cohort shape
    double start, end, tilt, rate;
    std::size_t first_bin, begin, end_index;  ///< split_values_[begin, end_index)
  };
  const RateTerms& rate_terms(double h, double dt);
  std::vector<RateTerms> rate_cache_;
  std::vector<LossSplit> split_cache_;
  std::vector<double> split_values_;
  std::size_t split_next_ = 0;  ///< the split_cache_ entry after the last one used (tried first)
  // The cohort's mass at its ages t − s into the class bins of row cls of `table`.
  void add_ages(std::vector<double>& table, std::size_t cls, const Cohort& c, double t, double mass);
  void compact(std::size_t i, double t);
  std::size_t bin(double x) const;

  double n_contacts_, scale_, width_, age_cap_;
  std::size_t classes_ = 1;    ///< threshold classes per site: cohorts_[site × classes_ + class]
  double clock_ = 0.0;
  core::FrontClasses front_;
  std::vector<double> edges_;  ///< class_time_edges
  std::size_t bins_;
  std::vector<std::vector<Cohort>> cohorts_;
  std::vector<std::size_t> compacted_size_;
  std::vector<double> lifetime_, age_, detach_total_, attach_total_, snapshots_per_phase_;
  std::vector<double> snapshot_t_, snapshot_phase_, region_age_rows_;  ///< per contact snapshot
  std::vector<double> threshold_edges_, spread_;                       ///< set_thresholds
  std::vector<double> class_threshold_, region_threshold_rows_;       ///< [12 × nt], [snapshots × 3 · nt]
  void snapshot_thresholds(bool classed);
  std::size_t max_cohorts_ = 0;
  // The shared tail of each site: classes [tail_[i], B) have had bit for bit the same inputs (attached fraction,
  // hazard, total) at every step so far — at a site the front has not reached, every class; behind it, the
  // classes never overloaded — so their cohorts are the same: held once, at class tail_[i], and counted
  // B − tail_[i] times. When some of them get different inputs (τ passes their thresholds) they leave the
  // tail with a copy of its cohorts. Exact: the same operations on the same numbers, only the tables' sums
  // are m·x instead of m additions of x (round-off).
  std::vector<std::size_t> tail_;
  std::size_t split_tail(std::size_t i, std::span<const double> area0, std::span<const double> hazard,
                         std::span<const double> totals);
  double multiplicity(std::size_t k) const {
    const std::size_t i = k / classes_, b = k % classes_;
    return b == tail_[i] ? static_cast<double>(classes_ - b) : 1.0;
  }
};

/// For each class b of `classes` quantile bins of g ([b/B, (b + 1)/B)), the fraction of its thresholds in each bin
/// of `edges` [B × (edges.size() − 1)]: B (min(G(e_{j+1}), (b+1)/B) − max(G(e_j), b/B))⁺; a degenerate g (every
/// threshold 1): all in the bin of 1.
std::vector<double> threshold_spread(const discrete::ThresholdDistribution& g, std::size_t classes,
                                     const std::vector<double>& edges);

/// One row of the goodness of fit: a statistic ("lifetime", "age" or "threshold") of one class.
struct ContactFit {
  std::string statistic;
  std::size_t phase = 0, region = 0;
  double measured_total = 0, predicted_total = 0;  ///< counts (predicted: expected)
  double ks_distance = 0;   ///< max over the class edges of |F_measured − F_predicted|, whole population
  double thinned_size = 0;  ///< m (or the measured total if smaller)
  double chi2 = 0;          ///< Pearson X² of the thinned sample against the predicted proportions
  double dof = 0;           ///< merged bins − 1 (0: no test)
  double p_value = 1;       ///< P(χ²_dof ≥ X²); 1 when not tested
  bool tested = false;      ///< enough contacts (measured_total ≥ min_total) and dof ≥ 1
};

/// A per-snapshot region table (`table`: region_age_counts or region_threshold_counts [ns, 3 · nb]) by class,
/// summed over the contact snapshots at which both models were in the same phase: {measured, predicted} as
/// [12, nb] tables. Empty tables when either lacks the table or the snapshots of the two do not match in
/// number and time.
std::pair<Table2D, Table2D> matched_tables(const ModelResult& measured, const ModelResult& predicted,
                                           const std::string& table);
inline std::pair<Table2D, Table2D> matched_age_tables(const ModelResult& measured, const ModelResult& predicted) {
  return matched_tables(measured, predicted, "region_age_counts");
}

/// The goodness of fit of every class of one statistic: measured [12, nb] and predicted [12, nb]
/// counts on the same edges; classes with fewer than min_total measured contacts are not tested.
/// m = ∞ tests the whole population (valid when the contacts are independent draws of the prediction:
/// deterministic rates, tests/test_contact_stats.cpp).
std::vector<ContactFit> contact_fit(const std::string& statistic, const Table2D& measured, const Table2D& predicted,
                                    double m = 2000, double min_total = 500, std::uint64_t seed = 12);

}  // namespace slipfront::compare
