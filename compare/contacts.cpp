#include "compare/contacts.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/random/binomial_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slipfront::compare {
namespace {

constexpr double negligible = 1e-14;  // cohorts below this fraction of a site are dropped

// (1 − e^{−x dt})/x for any real x (x < 0 allowed: a wrong prediction's hazard above the healing rate).
double weight(double x, double dt) { return x != 0.0 ? -std::expm1(-x * dt) / x : dt; }

}  // namespace

ContactPrediction::ContactPrediction(std::size_t sites, double contacts_per_site, double hazard_scale,
                                     double cohort_width, double age_cap, std::size_t classes)
    : n_contacts_(contacts_per_site), scale_(hazard_scale), width_(cohort_width), age_cap_(age_cap),
      classes_(classes), edges_(discrete::class_time_edges()), bins_(edges_.size() - 1), cohorts_(sites * classes),
      compacted_size_(sites * classes, 0),
      lifetime_(core::FrontClasses::count * bins_, 0.0), age_(core::FrontClasses::count * bins_, 0.0),
      detach_total_(sites, 0.0), attach_total_(sites, 0.0), snapshots_per_phase_(core::FrontClasses::phases, 0.0) {
  if (!(cohort_width > 0.0)) throw std::invalid_argument("ContactPrediction: cohort_width must be > 0");
  if (classes == 0) throw std::invalid_argument("ContactPrediction: at least one class per site");
}

std::size_t ContactPrediction::cohorts(std::size_t i) const {
  std::size_t n = 0;
  for (std::size_t b = 0; b < classes_; ++b) n += cohorts_[i * classes_ + b].size();
  return n;
}

void ContactPrediction::start(std::span<const double> areas) {
  for (std::size_t i = 0; i < cohorts_.size(); ++i) {
    cohorts_[i].clear();
    if (areas[i] > negligible) cohorts_[i].push_back({0.0, 0.0, areas[i], 0.0, 0.0});
  }
  // the shared tail: the last classes of a site with the same attached fraction (their cohorts are the same)
  const std::size_t sites = cohorts_.size() / classes_;
  tail_.assign(sites, 0);
  for (std::size_t i = 0; i < sites; ++i) {
    const double* a = areas.data() + i * classes_;
    std::size_t g = classes_ - 1;
    while (g > 0 && a[g - 1] == a[classes_ - 1]) --g;
    tail_[i] = g;
    for (std::size_t b = g + 1; b < classes_; ++b) cohorts_[i * classes_ + b].clear();
  }
  max_cohorts_ = 1;
}

std::size_t ContactPrediction::split_tail(std::size_t i, std::span<const double> area0, std::span<const double> hazard,
                                          std::span<const double> totals) {
  const std::size_t first = i * classes_, last = first + classes_ - 1, g = tail_[i];
  auto same = [&](std::size_t k) {
    return area0[k] == area0[last] && hazard[k] == hazard[last] && (totals.empty() || totals[k] == totals[last]);
  };
  std::size_t h = classes_ - 1;  // the classes [h, B) get the same inputs this step
  while (h > g && same(first + h - 1)) --h;
  if (h > g) {  // classes [g, h) leave the tail: each with a copy of its cohorts (the same until now)
    for (std::size_t b = g + 1; b <= h; ++b) {
      cohorts_[first + b] = cohorts_[first + g];
      compacted_size_[first + b] = compacted_size_[first + g];
    }
    tail_[i] = h;
  }
  return tail_[i];
}

std::size_t ContactPrediction::bin(double x) const {
  const auto it = std::upper_bound(edges_.begin() + 1, edges_.end() - 1, x);
  return static_cast<std::size_t>(it - (edges_.begin() + 1));
}

double ContactPrediction::mean_back(double tilt, double w) {
  const double lw = tilt * w;  // 1/tilt − w/(e^{tilt w} − 1), → w/2 as tilt w → 0
  return lw < 1e-6 ? 0.5 * w * (1.0 - lw / 6.0) : 1.0 / tilt - w / std::expm1(lw);
}

