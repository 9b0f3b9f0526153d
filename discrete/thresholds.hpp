#pragma once
// Yield-threshold distributions g of docs/model.md §2: mean 1, relative width (standard deviation) w.
//   delta     s = 1 (w must be 0)
//   uniform   U[1 − √3 w, 1 + √3 w]                          exists for w ≤ 1/√3 (support s ≥ 0)
//   gaussian  normal truncated to s > 0, parent (m, s0) solved so the truncated law has mean 1, sd w;
//             exists for w < 1 (the supremum is the exponential limit m → −∞); built for w ≤ 0.99
//   weibull   shape k with coefficient of variation w, scale 1/Γ(1 + 1/k); exists for every w > 0;
//             built for w ≤ 10 (k ≥ 0.188: beyond, the law is a few huge thresholds among
//             vanishing ones and the count representation's bins lose their meaning)
// Construction solves for the parameters with a bracketing root finder (Boost TOMS 748) and
// refuses (core::ParamError naming discrete.width) when the width is outside the domain, the
// solver does not converge, or the constructed law's theoretical mean and sd differ from 1 and w
// by more than 1e-9 (docs/robustness.md §2). Conditional means over quantile intervals (the count
// representation's bins) are closed forms.
// Sampling is by inversion (one uniform per draw), so draws are identical across standard libraries.
#include <string>

namespace slipfront::discrete {

/// The largest relative width the distribution `kind` is built for with mean 1 (see above):
/// delta 0, uniform 1/√3, gaussian 0.99, weibull 10. Throws ParamError for an unknown kind.
double max_width(const std::string& kind);

class ThresholdDistribution {
 public:
  /// Throws core::ParamError("discrete.width" or "discrete.threshold", reason) when the law
  /// cannot be built (see the header comment).
  ThresholdDistribution(const std::string& kind, double width);

  const std::string& kind() const { return kind_; }
  double width() const { return width_; }
  bool degenerate() const { return kind_ == "delta" || width_ == 0.0; }  ///< every threshold is 1

  double cdf(double s) const;       ///< G(s) = P(threshold ≤ s)
  double quantile(double p) const;  ///< G^{-1}(p), p in [0, 1]
  /// Mean of the threshold conditional on its quantile lying in [p0, p1] (for quantile bins):
  /// closed forms (uniform: midpoint; gaussian: the truncated-normal mean; weibull: regularized
  /// incomplete gamma functions).
  double conditional_mean(double p0, double p1) const;
  /// Theoretical mean and standard deviation of the constructed law (closed forms of its
  /// parameters; checked against 1 and w at construction).
  double mean() const;
  double stddev() const;
  /// Parameters: uniform (lower, upper) bounds; gaussian parent (mean, sd); weibull (shape, scale).
  double parameter_a() const { return a_; }
  double parameter_b() const { return b_; }

  /// Draw from a uniform number u in (0, 1).
  double from_uniform(double u) const { return degenerate() ? 1.0 : quantile(u); }

 private:
  std::string kind_;
  double width_;
  double a_ = 0, b_ = 0;  // uniform bounds / gaussian parent (mean, sd) / weibull (shape, scale)
  double tail0_ = 1.0;    // gaussian: parent mass above 0, Q((0 − m)/s0)
};

}  // namespace slipfront::discrete
