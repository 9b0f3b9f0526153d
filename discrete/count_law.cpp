#include "discrete/count_law.hpp"
#include "discrete/normal_load.hpp"

#include "core/interrupt.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace slipfront::discrete {

namespace detail {

// Spread x contacts uniformly over the bins [lo, hi) (a multinomial with equal probabilities), adding them to
// counts[b]. Sparse (x < 8 per bin): each contact's bin drawn uniformly, x draws; dense: successive binomials
// 1/(hi − b), at most hi − lo draws (`share[m]`: BinomialRate(1/m), m ≥ 2). The same multinomial either way; the
// sparse draw costs one engine call per contact where the binomials cost an inversion each (docs/performance.md
// §17: the disordered validity_friction runs at N ≤ 10^4 held mostly empty bins).
inline void spread_uniform(Engine& e, double x, double* counts, std::size_t lo, std::size_t hi,
                           const std::vector<BinomialRate>& share) {
  const std::size_t m = hi - lo;
  if (m == 0 || !(x > 0.0)) return;
  if (m == 1) {  // one bin (w = 0, or one class overloaded): no draw
    counts[lo] += x;
    return;
  }
  if (x < 8.0 * static_cast<double>(m)) {
    for (auto j = static_cast<std::int64_t>(x); j > 0; --j) counts[lo + uniform_below(e, m)] += 1.0;
    return;
  }
  for (std::size_t b = lo; b < hi && x > 0.0; ++b) {
    const std::size_t left = hi - b;
    const double y = left == 1 ? x : binomial(e, x, share[left]);
    counts[b] += y;
    x -= y;
  }
}

// Whole-number split of `total` over bins with whole cumulative weights C_0 = 0 … C_B:
// out[b] = ⌊C_{b+1} total / C_B⌋ − ⌊C_b total / C_B⌋ (expectation rounding, in integers: the parts
// sum to total and out[b] ≤ ⌈(C_{b+1} − C_b) total / C_B⌉).
inline void split_rounded(double total, std::span<const std::int64_t> cumulative, double* out) {
  const std::int64_t whole = cumulative.back(), n = static_cast<std::int64_t>(total);
  std::int64_t prev = 0;
  for (std::size_t b = 0; b + 1 < cumulative.size(); ++b) {
    const std::int64_t next = cumulative[b + 1] * n / whole;
    out[b] = static_cast<double>(next - prev);
    prev = next;
  }
}

// σ̄' of docs/model.md §2: relax() of core/exact_update.hpp; at rate 0 it is σ̄ + source Δt, computed
// without the exponential (bit for bit what relax() returns there: e^{−0} = 1, weight = Δt).
inline double relax_stress(double sb, double source, double rate, double dt) {
  return rate > 0.0 ? core::relax(sb, source, rate, dt) : sb + source * dt;
}

/// Persistent worker threads; step k hands each thread the chunks of 64 sites c with
/// c mod T = its index (interleaved, so that a front near one end still spreads over threads).
/// Each site draws only from its own stream, so the result does not depend on T.
class SitePool {
 public:
  static constexpr std::size_t chunk = 64;

  explicit SitePool(int threads) : threads_(static_cast<std::size_t>(threads)) {
    for (std::size_t t = 1; t < threads_; ++t)
      workers_.emplace_back([this, t](std::stop_token st) { work(st, t); });
  }
  ~SitePool() {
    for (auto& w : workers_) w.request_stop();
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
  }
  std::size_t threads() const { return threads_; }

  bool run(CountLaw* law, double dt, const double* v) {
    law_ = law;
    dt_ = dt;
    v_ = v;
    any_.store(false, std::memory_order_relaxed);
    pending_.store(threads_ - 1, std::memory_order_relaxed);
    generation_.fetch_add(1, std::memory_order_release);
    generation_.notify_all();
    bool any = part(0);
    for (std::size_t p = pending_.load(std::memory_order_acquire); p != 0; p = pending_.load(std::memory_order_acquire))
      pending_.wait(p, std::memory_order_acquire);
    return any || any_.load(std::memory_order_relaxed);
  }

