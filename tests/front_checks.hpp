#pragma once
// Shared checks of the strip and in-plane front solvers' tests (test_strip_front, test_inplane_front,
// test_slow_inplane_front): the 1D front each thin strip must tend to, the order and Richardson limit of that approach,
// and the successive orders of a mesh sequence.
#include <catch2/catch.hpp>

#include <cmath>
#include <utility>
#include <vector>

#include "compare/fit.hpp"
#include "continuum/steady_front.hpp"
#include "core/params.hpp"

namespace slipfront::testing {

/// c of the 1D steady front (the chain of μ = 300, ρ = 0.01) of `law` at σ_d: what a strip of the same plate stiffness
/// tends to as H → 0.
inline double one_dimensional_speed(const core::InterfaceParams& law, double sigma_d) {
  const auto f = continuum::solve_steady_front(law, core::BulkParams{0.01, 300.0, 300.0}, sigma_d);
  REQUIRE(f.status == continuum::FrontStatus::converged);
  return f.c;
}

/// Order p of |c(H) − c_1D| = a H^p fitted over H, and the Richardson limit from the two smallest H,
/// c(H₁) − (c(H₂) − c(H₁))/((H₂/H₁)² − 1).
struct ThinLimit {
  double order, limit;
};
inline ThinLimit thin_limit(const std::vector<double>& H, const std::vector<double>& c, double c_1d) {
  std::vector<double> gap;
  for (double ci : c) gap.push_back(std::abs(ci - c_1d));
  const auto fit = compare::fit_power_law(H, gap);
  const double r2 = (H[1] / H[0]) * (H[1] / H[0]);
  return {fit.slope, c[0] - (c[1] - c[0]) / (r2 - 1.0)};
}

/// The two successive observed orders log2(|c₁ − c₀| / |c₂ − c₁|), log2(|c₂ − c₁| / |c₃ − c₂|) of four values on meshes
/// refined by two each time.
inline std::pair<double, double> successive_orders(const std::vector<double>& c) {
  REQUIRE(c.size() == 4);
  return {std::log2(std::abs(c[1] - c[0]) / std::abs(c[2] - c[1])), std::log2(std::abs(c[2] - c[1]) / std::abs(c[3] - c[2]))};
}

}  // namespace slipfront::testing
