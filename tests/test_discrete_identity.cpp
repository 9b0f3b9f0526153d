// docs/model.md §2, hierarchy item 1 (identity): with w = 0 and the noise switched off, the discrete
// ensemble in the count representation IS the continuum law — same grid, same Δt, fields equal to
// round-off. Tolerance: 1e-12 relative to the field's largest magnitude at that time (the two laws
// compute the same exact update by different but algebraically equal groupings, so they differ by
// a few ulps per step); event times must be identical (the same step decides them).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

constexpr double tolerance = 1e-12;

compare::Scene noise_off(compare::Scene s) {
  s = testing::noise_off_count(s);
  s.discrete.seed = 7;
  return s;
}

// fig1 (docs/model.md §4, testing::fig1_scene: edge loading, ρ = 0.01, μ = 300, κ = 8, α = 1.05, η = 0.1,
// K = 2.5, v_d = 0.3, L = 300, dx = 0.5, cfl = 0.5) with a short t_end: through first yield
// (t* = 25.71) to t = 40.
compare::Scene fig1_short() {
  compare::Scene s = testing::fig1_scene();
  s.name = "fig1_identity";
  s.time.t_end = 40.0;
  s.output.snapshot_dt = 5.0;
  return noise_off(s);
}



void require_same_events(const compare::Events& c, const compare::Events& d) {
  CHECK(testing::same(c.t_star, d.t_star));
  CHECK(testing::same(c.t_hat, d.t_hat));
  CHECK(testing::same(c.t_arrest, d.t_arrest));
}

// Every column of `c` compared with the same column of `d`; returns the largest relative difference.
double columns_diff(const compare::Columns& c, const compare::Columns& d) {
  double worst = 0.0;
  for (const auto& [name, col] : c) {
    INFO("column " << name);
    REQUIRE(d.count(name) == 1);
    const double e = testing::max_relative_difference(col, d.at(name));
    CHECK(e <= tolerance);
    worst = std::max(worst, e);
  }
  return worst;
}

}  // namespace

TEST_CASE("discrete identity: fig1 through first yield, w = 0 and noise off", "[discrete][identity]") {
  const compare::Scene s = fig1_short();
  s.validate();
  const auto r = compare::run_scene(s, {});
  REQUIRE(r.size() == 2);
  const auto& c = r[0];
  const auto& d = r[1];
  REQUIRE(c.status == slipfront::compare::RunStatus::complete);
  REQUIRE(d.status == slipfront::compare::RunStatus::complete);
  REQUIRE(c.snapshot_t == d.snapshot_t);
  REQUIRE(c.snapshot_t.size() == 9);  // t = 0, 5, ..., 40
  const std::size_t nx = c.x.size();
  double worst = 0.0;
  for (const char* field : {"A", "sigma_bar", "u", "v"}) {
    for (std::size_t k = 0; k < c.snapshot_t.size(); ++k) {
      INFO(field << " at t = " << c.snapshot_t[k]);
      const auto a = std::span<const double>(c.snapshots.at(field)).subspan(k * nx, nx);
      const auto b = std::span<const double>(d.snapshots.at(field)).subspan(k * nx, nx);
      const double e = testing::max_relative_difference(a, b);
      CHECK(e <= tolerance);
      worst = std::max(worst, e);
    }
  }
  worst = std::max(worst, columns_diff(c.series, d.series));
  std::printf("identity fig1 (t_end = 40): max relative difference %.3g; t* = %.6f (continuum) %.6f (discrete)\n",
              worst, c.events.t_star, d.events.t_star);
  // The run must go through first yield (docs/model.md §1: t* = 25.71) and leave a front behind.
  CHECK(c.events.t_star == Approx(25.71).epsilon(0.01));
  const auto area_end = std::span<const double>(d.snapshots.at("A")).subspan(8 * nx, nx);
  CHECK(*std::min_element(area_end.begin(), area_end.end()) < 0.99);
  require_same_events(c.events, d.events);
  require_same_events(c.events_alt, d.events_alt);
}

TEST_CASE("discrete identity: 0D imposed slip-rate history with steps", "[discrete][identity]") {
  compare::Scene s = testing::imposed_rate_scene();
  s.name = "velocity_step_identity";
  s.drive.v = {0.5, 3.0, 0.05, 1.0, 0.0, 2.0};
  s.drive.v_times = {0.0, 10.0, 20.0, 40.0, 50.0, 55.0};
  s.time.t_end = 70.0;
  s.time.dt = 0.01;
  s.output.series_dt = 0.0;  // every step
  s = noise_off(s);
  s.validate();
  const auto r = compare::run_scene(s, {});
  REQUIRE(r.size() == 2);
  REQUIRE(r[1].status == slipfront::compare::RunStatus::complete);
  REQUIRE(r[0].series.at("t").size() == r[1].series.at("t").size());
  const double worst = columns_diff(r[0].series, r[1].series);
  std::printf("identity velocity steps: max relative difference %.3g, t* = %.4f\n", worst, r[1].events.t_star);
  CHECK(std::isfinite(r[0].events.t_star));
  require_same_events(r[0].events, r[1].events);
}