double ContactPrediction::share_before(const Cohort& c, double x) {
  if (x >= c.end) return 1.0;
  if (x < c.start) return 0.0;
  const double w = c.end - c.start, lw = c.tilt * w;
  if (lw < 1e-9) return (x - c.start) / w;  // uniform
  return (std::expm1(c.tilt * (x - c.end)) - std::expm1(-lw)) / -std::expm1(-lw);
}

void ContactPrediction::add_losses(std::size_t cls, const Cohort& c, double mass, double t0, double dt, double rate,
                                   std::size_t b) {
  double* row = lifetime_.data() + cls * bins_;
  const double l_max = t0 + dt - c.start;
  if (edges_[b + 1] >= l_max) {  // the usual case: the whole loss in one bin
    row[b] += mass;
    return;
  }
  // the cumulative fractions at the edges the lifetimes straddle depend on the cohort's shape and the
  // step, not on its mass: computed once per site and step for every class with this shape (split_cache_)
  // (the classes' cohorts come in the same order: the entry after the last one used is tried first)
  const LossSplit* split = nullptr;
  auto fits = [&](const LossSplit& e) { return e.start == c.start && e.end == c.end && e.tilt == c.tilt && e.rate == rate; };
  if (split_next_ < split_cache_.size() && fits(split_cache_[split_next_])) {
    split = &split_cache_[split_next_];
  } else {
    for (const LossSplit& e : split_cache_)
      if (fits(e)) {
        split = &e;
        break;
      }
  }
  if (split == nullptr) {
    // F(x): the fraction of the step's loss that happened by t0 + x (frozen hazard)
    const double norm = -std::expm1(-rate * dt);
    auto lost_by = [&](double x) {
      if (x <= 0.0) return 0.0;
      if (x >= dt) return 1.0;
      return rate * dt < 1e-12 ? x / dt : -std::expm1(-rate * x) / norm;
    };
    // P(lifetime < l) = ∫ density(s) F(l + s − t0) ds: the attachment times after t0 + dt − l count
    // whole; those in (t0 − l, t0 + dt − l) by 5-point Gauss–Legendre on the smooth integrand
    static constexpr double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                     0.9061798459386640};
    static constexpr double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                     0.2369268850561891};
    const double width = c.end - c.start;
    auto cdf = [&](double l) {
      if (width <= 0.0) return lost_by(l + c.end - t0);
      double p = 1.0 - share_before(c, t0 + dt - l);
      const double lo = std::max(c.start, t0 - l), hi = std::min(c.end, t0 + dt - l);
      if (hi > lo) {
        const double lw = c.tilt * width;
        const double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
        double sum = 0.0;
        for (int k = 0; k < 5; ++k) {
          const double s = mid + half * gx[k];
          const double dens = lw < 1e-9 ? 1.0 / width : c.tilt * std::exp(c.tilt * (s - c.end)) / -std::expm1(-lw);
          sum += gw[k] * dens * lost_by(l + s - t0);
        }
        p += half * sum;
      }
      return std::clamp(p, 0.0, 1.0);
    };
    LossSplit e{c.start, c.end, c.tilt, rate, b, split_values_.size(), 0};
    double done = 0.0;
    for (std::size_t k = b; edges_[k + 1] < l_max; ++k) {
      done = std::max(done, cdf(edges_[k + 1]));
      split_values_.push_back(done);
    }
    e.end_index = split_values_.size();
    split_cache_.push_back(e);
    split = &split_cache_.back();
  }
  split_next_ = static_cast<std::size_t>(split - split_cache_.data()) + 1;
  double done = 0.0;
  for (std::size_t k = split->begin; k < split->end_index; ++k, ++b) {
    const double f = split_values_[k];
    row[b] += mass * (f - done);
    done = f;
  }
  row[b] += mass * (1.0 - done);
}

