#include "discrete/thresholds.hpp"

#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/weibull.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "continuum/params.hpp"

namespace slipfront::discrete {
namespace {

// Truncated (s > 0) normal with parent (m, s0): mean and sd.
void truncated_moments(double m, double s0, double& mean, double& sd) {
  const boost::math::normal z;
  const double a = -m / s0;
  const double tail = boost::math::cdf(boost::math::complement(z, a));
  const double lam = boost::math::pdf(z, a) / tail;
  mean = m + s0 * lam;
  sd = s0 * std::sqrt(std::max(0.0, 1.0 + a * lam - lam * lam));
}

}  // namespace

ThresholdDistribution::ThresholdDistribution(const std::string& kind, double width) : kind_(kind), width_(width) {
  if (kind == "delta") {
    if (width != 0.0) throw continuum::ParamError("discrete.width", "a delta distribution has width 0");
  } else if (kind == "uniform") {
    a_ = 1.0 - std::sqrt(3.0) * width;
    b_ = 1.0 + std::sqrt(3.0) * width;
    if (a_ < 0.0) throw continuum::ParamError("discrete.width", "uniform thresholds need w <= 1/sqrt(3)");
  } else if (kind == "gaussian") {
    // Fixed-point iteration on the parent (m, s0) so that the truncated law has mean 1, sd w.
    double m = 1.0, s0 = width;
    for (int it = 0; it < 200 && width > 0; ++it) {
      double mu, sd;
      truncated_moments(m, s0, mu, sd);
      m += 1.0 - mu;
      s0 *= width / sd;
    }
    a_ = m;
    b_ = s0;
  } else if (kind == "weibull") {
    if (width > 0) {
      // CV(k)² = Γ(1+2/k)/Γ(1+1/k)² − 1 decreases in k: bisect on log k.
      auto cv = [](double k) {
        const double g1 = boost::math::tgamma(1.0 + 1.0 / k), g2 = boost::math::tgamma(1.0 + 2.0 / k);
        return std::sqrt(g2 / (g1 * g1) - 1.0);
      };
      double lo = std::log(0.05), hi = std::log(1e4);
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (cv(std::exp(mid)) > width ? lo : hi) = mid;
      }
      a_ = std::exp(0.5 * (lo + hi));
      b_ = 1.0 / boost::math::tgamma(1.0 + 1.0 / a_);
    }
  } else {
    throw continuum::ParamError("discrete.threshold", "unknown distribution '" + kind + "'");
  }
}

double ThresholdDistribution::cdf(double s) const {
  if (degenerate()) return s >= 1.0 ? 1.0 : 0.0;
  if (kind_ == "uniform") return std::clamp((s - a_) / (b_ - a_), 0.0, 1.0);
  if (kind_ == "gaussian") {
    if (s <= 0) return 0.0;
    const boost::math::normal parent(a_, b_);
    const double c0 = boost::math::cdf(parent, 0.0);
    return (boost::math::cdf(parent, s) - c0) / (1.0 - c0);
  }
  if (s <= 0) return 0.0;
  return boost::math::cdf(boost::math::weibull(a_, b_), s);
}

double ThresholdDistribution::quantile(double p) const {
  if (degenerate()) return 1.0;
  p = std::clamp(p, 0.0, 1.0);
  if (kind_ == "uniform") return a_ + p * (b_ - a_);
  if (kind_ == "gaussian") {
    const boost::math::normal parent(a_, b_);
    const double c0 = boost::math::cdf(parent, 0.0);
    const double q = c0 + p * (1.0 - c0);
    if (q >= 1.0) return std::numeric_limits<double>::infinity();
    return q <= 0.0 ? 0.0 : boost::math::quantile(parent, q);
  }
  if (p >= 1.0) return std::numeric_limits<double>::infinity();
  return p <= 0.0 ? 0.0 : boost::math::quantile(boost::math::weibull(a_, b_), p);
}

double ThresholdDistribution::conditional_mean(double p0, double p1) const {
  if (degenerate()) return 1.0;
  if (p1 <= p0) return quantile(p0);
  // E[s | p in [p0, p1]] = (1/(p1−p0)) ∫ G^{-1}(p) dp; the integrand may diverge (weakly) at p = 1.
  auto f = [this](double p) { return quantile(p); };
  const double I = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, p0, p1, 10, 1e-12);
  return I / (p1 - p0);
}

double ThresholdDistribution::mean() const { return degenerate() ? 1.0 : conditional_mean(0.0, 1.0); }

double ThresholdDistribution::stddev() const {
  if (degenerate()) return 0.0;
  auto f = [this](double p) { const double d = quantile(p) - 1.0; return d * d; };
  const double m = mean();
  const double v = boost::math::quadrature::gauss_kronrod<double, 31>::integrate(f, 0.0, 1.0, 12, 1e-12);
  return std::sqrt(std::max(0.0, v - (m - 1.0) * (m - 1.0)));
}

}  // namespace slipfront::discrete
