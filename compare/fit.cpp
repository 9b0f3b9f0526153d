#include "compare/fit.hpp"

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

}  // namespace slipfront::compare