void ContactPrediction::add_ages(std::vector<double>& table, std::size_t cls, const Cohort& c, double t, double mass) {
  double* row = table.data() + cls * bins_;
  const double lo = t - c.end, hi = t - c.start;
  std::size_t b = bin(lo);
  if (!(hi > lo) || edges_[b + 1] >= hi) {
    row[b] += mass;
    return;
  }
  double done = 0.0;  // P(age < a) = P(s > t − a)
  for (; edges_[b + 1] < hi; ++b) {
    const double f = std::max(done, 1.0 - share_before(c, t - edges_[b + 1]));
    row[b] += mass * (f - done);
    done = f;
  }
  row[b] += mass * (1.0 - done);
}

const ContactPrediction::RateTerms& ContactPrediction::rate_terms(double h, double dt) {
  for (const RateTerms& e : rate_cache_)
    if (e.h == h) return e;
  RateTerms e;
  e.h = h;
  e.hs = scale_ * h;
  const double hs = e.hs, r = 1.0 + h;
  e.birth_weight = weight(r, dt);
  e.back = mean_back(hs, dt);
  if (hs > 0.0) {
    e.decay = std::exp(-hs * dt);
    e.loss = -std::expm1(-hs * dt);
    e.surv_weight = weight(hs, dt);
    e.surv_exp = std::exp(-hs * dt);
    e.surv_cross = weight(r - hs, dt);
    // the lifetimes of the contacts born and lost in the step: density ∝ e^{−hs l} (dt − l) on [0, dt]
    // (constant attachment rate over the step), the cumulative fractions at the class edges below dt
    const double x = hs * dt;
    auto cdf = [&](double l) {  // fraction of the step's own losses with lifetime < l
      if (x < 1e-3) return (dt * l - 0.5 * l * l) / (0.5 * dt * dt);
      return ((1.0 / hs - dt) * std::expm1(-hs * l) + l * std::exp(-hs * l)) /
             ((1.0 / hs - dt) * std::expm1(-x) + dt * std::exp(-x));
    };
    e.young_begin = split_values_.size();
    for (std::size_t b = 0; edges_[b + 1] < dt; ++b) split_values_.push_back(cdf(edges_[b + 1]));
    e.young_end = split_values_.size();
  }
  rate_cache_.push_back(e);
  return rate_cache_.back();
}

