#include "discrete/thresholds.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/weibull.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "core/params.hpp"

namespace slipfront::discrete {
namespace {

using core::format_number;
using core::ParamError;

constexpr double inf = std::numeric_limits<double>::infinity();
const double uniform_max_width = 1.0 / std::numbers::sqrt3;  // 1/√3, as the old check computed it
constexpr double gaussian_max_width = 0.99;
constexpr double weibull_max_width = 10.0;
constexpr double moment_tolerance = 1e-9;  // |mean − 1| and |sd − w| / w after construction

const boost::math::normal standard_normal;

// Standard normal density and upper tail Q(z) = 1 − Φ(z) (Boost: accurate in both tails).
double phi(double z) { return boost::math::pdf(standard_normal, z); }
double upper_tail(double z) { return boost::math::cdf(boost::math::complement(standard_normal, z)); }

// Truncated (s > 0) normal with parent (m, s0), written with a = −m/s0 and λ = φ(a)/Q(a) (the
// inverse Mills ratio): mean = s0 (λ − a), variance = s0² (1 + aλ − λ²). Its coefficient of
// variation depends on a only and increases from 0 (a → −∞) to 1 (a → +∞, the exponential limit).
double inverse_mills(double a) { return phi(a) / upper_tail(a); }
double truncated_cv(double a) {
  const double lam = inverse_mills(a);
  return std::sqrt(std::max(0.0, 1.0 + a * lam - lam * lam)) / (lam - a);
}

// log Γ(1 + x), accurate for small x too (Boost's tgamma1pm1).
double lgamma1p(double x) { return std::log1p(boost::math::tgamma1pm1(x)); }
// Coefficient of variation of a Weibull law of shape k: sqrt(Γ(1+2/k)/Γ(1+1/k)² − 1), decreasing in k.
double weibull_cv(double k) { return std::sqrt(std::expm1(lgamma1p(2.0 / k) - 2.0 * lgamma1p(1.0 / k))); }

// A root of f on [lo, hi] (f(lo), f(hi) of opposite signs) to ~1e-15 relative, or NaN when the
// bracket is wrong or TOMS 748 did not converge in 200 iterations.
template <class F>
double solve(F f, double lo, double hi) {
  const double flo = f(lo), fhi = f(hi);
  if (!(std::isfinite(flo) && std::isfinite(fhi)) || (flo > 0) == (fhi > 0)) return std::nan("");
  std::uintmax_t iterations = 200;
  const auto r = boost::math::tools::toms748_solve(f, lo, hi, flo, fhi, boost::math::tools::eps_tolerance<double>(50),
                                                   iterations);
  if (iterations >= 200) return std::nan("");
  return 0.5 * (r.first + r.second);
}

[[noreturn]] void refuse_width(const std::string& kind, double w, const std::string& why) {
  throw ParamError("discrete.width", "a " + kind + " threshold law with mean 1 and width " + format_number(w) + " " + why);
}

}  // namespace

double max_width(const std::string& kind) {
  if (kind == "delta") return 0.0;
  if (kind == "uniform") return uniform_max_width;
  if (kind == "gaussian") return gaussian_max_width;
  if (kind == "weibull") return weibull_max_width;
  throw ParamError("discrete.threshold", "unknown distribution '" + kind + "' (expected delta, uniform, gaussian or weibull)");
}

ThresholdDistribution::ThresholdDistribution(const std::string& kind, double width) : kind_(kind), width_(width) {
  const double w_max = max_width(kind);  // throws for an unknown kind
  if (!std::isfinite(width) || width < 0.0) throw ParamError("discrete.width", "must be >= 0, got " + format_number(width));
  if (kind == "delta" && width != 0.0)
    throw ParamError("discrete.width", "a delta distribution has width 0 (choose uniform, gaussian or weibull)");
  if (width > w_max) {
    if (kind == "uniform")
      refuse_width(kind, width, "needs w <= 1/sqrt(3) = 0.5774 (its support 1 ± sqrt(3) w must stay >= 0)");
    if (kind == "gaussian")
      refuse_width(kind, width,
                   "does not exist for w >= 1 (truncated at 0, its coefficient of variation is below 1: the limit "
                   "is the exponential law) and is built for w <= 0.99");
    refuse_width(kind, width, "is built for w <= 10 (shape k >= 0.188; docs/robustness.md)");
  }
  if (degenerate()) return;
  if (kind == "uniform") {
    a_ = 1.0 - std::numbers::sqrt3 * width;
    b_ = 1.0 + std::numbers::sqrt3 * width;
    a_ = std::max(a_, 0.0);  // w = 1/√3 rounds to a tiny negative bound
  } else if (kind == "gaussian") {
    // CV(a) = w on a ∈ [−1/w − 10, 12] (CV(−1/w − 10) < w, CV(12) > 0.99), then s0 = 1/(λ − a) so
    // that the truncated mean s0 (λ − a) is 1, and m = −a s0.
    const double a = solve([w = width](double x) { return truncated_cv(x) - w; }, -1.0 / width - 10.0, 12.0);
    if (!std::isfinite(a)) refuse_width(kind, width, "could not be built: the root finder did not converge");
    b_ = 1.0 / (inverse_mills(a) - a);
    a_ = -a * b_;
    tail0_ = upper_tail(a);
  } else {
    // CV(k) = w on log k ∈ [log 0.1, log(2/w + 10)] (CV(0.1) = 430 > 10, CV(k) ≈ 1.28/k for large k).
    const double logk = solve([w = width](double x) { return weibull_cv(std::exp(x)) - w; }, std::log(0.1),
                              std::log(2.0 / width + 10.0));
    if (!std::isfinite(logk)) refuse_width(kind, width, "could not be built: the root finder did not converge");
    a_ = std::exp(logk);
    b_ = std::exp(-lgamma1p(1.0 / a_));  // scale 1/Γ(1 + 1/k): mean 1
  }
  // The constructed law's own mean and sd (closed forms of its parameters) must be 1 and w.
  const double m = mean(), sd = stddev();
  if (!(std::abs(m - 1.0) <= moment_tolerance && std::abs(sd - width) <= moment_tolerance * width + 1e-15))
    refuse_width(kind, width,
                 "could not be built to 1e-9: its mean is " + format_number(m) + " and its sd " + format_number(sd));
}

double ThresholdDistribution::cdf(double s) const {
  if (degenerate()) return s >= 1.0 ? 1.0 : 0.0;
  if (kind_ == "uniform") return std::clamp((s - a_) / (b_ - a_), 0.0, 1.0);
  if (s <= 0) return 0.0;
  if (kind_ == "gaussian") return std::clamp(1.0 - upper_tail((s - a_) / b_) / tail0_, 0.0, 1.0);
  return boost::math::cdf(boost::math::weibull(a_, b_), s);
}

double ThresholdDistribution::quantile(double p) const {
  if (degenerate()) return 1.0;
  p = std::clamp(p, 0.0, 1.0);
  if (kind_ == "uniform") return a_ + p * (b_ - a_);
  if (p >= 1.0) return inf;
  if (p <= 0.0) return 0.0;
  if (kind_ == "gaussian") {
    // upper tail of the parent: Q((s − m)/s0) = (1 − p) Q0 (accurate however far the parent's mean lies below 0)
    const double q = (1.0 - p) * tail0_;
    if (q <= 0.0) return inf;
    return std::max(0.0, a_ + b_ * boost::math::quantile(boost::math::complement(standard_normal, q)));
  }
  return boost::math::quantile(boost::math::weibull(a_, b_), p);
}

double ThresholdDistribution::conditional_mean(double p0, double p1) const {
  if (degenerate()) return 1.0;
  p0 = std::clamp(p0, 0.0, 1.0);
  p1 = std::clamp(p1, 0.0, 1.0);
  if (p1 <= p0) return quantile(p0);
  if (kind_ == "uniform") return a_ + 0.5 * (p0 + p1) * (b_ - a_);
  if (kind_ == "gaussian") {
    // E[s | s ∈ [G⁻¹(p0), G⁻¹(p1)]] = m + s0 (φ(z0) − φ(z1)) / ((p1 − p0) Q0),  z = (s − m)/s0
    const double z0 = p0 <= 0.0 ? -a_ / b_ : (quantile(p0) - a_) / b_;
    const double f1 = p1 >= 1.0 ? 0.0 : phi((quantile(p1) - a_) / b_);
    return std::max(0.0, a_ + b_ * (phi(z0) - f1) / ((p1 - p0) * tail0_));
  }
  // Weibull: s = λ x^{1/k} with x ~ Exp(1); E[s; x ∈ [x0, x1]] = λ Γ(1+1/k) (P(1+1/k, x1) − P(1+1/k, x0))
  // and λ Γ(1+1/k) = 1. Differences of the upper tails Q where the lower ones would cancel.
  const double c = 1.0 + 1.0 / a_;
  const double x0 = -std::log1p(-p0), x1 = p1 >= 1.0 ? inf : -std::log1p(-p1);
  const double lower = p1 >= 1.0 ? 1.0 : boost::math::gamma_p(c, x1);
  const double mass = lower < 0.5 ? lower - boost::math::gamma_p(c, x0)
                                  : boost::math::gamma_q(c, x0) - (p1 >= 1.0 ? 0.0 : boost::math::gamma_q(c, x1));
  return mass / (p1 - p0);
}

double ThresholdDistribution::mean() const {
  if (degenerate()) return 1.0;
  if (kind_ == "uniform") return 0.5 * (a_ + b_);
  if (kind_ == "gaussian") return b_ * (inverse_mills(-a_ / b_) + a_ / b_);
  return b_ * std::exp(lgamma1p(1.0 / a_));
}

double ThresholdDistribution::stddev() const {
  if (degenerate()) return 0.0;
  if (kind_ == "uniform") return (b_ - a_) / (2.0 * std::numbers::sqrt3);
  if (kind_ == "gaussian") {
    const double a = -a_ / b_, lam = inverse_mills(a);
    return b_ * std::sqrt(std::max(0.0, 1.0 + a * lam - lam * lam));
  }
  return b_ * std::exp(lgamma1p(1.0 / a_)) * weibull_cv(a_);
}

}  // namespace slipfront::discrete
