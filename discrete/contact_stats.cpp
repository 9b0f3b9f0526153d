#include "discrete/contact_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slipfront::discrete {

Histogram::Histogram(std::vector<double> edges) : edges_(std::move(edges)) {
  if (edges_.size() < 2 || !std::is_sorted(edges_.begin(), edges_.end()))
    throw std::invalid_argument("Histogram: need at least two ascending edges");
  counts_.assign(edges_.size() - 1, 0.0);
  // interior edges e_1 .. e_{n−1} geometric (ratio constant to 1e-12) and positive: the fast path
  const std::size_t n = edges_.size() - 1;
  if (n >= 4 && edges_[1] > 0.0 && std::isfinite(edges_[n - 1])) {
    const double ratio = std::log2(edges_[2] / edges_[1]);
    bool geometric = ratio > 0.0;
    for (std::size_t k = 2; geometric && k < n; ++k)
      geometric = std::abs(std::log2(edges_[k] / edges_[k - 1]) - ratio) < 1e-9 * ratio;
    if (geometric) {
      geometric_ = true;
      log2_lo_ = std::log2(edges_[1]);
      bins_per_log2_ = 1.0 / ratio;
    }
  }
}

std::size_t Histogram::bin(double x) const {
  // bin b holds [e_b, e_{b+1}); below e_1 → bin 0, at or above e_{n−1} (or NaN) → the last bin
  const std::size_t last = edges_.size() - 2;
  if (geometric_) {
    if (x < edges_[1]) return 0;
    if (!(x < edges_[last])) return last;
    // log2 x ≈ e + p(m), x = m 2^e, m ∈ [0.5, 1): a least-squares cubic within 0.0014 of log2 m; the loops make
    // the result exact
    int e = 0;
    const double m = std::frexp(x, &e);
    const double l2 = e + (-3.13382433 + m * (6.02148744 + m * (-4.11800022 + m * 1.23131817)));
    auto k = static_cast<std::ptrdiff_t>(1.0 + std::floor((l2 - log2_lo_) * bins_per_log2_));
    k = std::clamp<std::ptrdiff_t>(k, 1, static_cast<std::ptrdiff_t>(last) - 1);
    auto b = static_cast<std::size_t>(k);
    while (x < edges_[b]) --b;
    while (x >= edges_[b + 1]) ++b;
    return b;
  }
  const auto it = std::upper_bound(edges_.begin() + 1, edges_.end() - 1, x);
  return static_cast<std::size_t>(it - (edges_.begin() + 1));
}

void Histogram::clear() { std::fill(counts_.begin(), counts_.end(), 0.0); }

std::vector<double> log_time_edges(double lo, double hi, int per_decade) {
  std::vector<double> e{0.0};
  const int decades = static_cast<int>(std::lround(std::log10(hi / lo)));
  for (int k = 0; k <= decades * per_decade; ++k) e.push_back(lo * std::pow(10.0, static_cast<double>(k) / per_decade));
  e.push_back(std::numeric_limits<double>::infinity());
  return e;
}

std::vector<double> linear_edges(double s_max, int n) {
  std::vector<double> e;
  for (int k = 0; k <= n; ++k) e.push_back(s_max * static_cast<double>(k) / n);
  e.push_back(std::numeric_limits<double>::infinity());
  return e;
}

std::vector<double> threshold_edges(double width) { return linear_edges(std::max(2.0, 1.0 + 8.0 * width), 100); }

std::vector<double> class_time_edges() {
  const std::vector<double> fine = log_time_edges();  // fine[k] = 1e-6 · 10^{(k−1)/10}, k ≥ 1
  std::vector<double> e{0.0};
  for (std::size_t k = 31; k <= 101; k += 2) e.push_back(fine[k]);  // 1e-3 … 1e4
  e.push_back(std::numeric_limits<double>::infinity());
  return e;
}

std::vector<std::size_t> coarse_bin_map(const std::vector<double>& fine, const std::vector<double>& coarse) {
  const Histogram h(coarse);
  std::vector<std::size_t> map(fine.size() - 1);
  for (std::size_t b = 0; b + 1 < fine.size(); ++b) map[b] = h.bin(fine[b]);
  return map;
}

