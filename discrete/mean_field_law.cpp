#include "discrete/mean_field_law.hpp"
#include "discrete/normal_load.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace slipfront::discrete {

namespace {
const DiscreteParams& validated(const DiscreteParams& dp) {
  dp.validate_threshold_law();
  return dp;
}
}  // namespace

MeanFieldLaw::MeanFieldLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites)
    : ip_(ip), g_(validated(dp).threshold, dp.width) {
  if (sites == 0) throw std::invalid_argument("MeanFieldLaw: no sites");
  nbins_ = g_.degenerate() ? 1 : static_cast<std::size_t>(dp.bins);
  quenched_ = dp.renewal == "quenched";
  // the count representation's classes (CountLaw): quantile bins [b/B, (b+1)/B) of g at their conditional means
  thresholds_.resize(nbins_);
  const double B = static_cast<double>(nbins_);
  for (std::size_t b = 0; b < nbins_; ++b)
    thresholds_[b] = g_.conditional_mean(static_cast<double>(b) / B, static_cast<double>(b + 1) / B);
  att_.assign(sites * nbins_, 0.0);
  aging_ = ip.ages_contacts();
  if (aging_) {
    cohorts_.resize(sites * nbins_);
    class_area_.assign(sites * nbins_, 0.0);
  }
  area_.assign(sites, 1.0);
  sigma_bar_.assign(sites, 0.0);
  for (std::size_t i = 0; i < sites; ++i) set_site(i, 1.0, 0.0);
}

void MeanFieldLaw::set_normal_load(std::span<const double> factor) {
  if (factor.size() != size()) throw std::invalid_argument("MeanFieldLaw::set_normal_load: one factor per site");
  if (aging_) throw std::invalid_argument("MeanFieldLaw::set_normal_load: not with aging (docs/model.md §12)");
  install_resting_areas(factor, ip_, rest_, sigma_bar_, reattach_, scaled_);
  if (scaled_)
    for (std::size_t i = 0; i < size(); ++i) area_[i] = rest_[i] * total(i);
}

void MeanFieldLaw::set_site(std::size_t i, double area_given, double sigma_bar) {
  const double area = scaled_ ? area_given / rest_[i] : area_given;  // the attached fraction (contacts of area a_i)
  if (!(area >= 0.0 && area <= 1.0)) throw std::invalid_argument("MeanFieldLaw::set_site: A must lie in [0, 1]");
  double* a = att_.data() + i * nbins_;
  const double B = static_cast<double>(nbins_);
  for (std::size_t b = 0; b < nbins_; ++b) a[b] = area / B;
  area_[i] = scaled_ ? rest_[i] * total(i) : total(i);
  sigma_bar_[i] = sigma_bar;
  if (aging_)  // every attached contact new: area 1 each (docs/model.md §11.3)
    for (std::size_t b = 0; b < nbins_; ++b) {
      cohorts_[i * nbins_ + b].reset(a[b]);
      class_area_[i * nbins_ + b] = a[b];
    }
}

double MeanFieldLaw::total(std::size_t i) const {
  double sum = 0.0;
  for (const double n : attached(i)) sum += n;
  return sum;
}

double MeanFieldLaw::detached(std::size_t i, std::size_t b) const {
  return quenched_ ? 1.0 / static_cast<double>(nbins_) - att_[i * nbins_ + b]
                   : 1.0 - (aging_ || scaled_ ? total(i) : area_[i]);
}

// Overloaded classes: s_b < τ (thresholds ascending, so a prefix).
std::size_t MeanFieldLaw::overloaded_classes(double tau) const {
  if (nbins_ == 1) return tau > thresholds_[0] ? 1 : 0;
  return static_cast<std::size_t>(std::lower_bound(thresholds_.begin(), thresholds_.end(), tau) - thresholds_.begin());
}

double MeanFieldLaw::overloaded_fraction(std::size_t i, double v) const {
  const double tau = core::contact_stress(sigma_bar_[i] + ip_.eta * v, area_[i]);
  const std::size_t k = overloaded_classes(tau);
  if (!(area_[i] > 0.0)) return 1.0;
  const std::vector<double>& share = aging_ ? class_area_ : att_;  // aging: the overloaded share of the area
  double over = 0.0;
  for (std::size_t b = 0; b < k; ++b) over += share[i * nbins_ + b];
  return over / (scaled_ ? total(i) : area_[i]);  // instantaneous load: of the attached contacts, not their area
}

void MeanFieldLaw::class_rates(std::size_t, double v, double area, double sigma_bar, std::span<const double> n,
                               std::span<double> hazard, std::span<double> total) const {
  const std::size_t k = overloaded_classes(core::contact_stress(sigma_bar + ip_.eta * v, area));
  const double inv_b = 1.0 / static_cast<double>(nbins_), detach = ip_.kappa * std::abs(v);
  const double pool = quenched_ ? 0.0 : (1.0 - area) * inv_b;
  for (std::size_t b = 0; b < nbins_; ++b) {
    hazard[b] = b < k ? detach : 0.0;
    total[b] = quenched_ ? inv_b : n[b] + pool;
  }
}

