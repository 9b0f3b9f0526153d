// Issue 36, "what must be shown": `fronts` with the default options on homogeneous strips at H = 17, 50, 200
// (homogeneous_front's column mu = 300, rho = 0.01) stores every speed within its stored estimate of the
// converged value, checked against the same computation on twice the rows (and the same intervals, whose error
// is ~1e-9 of c here): c_min, the front at the scene's sigma_d and every profile (each at a fixed sigma_d, so the
// two runs compare point for point). Also the example: at H = 50 the scene's front is within 1e-3 of the
// converged value 48.032 (the fixed-grading Richardson limit of 8 ... 64 rows, docs/fronts.md §10.20), where the
// old default (8 rows) was 0.75 % off. Slow: the reference at H = 50 is a branch on 64 rows (~600 s of CPU in all;
// re-run 2026-11-27 with the budget in place: passed, 77 assertions, 591 s of CPU; H = 17 met on 16 rows, H = 50 met
// on 32, c(0.5) = 48.0588 +- 0.041 against 48.0472 on 64 rows, 5.6e-4 from 48.032). H = 200 is not here: with the
// budget its default stops at 32 rows, NOT met (budget), and the reference on twice the rows (64, ~700 s of CPU, ~40
// min of wall time on the shared machine) was not measured with it (docs/fronts.md §10.20).
#include <catch2/catch.hpp>

#include <cmath>

#include "compare/fronts.hpp"
#include "scenes.hpp"

namespace compare = slipfront::compare;

TEST_CASE("slow fronts accuracy: default fronts at H = 17, 50 are within their estimates of twice the rows",
          "[fronts][strip][slow]") {
  for (double H : {17.0, 50.0}) {
    compare::Scene s = slipfront::testing::homogeneous_scene(0.5, 150.0, 20.0);
    s.bulk.height = H;
    const compare::FrontsResult r = compare::compute_fronts(s, false);
    INFO("H = " << H << ": " << r.labels.at("accuracy") << "; " << r.labels.at("resolution"));
    REQUIRE(r.status == compare::RunStatus::complete);
    CHECK(r.scalars.at("rtol_met") == 1.0);
    compare::StripFrontsSettings twice;
    twice.rows = 2 * static_cast<int>(r.scalars.at("rows"));
    twice.intervals = static_cast<int>(r.scalars.at("intervals"));
    const compare::FrontsResult ref = compare::compute_fronts(s, false, {}, twice);
    REQUIRE(ref.status == compare::RunStatus::complete);
    auto within = [&](const char* what, double c, double err, double c_ref) {
      INFO(what << ": " << c << " +- " << err << " against " << c_ref << " on twice the rows");
      CHECK(std::isfinite(err));
      CHECK(std::abs(c - c_ref) <= err);
      CHECK(err <= 1e-3 * c);
    };
    within("c_min", r.scalars.at("c_min"), r.scalars.at("c_min_error"), ref.scalars.at("c_min"));
    within("c at the scene's sigma_d", r.scalars.at("c_at_scene_sigma_d"), r.scalars.at("c_at_scene_sigma_d_error"),
           ref.scalars.at("c_at_scene_sigma_d"));
    REQUIRE(r.profiles.size() == ref.profiles.size());
    for (std::size_t k = 0; k < r.profiles.size(); ++k) {
      REQUIRE(r.profiles[k].sigma_d == ref.profiles[k].sigma_d);
      within("profile", r.profiles[k].c, r.profiles[k].c_error, ref.profiles[k].c);
    }
    if (H == 50.0) CHECK(std::abs(r.scalars.at("c_at_scene_sigma_d") / 48.032 - 1.0) < 1e-3);
  }
}