TEST_CASE("discrete identity: 0D steady friction law sweep", "[discrete][identity]") {
  compare::Scene s = testing::imposed_rate_scene();
  s.name = "friction_law_identity";
  s.drive.sweep_points = 7;
  s.drive.v_min = 1e-2;
  s.drive.v_max = 1e2;
  s.time.t_end = 20.0;
  s.time.slip_end = 20.0;
  s.time.steps = 2000;
  s = noise_off(s);
  s.validate();
  const auto r = compare::run_scene(s, {});
  REQUIRE(r.size() == 2);
  const double worst = columns_diff(r[0].friction_law, r[1].friction_law);
  std::printf("identity friction-law sweep: max relative difference %.3g\n", worst);
}

// 0D spring block (docs/model.md §1): ρ v̇ = K (v_d t − u) − σ̄ − η v, ρ = 0.01, v_d = 0.3. With K = 2.5 the
// block yields once (t* ≈ 4.6) and settles into steady sliding at v_d; with K = 0.5 it stick-slips.
TEST_CASE("discrete identity: 0D spring block", "[discrete][identity]") {
  const double K = GENERATE(2.5, 0.5);
  compare::Scene s = noise_off(testing::spring_block_scene(K > 1.0 ? 40.0 : 120.0));  // series every step
  s.name = "spring_block_identity";
  s.drive.K = K;
  s.validate();
  const auto r = compare::run_scene(s, {});
  REQUIRE(r.size() == 2);
  REQUIRE(r[1].status == slipfront::compare::RunStatus::complete);
  double worst = columns_diff(r[0].series, r[1].series);
  const std::size_t cycles = r[0].cycles.count("t_start") ? r[0].cycles.at("t_start").size() : 0;
  if (cycles > 0) worst = std::max(worst, columns_diff(r[0].cycles, r[1].cycles));
  std::printf("identity spring block K = %g: max relative difference %.3g, t* = %.4f, %zu stick-slip cycles\n", K,
              worst, r[1].events.t_star, cycles);
  CHECK(std::isfinite(r[0].events.t_star));
  if (K < 1.0) {
    CHECK(cycles >= 5);  // the scene does stick-slip
    REQUIRE(r[1].cycles.count("t_start") == 1);
    CHECK(r[0].cycles.at("t_start") == r[1].cycles.at("t_start"));
  }
  require_same_events(r[0].events, r[1].events);
}

// Homogeneous loading (docs/model.md §1): uniform σ_d = 0.5, a nucleation patch 0 ≤ x < 150 started in steady
// sliding (set_site with A = A_ss < 1), paper parameters; both renewal options (identical at w = 0).
TEST_CASE("discrete identity: homogeneous front from a nucleation patch", "[discrete][identity]") {
  const std::string renewal = GENERATE(std::string("fresh"), std::string("quenched"));
  compare::Scene s = noise_off(testing::homogeneous_scene(0.5, 150.0, 10.0));
  s.name = "homogeneous_identity";
  s.output.snapshot_dt = 2.0;
  s.discrete.renewal = renewal;
  s.validate();
  const auto r = compare::run_scene(s, {});
  REQUIRE(r.size() == 2);
  REQUIRE(r[1].status == slipfront::compare::RunStatus::complete);
  const std::size_t nx = r[0].x.size();
  double worst = 0.0;
  for (const char* field : {"A", "sigma_bar", "u", "v"})
    for (std::size_t k = 0; k < r[0].snapshot_t.size(); ++k) {
      INFO(field << " at t = " << r[0].snapshot_t[k]);
      const double e = testing::max_relative_difference(std::span<const double>(r[0].snapshots.at(field)).subspan(k * nx, nx),
                                std::span<const double>(r[1].snapshots.at(field)).subspan(k * nx, nx));
      CHECK(e <= tolerance);
      worst = std::max(worst, e);
    }
  worst = std::max(worst, columns_diff(r[0].series, r[1].series));
  std::printf("identity homogeneous front (%s): max relative difference %.3g\n", renewal.c_str(), worst);
  require_same_events(r[0].events, r[1].events);
}
