#include "discrete/agent_law.hpp"
#include "discrete/normal_load.hpp"

#include "core/interrupt.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slipfront::discrete {

namespace {

constexpr std::size_t npos = static_cast<std::size_t>(-1);
constexpr double inf = std::numeric_limits<double>::infinity();

/// Exp(1) by inversion of one uniform (identical across standard libraries).
inline double exp1(Engine& e) { return -std::log(uniform01(e)); }

}  // namespace

AgentLaw::AgentLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites)
    : ip_(ip), dp_(dp), g_((dp.validate(), ThresholdDistribution(dp.threshold, dp.width))) {
  if (sites == 0) throw std::invalid_argument("AgentLaw: no sites");
  if (!dp.noise)
    throw core::ParamError("discrete.noise",
                                "the agent representation has whole contacts: noise = false needs representation = count");
  n_contacts_ = static_cast<std::size_t>(dp.contacts_per_site);
  aging_ = ip.ages_contacts();
  degenerate_ = g_.degenerate();
  quenched_ = dp.renewal == "quenched";
  if (!degenerate_) {
    // B ≈ 4√N quantile bins of g: the bin straddling τ holds ~√N/4 attached contacts.
    const auto root = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(n_contacts_))));
    nbins_ = std::clamp<std::size_t>(4 * root, 1, std::min<std::size_t>(n_contacts_, 4096));
    edges_.resize(nbins_ + 1);
    for (std::size_t b = 0; b <= nbins_; ++b)
      edges_[b] = g_.quantile(static_cast<double>(b) / static_cast<double>(nbins_));
  }
  sites_.resize(sites);
  area_.assign(sites, 1.0);
  sigma_bar_.assign(sites, 0.0);
  if (dp.contact_statistics) stats_ = ContactStats(sites, threshold_edges(dp.width));
  for (std::size_t i = 0; i < sites; ++i) {
    core::poll_stop();  // seconds for 10^8 contacts: a stop request is honoured per site
    set_site(i, 1.0, 0.0);
  }
}

std::size_t AgentLaw::bin_of(double s) const {
  if (nbins_ == 1) return 0;
  // bin b holds [e_b, e_{b+1}): the number of interior edges e_1..e_{B−1} that are ≤ s
  const auto first = edges_.begin() + 1, last = edges_.begin() + static_cast<std::ptrdiff_t>(nbins_);
  return static_cast<std::size_t>(std::upper_bound(first, last, s) - first);
}

double AgentLaw::draw_threshold(Engine& e) const { return degenerate_ ? 1.0 : g_.from_uniform(uniform01(e)); }

void AgentLaw::set_normal_load(std::span<const double> factor) {
  if (factor.size() != size()) throw std::invalid_argument("AgentLaw::set_normal_load: one factor per site");
  if (aging_) throw std::invalid_argument("AgentLaw::set_normal_load: not with aging (docs/model.md §12)");
  install_resting_areas(factor, ip_, rest_, sigma_bar_, reattach_, scaled_);
  const double inv_n = 1.0 / static_cast<double>(n_contacts_);
  for (std::size_t i = 0; i < size(); ++i)
    area_[i] = (scaled_ ? rest_[i] : 1.0) * (static_cast<double>(sites_[i].n_att) * inv_n);
}

void AgentLaw::set_site(std::size_t i, double area_given, double sigma_bar) {
  const double area = scaled_ ? area_given / rest_[i] : area_given;  // the attached fraction (contacts of area a_i)
  if (!(area >= 0.0 && area <= 1.0)) throw std::invalid_argument("AgentLaw::set_site: A must lie in [0, 1]");
  Site& st = sites_[i];
  st.engine = site_engine(dp_.seed, i);
  st.bins.assign(nbins_, {});
  if (nbins_ > 1) st.counts.reset(nbins_);
  st.detached.clear();
  st.detach_mark = st.attach_mark = -1.0;
  const auto n = static_cast<std::size_t>(std::llround(area * static_cast<double>(n_contacts_)));
  for (std::size_t k = 0; k < n; ++k) {
    const double s = draw_threshold(st.engine);
    if (!degenerate_) stats_.drawn(s);
    const std::size_t b = bin_of(s);
    st.bins[b].push_back({s, t_});
    if (nbins_ > 1) st.counts.add(b, 1);
  }
  st.detached.reserve(n_contacts_ - n);
  for (std::size_t k = n; k < n_contacts_; ++k) {
    const double s = quenched_ ? draw_threshold(st.engine) : std::numeric_limits<double>::quiet_NaN();
    if (quenched_ && !degenerate_) stats_.drawn(s);
    st.detached.push_back({t_, s});
  }
  st.n_att = n;
  st.attach_time_sum = static_cast<double>(n) * t_;
  st.pristine = true;
  st.set_at = t_;
  area_[i] = (scaled_ ? rest_[i] : 1.0) * (static_cast<double>(n) / static_cast<double>(n_contacts_));
  sigma_bar_[i] = sigma_bar;
}