void ContactPrediction::step(double dt, std::span<const double> area0, std::span<const double> hazard,
                             std::span<const double> totals) {
  const double t0 = clock_, t1 = t0 + dt;
  clock_ = t1;
  std::size_t tail = 0;
  for (std::size_t k = 0; k < cohorts_.size(); ++k) {
    const std::size_t i = k / classes_;  // the site of sub-population k
    if (k % classes_ == 0) {             // what the classes of one site share (RateTerms, LossSplit)
      rate_cache_.clear();
      split_cache_.clear();
      split_values_.clear();
      tail = i * classes_ + split_tail(i, area0, hazard, totals);
    }
    if (k > tail) continue;  // in the shared tail, held at class `tail`
    split_next_ = 0;
    const double nm = k == tail ? n_contacts_ * static_cast<double>(classes_ - k % classes_) : n_contacts_;
    const RateTerms rt = rate_terms(hazard[k], dt);
    const double hs = rt.hs, a0 = area0[k], r = 1.0 + rt.h, T = totals.empty() ? 1.0 : totals[k];
    const std::size_t cls = front_.class_of(i);
    const bool classed = front_.classed();  // phase next_event: the cohorts go on, their losses are not classed
    // attachments over the step, ∫(T − A) dt with A(u) = T/r + (a0 − T/r) e^{−ru} (the law's own A; T = 1:
    // the same operations as before classes existed, 1.0 × x being x)
    const double births = T * dt - (T * dt / r + (a0 - T / r) * rt.birth_weight);
    auto& cs = cohorts_[k];
    double lost = 0.0, survivors = births;
    if (hs > 0.0) {
      // every cohort decays by e^{−hs dt}; its loss goes to the lifetimes of the site's class
      const double decay = rt.decay, loss = rt.loss;
      // the cohorts are in attachment order, oldest first: their shortest lifetimes t0 − end decrease, and
      // the bin of each is found by walking down from the previous one (bin() of the first)
      std::size_t w = 0, b = cs.empty() ? 0 : bin(t0 - cs.front().end);
      bool dropped = false;
      double* lrow = lifetime_.data() + cls * bins_;
      const double t1_less = t0 + dt;
      for (std::size_t j = 0; j < cs.size(); ++j) {
        Cohort& c = cs[j];
        const double gone = c.mass * loss;
        c.mass *= decay;
        lost += gone;
        const double l_min = t0 - c.end;
        while (b > 0 && l_min < edges_[b]) --b;
        if (classed) {
          if (edges_[b + 1] >= t1_less - c.start) lrow[b] += gone * nm;  // add_losses' usual case, inline
          else add_losses(cls, c, gone * nm, t0, dt, hs, b);
        }
        dropped |= !(c.mass >= negligible);
      }
      if (dropped) {
        for (std::size_t j = 0; j < cs.size(); ++j)
          if (cs[j].mass >= negligible) cs[w++] = cs[j];
        cs.resize(w);
      }
      // the contacts born in the step that are still attached at its end, and the lifetimes of the
      // others (RateTerms: their cumulative fractions at the class edges below dt)
      survivors = (T - T / r) * rt.surv_weight - (a0 - T / r) * rt.surv_exp * rt.surv_cross;
      const double gone_new = std::max(0.0, births - survivors);
      lost += gone_new;
      if (gone_new > 0.0 && classed) {
        std::size_t yb = 0;
        double done = 0.0;
        for (std::size_t q = rt.young_begin; q < rt.young_end; ++q, ++yb) {
          const double f = split_values_[q];
          lrow[yb] += gone_new * nm * (f - done);
          done = f;
        }
        lrow[yb] += gone_new * nm * (1.0 - done);
      }
    }
    if (survivors >= negligible) cs.push_back({t0, t1, survivors, hs, t1 - rt.back});
    detach_total_[i] += lost * nm;
    attach_total_[i] += births * nm;
    if (cs.size() > compacted_size_[k] + 16) compact(k, t1);
    max_cohorts_ = std::max(max_cohorts_, cs.size());
  }
}

// Merge neighbours (oldest first) while the merged attachment interval is at most width × its youngest
// age, or that age is past age_cap.
void ContactPrediction::compact(std::size_t i, double t) {
  auto& cs = cohorts_[i];
  std::size_t w = 0;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    if (w > 0) {
      Cohort& prev = cs[w - 1];
      const double young = t - cs[k].end;
      if (cs[k].end - prev.start <= width_ * young || young >= age_cap_) {
        prev.end = cs[k].end;
        prev.mean = (prev.mass * prev.mean + cs[k].mass * cs[k].mean) / (prev.mass + cs[k].mass);
        prev.mass += cs[k].mass;
        prev.tilt = 0.0;  // old and narrow against its age: uniform (its mean is kept)
        continue;
      }
    }
    cs[w++] = cs[k];
  }
  cs.resize(w);
  compacted_size_[i] = w;
}

void ContactPrediction::set_thresholds(std::vector<double> edges, std::vector<double> spread) {
  if (edges.size() < 2 || spread.size() != classes_ * (edges.size() - 1))
    throw std::invalid_argument("ContactPrediction::set_thresholds: the spread is not [classes x threshold bins]");
  threshold_edges_ = std::move(edges);
  spread_ = std::move(spread);
  class_threshold_.assign(core::FrontClasses::count * (threshold_edges_.size() - 1), 0.0);
}

