#pragma once
// Contact statistics of the agent representation (docs/model.md §2 hierarchy item 5, docs/model.md §5
// /discrete/contacts): what renewal theory predicts in steady sliding at imposed v with w = 0 —
// attached lifetimes ~ Exp(κv), detached durations ~ Exp(1), ages of attached contacts ~ Exp(κv).
//
// Collected online by the law (record_lifetime / record_detached at each event, a snapshot of the
// attached contacts at the runner's snapshot times) and handed to the runner as plain tables
// (ContactTables), which it copies into compare::ModelResult::contacts / contacts_2d. Nothing here
// knows about compare/ or HDF5.
//
// Tables (names are the HDF5 dataset names under /<model>/contacts/):
//   lifetime_hist_edges [nb+1], lifetime_hist_counts [nb]   completed attachments (fixed log edges)
//   lifetimes, lifetime_start_t [n]                        raw values, only if n ≤ raw_cap
//   detached_hist_edges [nb+1], detached_hist_counts [nb]  completed detached periods
//   detached_durations, detached_start_t [n]               raw values, only if n ≤ raw_cap
//   lifetime_total, detached_total [1]                     how many were counted
//   snapshot_t [ns]                                        times of the snapshots
//   age_hist_edges [nb+1], age_hist_counts [ns, nb]        ages t − t_attach of attached contacts
//   threshold_hist_edges [nb+1], threshold_hist_counts [ns, nb]   thresholds of attached contacts
//   detachments_per_site [ns, nx]                          detachments in (t_{k−1}, t_k] (row 0: since start)
//   attachments_per_site [ns, nx]                          attachments in the same intervals
// Resolved in space and time (docs/model.md §7.2): 12 classes, region (behind | tip | ahead of the front)
// × phase (before yield | slow front | transient | after arrest), row c = 3 · phase + region, set by the
// runner at every tip sample (set_front: FrontClasses):
//   class_time_edges [nc+1]                                 {0, 1e-3 … 1e4 (5 per decade), ∞}: every other
//                                                           edge of the log time edges in [1e-3, 1e4]
//   class_lifetime_counts [12, nc]                          completed attachments by lifetime, classed
//                                                           at the detachment
//   class_age_counts [12, nc]                               ages of attached contacts, summed over the
//                                                           contact snapshots, classed at the snapshot
//   class_threshold_counts [12, nt]                         thresholds of attached contacts, likewise
//   region_age_counts [ns, 3 · nc]                          ages at each contact snapshot by region
//                                                           (behind | tip | ahead, nc bins each)
//   region_threshold_counts [ns, 3 · nt]                    thresholds at each contact snapshot by region
//   contact_snapshot_phase [ns]                             the phase at each contact snapshot
//   threshold_drawn_counts [nt]                             every threshold drawn from g (w > 0)
//   contact_snapshots_per_phase [4]                         contact snapshots taken in each phase
//   detachments_total_per_site, attachments_total_per_site [nx]   over the whole run
// Memory: fixed-size histograms and per-site counters (independent of t_end); the per-snapshot rows
// (age/threshold_hist_counts, *_per_site) grow with the number of contact snapshots, as the field
// snapshots do; the raw values stop at raw_cap.
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "core/contacts.hpp"

namespace slipfront::discrete {


/// Histogram on fixed edges; values outside [edges.front(), edges.back()) are counted in the first /
/// last bin (the default edges start at 0 and end at +∞, so nothing is clipped).
class Histogram {
 public:
  Histogram() = default;
  explicit Histogram(std::vector<double> edges);
  void add(double x) { counts_[bin(x)] += 1.0; }
  /// The bin of x: b with e_b ≤ x < e_{b+1}; below e_0 → 0, at or above the last edge → the last bin.
  std::size_t bin(double x) const;
  void add_to(std::size_t b, double count = 1.0) { counts_[b] += count; }
  const std::vector<double>& edges() const { return edges_; }
  const std::vector<double>& counts() const { return counts_; }
  std::size_t bins() const { return counts_.size(); }
  void clear();
  template <class Ar>
  void serialize(Ar& ar) {
    ar(edges_, counts_, geometric_, log2_lo_, bins_per_log2_);
  }