// Step 1: the members (overloaded attached contacts, τ > s) at the frozen τ.
AgentLaw::Load AgentLaw::classify(Site& st, double tau) const {
  Load ld;
  if (degenerate_) {  // every threshold is 1: all members or none
    ld.full_bins = tau > 1.0 ? 1 : 0;
    ld.members = ld.full_bins ? st.n_att : 0;
    return ld;
  }
  const auto first = edges_.begin() + 1, last = edges_.begin() + static_cast<std::ptrdiff_t>(nbins_);
  ld.full_bins = static_cast<std::size_t>(std::upper_bound(first, last, tau) - first);  // e_{b+1} ≤ τ
  if (ld.full_bins < nbins_ && edges_[ld.full_bins] < tau) {  // e_b < τ < e_{b+1}: scan this bin
    ld.partial = ld.full_bins;
    auto& bin = st.bins[ld.partial];
    const auto mid = std::partition(bin.begin(), bin.end(), [tau](const AttachedContact& c) { return c.threshold < tau; });
    ld.partial_members = static_cast<std::size_t>(mid - bin.begin());
  }
  const std::size_t full = nbins_ == 1 ? (ld.full_bins ? st.n_att : 0)
                                       : static_cast<std::size_t>(st.counts.prefix(ld.full_bins));
  ld.members = full + ld.partial_members;
  return ld;
}

// A contact attaching during the step joins its bin; it is a member if its bin is below τ, or it
// straddles τ and s < τ (then it is swapped into the member prefix of that bin).
void AgentLaw::add_attached(Site& st, Load& ld, AttachedContact c, double tau) {
  const std::size_t b = bin_of(c.threshold);
  auto& bin = st.bins[b];
  bin.push_back(c);
  if (nbins_ > 1) st.counts.add(b, 1);
  ++st.n_att;
  st.attach_time_sum += c.attached_at;
  if (b < ld.full_bins) {
    ++ld.members;
  } else if (b == ld.partial && c.threshold < tau) {
    std::swap(bin[ld.partial_members], bin.back());
    ++ld.partial_members;
    ++ld.members;
  }
}

// Remove the member of rank `rank` (full bins in order, then the members of the straddling bin).
AttachedContact AgentLaw::remove_member(Site& st, Load& ld, std::uint64_t rank) {
  const std::uint64_t in_full = ld.members - ld.partial_members;
  AttachedContact c;
  std::size_t b;
  if (rank < in_full) {
    std::size_t j;
    if (nbins_ == 1) {
      b = 0;
      j = static_cast<std::size_t>(rank);
    } else {
      auto r = static_cast<std::int64_t>(rank);
      b = st.counts.find(r);
      j = static_cast<std::size_t>(r);
    }
    auto& bin = st.bins[b];
    c = bin[j];
    bin[j] = bin.back();
    bin.pop_back();
  } else {
    b = ld.partial;
    auto& bin = st.bins[b];
    const auto j = static_cast<std::size_t>(rank - in_full);
    const std::size_t last_member = ld.partial_members - 1;
    c = bin[j];
    bin[j] = bin[last_member];     // keep the members a prefix
    bin[last_member] = bin.back();
    bin.pop_back();
    --ld.partial_members;
  }
  if (nbins_ > 1) st.counts.add(b, -1);
  --ld.members;
  --st.n_att;
  st.attach_time_sum -= c.attached_at;
  return c;
}

// Remove the attached non-member of rank `rank` (docs/model.md §12.2: spontaneous detachment under a re-attaching
// load): first the straddling bin's non-members (after its member prefix), then the bins above the members.
AttachedContact AgentLaw::remove_non_member(Site& st, const Load& ld, std::uint64_t rank) {
  std::size_t b = 0, j = 0;
  const std::size_t partial_rest = ld.partial == npos ? 0 : st.bins[ld.partial].size() - ld.partial_members;
  if (rank < partial_rest) {
    b = ld.partial;
    j = ld.partial_members + static_cast<std::size_t>(rank);
  } else if (nbins_ == 1) {
    j = static_cast<std::size_t>(rank);
  } else {
    const std::size_t first = ld.partial == npos ? ld.full_bins : ld.partial + 1;
    auto r = st.counts.prefix(first) + static_cast<std::int64_t>(rank - partial_rest);
    b = st.counts.find(r);
    j = static_cast<std::size_t>(r);
  }
  auto& bin = st.bins[b];
  const AttachedContact c = bin[j];
  bin[j] = bin.back();
  bin.pop_back();
  if (nbins_ > 1) st.counts.add(b, -1);
  --st.n_att;
  st.attach_time_sum -= c.attached_at;
  return c;
}