void ContactPrediction::snapshot_thresholds(bool classed) {
  const std::size_t nt = threshold_edges_.size() - 1, regions = core::FrontClasses::regions, B = classes_;
  const std::size_t first = region_threshold_rows_.size();
  region_threshold_rows_.resize(first + regions * nt, 0.0);
  if (!classed) return;  // phase next_event: rows of zeros, as the agent's
  // the attached mass per (region, class); a shared tail counts once for each of its classes [tail_, B): added
  // at tail_ to a running sum over the classes (tail)
  std::vector<double> mass(regions * B, 0.0), tail(regions * B, 0.0);
  for (std::size_t k = 0; k < cohorts_.size(); ++k) {
    const std::size_t i = k / B, b = k % B;
    double m = 0.0;
    for (const Cohort& c : cohorts_[k]) m += c.mass;
    if (m == 0.0) continue;
    const std::size_t r = front_.class_of(i) % regions;
    (b == tail_[i] ? tail : mass)[r * B + b] += m * n_contacts_;
  }
  double* rows = region_threshold_rows_.data() + first;
  double* cls_rows = class_threshold_.data() + regions * front_.phase * nt;
  for (std::size_t r = 0; r < regions; ++r) {
    double run = 0.0;
    for (std::size_t b = 0; b < B; ++b) {
      run += tail[r * B + b];
      const double m = mass[r * B + b] + run;
      if (m == 0.0) continue;
      const double* w = spread_.data() + b * nt;
      for (std::size_t j = 0; j < nt; ++j) rows[r * nt + j] += m * w[j];
    }
    for (std::size_t j = 0; j < nt; ++j) cls_rows[r * nt + j] += rows[r * nt + j];
  }
}

void ContactPrediction::snapshot() {
  const double t = clock_;
  snapshot_t_.push_back(t);
  snapshot_phase_.push_back(static_cast<double>(front_.phase));
  if (!spread_.empty()) snapshot_thresholds(front_.classed());
  if (!front_.classed()) {  // phase next_event: a snapshot with no classed ages (rows of zeros, as the agent's)
    region_age_rows_.insert(region_age_rows_.end(), core::FrontClasses::regions * bins_, 0.0);
    return;
  }
  snapshots_per_phase_[front_.phase] += 1.0;
  // this snapshot's ages by region: the class rows of the current phase, before and after
  const std::size_t regions = core::FrontClasses::regions, first = regions * front_.phase * bins_;
  std::vector<double> before(age_.begin() + static_cast<std::ptrdiff_t>(first),
                             age_.begin() + static_cast<std::ptrdiff_t>(first + regions * bins_));
  for (std::size_t k = 0; k < cohorts_.size(); ++k) {
    const std::size_t cls = front_.class_of(k / classes_);
    const double nm = n_contacts_ * multiplicity(k);  // the shared tail counts B − tail_ times (empty beyond it)
    for (const Cohort& c : cohorts_[k]) add_ages(age_, cls, c, t, c.mass * nm);
  }
  for (std::size_t k = 0; k < regions * bins_; ++k) region_age_rows_.push_back(age_[first + k] - before[k]);
}

double ContactPrediction::mean_age(std::size_t i) const {
  const double t = clock_;
  double m = 0.0, s = 0.0;
  for (std::size_t b = 0; b < classes_; ++b) {
    const double mult = multiplicity(i * classes_ + b);
    for (const Cohort& c : cohorts_[i * classes_ + b]) {
      m += c.mass * mult;
      s += c.mass * mult * (t - c.mean);
    }
  }
  return m > 0.0 ? s / m : std::numeric_limits<double>::quiet_NaN();
}

double ContactPrediction::attached_mass(std::size_t i) const {
  double m = 0.0;
  for (std::size_t b = 0; b < classes_; ++b) {
    const double mult = multiplicity(i * classes_ + b);
    for (const Cohort& c : cohorts_[i * classes_ + b]) m += c.mass * mult;
  }
  return m;
}

