// The accuracy-stepped integrator on the in-plane strip (issue 38; docs/numerics.md §8.9): fig1_inplane's events
// with the adaptive Rosenbrock integrator (core::AdaptiveSimulation on core::InPlane) against the explicit reference
// scheme. Slow (~2 min of CPU: the explicit run is ~110 000 steps of 42 070 dofs).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <utility>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

/// configs/fig1_inplane.toml's body and grid (H = 17, ν = 1/3, dx = dy = 0.5: 601 × 35 nodes), the continuum model,
/// to t = 110 (t^ ≈ 98, the arrest by ≈ 103).
compare::Scene fig1_inplane() {
  compare::Scene s = testing::fig1_scene();
  s.name = "fig1_inplane_adaptive_test";
  s.bulk.height = 17.0;
  s.bulk.body_name = "inplane";
  s.bulk.poisson = 1.0 / 3.0;
  s.grid.dy = 0.5;
  s.time.t_end = 110.0;
  s.output.snapshot_dt = 10.0;
  s.output.series_dt = 0.5;
  s.models = {"continuum"};
  return s;
}

std::pair<compare::ModelResult, double> run_one(const compare::Scene& s) {
  s.validate();
  const std::clock_t c0 = std::clock();
  auto out = compare::run_scene(s, {});
  const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  REQUIRE(out.size() == 1);
  INFO(out[0].message);
  REQUIRE(out[0].status == compare::RunStatus::complete);
  return {std::move(out[0]), cpu};
}

double rel(double a, double b) { return std::abs(a / b - 1.0); }

}  // namespace

TEST_CASE("inplane adaptive: fig1_inplane events against the explicit reference within 1%", "[inplane][adaptive]") {
  // The explicit scheme at the scene's cfl 0.5; the adaptive integrator at rtol 3e-2 (atol 3e-4), switchings grouped
  // (the default): t*, t^, c_transient and x_arrest each within 1 % (measured: docs/numerics.md §8.9).
  const compare::Scene s = fig1_inplane();
  const auto [e, cpu_e] = run_one(s);
  compare::Scene a = s;
  a.time.integrator = core::Integrator::adaptive_rosenbrock;
  a.time.rtol = 3e-2;
  a.time.atol = 3e-4;
  const auto [r, cpu_a] = run_one(a);
  REQUIRE(r.labels.at("integrator") == "adaptive");
  std::printf("fig1_inplane explicit cfl 0.5 (%.1f s CPU, %g steps) vs adaptive rtol 3e-2 (%.1f s CPU, %g steps): "
              "t* %+.2e, t^ %+.2e, c_transient %+.2e, x_arrest %+.2e\n",
              cpu_e, e.scalars.at("steps"), cpu_a, r.scalars.at("steps"), r.events.t_star / e.events.t_star - 1,
              r.events.t_hat / e.events.t_hat - 1, r.events.c_transient / e.events.c_transient - 1,
              r.events.x_arrest / e.events.x_arrest - 1);
  for (const auto* ev : {&e.events, &r.events}) {
    REQUIRE(std::isfinite(ev->t_star));
    REQUIRE(std::isfinite(ev->t_hat));
    REQUIRE(std::isfinite(ev->c_transient));
    REQUIRE(std::isfinite(ev->x_arrest));
  }
  CHECK(rel(r.events.t_star, e.events.t_star) < 0.01);
  CHECK(rel(r.events.t_hat, e.events.t_hat) < 0.01);
  CHECK(rel(r.events.c_transient, e.events.c_transient) < 0.01);
  CHECK(rel(r.events.x_arrest, e.events.x_arrest) < 0.01);
  CHECK(r.scalars.at("steps") < 0.01 * e.scalars.at("steps"));  // the step is set by the physics, not by c_p
}