 private:
  std::vector<double> edges_, counts_;
  // Geometric interior edges (log_time_edges): bin() guesses the bin from the binary exponent and a
  // polynomial log2 of the mantissa, then corrects it against the edges (the same bin as the search).
  bool geometric_ = false;
  double log2_lo_ = 0.0, bins_per_log2_ = 0.0;
};

/// Edges {0, lo, lo·10^{1/k}, ..., hi, +∞}: times spanning many decades (lifetimes, ages).
std::vector<double> log_time_edges(double lo = 1e-6, double hi = 1e6, int per_decade = 10);
/// Edges {0, s_max/n, ..., s_max, +∞}: thresholds.
std::vector<double> linear_edges(double s_max, int n);
/// The threshold edges of the contact statistics for relative width w: linear_edges(max(2, 1 + 8w), 100) (the
/// agent's histograms and the mean-field prediction of them, compare/contacts.hpp).
std::vector<double> threshold_edges(double width);
/// Edges of the class tables: {0, 1e-3, 1e-3·10^{1/5}, …, 1e4, +∞}, each (but 0 and ∞) an edge of
/// log_time_edges() (the same doubles), so every bin of those lies inside one class bin.
std::vector<double> class_time_edges();
/// For each bin of the histogram on `fine` edges, the bin of `coarse` (every edge of which is one of
/// `fine`'s) that contains it.
std::vector<std::size_t> coarse_bin_map(const std::vector<double>& fine, const std::vector<double>& coarse);

class ContactStats {
 public:
  /// Raw lifetimes / durations are kept while there are at most this many (histograms always).
  static constexpr std::size_t raw_cap = 100000;

  ContactStats() = default;  ///< disabled: every call is a no-op
  /// Enabled, for `sites` sites; thresholds histogrammed on `edges` (threshold_edges(w)).
  ContactStats(std::size_t sites, std::vector<double> edges);

  bool enabled() const { return enabled_; }

  /// Where the sites are relative to the front (the runner, at every tip sample; docs/model.md §7.2).
  void set_front(const core::FrontClasses& f) { front_ = f; }
  const core::FrontClasses& front() const { return front_; }
  std::size_t class_of(std::size_t site) const { return front_.class_of(site); }

  /// A completed attachment of a contact of `site`: attached at `start`, lasted `lifetime`.
  void record_lifetime(std::size_t site, double start, double lifetime) {
    if (!enabled_) return;
    const std::size_t b = lifetime_.bin(lifetime);
    lifetime_.add_to(b);
    if (front_.classed()) class_lifetime_[front_.class_of(site) * class_bins_ + class_bin_[b]] += 1.0;
    ++detach_total_[site];
    ++detach_count_[site];
    ++n_lifetimes_;
    if (n_lifetimes_ <= raw_cap) {
      lifetimes_.push_back(lifetime);
      lifetime_start_.push_back(start);
    }
  }
  /// A completed detached period of a contact of `site`: detached at `start`, lasted `duration`.
  void record_detached(std::size_t site, double start, double duration) {
    if (!enabled_) return;
    detached_.add(duration);
    ++attach_total_[site];
    ++attach_count_[site];
    ++n_detached_;
    if (n_detached_ <= raw_cap) {
      detached_durations_.push_back(duration);
      detached_start_.push_back(start);
    }
  }

