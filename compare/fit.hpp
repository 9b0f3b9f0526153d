#pragma once
// Fits for convergence studies: least-squares lines with confidence intervals (Student t), and
// power laws fitted as lines in log–log. Written by hand (a dozen lines of algebra) rather than
// pulling in a statistics library; the t quantile comes from Boost.Math.
#include <functional>
#include <span>
#include <vector>

namespace slipfront::compare {

struct LineFit {
  double slope, intercept;
  double slope_stderr, intercept_stderr;
  double slope_ci_low, slope_ci_high;  ///< two-sided confidence interval at `confidence`
  double r2;
  int n;
  double confidence;
};

/// Mean and sample standard deviation of the finite values of v (NaN with none, or with fewer than 2 for the sd),
/// and how many are finite.
double mean_of(std::span<const double> v);
double sd_of(std::span<const double> v);
int finite_count(std::span<const double> v);
/// Least-squares slope through the origin of y(x) over the pairs with both finite (NaN with none).
double slope_through_origin(std::span<const double> x, std::span<const double> y);

/// Ordinary least squares y = a + b x (optionally weighted by 1/sigma²); NaN fields with n < 3.
LineFit fit_line(std::span<const double> x, std::span<const double> y, double confidence = 0.95);
LineFit fit_line_weighted(std::span<const double> x, std::span<const double> y, std::span<const double> sigma,
                          double confidence = 0.95);

/// err ≈ C x^p: the line fit of log err against log x (slope = p); points with err ≤ 0 are dropped.
LineFit fit_power_law(std::span<const double> x, std::span<const double> err, double confidence = 0.95);

/// y ≈ C x_1^{p_1} ... x_k^{p_k}: ordinary least squares of log y on (1, log x_1, ..., log x_k) (Eigen's
/// column-pivoting QR), with Student-t intervals on n − k − 1 degrees of freedom; points with a
/// non-positive or non-finite value dropped. `exponents` empty when fewer than k + 2 points remain or
/// the design is rank deficient (a factor that never varies).
struct PowerLawFit {
  std::vector<double> exponents, stderrs, ci_low, ci_high;
  double prefactor = 0.0;
  double log_rms = 0.0;  ///< RMS of the log residuals
  int n = 0;
};
PowerLawFit fit_power_law_multi(const std::vector<std::vector<double>>& factors, std::span<const double> y,
                                double confidence = 0.95);

/// Minimum of a tabulated curve y(x) with x > 0 (the steady friction law σ(v)): the parabola in log x
/// through the smallest y and its two neighbours (the ends excluded: the three points around the
/// smallest interior one). `found` is false when the parabola does not open upwards or fewer than
/// three points are given.
struct TabulatedMinimum {
  bool found = false;
  double x = 0.0, y = 0.0;
  std::size_t index = 0;  ///< the middle of the three points
};
TabulatedMinimum parabola_minimum_log(std::span<const double> x, std::span<const double> y);

/// Golden-section search for the minimum of a unimodal f on [lo, hi], to a bracket of width `tol`;
/// returns the bracket's midpoint.
double golden_section_minimum(const std::function<double(double)>& f, double lo, double hi, double tol);

}  // namespace slipfront::compare
