// Steady fronts in the strip, slow tier (continuum/strip_front.hpp, docs/fronts.md §10.6–§10.9): the branch
// continued in σ_d to its end at several H with c_min(H) → the 1D c_min at second order, and the fronts of
// one strip material (μ', ρ' fixed) from the 1D limit to H = 64, converged across the height.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "compare/fit.hpp"
#include "continuum/steady_front.hpp"
#include "continuum/strip_front.hpp"

namespace continuum = slipfront::continuum;
namespace core = slipfront::core;
using continuum::BranchEnd;
using continuum::FrontStatus;
using continuum::StripFront;

namespace {
const core::InterfaceParams paper{1.05, 8.0, 0.1};
constexpr double c_min_1d = 11.28108382;  // docs/fronts.md §5
}  // namespace

TEST_CASE("strip front: the branch ends at the saddle-node and c_min(H) -> the 1D c_min as H^2", "[strip][front][branch]") {
  // μ = 300, ρ = 0.01 integrated over the height (μ' = μ/H), 4 rows, 300 intervals: about 3.5 s a branch.
  continuum::StripContinuationOptions o;
  o.front.rows = 4;
  o.front.intervals = 300;
  std::vector<double> H{0.5, 1.0, 2.0}, gap;
  for (double h : H) {
    const auto br = continuum::continue_strip_fronts(paper, {0.01, 300.0, 300.0, h}, o);
    INFO("H = " << h << ": " << br.reason);
    REQUIRE(br.end == BranchEnd::saddle_node);
    CHECK(br.folds.empty());
    CHECK(br.points.size() > 20);
    for (std::size_t i = 1; i < br.points.size(); ++i) {
      CHECK(br.points[i].sigma_d < br.points[i - 1].sigma_d);
      CHECK(br.points[i].c < br.points[i - 1].c);
      CHECK(br.points[i].overstress_margin > 0.0);
      CHECK(br.points[i].min_slip_rate > 0.0);
    }
    CHECK(br.c_min_at_end);
    CHECK(br.last.saddle_node_limit);
    CHECK(std::abs(br.sigma_d_at_c_min - continuum::steady_minimum_stress(paper)) < 1e-12);
    gap.push_back(br.c_min - c_min_1d);
  }
  // Observed c_min(H) − c_min(1D) = +5.45e−5, +2.255e−4, +9.29e−4: 2.2e−4 H².
  for (double g : gap) CHECK(g > 0.0);
  const auto fit = slipfront::compare::fit_power_law(H, gap);
  WARN("c_min(H) - c_min(1D) ~ H^" << fit.slope);
  CHECK(std::abs(fit.slope - 2.0) < 0.05);
}

TEST_CASE("strip front: one material from the 1D limit to H = 64 (mu', rho' fixed)", "[strip][front][material]") {
  // μ' = 300, ρ' = 0.01 (the paper's material at H = 1), σ_d = 0.5, H = 0.25 … 64, each solve started from
  // the previous H. The 1D front of the same column stiffness μ = μ'H is faster at every H and both run
  // toward c_s = 173.2 as H grows (c ∝ sqrt(μ) in 1D): c/c_s = 0.19 (H = 0.25), 0.35 (1), 0.83 (16), 0.95 (64).
  const double mus = 300.0, rhos = 0.01, cs = std::sqrt(mus / rhos);
  continuum::StripFrontOptions o;
  o.rows = 8;
  o.intervals = 300;
  StripFront prev;
  double last_ratio = 0.0, last_gap = 0.0;
  for (double H = 0.25; H <= 64.0; H *= 4.0) {
    const core::BulkParams b{rhos * H, mus * H, 300.0, H};
    const StripFront f = continuum::solve_strip_front(paper, b, 0.5, o, H > 0.25 ? &prev : nullptr);
    REQUIRE(f.status == FrontStatus::converged);
    const auto f1 = continuum::solve_steady_front(paper, core::BulkParams{b.rho, b.mu, b.length}, 0.5);
    REQUIRE(f1.status == FrontStatus::converged);
    const double gap = 1.0 - f.c / f1.c;
    INFO("H = " << H << ": c = " << f.c << ", 1D " << f1.c);
    CHECK(f.c / cs > last_ratio);
    CHECK(gap > last_gap);
    last_ratio = f.c / cs;
    last_gap = gap;
    prev = f;
  }
  CHECK(last_ratio > 0.94);
  // Across the height at H = 64: 8, 16, 32 rows (first row spacing 0.25 … graded) converge at ≥ 2nd order.
  std::vector<double> c;
  for (int M : {8, 16, 32}) {
    o.rows = M;
    const StripFront f = continuum::solve_strip_front(paper, {rhos * 64.0, mus * 64.0, 300.0, 64.0}, 0.5, o, &prev);
    REQUIRE(f.status == FrontStatus::converged);
    c.push_back(f.c);
  }
  WARN("H = 64: c = " << c[0] << ", " << c[1] << ", " << c[2] << " with 8, 16, 32 rows");
  CHECK(std::abs(c[1] - c[0]) / std::abs(c[2] - c[1]) > 3.5);
  CHECK(std::abs(c[2] - c[1]) / c[2] < 2e-5);
}
