#pragma once
// Relative differences of a model against its reference, with one rule for what is not a number
// (docs/output.md /compare): every comparison metric, study table and test that speaks of "relative
// difference" calls these.
//
// The rule: a pair (reference a, value b) counts only where both are finite. Where the reference
// vanishes the relative difference is 0 if the value vanishes too and NaN otherwise (the absolute
// difference is what to report then). A pair with a non-finite member is NaN (scalar) or left out of
// the sums (fields and series: a front that does not exist at some times, a series cut short by a
// failed run); no pair left is NaN.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

namespace slipfront::compare {

/// (b − a)/|a| under the rule above.
inline double relative_difference(double a, double b) {
  if (!std::isfinite(a) || !std::isfinite(b)) return std::numeric_limits<double>::quiet_NaN();
  if (a != 0.0) return (b - a) / std::abs(a);
  return b == 0.0 ? 0.0 : std::numeric_limits<double>::quiet_NaN();
}

/// sqrt(Σ (b_i − a_i)² / Σ a_i²) over the common length of a (reference) and b, under the rule
/// above: the relative L2 distance of two fields on the same nodes, or the relative RMS distance of
/// two series on the same times.
inline double relative_rms_distance(std::span<const double> a, std::span<const double> b) {
  double num = 0.0, den = 0.0;
  bool any = false;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(a[i]) || !std::isfinite(b[i])) continue;
    any = true;
    num += (b[i] - a[i]) * (b[i] - a[i]);
    den += a[i] * a[i];
  }
  if (!any) return std::numeric_limits<double>::quiet_NaN();
  if (den > 0.0) return std::sqrt(num / den);
  return num > 0.0 ? std::numeric_limits<double>::quiet_NaN() : 0.0;
}

}  // namespace slipfront::compare
