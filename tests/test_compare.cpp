// The comparison layer (issue 4): alongside runs, online field distances, study analysis, fits.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/difference.hpp"
#include "compare/fit.hpp"
#include "compare/pool.hpp"
#include "compare/runner.hpp"
#include "studies/study.hpp"

using namespace slipfront;
using compare::ModelResult;
using compare::Scene;

namespace {

Scene load(const std::string& config, std::vector<std::string> overrides) {
  return app::load_scene(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/" + config, overrides);
}

// Short fig1 through first yield and into the slow front, both models, noisy count representation.
Scene short_fig1(const std::string& representation = "count") {
  return load("fig1.toml", {"models=[\"continuum\",\"discrete\"]", "time.t_end=45", "grid.dx=1.0",
                            "bulk.length=100", "discrete.contacts_per_site=200",
                            "discrete.representation=" + representation, "output.snapshot_dt=5",
                            "output.series_dt=0.5", "output.compare_dt=5"});
}

// Bit-for-bit equality of two column maps (NaN included: compare the bits, not the values).
bool same_bits(const compare::Columns& a, const compare::Columns& b) {
  if (a.size() != b.size()) return false;
  for (const auto& [name, col] : a) {
    const auto it = b.find(name);
    if (it == b.end() || it->second.size() != col.size()) return false;
    if (!col.empty() && std::memcmp(col.data(), it->second.data(), col.size() * sizeof(double)) != 0) return false;
  }
  return true;
}

void require_identical(const ModelResult& a, const ModelResult& b) {
  REQUIRE(a.model == b.model);
  REQUIRE(a.status == b.status);
  REQUIRE(same_bits(a.series, b.series));
  REQUIRE(a.snapshot_t == b.snapshot_t);
  REQUIRE(same_bits(a.snapshots, b.snapshots));
  const auto same = [](double x, double y) { return (std::isnan(x) && std::isnan(y)) || x == y; };
  CHECK(same(a.events.t_star, b.events.t_star));
  CHECK(same(a.events.t_hat, b.events.t_hat));
  CHECK(same(a.events_alt.c_slow, b.events_alt.c_slow));
}

}  // namespace

TEST_CASE("compare: an alongside run reproduces separate runs of each model bit for bit", "[compare]") {
  // The lockstep runner advances both models with their own state; nothing may leak between them.
  for (const char* rep : {"count", "agent"}) {
    const Scene s = short_fig1(rep);
    const auto together = compare::run_scene_alongside(s, {});
    const auto apart = compare::run_scene(s, {});
    REQUIRE(together.models.size() == 2);
    REQUIRE(apart.size() == 2);
    require_identical(together.models[0], apart[0]);
    require_identical(together.models[1], apart[1]);
    // and the comparison was computed online at the compare cadence: t = 0, 5, ..., 45
    REQUIRE(together.comparison.fields.at("t").size() == 10);
    CHECK(together.comparison.definitions.count("fields/A_distance") == 1);
  }
}

TEST_CASE("compare: noise off and w = 0 gives zero field distances and zero event differences", "[compare]") {
  // docs/model.md §2 hierarchy item 1 seen through the comparison layer: the metrics must vanish exactly.
  Scene s = short_fig1();
  s.discrete.noise = false;
  const auto r = compare::run_scene_alongside(s, {});
  const auto& f = r.comparison.fields;
  for (const char* col : {"A_distance", "sigma_bar_distance", "v_distance", "u_distance"})
    for (double d : f.at(col)) CHECK(d == 0.0);
  CHECK(r.comparison.metrics.at("t_star_rel_diff") == 0.0);
  CHECK(r.comparison.metrics.at("drive_force_history_distance") == 0.0);
  // with noise on the same metrics are positive: the comparison is not blind
  const auto noisy = compare::run_scene_alongside(short_fig1(), {});
  CHECK(noisy.comparison.fields.at("A_distance").back() > 0.0);
  CHECK(noisy.comparison.metrics.at("drive_force_history_distance") > 0.0);
}

TEST_CASE("compare: relative differences and their NaN rule (compare/difference.hpp)", "[compare]") {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const std::vector<double> a{3, 4}, b{3, 4}, c{0, 0}, d{6, 8};
  CHECK(compare::relative_rms_distance(a, b) == 0.0);
  CHECK(compare::relative_rms_distance(a, d) == Approx(1.0).epsilon(1e-15));
  CHECK(compare::relative_rms_distance(c, c) == 0.0);
  // a reference field that vanishes has no relative distance: NaN, not ±inf (issue 10)
  CHECK(std::isnan(compare::relative_rms_distance(c, a)));
  // pairs with a non-finite member are left out (a front that does not exist at some times); none left: NaN
  const std::vector<double> tip_a{1, nan, 3}, tip_b{2, 5, nan};
  CHECK(compare::relative_rms_distance(tip_a, tip_b) == Approx(1.0).epsilon(1e-15));  // only (1, 2)
  const std::vector<double> none_a{nan, 1}, none_b{2, inf};
  CHECK(std::isnan(compare::relative_rms_distance(none_a, none_b)));
  // the common length only (a series cut short by a failed run)
  CHECK(compare::relative_rms_distance(d, std::vector<double>{6}) == 0.0);
  // scalars: (b - a)/|a|; 0/0 is 0; x/0 and anything non-finite is NaN
  CHECK(compare::relative_difference(-2.0, -1.0) == Approx(0.5));
  CHECK(compare::relative_difference(0.0, 0.0) == 0.0);
  CHECK(std::isnan(compare::relative_difference(0.0, 1.0)));
  CHECK(std::isnan(compare::relative_difference(nan, 1.0)));
  CHECK(std::isnan(compare::relative_difference(1.0, inf)));
}

namespace {
// A study executed as `slipfront study` does it: expand, run every point on a pool, analyse.
studies::StudyReport run_study(const compare::StudySpec& spec, unsigned threads) {
  const auto runs = compare::expand(spec);
  std::vector<Scene> scenes;
  for (const auto& r : runs) scenes.push_back(app::load_scene(spec.scene_file, r.overrides));
  std::vector<std::vector<ModelResult>> results(runs.size());
  compare::run_pool(runs.size(), threads,
                    [&](std::size_t i) { results[i] = compare::run_scene_alongside(scenes[i], {}).models; });
  return studies::analyse_study(spec, runs, scenes, results);
}

compare::StudySpec small_friction_study(std::vector<std::string> Ns, int seeds) {
  compare::StudySpec spec;
  spec.name = "test";
  spec.kind = "friction_law";
  spec.scene_file = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/friction_law.toml";
  // v in [3, 30]: the mean-field regime of the steady law (below v ~ 1, small N re-sticks: a bias,
  // reported separately by the study, see docs/studies.md)
  spec.common = {"models=[\"continuum\",\"discrete\"]", "drive.v_min=3", "drive.v_max=30", "drive.points=4",
                 "time.steps=2000", "time.slip_end=100"};
  spec.groups.push_back({"", {{"discrete.contacts_per_site", std::move(Ns)}}});
  spec.seeds = seeds;
  return spec;
}
}  // namespace

TEST_CASE("compare: a study's results do not depend on the number of threads", "[compare]") {
  const auto spec = small_friction_study({"100", "1000"}, 3);
  const auto one = run_study(spec, 1), two = run_study(spec, 2), five = run_study(spec, 5);
  REQUIRE(one.tables == two.tables);
  REQUIRE(one.tables == five.tables);
  REQUIRE(one.scalars == two.scalars);
}

TEST_CASE("compare: friction-law study, the random error falls like N^(-1/2)", "[compare]") {
  // Mean-field limit (docs/model.md §2 item 2) in the default tier: N = 1e2 .. 1e5, 12 seeds, short averaging.
  // Tolerance: the fitted exponent within 0.15 of -1/2 and its 95% interval covering -1/2. The
  // seeds are fixed, so the outcome is deterministic; the stated false-alarm rate of the interval
  // check for a correct model is 5% per fresh set of seeds (this set passes).
  const auto rep = run_study(small_friction_study({"100", "1000", "10000", "100000"}, 12), 2);
  const double p = rep.scalars.at("friction_law_random_exponent");
  WARN("fitted exponent " << p << " (95% CI " << rep.scalars.at("friction_law_random_exponent_ci_low") << " .. "
                          << rep.scalars.at("friction_law_random_exponent_ci_high") << ")");
  CHECK(std::abs(p + 0.5) < 0.15);
  CHECK(rep.scalars.at("friction_law_random_exponent_ci_low") <= -0.5);
  CHECK(rep.scalars.at("friction_law_random_exponent_ci_high") >= -0.5);
  // the bias is below the random error at every N in this regime
  const auto& t = rep.tables.at("friction_law_error");
  for (std::size_t k = 0; k < t.at("N").size(); ++k) CHECK(t.at("bias")[k] < 3.0 * t.at("random")[k]);
}

TEST_CASE("compare: expand makes the cartesian product of a group times seeds, groups in union", "[compare]") {
  compare::StudySpec spec;
  spec.common = {"a=1"};
  spec.seeds = 2;
  spec.groups.push_back({"g1", {{"x", {"1", "2"}}, {"y", {"10", "20", "30"}}}});
  spec.groups.push_back({"g2", {{"z", {"5"}}}});
  const auto runs = compare::expand(spec);
  REQUIRE(runs.size() == (2 * 3 + 1) * 2);
  CHECK(runs[0].point.at("x") == "1");
  CHECK(runs[0].point.at("y") == "10");
  CHECK(runs[0].overrides == std::vector<std::string>{"a=1", "x=1", "y=10", "discrete.seed=1"});
  CHECK(runs[1].seed == 2);
  CHECK(runs[2].point.at("y") == "20");
  CHECK(runs[12].group == "g2");
  CHECK(runs[12].point.at("z") == "5");
}
