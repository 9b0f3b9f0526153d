#pragma once
// The N^-1/2 check of an ensemble against its mean field (docs/model.md §2 hierarchy item 2), shared by the tests of
// the contact laws (test_aging, test_normal_load): the RMS over sites of the ensemble's A_i about the mean field's,
// and the fitted exponent of err ≈ C N^p.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <span>
#include <utility>
#include <vector>

#include "compare/fit.hpp"

namespace slipfront::testing {

/// RMS over the sites of a_i − ref.
inline double rms_about(std::span<const double> a, double ref) {
  double ss = 0.0;
  for (const double x : a) ss += (x - ref) * (x - ref);
  return std::sqrt(ss / static_cast<double>(a.size()));
}

/// For each named series of errors at the contact numbers ns: fit err ≈ C N^p (compare::fit_power_law), print p and
/// its 95 % CI, and check |p + 1/2| < tolerance.
inline void check_inverse_sqrt_rate(std::span<const double> ns,
                                    const std::vector<std::pair<const char*, std::vector<double>>>& errors,
                                    double tolerance) {
  for (const auto& [what, err] : errors) {
    const auto fit = compare::fit_power_law(ns, err);
    std::printf("%s: p = %.3f (95%% CI %.3f .. %.3f)\n", what, fit.slope, fit.slope_ci_low, fit.slope_ci_high);
    CHECK(std::abs(fit.slope + 0.5) < tolerance);
  }
}

}  // namespace slipfront::testing