core::ContactTables ContactPrediction::tables() const {
  core::ContactTables out;
  auto& c = out.columns;
  c["class_time_edges"] = edges_;
  c["contact_snapshots_per_phase"] = snapshots_per_phase_;
  c["detachments_total_per_site"] = detach_total_;
  c["attachments_total_per_site"] = attach_total_;
  double total = 0.0;
  for (double x : lifetime_) total += x;
  c["lifetime_total"] = {total};
  out.tables["class_lifetime_counts"] = {bins_, lifetime_};
  out.tables["class_age_counts"] = {bins_, age_};
  out.tables["region_age_counts"] = {core::FrontClasses::regions * bins_, region_age_rows_};
  c["snapshot_t"] = snapshot_t_;
  c["contact_snapshot_phase"] = snapshot_phase_;
  if (!spread_.empty()) {
    const std::size_t nt = threshold_edges_.size() - 1;
    c["threshold_hist_edges"] = threshold_edges_;
    out.tables["class_threshold_counts"] = {nt, class_threshold_};
    out.tables["region_threshold_counts"] = {core::FrontClasses::regions * nt, region_threshold_rows_};
  }
  return out;
}

std::vector<double> threshold_spread(const discrete::ThresholdDistribution& g, std::size_t classes,
                                     const std::vector<double>& edges) {
  const std::size_t nt = edges.size() - 1, B = classes;
  std::vector<double> out(B * nt, 0.0);
  if (g.degenerate()) {
    const std::size_t j = discrete::Histogram(edges).bin(1.0);
    for (std::size_t b = 0; b < B; ++b) out[b * nt + j] = 1.0;
    return out;
  }
  std::vector<double> G(nt + 1);
  for (std::size_t j = 0; j <= nt; ++j) G[j] = std::isfinite(edges[j]) ? g.cdf(edges[j]) : 1.0;
  G.front() = 0.0;  // every support is s ≥ 0 (discrete/thresholds.hpp); the last bin is [s_max, ∞)
  G.back() = 1.0;
  const double nb = static_cast<double>(B);
  for (std::size_t b = 0; b < B; ++b) {
    const double lo = static_cast<double>(b) / nb, hi = static_cast<double>(b + 1) / nb;
    for (std::size_t j = 0; j < nt; ++j)
      out[b * nt + j] = nb * std::max(0.0, std::min(G[j + 1], hi) - std::max(G[j], lo));
  }
  return out;
}

std::pair<Table2D, Table2D> matched_tables(const ModelResult& measured, const ModelResult& predicted,
                                           const std::string& table) {
  std::pair<Table2D, Table2D> out;
  const auto find_col = [](const ModelResult& r, const char* name) -> const std::vector<double>* {
    const auto it = r.contacts.find(name);
    return it == r.contacts.end() ? nullptr : &it->second;
  };
  const auto* tm = find_col(measured, "snapshot_t");
  const auto* tp = find_col(predicted, "snapshot_t");
  const auto* pm = find_col(measured, "contact_snapshot_phase");
  const auto* pp = find_col(predicted, "contact_snapshot_phase");
  const auto am = measured.contacts_2d.find(table), ap = predicted.contacts_2d.find(table);
  if (!tm || !tp || !pm || !pp || am == measured.contacts_2d.end() || ap == predicted.contacts_2d.end()) return out;
  const std::size_t ns = tm->size(), cols = am->second.cols, regions = core::FrontClasses::regions;
  if (tp->size() != ns || pm->size() != ns || pp->size() != ns || ap->second.cols != cols || cols % regions != 0 ||
      am->second.data.size() != ns * cols || ap->second.data.size() != ns * cols)
    return out;
  for (std::size_t k = 0; k < ns; ++k)
    if (std::abs((*tm)[k] - (*tp)[k]) > 1e-9 * std::max(1.0, std::abs((*tm)[k]))) return out;
  const std::size_t nb = cols / regions;
  for (Table2D* t : {&out.first, &out.second}) {
    t->cols = nb;
    t->data.assign(core::FrontClasses::count * nb, 0.0);
  }
  for (std::size_t k = 0; k < ns; ++k) {
    if ((*pm)[k] != (*pp)[k]) continue;  // the models are in different phases: different moments
    const auto phase = static_cast<std::size_t>((*pm)[k]);
    if (phase >= core::FrontClasses::phases) continue;  // next_event: not classed
    for (std::size_t j = 0; j < cols; ++j) {
      out.first.data[phase * cols + j] += am->second.data[k * cols + j];
      out.second.data[phase * cols + j] += ap->second.data[k * cols + j];
    }
  }
  return out;
}

