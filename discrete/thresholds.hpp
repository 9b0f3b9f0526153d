#pragma once
// Yield-threshold distributions g of docs/model.md §2: mean 1, relative width (standard deviation) w.
//   delta     s = 1 (w must be 0; any w with "delta" means w is ignored only when 0: validated)
//   uniform   U[1 − √3 w, 1 + √3 w]
//   gaussian  normal truncated to s > 0, parent (m, s0) solved so the truncated law has mean 1, sd w
//   weibull   shape k with coefficient of variation w, scale 1/Γ(1 + 1/k)
// Sampling is by inversion (one uniform per draw), so draws are identical across standard libraries.
#include <string>

namespace slipfront::discrete {

class ThresholdDistribution {
 public:
  ThresholdDistribution(const std::string& kind, double width);

  const std::string& kind() const { return kind_; }
  double width() const { return width_; }
  bool degenerate() const { return kind_ == "delta" || width_ == 0.0; }  ///< every threshold is 1

  double cdf(double s) const;       ///< G(s) = P(threshold ≤ s)
  double quantile(double p) const;  ///< G^{-1}(p), p in [0, 1]
  /// Mean of the threshold conditional on its quantile lying in [p0, p1] (for quantile bins).
  double conditional_mean(double p0, double p1) const;
  /// Theoretical mean and standard deviation (checks: 1 and w).
  double mean() const;
  double stddev() const;

  /// Draw from a uniform number u in (0, 1).
  double from_uniform(double u) const { return degenerate() ? 1.0 : quantile(u); }

 private:
  std::string kind_;
  double width_;
  double a_ = 0, b_ = 0;  // uniform bounds / gaussian parent (mean, sd) / weibull (shape, scale)
};

}  // namespace slipfront::discrete
