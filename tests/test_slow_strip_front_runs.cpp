// Strip fronts in time, grid convergence (slow tier; issue 20 item 3, docs/fronts.md §10.15): the gap between
// the speed of the strip run started from the solved strip front and the solved speed shrinks as dx and dy
// are halved together (the solved front is on the run's rows at each grid).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "compare/initial.hpp"
#include "compare/runner.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

// c_front/c − 1 of the strip run started from the solved front (body "inplane": the in-plane strip, ν = 1/3).
double gap(double H, double sigma_d, double dx, double dy, const std::string& body = "") {
  compare::Scene s = testing::strip_front_start_scene(H, sigma_d, dx, dy, body);
  const auto front = compare::front_start(s);
  REQUIRE(front);
  s.time.t_end = 200.0 / front->c;
  s.validate();
  auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  REQUIRE(out[0].status == compare::RunStatus::complete);
  const double g = out[0].events.c_front / front->c - 1.0;
  std::printf("%s front run H = %g, sigma_d = %g, dx = %g, dy = %g: c = %.6f, gap %+.3e\n",
              body == "inplane" ? "in-plane" : "strip", H, sigma_d, dx, dy, front->c, g);
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

TEST_CASE("slow strip front runs: in-plane runs from the solved in-plane front keep its speed at two H and two sigma_d",
          "[slow][inplane][fronts]") {
  // Issue 39's test (docs/fronts.md §11.10): the in-plane strip (ν = 1/3, the paper's column μ = 300 = E'H, ρ = 0.01) at
  // H = 2 (dx = dy = 0.5) and H = 17 (dx = 0.5, dy = 1), σ_d = 0.3 and 0.5, started from the in-plane front solved on the
  // run's rows, explicit, 200 units of travel: every gap within 0.5 % (issue 39's bound). Then the grid halved (dx, dy)
  // at H = 2, σ_d = 0.5: the gap smaller. Measured (2026-11-27; 82 s of CPU): gaps −9.17e−4, −9.25e−4 (H = 2, σ_d = 0.3,
  // 0.5), −2.94e−3, −2.87e−3 (H = 17); H = 2, σ_d = 0.5 halved: −4.12e−4 (ratio 2.24). Finding: at H = 17, dy = 1 the
  // in-plane gap is 2.6x the antiplane strip's (the lumped rows of the solve against the Q1 body, docs/fronts.md §11.10).
  struct Case { double H, sd, dy; };
  for (const Case c : {Case{2.0, 0.3, 0.5}, Case{2.0, 0.5, 0.5}, Case{17.0, 0.3, 1.0}, Case{17.0, 0.5, 1.0}}) {
    const double g = gap(c.H, c.sd, 0.5, c.dy, "inplane");
    INFO("H = " << c.H << ", sigma_d = " << c.sd << ": gap " << g);
    CHECK(std::abs(g) < 5e-3);
  }
  const double coarse = gap(2.0, 0.5, 0.5, 0.5, "inplane"), fine = gap(2.0, 0.5, 0.25, 0.25, "inplane");
  INFO("H = 2, sigma_d = 0.5: " << coarse << " -> " << fine);
  CHECK(std::abs(fine) < std::abs(coarse));
}