std::vector<ContactFit> contact_fit(const std::string& statistic, const Table2D& measured, const Table2D& predicted,
                                    double m, double min_total, std::uint64_t seed) {
  if (measured.cols != predicted.cols || measured.data.size() != predicted.data.size() || measured.cols == 0)
    throw std::invalid_argument("contact_fit: measured and predicted tables differ in shape");
  const std::size_t nb = measured.cols, rows = measured.data.size() / nb;
  std::vector<ContactFit> out;
  boost::random::mt19937_64 engine(seed);
  for (std::size_t cls = 0; cls < rows; ++cls) {
    ContactFit f;
    f.statistic = statistic;
    f.phase = cls / core::FrontClasses::regions;
    f.region = cls % core::FrontClasses::regions;
    const double* n = measured.data.data() + cls * nb;
    const double* mu = predicted.data.data() + cls * nb;
    for (std::size_t k = 0; k < nb; ++k) {
      f.measured_total += n[k];
      f.predicted_total += mu[k];
    }
    if (!(f.measured_total > 0.0 && f.predicted_total > 0.0)) {
      f.ks_distance = f.measured_total == f.predicted_total ? 0.0 : 1.0;
      out.push_back(f);
      continue;
    }
    // the whole population: binned Kolmogorov distance
    double fm = 0.0, fp = 0.0;
    for (std::size_t k = 0; k < nb; ++k) {
      fm += n[k] / f.measured_total;
      fp += mu[k] / f.predicted_total;
      f.ks_distance = std::max(f.ks_distance, std::abs(fm - fp));
    }
    // bins merged until each predicted probability is ≥ 5/m' (the tail left over joins the last group)
    f.thinned_size = f.measured_total > m ? std::floor(m) : f.measured_total;
    const double need = 5.0 / f.thinned_size;
    std::vector<double> p, q;
    double acc_p = 0.0, acc_q = 0.0;
    for (std::size_t k = 0; k < nb; ++k) {
      acc_p += mu[k] / f.predicted_total;
      acc_q += n[k] / f.measured_total;
      if (acc_p >= need) {
        p.push_back(acc_p);
        q.push_back(acc_q);
        acc_p = acc_q = 0.0;
      }
    }
    if (!p.empty()) {
      p.back() += acc_p;
      q.back() += acc_q;
    }
    f.dof = p.size() > 1 ? static_cast<double>(p.size() - 1) : 0.0;
    // thinning: a uniform subsample of m' measured contacts, multinomial over the merged bins (no
    // thinning when there are at most m: the measured counts themselves)
    const bool thin = f.measured_total > m;
    auto left = static_cast<long long>(f.thinned_size);
    double rest = 1.0;
    for (std::size_t g = 0; g < p.size(); ++g) {
      double y = q[g] * f.measured_total;
      if (thin) {
        long long draw = left;
        if (g + 1 < p.size()) {
          const double prob = rest > 0.0 ? std::clamp(q[g] / rest, 0.0, 1.0) : 0.0;
          draw = boost::random::binomial_distribution<long long>(left, prob)(engine);
        }
        left -= draw;
        rest -= q[g];
        y = static_cast<double>(draw);
      }
      const double e = f.thinned_size * p[g];
      f.chi2 += (y - e) * (y - e) / e;
    }
    f.tested = f.measured_total >= min_total && f.dof >= 1.0;
    if (f.dof >= 1.0) {
      const boost::math::chi_squared chi(f.dof);
      f.p_value = boost::math::cdf(boost::math::complement(chi, f.chi2));
    }
    out.push_back(f);
  }
  return out;
}

}  // namespace slipfront::compare