ContactStats::ContactStats(std::size_t sites, std::vector<double> edges)
    : enabled_(true), sites_(sites), lifetime_(log_time_edges()), detached_(log_time_edges()),
      age_(log_time_edges()), threshold_(edges), drawn_(std::move(edges)),
      class_bin_(coarse_bin_map(log_time_edges(), class_time_edges())), class_edges_(class_time_edges()),
      snapshots_per_phase_(core::FrontClasses::phases, 0.0), detach_total_(sites, 0), attach_total_(sites, 0),
      detach_count_(sites, 0), attach_count_(sites, 0) {
  class_bins_ = class_edges_.size() - 1;
  class_lifetime_.assign(core::FrontClasses::count * class_bins_, 0.0);
  class_age_.assign(core::FrontClasses::count * class_bins_, 0.0);
  class_threshold_.assign(core::FrontClasses::count * threshold_.bins(), 0.0);
  region_age_row_.assign(core::FrontClasses::regions * class_bins_, 0.0);
  region_threshold_row_.assign(core::FrontClasses::regions * threshold_.bins(), 0.0);
}

void ContactStats::begin_snapshot(double t) {
  snapshot_t_.push_back(t);
  if (front_.classed()) snapshots_per_phase_[front_.phase] += 1.0;
  snapshot_phase_.push_back(static_cast<double>(front_.phase));
  std::fill(region_age_row_.begin(), region_age_row_.end(), 0.0);
  std::fill(region_threshold_row_.begin(), region_threshold_row_.end(), 0.0);
  age_.clear();
  threshold_.clear();
}

void ContactStats::end_snapshot() {
  region_age_rows_.insert(region_age_rows_.end(), region_age_row_.begin(), region_age_row_.end());
  region_threshold_rows_.insert(region_threshold_rows_.end(), region_threshold_row_.begin(), region_threshold_row_.end());
  age_rows_.insert(age_rows_.end(), age_.counts().begin(), age_.counts().end());
  threshold_rows_.insert(threshold_rows_.end(), threshold_.counts().begin(), threshold_.counts().end());
  for (std::size_t i = 0; i < sites_; ++i) {
    detach_rows_.push_back(static_cast<double>(detach_count_[i]));
    attach_rows_.push_back(static_cast<double>(attach_count_[i]));
  }
  std::fill(detach_count_.begin(), detach_count_.end(), 0);
  std::fill(attach_count_.begin(), attach_count_.end(), 0);
}

core::ContactTables ContactStats::tables() const {
  core::ContactTables out;
  if (!enabled_) return out;
  auto& c = out.columns;
  c["lifetime_hist_edges"] = lifetime_.edges();
  c["lifetime_hist_counts"] = lifetime_.counts();
  c["lifetime_total"] = {static_cast<double>(n_lifetimes_)};
  c["detached_hist_edges"] = detached_.edges();
  c["detached_hist_counts"] = detached_.counts();
  c["detached_total"] = {static_cast<double>(n_detached_)};
  if (raw_ok(n_lifetimes_)) {
    c["lifetimes"] = lifetimes_;
    c["lifetime_start_t"] = lifetime_start_;
  }
  if (raw_ok(n_detached_)) {
    c["detached_durations"] = detached_durations_;
    c["detached_start_t"] = detached_start_;
  }
  c["snapshot_t"] = snapshot_t_;
  c["age_hist_edges"] = age_.edges();
  c["threshold_hist_edges"] = threshold_.edges();
  out.tables["age_hist_counts"] = {age_.bins(), age_rows_};
  out.tables["threshold_hist_counts"] = {threshold_.bins(), threshold_rows_};
  out.tables["detachments_per_site"] = {sites_, detach_rows_};
  out.tables["attachments_per_site"] = {sites_, attach_rows_};
  // resolved by region and phase (docs/model.md §7.2)
  c["class_time_edges"] = class_edges_;
  c["threshold_drawn_counts"] = drawn_.counts();
  c["contact_snapshots_per_phase"] = snapshots_per_phase_;
  c["contact_snapshot_phase"] = snapshot_phase_;
  out.tables["region_age_counts"] = {core::FrontClasses::regions * class_bins_, region_age_rows_};
  out.tables["region_threshold_counts"] = {core::FrontClasses::regions * threshold_.bins(), region_threshold_rows_};
  auto& dt = c["detachments_total_per_site"];
  auto& at = c["attachments_total_per_site"];
  for (std::size_t i = 0; i < sites_; ++i) {
    dt.push_back(static_cast<double>(detach_total_[i]));
    at.push_back(static_cast<double>(attach_total_[i]));
  }
  out.tables["class_lifetime_counts"] = {class_bins_, class_lifetime_};
  out.tables["class_age_counts"] = {class_bins_, class_age_};
  out.tables["class_threshold_counts"] = {threshold_.bins(), class_threshold_};
  return out;
}

}  // namespace slipfront::discrete