// Step 3: the two-state chain of every contact of site i over [t0, t1] with frozen rates, event by
// event. Two Poisson processes: detachments of members (intensity K d) and attachments of detached
// contacts (intensity D); the next event of each is where its integrated intensity reaches its mark.
void AgentLaw::run_events(std::size_t i, Site& st, Load& ld, double tau, double detach, double t0, double t1) {
  Engine& e = st.engine;
  auto& pool = st.detached;
  double t = t0;
  // under a re-attaching load (docs/model.md §12.2) attach at rate a, and every attached contact detaches at 1 − a
  const double attach = reattach_ ? rest_[i] : 1.0, spont = reattach_ ? 1.0 - rest_[i] : 0.0;
  for (;;) {
    const double k_member = static_cast<double>(ld.members) * (spont > 0.0 ? detach + spont : detach);
    const double k_det = spont > 0.0 ? k_member + static_cast<double>(st.n_att - ld.members) * spont : k_member;
    const double k_att = reattach_ ? static_cast<double>(pool.size()) * attach
                                   : static_cast<double>(pool.size());  // attach rate 1 per detached contact
    if (k_det > 0.0 && st.detach_mark < 0.0) st.detach_mark = exp1(e);
    if (k_att > 0.0 && st.attach_mark < 0.0) st.attach_mark = exp1(e);
    const double t_det = k_det > 0.0 ? t + st.detach_mark / k_det : inf;
    const double t_att = k_att > 0.0 ? t + st.attach_mark / k_att : inf;
    const double t_next = std::min({t_det, t_att, t1});
    // the intensities accrued up to the next event (or the end of the step)
    if (k_det > 0.0) st.detach_mark = std::max(0.0, st.detach_mark - k_det * (t_next - t));
    if (k_att > 0.0) st.attach_mark = std::max(0.0, st.attach_mark - k_att * (t_next - t));
    if (!(t_next < t1)) return;  // nothing more in this step
    t = t_next;
    st.pristine = false;
    if (t_det <= t_att) {
      // a member detaches, chosen uniformly (under a re-attaching load, a non-member with its share of k_det)
      AttachedContact c;
      if (spont > 0.0 && uniform01(e) * k_det >= k_member) {
        const std::uint64_t others = st.n_att - ld.members;
        c = remove_non_member(st, ld, std::min<std::uint64_t>(others - 1, static_cast<std::uint64_t>(uniform01(e) * static_cast<double>(others))));
      } else {
        const auto rank = std::min<std::uint64_t>(ld.members - 1, static_cast<std::uint64_t>(uniform01(e) * static_cast<double>(ld.members)));
        c = remove_member(st, ld, rank);
      }
      st.detach_mark = -1.0;
      stats_.record_lifetime(i, c.attached_at, t - c.attached_at);
      pool.push_back({t, c.threshold});
    } else {
      // a detached contact attaches, chosen uniformly
      const auto j = std::min<std::size_t>(pool.size() - 1, static_cast<std::size_t>(uniform01(e) * k_att));
      const DetachedContact c = pool[j];
      pool[j] = pool.back();
      pool.pop_back();
      st.attach_mark = -1.0;
      double s = c.threshold;  // quenched; or fresh and re-attaching within the step it detached in
      if (!quenched_ && !(c.detached_at >= t0 && !std::isnan(s))) {
        s = draw_threshold(e);
        if (!degenerate_) stats_.drawn(s);
      }
      stats_.record_detached(i, c.detached_at, t - c.detached_at);
      add_attached(st, ld, {s, t}, tau);
    }
    ++changes_;
  }
}

