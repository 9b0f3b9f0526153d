// Steady fronts of the in-plane strip, slow tier (continuum/inplane_front.hpp, docs/fronts.md §11): the branch in σ_d
// to its end, the order across the rows, and the error estimate of `slipfront fronts` (rows and ξ, docs/fronts.md
// §10.20) against a finer solve. Paper parameters, μ = E'H and ρ integrated over the height, ν = 1/3.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "compare/fit.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/steady_front.hpp"
#include "front_checks.hpp"

namespace continuum = slipfront::continuum;
namespace core = slipfront::core;
namespace testing = slipfront::testing;
using continuum::FrontStatus;
using continuum::StripFront;
using continuum::StripFrontOptions;

namespace {
const core::InterfaceParams paper{1.05, 8.0, 0.1};
core::BulkParams inplane(double H) {
  core::BulkParams b{0.01, 300.0, 300.0, H};
  b.body_name = "inplane";
  return b;
}
}  // namespace

TEST_CASE("slow inplane front: the branch in sigma_d ends at the saddle-node, c_min at its end", "[inplane][front][slow]") {
  // H = 1 (c_s = 100): no front at σ_d = 0.8 (the 1D front of μ = E'H runs at 108 > c_s, refused at the mode count),
  // the first at 0.683 (c = 90.8 < c_R = 93.25), then 36 fronts to the limiting one, c_min = 11.28191 (1D: 11.28108).
  continuum::StripContinuationOptions o;
  o.front.rows = 4;
  o.front.intervals = 300;
  const auto br = continuum::continue_strip_fronts(paper, inplane(1.0), o);
  INFO(br.reason);
  REQUIRE(br.end == continuum::BranchEnd::saddle_node);
  REQUIRE(br.points.size() > 10);
  CHECK(br.folds.empty());
  CHECK(br.c_min_at_end);
  CHECK(br.last.saddle_node_limit);
  CHECK(br.first.sigma_d < 0.8);
  CHECK(br.first.c < continuum::inplane_material(inplane(1.0)).shear_speed);
  for (std::size_t k = 1; k < br.points.size(); ++k) {
    CHECK(br.points[k].sigma_d < br.points[k - 1].sigma_d);
    CHECK(br.points[k].c < br.points[k - 1].c);
    CHECK(br.points[k].overstress_margin > 0.0);
    CHECK(br.points[k].min_slip_rate > 0.0);
  }
  CHECK(br.c_min == Approx(11.2819079698).epsilon(1e-8));
  CHECK(br.c_min > 11.28108382);
}

TEST_CASE("slow inplane front: the rows converge at about 2nd order", "[inplane][front][slow]") {
  // H = 10, σ_d = 0.5, rows graded with fixed γ = 4, M = 4 … 32, 150 intervals: P1 across the height is 2nd order;
  // the tip's corner (as the antiplane strip's, docs/fronts.md §10.5) leaves k² log k and the in-plane coupling a slower
  // approach: observed successive orders 1.60, 1.77 (c = 58.4809, 58.2032, 58.1118, 58.0850).
  StripFrontOptions o;
  o.rows = 8;
  o.intervals = 150;
  o.domain_length = 330.0;
  o.grading = 6.0;
  o.row_grading = 4.0;
  const StripFront g = continuum::solve_inplane_front(paper, inplane(10.0), 0.5, o);
  REQUIRE(g.status == FrontStatus::converged);
  std::vector<double> c;
  for (int M : {4, 8, 16, 32}) {
    o.rows = M;
    const StripFront f = continuum::solve_inplane_front(paper, inplane(10.0), 0.5, o, &g);
    REQUIRE(f.status == FrontStatus::converged);
    c.push_back(f.c);
  }
  const auto [o1, o2] = testing::successive_orders(c);
  WARN("inplane rows: successive orders " << o1 << ", " << o2);
  CHECK(o2 > o1);
  CHECK(o2 > 1.6);
  CHECK(o2 < 2.1);
  CHECK(o2 > continuum::strip_row_order);  // the estimate's assumed order stays below the observed one
}

TEST_CASE("slow inplane front: the speed estimate of fronts covers the error against a 4x finer mesh", "[inplane][front][slow]") {
  // H = 2, σ_d = 0.5, 8 graded rows (first spacing 0.1), 300 intervals: estimate_strip_speed_error (rows on half the
  // rows at order strip_row_order, ξ on twice the intervals) against 32 rows and 1200 intervals of the same grading.
  StripFrontOptions o;
  o.rows = 8;
  o.intervals = 300;
  o.row_spacing = 0.1;
  const StripFront f = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o);
  REQUIRE(f.status == FrontStatus::converged);
  const auto e = continuum::estimate_strip_speed_error(f, o);
  INFO(e.note);
  REQUIRE(std::isfinite(e.total));
  StripFrontOptions fine = continuum::with_rows(2.0, o, 32);
  fine.intervals = 1200;
  const StripFront ref = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, fine, &f);
  REQUIRE(ref.status == FrontStatus::converged);
  const double error = std::abs(f.c - ref.c);
  WARN("inplane estimate " << e.total << " (rows " << e.rows << ", xi " << e.xi << ") against the error " << error);
  CHECK(error <= e.total);
  CHECK(e.total < 4.0 * error);  // not so large as to say nothing
}
