#include "discrete/aging.hpp"

#include <boost/math/special_functions/expint.hpp>

#include <cmath>

namespace slipfront::discrete {

namespace {
// ln(1 + x) for 0 ≤ x: its Taylor polynomial to x⁴ up to cached_log_series_max (error ≤ x⁵/5), std::log1p above.
double log1p_step(double x) {
  if (x > cached_log_series_max) return std::log1p(x);
  return x * (1.0 - x * (0.5 - x * (1.0 / 3.0 - 0.25 * x)));
}
}  // namespace

template <bool keep_logs>
void AgeCohorts::advance(double dt, double survive, double fresh, double tau) {
  for (auto& c : cohorts_) {
    c.mass *= survive;
    if constexpr (keep_logs) c.log += log1p_step(dt / (tau + c.age));  // ln(τ + a + Δt) − ln(τ + a)
    c.age += dt;
    c.lo += dt;
    c.hi += dt;
  }
  if (fresh > 0.0) cohorts_.push_back({fresh, 0.5 * dt, 0.0, dt, keep_logs ? std::log1p(0.5 * dt / tau) : 0.0});
  // merge neighbours (older c, newer n) while the span [n.lo, c.hi] stays within ε (τ_a + n.lo)
  std::size_t out = 0;
  for (std::size_t k = 1; k < cohorts_.size(); ++k) {
    Cohort& c = cohorts_[out];
    const Cohort& n = cohorts_[k];
    if (c.hi - n.lo <= cohort_merge_width * (tau + n.lo)) {
      const double m = c.mass + n.mass;
      if (m > 0.0) c.age = (c.mass * c.age + n.mass * n.age) / m;
      c.mass = m;
      c.lo = n.lo;
      if constexpr (keep_logs) c.log = std::log1p(c.age / tau);
    } else {
      cohorts_[++out] = n;
    }
  }
  if (!cohorts_.empty()) cohorts_.resize(out + 1);
}

template void AgeCohorts::advance<true>(double, double, double, double);
template void AgeCohorts::advance<false>(double, double, double, double);

double AgeCohorts::area(const core::InterfaceParams& p) const {
  double sum = 0.0;
  for (const auto& c : cohorts_) sum += c.mass * (1.0 + p.aging_b * c.log);
  return sum;
}

double AgeCohorts::area_recomputed(const core::InterfaceParams& p) const {
  double sum = 0.0;
  for (const auto& c : cohorts_) sum += c.mass * p.aged_area(c.age);
  return sum;
}

double AgeCohorts::mass() const {
  double sum = 0.0;
  for (const auto& c : cohorts_) sum += c.mass;
  return sum;
}

namespace {
// e^{x} E_1(x): Boost.Math below 50, the asymptotic series Σ (−1)^k k!/x^{k+1} (k ≤ 12, error < 13!/50^14) above.
double scaled_e1(double x) {
  if (x < 50.0) return std::exp(x) * boost::math::expint(1, x);
  double term = 1.0 / x, sum = 0.0;
  for (int k = 0; k <= 12; ++k) {
    sum += term;
    term *= -(k + 1) / x;
  }
  return sum;
}
// e^{−x} Ei(x), x > 0: Boost.Math below 500, the asymptotic series Σ k!/x^{k+1} above (k ≤ 12).
double scaled_ei(double x) {
  if (x < 500.0) return std::exp(-x) * boost::math::expint(x);
  double term = 1.0 / x, sum = 0.0;
  for (int k = 0; k <= 12; ++k) {
    sum += term;
    term *= (k + 1) / x;
  }
  return sum;
}
}  // namespace

double mean_log_age_exponential(double lambda, double tau) { return scaled_e1(lambda * tau); }

double aged_steady_area(const core::InterfaceParams& p, double v) {
  const double d = p.kappa * std::abs(v);
  return (1.0 + p.aging_b * mean_log_age_exponential(d, p.aging_tau)) / (1.0 + d);
}

double aged_steady_sigma(const core::InterfaceParams& p, double v) {
  return p.alpha * aged_steady_area(p, v) * (v >= 0 ? 1.0 : -1.0) + p.eta * v;
}

namespace {
// The contacts detached at t = 0 (a fraction 1 − φ0), attaching at unit rate: their expected area at t.
double reattached_area(const core::InterfaceParams& p, double phi0, double t) {
  const double tau = p.aging_tau, lg = std::log1p(t / tau);
  // ∫_0^t e^{−(t−s)} ln(1 + s/τ) ds = ln(1 + t/τ) − [e^{−(t+τ)} Ei(t + τ) − e^{−t} e^{−τ} Ei(τ)]
  const double j = lg - (scaled_ei(t + tau) - std::exp(-t) * scaled_ei(tau));
  return (1.0 - phi0) * (-std::expm1(-t) + p.aging_b * j);
}
}  // namespace

double aged_rest_area(const core::InterfaceParams& p, double phi0, double t) {
  return phi0 * (1.0 + p.aging_b * std::log1p(t / p.aging_tau)) + reattached_area(p, phi0, t);
}

double aged_hold_area(const core::InterfaceParams& p, double v, double t) {
  const double d = p.kappa * std::abs(v), phi0 = 1.0 / (1.0 + d), tau = p.aging_tau;
  const double survivors = std::log1p(t / tau) + scaled_e1(d * (tau + t));
  return phi0 * (1.0 + p.aging_b * survivors) + reattached_area(p, phi0, t);
}

}  // namespace slipfront::discrete