 private:
  bool part(std::size_t t) {
    const std::size_t n = law_->size();
    bool any = false;
    for (std::size_t lo = t * chunk; lo < n; lo += threads_ * chunk)
      any |= law_->advance_sites(lo, std::min(n, lo + chunk), dt_, v_);
    return any;
  }
  void work(std::stop_token st, std::size_t t) {
    std::uint64_t seen = 0;  // the generation at construction: no run can have started yet
    for (;;) {
      generation_.wait(seen, std::memory_order_acquire);
      seen = generation_.load(std::memory_order_acquire);
      if (st.stop_requested()) return;
      if (part(t)) any_.store(true, std::memory_order_relaxed);
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
    }
  }

  CountLaw* law_ = nullptr;
  std::size_t threads_;
  double dt_ = 0.0;
  const double* v_ = nullptr;
  std::atomic<std::uint64_t> generation_{0};
  std::atomic<std::size_t> pending_{0};
  std::atomic<bool> any_{false};
  std::vector<std::jthread> workers_;  // last member: joined first, while the rest is alive
};

}  // namespace detail

namespace {
const DiscreteParams& validated(const DiscreteParams& dp) {
  dp.validate();
  return dp;
}
}  // namespace

CountLaw::CountLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites)
    : ip_(ip), dp_(validated(dp)), g_(dp_.threshold, dp_.width) {
  if (sites == 0) throw std::invalid_argument("CountLaw: no sites");
  if (ip.ages_contacts())  // docs/model.md §11: counts keep no ages
    throw core::ParamError("discrete.representation", "the count representation keeps no contact ages: aging "
                                                      "(interface.aging_b > 0) needs representation = \"agent\"");
  nbins_ = g_.degenerate() ? 1 : static_cast<std::size_t>(dp.bins);
  quenched_ = dp.renewal == "quenched";
  noise_ = dp.noise;
  det_stride_ = quenched_ ? nbins_ : 1;
  n_contacts_ = static_cast<double>(dp.contacts_per_site);
  // Quantile bins [b/B, (b+1)/B) of g, each represented by its conditional mean (ascending).
  thresholds_.resize(nbins_);
  share_.resize(nbins_ + 1);
  for (std::size_t m = 2; m <= nbins_; ++m) share_[m] = detail::BinomialRate(1.0 / static_cast<double>(m));
  for (std::size_t b = 0; b < nbins_; ++b) {
    const double B = static_cast<double>(nbins_);
    thresholds_[b] = g_.conditional_mean(static_cast<double>(b) / B, static_cast<double>(b + 1) / B);
  }
  att_.assign(sites * nbins_, 0.0);
  if (keeps_unspread(dp_, nbins_)) unspread_.assign(sites, 0.0);
  det_.assign(sites * det_stride_, 0.0);
  n_att_.assign(sites, 0.0);
  area_.assign(sites, 1.0);
  sigma_bar_.assign(sites, 0.0);
  engines_.assign(sites, std::nullopt);  // seeded at each site's first draw (engine_at)
  for (std::size_t i = 0; i < sites; ++i) {
    core::poll_stop();
    set_site(i, 1.0, 0.0);
  }
}

// Worker threads only where there is more than one chunk of sites to share. A copy of the law
// starts its own threads at its first step.
int CountLaw::pool_threads() const {
  const auto chunks = static_cast<int>((size() + detail::SitePool::chunk - 1) / detail::SitePool::chunk);
  return std::min(dp_.threads, chunks);
}

CountLaw::~CountLaw() = default;
CountLaw::CountLaw(CountLaw&&) noexcept = default;
CountLaw& CountLaw::operator=(CountLaw&&) noexcept = default;
CountLaw::CountLaw(const CountLaw&) = default;
CountLaw& CountLaw::operator=(const CountLaw&) = default;

detail::PoolHandle::PoolHandle() = default;
detail::PoolHandle::~PoolHandle() = default;
detail::PoolHandle::PoolHandle(const PoolHandle&) {}
detail::PoolHandle& detail::PoolHandle::operator=(const PoolHandle&) {
  p.reset();
  return *this;
}
detail::PoolHandle::PoolHandle(PoolHandle&&) noexcept = default;
detail::PoolHandle& detail::PoolHandle::operator=(PoolHandle&&) noexcept = default;