core::LawStepInfo MeanFieldLaw::advance(double dt, std::span<const double> v) {
  if (v.size() != size()) throw std::invalid_argument("MeanFieldLaw::advance: one slip rate per site");
  if (dt != cached_dt_) {  // the classes with no detachment relax at rate 1: their factors depend on dt only
    free_exp_ = std::exp(-1.0 * dt);
    free_weight_ = core::relax_weight(1.0, dt);
    cached_dt_ = dt;
  }
  const double alpha = ip_.alpha, kappa = ip_.kappa, eta = ip_.eta;
  const std::size_t B = nbins_;
  const double inv_b = 1.0 / static_cast<double>(B);
  bool any = false;
  for (std::size_t i = 0; i < size(); ++i) {
    const double vi = v[i], speed = std::abs(vi), a0 = area_[i], sb = sigma_bar_[i];
    if (!std::isfinite(vi)) {  // the stepper reports it with the step and site
      sigma_bar_[i] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    if (aging_) {  // docs/model.md §11.3
      any |= advance_site_aging(i, dt, vi);
      continue;
    }
    // 1. load: τ at the start of the step, overloaded classes [0, k), the overloaded fraction Y
    double* n = att_.data() + i * B;
    const std::size_t k = overloaded_classes(core::contact_stress(sb + eta * vi, a0));
    double n_over = 0.0;
    for (std::size_t b = 0; b < k; ++b) n_over += n[b];
    const double n_att = scaled_ ? total(i) : a0;  // the attached fraction (a0 but under an instantaneous load)
    const double y = n_att > 0.0 ? n_over / n_att : 1.0;
    any |= speed > 0.0 && (n_over > 0.0 || !(a0 > 0.0));
    // 2. contacts: n_b' = relax(n_b, T_b, 1 + d_b, Δt), T_b and d_b frozen
    const double r_over = 1.0 + kappa * speed;
    const double e_over = std::exp(-r_over * dt), w_over = core::relax_weight(r_over, dt);
    const double pool = quenched_ ? 0.0 : (1.0 - n_att) * inv_b;  // fresh: the detached feed every class by 1/B
    double a1 = 0.0;
    for (std::size_t b = 0; b < B; ++b) {
      const double total_b = quenched_ ? inv_b : n[b] + pool;
      const double target = reattach_ ? rest_[i] * total_b : total_b;  // docs/model.md §12.2: the source a_i T_b
      const bool over = b < k;
      n[b] = n[b] * (over ? e_over : free_exp_) + target * (over ? w_over : free_weight_);
      a1 += n[b];
    }
    if (scaled_) a1 *= rest_[i];  // instantaneous load: contacts of area a_i
    area_[i] = a1;
    // 3. stress: exact with Ā = (A + A')/2 and Y frozen (rate 0: σ̄ + source Δt, as relax() gives it)
    const double source = alpha * 0.5 * (a0 + a1) * vi, rate = y * speed;
    sigma_bar_[i] = rate > 0.0 ? core::relax(sb, source, rate, dt) : sb + source * dt;
  }
  return {any};
}

// Site i's step with aging (docs/model.md §11.3): the class counts n_b exactly as advance() (the detached pool from
// the counts), then each class's cohorts: survivors e^{−d_b Δt}, the step's new contacts n_b' − n_b e^{−d_b Δt} at
// age Δt/2; A = Σ class areas, Y = the overloaded classes' share of the area at the start of the step. Returns
// whether the site yielded (advance()'s any_yield).
bool MeanFieldLaw::advance_site_aging(std::size_t i, double dt, double vi) {
  const std::size_t B = nbins_;
  const double inv_b = 1.0 / static_cast<double>(B), speed = std::abs(vi), a0 = area_[i], sb = sigma_bar_[i];
  double* n = att_.data() + i * B;
  double* class_area = class_area_.data() + i * B;
  const std::size_t k = overloaded_classes(core::contact_stress(sb + ip_.eta * vi, a0));
  double area_over = 0.0, n_over = 0.0;
  for (std::size_t b = 0; b < k; ++b) {
    area_over += class_area[b];
    n_over += n[b];
  }
  const double y = a0 > 0.0 ? area_over / a0 : 1.0;
  const double r_over = 1.0 + ip_.kappa * speed;
  const double e_over = std::exp(-r_over * dt), w_over = core::relax_weight(r_over, dt);
  const double survive_over = std::exp(-ip_.kappa * speed * dt);
  const double pool = quenched_ ? 0.0 : (1.0 - total(i)) * inv_b;
  double a1 = 0.0;
  for (std::size_t b = 0; b < B; ++b) {
    const double target = quenched_ ? inv_b : n[b] + pool;
    const bool over = b < k;
    const double n_new = n[b] * (over ? e_over : free_exp_) + target * (over ? w_over : free_weight_);
    const double survive = over ? survive_over : 1.0;
    AgeCohorts& c = cohorts_[i * B + b];
    c.step(dt, survive, std::max(0.0, n_new - n[b] * survive), ip_.aging_tau);
    n[b] = n_new;
    class_area[b] = c.area(ip_);
    a1 += class_area[b];
  }
  area_[i] = a1;
  const double source = ip_.alpha * 0.5 * (a0 + a1) * vi, rate = y * speed;
  sigma_bar_[i] = rate > 0.0 ? core::relax(sb, source, rate, dt) : sb + source * dt;
  return speed > 0.0 && (n_over > 0.0 || !(a0 > 0.0));
}

}  // namespace slipfront::discrete
