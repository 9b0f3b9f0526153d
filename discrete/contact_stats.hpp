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
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace slipfront::discrete {

/// Plain tables for the writer: 1D columns and row-major 2D tables [data.size()/cols, cols].
struct ContactTables {
  struct Table {
    std::size_t cols = 0;
    std::vector<double> data;
  };
  std::map<std::string, std::vector<double>> columns;
  std::map<std::string, Table> tables;
};

/// Histogram on fixed edges; values outside [edges.front(), edges.back()) are counted in the first /
/// last bin (the default edges start at 0 and end at +∞, so nothing is clipped).
class Histogram {
 public:
  Histogram() = default;
  explicit Histogram(std::vector<double> edges);
  void add(double x);
  const std::vector<double>& edges() const { return edges_; }
  const std::vector<double>& counts() const { return counts_; }
  std::size_t bins() const { return counts_.size(); }
  void clear();
  template <class Ar>
  void serialize(Ar& ar) {
    ar(edges_, counts_);
  }

 private:
  std::vector<double> edges_, counts_;
};

/// Edges {0, lo, lo·10^{1/k}, ..., hi, +∞}: times spanning many decades (lifetimes, ages).
std::vector<double> log_time_edges(double lo = 1e-6, double hi = 1e6, int per_decade = 10);
/// Edges {0, s_max/n, ..., s_max, +∞}: thresholds.
std::vector<double> linear_edges(double s_max, int n);

class ContactStats {
 public:
  /// Raw lifetimes / durations are kept while there are at most this many (histograms always).
  static constexpr std::size_t raw_cap = 100000;

  ContactStats() = default;  ///< disabled: every call is a no-op
  /// Enabled, for `sites` sites; thresholds histogrammed on [0, threshold_max] (+ overflow).
  ContactStats(std::size_t sites, double threshold_max);

  bool enabled() const { return enabled_; }

  /// A completed attachment of a contact of `site`: attached at `start`, lasted `lifetime`.
  void record_lifetime(std::size_t site, double start, double lifetime) {
    if (!enabled_) return;
    lifetime_.add(lifetime);
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
    ++attach_count_[site];
    ++n_detached_;
    if (n_detached_ <= raw_cap) {
      detached_durations_.push_back(duration);
      detached_start_.push_back(start);
    }
  }

  /// Snapshot at time t: call attached() for every attached contact between begin and end.
  void begin_snapshot(double t);
  void attached(double age, double threshold) {
    age_.add(age);
    threshold_.add(threshold);
  }
  void end_snapshot();

  std::size_t lifetime_count() const { return n_lifetimes_; }
  std::size_t detached_count() const { return n_detached_; }
  /// Raw values (empty once more than raw_cap were recorded).
  std::span<const double> lifetimes() const { return raw_ok(n_lifetimes_) ? lifetimes_ : std::span<const double>{}; }
  std::span<const double> lifetime_starts() const { return raw_ok(n_lifetimes_) ? lifetime_start_ : std::span<const double>{}; }
  std::span<const double> detached_durations() const { return raw_ok(n_detached_) ? detached_durations_ : std::span<const double>{}; }
  std::span<const double> detached_starts() const { return raw_ok(n_detached_) ? detached_start_ : std::span<const double>{}; }

  ContactTables tables() const;

  /// Checkpoints (continuum::Archive).
  template <class Ar>
  void serialize(Ar& ar) {
    ar(enabled_, sites_, lifetime_, detached_, age_, threshold_, n_lifetimes_, n_detached_, lifetimes_, lifetime_start_,
       detached_durations_, detached_start_, detach_count_, attach_count_, snapshot_t_, age_rows_, threshold_rows_,
       detach_rows_, attach_rows_);
  }

 private:
  static bool raw_ok(std::size_t n) { return n <= raw_cap; }

  bool enabled_ = false;
  std::size_t sites_ = 0;
  Histogram lifetime_, detached_, age_, threshold_;
  std::size_t n_lifetimes_ = 0, n_detached_ = 0;
  std::vector<double> lifetimes_, lifetime_start_, detached_durations_, detached_start_;
  std::vector<std::uint64_t> detach_count_, attach_count_;  ///< [sites] since the last snapshot
  std::vector<double> snapshot_t_, age_rows_, threshold_rows_, detach_rows_, attach_rows_;
};

}  // namespace slipfront::discrete