std::span<const double> CountLaw::attached(std::size_t i) const {
  settle(i);
  return std::span<const double>(att_).subspan(i * nbins_, nbins_);
}
std::span<const double> CountLaw::detached(std::size_t i) const {
  return std::span<const double>(det_).subspan(i * det_stride_, det_stride_);
}

void CountLaw::set_normal_load(std::span<const double> factor) {
  if (factor.size() != size()) throw std::invalid_argument("CountLaw::set_normal_load: one factor per site");
  install_resting_areas(factor, ip_, rest_, sigma_bar_, reattach_, scaled_);
  for (std::size_t i = 0; i < size(); ++i) area_[i] = area_of(i, n_att_[i]);
}

void CountLaw::set_site(std::size_t i, double area_given, double sigma_bar) {
  const double area = scaled_ ? area_given / rest_[i] : area_given;  // the attached fraction (contacts of area a_i)
  if (!(area >= 0.0 && area <= 1.0)) throw std::invalid_argument("CountLaw::set_site: A must lie in [0, 1]");
  if (!unspread_.empty()) unspread_[i] = 0.0;
  double* a = att(i);
  double* d = det(i);
  const double B = static_cast<double>(nbins_);
  double total = 0.0;  // summed as advance() sums it (Y = 1 exactly when every bin is overloaded)
  if (!noise_) {
    // Fractions of the site: A/B attached per bin.
    for (std::size_t b = 0; b < nbins_; ++b) total += (a[b] = area / B);
    if (quenched_)
      for (std::size_t b = 0; b < nbins_; ++b) d[b] = 1.0 / B - a[b];
    else
      d[0] = 1.0 - total;
    n_att_[i] = total;
    area_[i] = area_of(i, total);
  } else {
    // n = round(A N) contacts over equal-probability bins: a stratified sample of g (fresh); with
    // quenched thresholds the N thresholds of the site are split first, then the attached among them.
    const double n = std::round(area * n_contacts_);
    std::vector<std::int64_t> cum(nbins_ + 1);
    for (std::size_t b = 0; b <= nbins_; ++b) cum[b] = static_cast<std::int64_t>(b);
    if (!quenched_) {
      detail::split_rounded(n, cum, a);
      d[0] = n_contacts_ - n;
    } else {
      std::vector<double> per_bin(nbins_);
      detail::split_rounded(n_contacts_, cum, per_bin.data());
      for (std::size_t b = 0; b < nbins_; ++b) cum[b + 1] = cum[b] + static_cast<std::int64_t>(per_bin[b]);
      detail::split_rounded(n, cum, a);
      for (std::size_t b = 0; b < nbins_; ++b) d[b] = per_bin[b] - a[b];
    }
    for (std::size_t b = 0; b < nbins_; ++b) total += a[b];
    n_att_[i] = total;
    area_[i] = area_of(i, total);
  }
  sigma_bar_[i] = sigma_bar;
}

// Number of overloaded bins: s_b < τ (thresholds ascending, so a prefix).
std::size_t CountLaw::overloaded_bins(double tau) const {
  if (nbins_ == 1) return tau > thresholds_[0] ? 1 : 0;
  return static_cast<std::size_t>(std::lower_bound(thresholds_.begin(), thresholds_.end(), tau) - thresholds_.begin());
}

// The unspread arrivals are wholly overloaded at k = B and wholly not at k = 0; in between (the bins now differ in
// fate) they are settled first.
double CountLaw::overloaded_count(std::size_t i, std::size_t k) const {
  if (k > 0 && k < nbins_) settle(i);
  double over = k == nbins_ ? unspread(i) : 0.0;
  for (std::size_t b = 0; b < k; ++b) over += att_[i * nbins_ + b];
  return over;
}

double CountLaw::overloaded_fraction(std::size_t i, double v) const {
  const double tau = core::contact_stress(sigma_bar_[i] + ip_.eta * v, area_[i]);
  const std::size_t k = overloaded_bins(tau);
  if (!(n_att_[i] > 0.0)) return 1.0;
  return overloaded_count(i, k) / n_att_[i];
}