core::LawStepInfo AgentLaw::advance(double dt, std::span<const double> v) {
  if (v.size() != size()) throw std::invalid_argument("AgentLaw::advance: one slip rate per site");
  const double alpha = ip_.alpha, kappa = ip_.kappa, eta = ip_.eta;
  const double inv_n = 1.0 / static_cast<double>(n_contacts_);
  const double t0 = t_, t1 = t_ + dt;
  bool any = false;
  for (std::size_t i = 0; i < sites_.size(); ++i) {
    const double vi = v[i], speed = std::abs(vi), a0 = area_[i], sb = sigma_bar_[i];
    if (!std::isfinite(vi)) {  // the stepper reports it with the step and site; do not draw on it
      sigma_bar_[i] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    Site& st = sites_[i];
    // 1. load: contact stress at the start of the step, the members, Y_i
    const double tau = core::contact_stress(sb + eta * vi, a0);
    Load ld = classify(st, tau);
    const std::size_t n0 = st.n_att;
    double y = n0 > 0 ? static_cast<double>(ld.members) / static_cast<double>(n0) : 1.0;
    if (aging_ && !degenerate_ && n0 > 0) y = aged_overloaded_fraction(st, tau, t0);  // docs/model.md §11.2
    any |= speed > 0.0 && (ld.members > 0 || n0 == 0);
    // 2. idle: no member slipping and no detached contact — nothing is touched
    const double detach = kappa * speed;
    const bool turnover = reattach_ && rest_[i] < 1.0 && st.n_att > 0;  // spontaneous detachment (docs/model.md §12.2)
    if ((ld.members > 0 && detach > 0.0) || !st.detached.empty() || turnover)
      run_events(i, st, ld, tau, detach, t0, t1);  // 3. contacts
    // the area: n/N, or with aging the contacts' areas 1 + b ln(1 + age/τ_a) summed over N (docs/model.md §11.2)
    double a1 = aging_ ? aged_area_sum(st, t1) * inv_n : static_cast<double>(st.n_att) * inv_n;
    if (scaled_) a1 *= rest_[i];  // instantaneous load: contacts of area a_i (docs/model.md §12.2)
    area_[i] = a1;
    // 4. stress: exact update with Ā = (A + A')/2 and Y frozen (as the continuum friction law)
    sigma_bar_[i] = core::relax(sb, alpha * 0.5 * (a0 + a1) * vi, y * speed, dt);
  }
  t_ = t1;
  return {any};
}

double AgentLaw::overloaded_fraction(std::size_t i, double v) const {
  const Site& st = sites_[i];
  if (st.n_att == 0) return 1.0;
  const double tau = core::contact_stress(sigma_bar_[i] + ip_.eta * v, area_[i]);
  if (degenerate_) return tau > 1.0 ? 1.0 : 0.0;
  if (aging_) return aged_overloaded_fraction(st, tau, t_);
  // members: every contact of the bins wholly below τ, and those of the straddling bin with s < τ
  const auto first = edges_.begin() + 1, last = edges_.begin() + static_cast<std::ptrdiff_t>(nbins_);
  const auto full_bins = static_cast<std::size_t>(std::upper_bound(first, last, tau) - first);
  double members = static_cast<double>(st.counts.prefix(full_bins));
  if (full_bins < nbins_ && edges_[full_bins] < tau)
    for (const auto& c : st.bins[full_bins]) members += c.threshold < tau ? 1.0 : 0.0;
  return members / static_cast<double>(st.n_att);
}

// Aging (docs/model.md §11.2): Σ over the attached contacts of their areas 1 + b ln(1 + (t − t_attach)/τ_a).
double AgentLaw::aged_area_sum(const Site& st, double t) const {
  if (st.pristine) return static_cast<double>(st.n_att) * ip_.aged_area(t - st.set_at);  // one age for all
  double sum = 0.0;
  for (const auto& bin : st.bins)
    for (const auto& c : bin) sum += ip_.aged_area(t - c.attached_at);
  return sum;
}

// Aging: Y = the overloaded contacts' share of the attached area (each carries τ times its area, docs/model.md §11.2).
double AgentLaw::aged_overloaded_fraction(const Site& st, double tau, double t) const {
  double over = 0.0, all = 0.0;
  for (const auto& bin : st.bins)
    for (const auto& c : bin) {
      const double a = ip_.aged_area(t - c.attached_at);
      all += a;
      over += c.threshold < tau ? a : 0.0;
    }
  return all > 0.0 ? over / all : 1.0;
}

void AgentLaw::mean_age(std::span<double> out) const {
  for (std::size_t i = 0; i < sites_.size(); ++i) {
    const Site& st = sites_[i];
    out[i] = st.n_att > 0 ? t_ - st.attach_time_sum / static_cast<double>(st.n_att)
                          : std::numeric_limits<double>::quiet_NaN();
  }
}

void AgentLaw::record_contacts(double t) {
  if (!stats_.enabled()) return;
  stats_.begin_snapshot(t);
  for (std::size_t i = 0; i < sites_.size(); ++i) {
    const std::size_t cls = stats_.class_of(i);
    const Site& st = sites_[i];
    if (st.pristine) {  // untouched since set_site: one age for all (the same bins, one addition)
      if (st.n_att > 0) stats_.attached_age(cls, t_ - st.set_at, static_cast<double>(st.n_att));
    } else {
      for_each_attached(i, [&](const AttachedContact& c) { stats_.attached_age(cls, t_ - c.attached_at); });
    }
    if (degenerate_) {  // every threshold is 1: one addition per site
      if (sites_[i].n_att > 0) stats_.attached_threshold(cls, 1.0, static_cast<double>(sites_[i].n_att));
    } else {
      for_each_attached(i, [&](const AttachedContact& c) { stats_.attached_threshold(cls, c.threshold); });
    }
  }
  stats_.end_snapshot();
}

}  // namespace slipfront::discrete
