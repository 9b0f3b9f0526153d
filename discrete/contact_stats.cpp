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
}

void Histogram::add(double x) {
  // bin b holds [e_b, e_{b+1}); below e_0 → bin 0, at or above e_n → last bin
  const auto it = std::upper_bound(edges_.begin() + 1, edges_.end() - 1, x);
  counts_[static_cast<std::size_t>(it - (edges_.begin() + 1))] += 1.0;
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

ContactStats::ContactStats(std::size_t sites, double threshold_max)
    : enabled_(true), sites_(sites), lifetime_(log_time_edges()), detached_(log_time_edges()),
      age_(log_time_edges()), threshold_(linear_edges(threshold_max, 100)),
      detach_count_(sites, 0), attach_count_(sites, 0) {}

void ContactStats::begin_snapshot(double t) {
  snapshot_t_.push_back(t);
  age_.clear();
  threshold_.clear();
}

void ContactStats::end_snapshot() {
  age_rows_.insert(age_rows_.end(), age_.counts().begin(), age_.counts().end());
  threshold_rows_.insert(threshold_rows_.end(), threshold_.counts().begin(), threshold_.counts().end());
  for (std::size_t i = 0; i < sites_; ++i) {
    detach_rows_.push_back(static_cast<double>(detach_count_[i]));
    attach_rows_.push_back(static_cast<double>(attach_count_[i]));
  }
  std::fill(detach_count_.begin(), detach_count_.end(), 0);
  std::fill(attach_count_.begin(), attach_count_.end(), 0);
}

ContactTables ContactStats::tables() const {
  ContactTables out;
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
  return out;
}

}  // namespace slipfront::discrete
