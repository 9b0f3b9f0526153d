// Strip fronts in time, grid convergence (slow tier; issue 20 item 3, docs/fronts.md §10.15): the gap between
// the speed of the strip run started from the solved strip front and the solved speed shrinks as dx and dy
// are halved together (the solved front is on the run's rows at each grid).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include "compare/initial.hpp"
#include "compare/runner.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

double gap(double H, double sigma_d, double dx, double dy) {
  compare::Scene s = testing::homogeneous_scene(sigma_d, 0.0, 1.0);
  s.models = {"continuum"};
  s.bulk.height = H;
  s.bulk.length = 400.0;
  s.grid.dx = dx;
  s.grid.dy = dy;
  s.drive.start = "steady_front";
  s.drive.front_x = 100.0;
  s.measure.behind_tip_fraction = 0.7;
  s.output.snapshot_dt = 0.0;
  s.output.series_dt = 0.05;
  const auto front = compare::front_start(s);
  REQUIRE(front);
  s.time.t_end = 200.0 / front->c;
  s.validate();
  auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  REQUIRE(out[0].status == compare::RunStatus::complete);
  const double g = out[0].events.c_front / front->c - 1.0;
  std::printf("strip front run H = %g, sigma_d = %g, dx = %g, dy = %g: c = %.6f, gap %+.3e\n", H, sigma_d, dx, dy,
              front->c, g);
  return g;
}

}  // namespace

TEST_CASE("slow strip front runs: the speed gap converges with the grid", "[slow][strip][fronts]") {
  // dx = dy halved from 0.5 to 0.25 at H = 2 (σ_d = 0.3, 0.5) and dx 0.5 → 0.25, dy 1 → 0.5 at H = 17
  // (σ_d = 0.5): each gap within 0.5% and smaller at the finer grid by a factor > 1.6. Measured (finding): the
  // ratios are 1.69, 2.55, 2.01 — convergent, but not at one clean order (0.76–1.35; the 1D runs' 1.6–2.5
  // first-order bound fails at H = 2, σ_d = 0.5), so no upper bound is asserted (docs/fronts.md §10.15).
  struct Case { double H, sd, dx, dy; };
  for (const Case c : {Case{2.0, 0.3, 0.5, 0.5}, Case{2.0, 0.5, 0.5, 0.5}, Case{17.0, 0.5, 0.5, 1.0}}) {
    const double coarse = gap(c.H, c.sd, c.dx, c.dy), fine = gap(c.H, c.sd, 0.5 * c.dx, 0.5 * c.dy);
    INFO("H = " << c.H << ", sigma_d = " << c.sd << ": " << coarse << " -> " << fine);
    CHECK(std::abs(coarse) < 5e-3);
    CHECK(std::abs(fine) < std::abs(coarse));
    CHECK(coarse / fine > 1.6);
  }
}