  /// Snapshot at time t: between begin and end, for every attached contact, its age (attached_age)
  /// and threshold (attached_threshold; `count` contacts of one threshold at once), with the class of
  /// its site (class_of).
  void begin_snapshot(double t);
  void attached_age(std::size_t cls, double age, double count = 1.0) {
    const std::size_t b = age_.bin(age), cb = class_bin_[b];
    age_.add_to(b, count);
    if (cls >= core::FrontClasses::count) return;  // phase next_event: not classed
    class_age_[cls * class_bins_ + cb] += count;
    region_age_row_[(cls % core::FrontClasses::regions) * class_bins_ + cb] += count;
  }
  void attached_threshold(std::size_t cls, double threshold, double count = 1.0) {
    const std::size_t b = threshold_.bin(threshold);
    threshold_.add_to(b, count);
    if (cls >= core::FrontClasses::count) return;  // phase next_event: not classed
    class_threshold_[cls * threshold_.bins() + b] += count;
    region_threshold_row_[(cls % core::FrontClasses::regions) * threshold_.bins() + b] += count;
  }
  void attached(std::size_t cls, double age, double threshold) {
    attached_age(cls, age);
    attached_threshold(cls, threshold);
  }
  void end_snapshot();
  /// A threshold drawn from g (w > 0: at set_site, and at each attachment with fresh renewal).
  void drawn(double threshold) {
    if (enabled_) drawn_.add(threshold);
  }

  std::size_t lifetime_count() const { return n_lifetimes_; }
  std::size_t detached_count() const { return n_detached_; }
  /// Raw values (empty once more than raw_cap were recorded).
  std::span<const double> lifetimes() const { return raw_ok(n_lifetimes_) ? lifetimes_ : std::span<const double>{}; }
  std::span<const double> lifetime_starts() const { return raw_ok(n_lifetimes_) ? lifetime_start_ : std::span<const double>{}; }
  std::span<const double> detached_durations() const { return raw_ok(n_detached_) ? detached_durations_ : std::span<const double>{}; }
  std::span<const double> detached_starts() const { return raw_ok(n_detached_) ? detached_start_ : std::span<const double>{}; }

  core::ContactTables tables() const;

  /// Checkpoints (core::Archive).
  template <class Ar>
  void serialize(Ar& ar) {
    ar(enabled_, sites_, lifetime_, detached_, age_, threshold_, n_lifetimes_, n_detached_, lifetimes_, lifetime_start_,
       detached_durations_, detached_start_, detach_count_, attach_count_, snapshot_t_, age_rows_, threshold_rows_,
       detach_rows_, attach_rows_);
    // by region and phase (docs/model.md §7.2)
    ar(drawn_, front_, class_bin_, class_bins_, class_edges_, class_lifetime_, class_age_, class_threshold_,
       snapshots_per_phase_, snapshot_phase_, region_age_row_, region_age_rows_, detach_total_, attach_total_,
       region_threshold_row_, region_threshold_rows_);
  }

 private:
  static bool raw_ok(std::size_t n) { return n <= raw_cap; }

  bool enabled_ = false;
  std::size_t sites_ = 0;
  Histogram lifetime_, detached_, age_, threshold_, drawn_;
  core::FrontClasses front_;
  std::vector<std::size_t> class_bin_;  ///< log time bin → class time bin
  std::size_t class_bins_ = 0;
  std::vector<double> class_edges_, class_lifetime_, class_age_, class_threshold_;  ///< [12 × bins]
  std::vector<double> snapshots_per_phase_, snapshot_phase_, region_age_row_, region_age_rows_;
  std::vector<double> region_threshold_row_, region_threshold_rows_;  ///< [3 × nt], per snapshot
  std::vector<std::uint64_t> detach_total_, attach_total_;  ///< [sites] over the run
  std::size_t n_lifetimes_ = 0, n_detached_ = 0;
  std::vector<double> lifetimes_, lifetime_start_, detached_durations_, detached_start_;
  std::vector<std::uint64_t> detach_count_, attach_count_;  ///< [sites] since the last snapshot
  std::vector<double> snapshot_t_, age_rows_, threshold_rows_, detach_rows_, attach_rows_;
};

}  // namespace slipfront::discrete