void CountLaw::settle(std::size_t i) const {
  if (unspread_.empty() || !(unspread_[i] > 0.0)) return;
  detail::spread_uniform(engine_at(i), unspread_[i], att_.data() + i * nbins_, 0, nbins_, share_);
  unspread_[i] = 0.0;
}

core::LawStepInfo CountLaw::advance(double dt, std::span<const double> v) {
  if (v.size() != size()) throw std::invalid_argument("CountLaw::advance: one slip rate per site");
  if (dt != cached_dt_) {  // the non-overloaded transition (a = 1, d = 0) depends on dt only
    attach_only_ = core::two_state_transition(1.0, 0.0, dt);
    cached_free_exp_ = std::exp(-1.0 * dt);
    cached_dt_ = dt;
  }
  if (pool_threads() > 1) {
    if (!pool_.p) pool_.p = std::make_unique<detail::SitePool>(pool_threads());
    return {pool_.p->run(this, dt, v.data())};
  }
  return {advance_sites(0, size(), dt, v.data())};
}

bool CountLaw::advance_sites(std::size_t lo, std::size_t hi, double dt, const double* v) {
  const double alpha = ip_.alpha, kappa = ip_.kappa, eta = ip_.eta;
  bool any = false;
  for (std::size_t i = lo; i < hi; ++i) {
    const double vi = v[i], speed = std::abs(vi), a0 = area_[i], sb = sigma_bar_[i];
    if (!std::isfinite(vi)) {  // the stepper reports it with the step and site; do not draw on it
      sigma_bar_[i] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    // 1. load: contact stress at the start of the step, overloaded bins [0, k), yield fraction Y
    const double tau = core::contact_stress(sb + eta * vi, a0);
    if (noise_ && !reattach_ && n_att_[i] == n_contacts_ && tau <= thresholds_[0]) {
      // idle (every contact attached, none overloaded): the general path below with k = 0, A' = A
      // and Y = 0, without its calls — the same arithmetic, so the same bits
      sigma_bar_[i] = detail::relax_stress(sb, alpha * 0.5 * (a0 + a0) * vi, 0.0 * speed, dt);
      continue;
    }
    if (watch_reach_ > 0.0 && watches(i, vi, dt, watch_reach_)) {  // advance_watched: event by event
      any |= step_watched(i, vi, dt);
      continue;
    }
    const std::size_t k = overloaded_bins(tau);
    const double n_over = overloaded_count(i, k);
    const double n_att = n_att_[i];
    const double y = n_att > 0.0 ? n_over / n_att : 1.0;
    any |= speed > 0.0 && (n_over > 0.0 || !(n_att > 0.0));
    // 2.–3. contacts (the noisy step skips idle sites: no draw, no exponential)
    const double a1 = !noise_    ? step_contacts_mean(i, k, kappa * speed, dt)
                      : reattach_ ? step_contacts_reattaching(i, k, kappa * speed, dt)
                                  : step_contacts_sampled(i, k, n_over, kappa * speed, dt);
    // 4. stress: exact update with Ā = (A + A')/2 and Y frozen
    sigma_bar_[i] = detail::relax_stress(sb, alpha * 0.5 * (a0 + a1) * vi, y * speed, dt);
  }
  return any;
}

core::LawStepInfo CountLaw::advance_watched(double dt, std::span<const double> v, double reach) {
  watch_reach_ = reach;
  struct Reset {  // advance() alone never watches, whatever advance_watched's end (an exception included)
    double& r;
    ~Reset() { r = 0.0; }
  } reset{watch_reach_};
  return advance(dt, v);
}

bool CountLaw::watches(std::size_t i, double v, double dt, double reach) const {
  if (!may_watch(dp_, nbins_, !rest_.empty())) return false;
  const double n = n_att_[i];
  if (!(n > 0.0)) return false;
  const double tau = core::contact_stress(sigma_bar_[i] + ip_.eta * v, area_[i]);
  return std::abs(tau - thresholds_[0]) <= reach * tau / std::sqrt(n) &&
         n_contacts_ * (1.0 + ip_.kappa * std::abs(v)) * dt <= kWatchCap;
}

// One threshold s_0, fresh renewal, no load (watches): the site is n attached contacts and N − n detached ones, all
// overloaded or none (Y = 1 or 0). Between events A = n/N is fixed and σ̄ relaxes exactly (relax_stress at the rate
// Y|v|); an event comes at the total rate R = (N − n) + κ|v| n [τ > s_0] (an exponential waiting time), is an
// attachment with probability (N − n)/R, and τ is tested again after it. At most ~kWatchCap events (their number
// has a mean ≤ N (1 + κ|v|) dt ≤ kWatchCap).
bool CountLaw::step_watched(std::size_t i, double v, double dt) {
  const double alpha = ip_.alpha, eta = ip_.eta, speed = std::abs(v), detach = ip_.kappa * speed;
  const double s0 = thresholds_[0], total_contacts = n_contacts_;
  Engine& e = engine_at(i);
  double n = n_att_[i], sb = sigma_bar_[i], left = dt;
  bool any = false;
  for (;;) {
    const double a = area_of(i, n);
    const bool over = core::contact_stress(sb + eta * v, a) > s0;  // (n = 0: τ = ∞, over)
    any |= over && speed > 0.0;
    const double attach = total_contacts - n, rate = attach + (over ? detach * n : 0.0);
    const double wait = rate > 0.0 ? -std::log(uniform01(e)) / rate : std::numeric_limits<double>::infinity();
    sb = detail::relax_stress(sb, alpha * a * v, over ? speed : 0.0, std::min(wait, left));
    if (!(wait < left)) break;
    left -= wait;
    n += uniform01(e) * rate < attach ? 1.0 : -1.0;
  }
  att(i)[0] = n;
  det(i)[0] = total_contacts - n;
  n_att_[i] = n;
  area_[i] = area_of(i, n);
  sigma_bar_[i] = sb;
  return any;
}

// Noise on: binomial draws from the site's stream; returns A'.
double CountLaw::step_contacts_sampled(std::size_t i, std::size_t k, double n_over, double detach, double dt) {
  using detail::binomial;
  const std::size_t B = nbins_;
  double* at = att(i);
  double* de = det(i);
  const double n_det = n_contacts_ - n_att_[i];  // whole numbers: exact
  // 2. idle: nothing can change state
  if (!((n_over > 0.0 && detach > 0.0) || n_det > 0.0)) return area_[i];
  // 3. exact two-state transitions, rates frozen: a = 1; d = κ|v| in overloaded bins, 0 elsewhere
  const core::TwoStateTransition free_tr = attach_only_;
  const core::TwoStateTransition over_tr = k > 0 ? core::two_state_transition(1.0, detach, dt) : free_tr;
  const double leave_p = detach * over_tr.become_attached;  // 1 − P(att→att) = d (1 − e^{−rΔt})/r
  Engine& e = engine_at(i);
  if (!quenched_) {
    // Fresh thresholds: a detached contact falls in each bin with probability 1/B, so k/B of the
    // pool meets the overloaded rates (multinomial over bins, drawn as successive binomials).
    const double m_over = k == 0 ? 0.0 : k == B ? n_det : binomial(e, n_det, static_cast<double>(k) / static_cast<double>(B));
    const double x_over = binomial(e, m_over, over_tr.become_attached);
    const double x_free = binomial(e, n_det - m_over, free_tr.become_attached);
    // Every bin sharing one fate (k = 0 or B; docs/discrete.md, "Unspread arrivals"), the unspread arrivals are one
    // class: they detach together, and the attaching contacts join them instead of being spread over the bins.
    const bool unspread = !unspread_.empty() && (k == 0 || k == B);
    double left = 0.0;
    if (detach > 0.0 && k > 0) {
      const detail::BinomialRate leave(leave_p);  // one rate for every overloaded bin
      for (std::size_t b = 0; b < k; ++b) {
        const double x = binomial(e, at[b], leave);
        at[b] -= x;
        left += x;
      }
      if (unspread) {
        const double x = binomial(e, unspread_[i], leave);
        unspread_[i] -= x;
        left += x;
      }
    }
    if (unspread) {
      unspread_[i] += x_over + x_free;  // (one of them is 0)
    } else {
      detail::spread_uniform(e, x_over, at, 0, k, share_);
      detail::spread_uniform(e, x_free, at, k, B, share_);
    }
    de[0] = n_det - x_over - x_free + left;
  } else {
    const detail::BinomialRate leave(leave_p), attach_over(over_tr.become_attached), attach_free(free_tr.become_attached);
    for (std::size_t b = 0; b < B; ++b) {
      const bool over = b < k;
      const double out = over ? binomial(e, at[b], leave) : 0.0;
      const double in = binomial(e, de[b], over ? attach_over : attach_free);
      at[b] += in - out;
      de[b] += out - in;
    }
  }
  double n_new = unspread(i);
  for (std::size_t b = 0; b < B; ++b) n_new += at[b];
  n_att_[i] = n_new;
  return area_[i] = area_of(i, n_new);
}

// Noise on, re-attachment channel (docs/model.md §12.2): every contact's exact two-state step with attach rate a_i
// and detach rate 1 − a_i, plus κ|v| in the overloaded bins. The unspread arrivals are settled first and none are
// kept (every bin now detaches at rest too, so they do not share one fate).
double CountLaw::step_contacts_reattaching(std::size_t i, std::size_t k, double detach, double dt) {
  using detail::binomial;
  settle(i);
  const std::size_t B = nbins_;
  double* at = att(i);
  double* de = det(i);
  const double rest = rest_[i], n_det = n_contacts_ - n_att_[i];
  const core::TwoStateTransition free_tr = core::two_state_transition(rest, 1.0 - rest, dt);
  const core::TwoStateTransition over_tr = core::two_state_transition(rest, 1.0 - rest + detach, dt);
  const detail::BinomialRate leave_free(1.0 - free_tr.stay_attached), leave_over(1.0 - over_tr.stay_attached);
  Engine& e = engine_at(i);
  if (!quenched_) {
    const double m_over = k == 0 ? 0.0 : k == B ? n_det : binomial(e, n_det, static_cast<double>(k) / static_cast<double>(B));
    const double x_over = binomial(e, m_over, over_tr.become_attached);
    const double x_free = binomial(e, n_det - m_over, free_tr.become_attached);
    double left = 0.0;
    for (std::size_t b = 0; b < B; ++b) {
      const double x = binomial(e, at[b], b < k ? leave_over : leave_free);
      at[b] -= x;
      left += x;
    }
    detail::spread_uniform(e, x_over, at, 0, k, share_);
    detail::spread_uniform(e, x_free, at, k, B, share_);
    de[0] = n_det - x_over - x_free + left;
  } else {
    const detail::BinomialRate attach_over(over_tr.become_attached), attach_free(free_tr.become_attached);
    for (std::size_t b = 0; b < B; ++b) {
      const bool over = b < k;
      const double out = binomial(e, at[b], over ? leave_over : leave_free);
      const double in = binomial(e, de[b], over ? attach_over : attach_free);
      at[b] += in - out;
      de[b] += out - in;
    }
  }
  double n_new = 0.0;
  for (std::size_t b = 0; b < B; ++b) n_new += at[b];
  n_att_[i] = n_new;
  return area_[i] = area_of(i, n_new);
}

// Noise off: every draw replaced by its expectation, in fractions of the site. The expected
// attached fraction of bin b (total T_b, attach rate a = 1, detach rate d_b) after the step is
//   n_b P(att→att) + (T_b − n_b) P(det→att) = relax(n_b, a T_b, a + d_b, Δt),
// the exact solution of dn_b/dt = a (T_b − n_b) − d_b n_b; written with relax() it is, for w = 0
// (B = 1, T = 1), the very arithmetic of FrictionLaw::advance. Every site is updated (no skip), as
// in the continuum law. Fresh: T_b = n_b + (1 − Σn)/B (the pool spreads evenly); quenched: T_b = 1/B.
// Re-attachment channel of a normal load (docs/model.md §12.2): a = a_i and detach 1 − a_i + d_b, so
// dn_b/dt = a_i T_b − (1 + d_b) n_b: the source a_i T_b at the same rates (w = 0: FrictionLaw's a_i · w).
double CountLaw::step_contacts_mean(std::size_t i, std::size_t k, double detach, double dt) {
  const std::size_t B = nbins_;
  const double inv_b = 1.0 / static_cast<double>(B);
  double* at = att(i);
  double* de = det(i);
  // relax(y, s, r, dt) = y e^{−r dt} + s relax_weight(r, dt): the two rates' factors, computed once
  const double r_over = 1.0 + detach;
  const double e_over = std::exp(-r_over * dt), w_over = core::relax_weight(r_over, dt);
  const double e_free = cached_free_exp_, w_free = attach_only_.become_attached;
  const double pool = quenched_ ? 0.0 : (1.0 - n_att_[i]) * inv_b;
  double n_new = 0.0;
  for (std::size_t b = 0; b < B; ++b) {
    const double total = quenched_ ? inv_b : at[b] + pool;
    const double source = reattach_ ? rest_[i] * total : total;
    const bool over = b < k;
    at[b] = at[b] * (over ? e_over : e_free) + source * (over ? w_over : w_free);
    if (quenched_) de[b] = total - at[b];
    n_new += at[b];
  }
  if (!quenched_) de[0] = 1.0 - n_new;
  n_att_[i] = n_new;
  return area_[i] = area_of(i, n_new);
}

std::string CountLaw::save_state() const {
  std::ostringstream os;
  // Version 2 adds each site's unspread arrivals after its bins (saved as they are: saving does not settle them,
  // so a run that writes checkpoints draws what one that does not draws); version 1 (no unspread) still loads.
  os << "slipfront-count-law 2 " << size() << ' ' << nbins_ << ' ' << det_stride_ << ' ' << dp_.contacts_per_site
     << ' ' << (noise_ ? 1 : 0) << '\n';
  char buf[40];
  auto put = [&](double x) {
    std::snprintf(buf, sizeof buf, "%a", x);
    os << buf << ' ';
  };
  for (std::size_t i = 0; i < size(); ++i) {
    put(sigma_bar_[i]);
    for (double x : std::span<const double>(att_).subspan(i * nbins_, nbins_)) put(x);
    put(unspread(i));
    for (double x : detached(i)) put(x);
    os << '\n' << discrete::save_state(engine_at(i)) << '\n';  // (an unused engine: its seeded state)
  }
  return os.str();
}

void CountLaw::load_state(const std::string& text) {
  std::istringstream is(text);
  std::string magic;
  int version = 0;
  std::size_t sites = 0, nb = 0, stride = 0;
  long n = 0;
  int noise = 0;
  is >> magic >> version >> sites >> nb >> stride >> n >> noise;
  if (!is || magic != "slipfront-count-law" || (version != 1 && version != 2) || sites != size() || nb != nbins_ ||
      stride != det_stride_ || n != dp_.contacts_per_site || (noise != 0) != noise_)
    throw std::invalid_argument("CountLaw::load_state: state of a different law");
  auto get = [&]() {
    std::string tok;
    is >> tok;
    char* end = nullptr;
    const double x = std::strtod(tok.c_str(), &end);
    if (tok.empty() || end != tok.c_str() + tok.size()) throw std::invalid_argument("CountLaw::load_state: bad number");
    return x;
  };
  for (std::size_t i = 0; i < sites; ++i) {
    sigma_bar_[i] = get();
    double total = 0.0;
    for (std::size_t b = 0; b < nbins_; ++b) total += (att(i)[b] = get());
    const double unspread = version >= 2 ? get() : 0.0;
    if (unspread != 0.0 && unspread_.empty())
      throw std::invalid_argument("CountLaw::load_state: unspread contacts in a law that keeps none");
    if (!unspread_.empty()) unspread_[i] = unspread;
    total += unspread;
    for (std::size_t b = 0; b < det_stride_; ++b) det(i)[b] = get();
    n_att_[i] = total;
    area_[i] = area_of(i, total);
    std::string line;
    std::getline(is >> std::ws, line);
    discrete::load_state(engines_[i].emplace(), line);
  }
  if (!is) throw std::invalid_argument("CountLaw::load_state: truncated state");
  cached_dt_ = -1.0;
}

double CountLaw::area_of(std::size_t i, double attached_total) const {
  const double fraction = noise_ ? attached_total / n_contacts_ : attached_total;  // A = n/N; noise off: fractions
  return scaled_ ? rest_[i] * fraction : fraction;  // instantaneous load: contacts of area a_i (docs/model.md §12)
}

}  // namespace slipfront::discrete
