#include "compare/fit.hpp"

#include <algorithm>

#include <Eigen/Dense>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <vector>

namespace slipfront::compare {
namespace {
constexpr double nan_v = std::numeric_limits<double>::quiet_NaN();
}

LineFit fit_line_weighted(std::span<const double> x, std::span<const double> y, std::span<const double> sigma,
                          double confidence) {
  LineFit f{nan_v, nan_v, nan_v, nan_v, nan_v, nan_v, nan_v, static_cast<int>(x.size()), confidence};
  const std::size_t n = x.size();
  if (n < 2) return f;
  double sw = 0, sx = 0, sy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = sigma.empty() ? 1.0 : 1.0 / (sigma[i] * sigma[i]);
    sw += w; sx += w * x[i]; sy += w * y[i];
  }
  const double mx = sx / sw, my = sy / sw;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = sigma.empty() ? 1.0 : 1.0 / (sigma[i] * sigma[i]);
    sxx += w * (x[i] - mx) * (x[i] - mx);
    sxy += w * (x[i] - mx) * (y[i] - my);
    syy += w * (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0) return f;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double rss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = sigma.empty() ? 1.0 : 1.0 / (sigma[i] * sigma[i]);
    const double r = y[i] - f.intercept - f.slope * x[i];
    rss += w * r * r;
  }
  f.r2 = syy > 0 ? 1.0 - rss / syy : 1.0;
  if (n < 3) return f;
  const double dof = static_cast<double>(n) - 2.0;
  const double s2 = rss / dof;  // residual variance (scale of the weights estimated from the data)
  f.slope_stderr = std::sqrt(s2 / sxx);
  f.intercept_stderr = std::sqrt(s2 * (1.0 / sw + mx * mx / sxx));
  const boost::math::students_t t(dof);
  const double q = boost::math::quantile(boost::math::complement(t, 0.5 * (1.0 - confidence)));
  f.slope_ci_low = f.slope - q * f.slope_stderr;
  f.slope_ci_high = f.slope + q * f.slope_stderr;
  return f;
}

LineFit fit_line(std::span<const double> x, std::span<const double> y, double confidence) {
  return fit_line_weighted(x, y, {}, confidence);
}

LineFit fit_power_law(std::span<const double> x, std::span<const double> err, double confidence) {
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (err[i] > 0 && x[i] > 0 && std::isfinite(err[i])) { lx.push_back(std::log(x[i])); ly.push_back(std::log(err[i])); }
  return fit_line(lx, ly, confidence);
}

PowerLawFit fit_power_law_multi(const std::vector<std::vector<double>>& factors, std::span<const double> y,
                                double confidence) {
  PowerLawFit f;
  const std::size_t k = factors.size();
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < y.size(); ++i) {
    bool ok = y[i] > 0 && std::isfinite(y[i]);
    for (const auto& x : factors) ok = ok && i < x.size() && x[i] > 0 && std::isfinite(x[i]);
    if (ok) keep.push_back(i);
  }
  f.n = static_cast<int>(keep.size());
  if (keep.size() < k + 2) return f;
  Eigen::MatrixXd a(keep.size(), k + 1);
  Eigen::VectorXd b(keep.size());
  for (std::size_t r = 0; r < keep.size(); ++r) {
    a(r, 0) = 1.0;
    for (std::size_t c = 0; c < k; ++c) a(r, c + 1) = std::log(factors[c][keep[r]]);
    b(r) = std::log(y[keep[r]]);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < static_cast<Eigen::Index>(k + 1)) return f;
  const Eigen::VectorXd coef = qr.solve(b);
  const Eigen::VectorXd res = b - a * coef;
  const double dof = static_cast<double>(keep.size() - k - 1);
  const double s2 = res.squaredNorm() / dof;
  const Eigen::MatrixXd cov = s2 * (a.transpose() * a).inverse();
  const boost::math::students_t t(dof);
  const double q = boost::math::quantile(boost::math::complement(t, 0.5 * (1.0 - confidence)));
  f.prefactor = std::exp(coef(0));
  f.log_rms = std::sqrt(res.squaredNorm() / static_cast<double>(keep.size()));
  for (std::size_t c = 0; c < k; ++c) {
    const double p = coef(c + 1), se = std::sqrt(cov(c + 1, c + 1));
    f.exponents.push_back(p);
    f.stderrs.push_back(se);
    f.ci_low.push_back(p - q * se);
    f.ci_high.push_back(p + q * se);
  }
  return f;
}

TabulatedMinimum parabola_minimum_log(std::span<const double> xs, std::span<const double> ys) {
  TabulatedMinimum m;
  if (ys.size() < 3 || xs.size() != ys.size()) return m;
  auto k = static_cast<std::size_t>(std::min_element(ys.begin(), ys.end()) - ys.begin());
  k = std::clamp<std::size_t>(k, 1, ys.size() - 2);
  m.index = k;
  const double x0 = std::log(xs[k - 1]), x1 = std::log(xs[k]), x2 = std::log(xs[k + 1]);
  const double y0 = ys[k - 1], y1 = ys[k], y2 = ys[k + 1];
  const double d = (x0 - x1) * (x0 - x2) * (x1 - x2);
  const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
  const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
  const double c = (x1 * x2 * (x1 - x2) * y0 + x2 * x0 * (x2 - x0) * y1 + x0 * x1 * (x0 - x1) * y2) / d;
  if (!(a > 0)) return m;
  m.found = true;
  m.x = std::exp(-b / (2 * a));
  m.y = c - b * b / (4 * a);
  return m;
}

double golden_section_minimum(const std::function<double(double)>& f, double lo, double hi, double tol) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double p1 = hi - g * (hi - lo), p2 = lo + g * (hi - lo), f1 = f(p1), f2 = f(p2);
  while (hi - lo > tol) {
    if (f1 < f2) {
      hi = p2;
      p2 = p1;
      f2 = f1;
      p1 = hi - g * (hi - lo);
      f1 = f(p1);
    } else {
      lo = p1;
      p1 = p2;
      f1 = f2;
      p2 = lo + g * (hi - lo);
      f2 = f(p2);
    }
  }
  return 0.5 * (lo + hi);
}

double mean_of(std::span<const double> v) {
  double s = 0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) { s += x; ++n; }
  return n ? s / n : std::numeric_limits<double>::quiet_NaN();
}

double sd_of(std::span<const double> v) {
  const double m = mean_of(v);
  double s = 0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) { s += (x - m) * (x - m); ++n; }
  return n > 1 ? std::sqrt(s / (n - 1)) : std::numeric_limits<double>::quiet_NaN();
}

int finite_count(std::span<const double> v) {
  return static_cast<int>(std::count_if(v.begin(), v.end(), [](double x) { return std::isfinite(x); }));
}

double slope_through_origin(std::span<const double> x, std::span<const double> y) {
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size() && k < y.size(); ++k)
    if (std::isfinite(x[k]) && std::isfinite(y[k])) { sxy += x[k] * y[k]; sxx += x[k] * x[k]; }
  return sxx > 0 ? sxy / sxx : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace slipfront::compare
