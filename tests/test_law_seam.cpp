// The law seam of the run layer (issue 37 item 3): a model is a row of the model table (compare/models.hpp) and a type
// of a model set (compare/laws.hpp: ModelSet; the program's is ShippedModels) that builds its law; the lockstep runs
// every model a scene lists, any number (compare/lockstep.hpp); a law gives its own steady state for the nucleation
// patch (core::LawHooks::steady_state). A test law in its own file (tests/laws/quadratic_detachment.hpp: detachment
// rate κv² instead of κ|v|), registered below as a fourth model of a test set, runs through the real dispatch
// (ModelSet::with_law, with_integrator), the run (DynamicRun, run_loop, the lockstep), the recorder and the writer,
// and needs no change outside its own files.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "compare/laws.hpp"
#include "compare/lockstep.hpp"
#include "compare/runner.hpp"
#include "h5content.hpp"
#include "laws/quadratic_detachment.hpp"
#include "laws/redrawn_threshold.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using testing::QuadraticDetachmentLaw;

namespace {

// The test law as a model: its row of the table and how its law is built (as compare::ContinuumModel).
struct QuadraticModel {
  static constexpr compare::ModelKind kind{"quadratic", "interface",
                                           "testing::QuadraticDetachmentLaw(interface, sites): detachment rate kappa v^2",
                                           {}, "one exact update (a few exponentials)"};
  template <class F>
  static decltype(auto) with_law(const compare::Scene& s, F&& f) {
    return f([&](std::size_t n) { return QuadraticDetachmentLaw(s.interface, n); });
  }
  static void label(const compare::Scene&, compare::ModelResult& r) { r.labels["detachment"] = "kappa v^2"; }
};
// The shipped models and the test law: the whole registration.
using TestModels = compare::ModelSet<compare::ContinuumModel, compare::MeanFieldModel, compare::DiscreteModel, QuadraticModel>;

// A short homogeneous run with a nucleation patch (L = 60, dx = 1, sigma_d = 0.55): a front runs from the patch;
// the discrete model as counts (N = 200, noise on), compared online with mean_field every 0.5.
compare::Scene seam_scene(core::Integrator integrator) {
  compare::Scene s = testing::short_front_scene(integrator);
  s.output.compare_dt = 0.5;
  s.models = {"continuum", "mean_field", "discrete"};
  s.discrete.representation = "count";
  s.discrete.contacts_per_site = 200;
  s.discrete.seed = 3;
  s.validate();
  s.models.push_back("quadratic");  // not a shipped model: Scene::validate knows the shipped table only
  return s;
}

// One model of `s` alone, through the test set's dispatch and compare::run_model (as compare::run_scene runs it).
compare::ModelResult alone(const compare::Scene& s, const std::string& model) {
  compare::Scene one = s;
  one.models = {model};
  return TestModels::with_law(one, model, [&](auto make) {
    using Law = decltype(make(std::size_t{1}));
    return compare::run_model<Law>(one, make, model, compare::RunControl{});
  });
}

const compare::ModelResult& result_of(const compare::SceneResult& r, const std::string& model) {
  for (const auto& m : r.models)
    if (m.model == model) return m;
  FAIL("no result of " << model);
  return r.models.front();
}

}  // namespace

TEST_CASE("law seam: the model table is the one switch from a name to a law", "[law][models]") {
  // the shipped set is the table's rows in order (a static_assert in compare/laws.hpp); the test set adds one
  CHECK(compare::ShippedModels::names() == compare::model_names());
  CHECK(TestModels::names() == "continuum, mean_field, discrete or quadratic");
  CHECK(TestModels::find("quadratic") == &QuadraticModel::kind);
  CHECK(compare::find_model_kind("quadratic") == nullptr);
  const compare::Scene s = seam_scene(core::Integrator::central_difference);
  CHECK(TestModels::with_law(s, "quadratic", [](auto make) { return std::string(typeid(make(1)).name()); }) ==
        typeid(QuadraticDetachmentLaw).name());
  CHECK_THROWS_WITH(compare::with_model_law(s, "quadratic", [](auto) { return 0; }),
                    Catch::Contains("unknown model 'quadratic'"));
}

TEST_CASE("law seam: a test law registered in a model set runs in a lockstep of four models, through the recorder and "
          "the writer",
          "[law][models]") {
  for (const auto integrator : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal}) {
    INFO(core::to_string(integrator));
    const compare::Scene s = seam_scene(integrator);
    const compare::SceneResult all = compare::run_in_lockstep<TestModels>(s, compare::RunControl{});
    REQUIRE(all.models.size() == 4);
    for (std::size_t k = 0; k < 4; ++k) {
      CHECK(all.models[k].model == s.models[k]);  // in the scene's order
      CHECK(all.models[k].status == compare::RunStatus::complete);
    }

    // Each model in the lockstep is the model alone, bit for bit (the quadratic law included).
    for (const std::string m : {"continuum", "quadratic", "mean_field"}) {
      INFO(m);
      const compare::ModelResult one = alone(s, m);
      CHECK(testing::same(result_of(all, m).series, one.series));
      CHECK(testing::same(result_of(all, m).snapshots, one.snapshots));
    }
    CHECK(result_of(all, "quadratic").labels.at("detachment") == "kappa v^2");  // the model's label
    CHECK(result_of(all, "mean_field").labels.count("threshold") == 1);

    // The discrete model is compared with the first reference of its row that runs: mean_field, fields online.
    CHECK(all.comparison.reference == "mean_field");
    REQUIRE(all.comparison.fields.count("A_distance"));
    CHECK(all.comparison.fields.at("t").size() == 7);  // t = 0, 0.5, ..., 3

    // The patch starts in each law's own steady state at sigma_d (core::LawHooks::steady_state).
    const QuadraticDetachmentLaw q(s.interface, 1);
    const double vq = q.steady_velocity(0.55), vc = continuum::strengthening_branch_velocity(s.interface, 0.55);
    CHECK(q.steady_sliding(vq).sigma == Approx(0.55).epsilon(1e-12));
    CHECK(vq > vc);
    const auto& a_q = result_of(all, "quadratic").snapshots.at("A");
    const auto& a_c = result_of(all, "continuum").snapshots.at("A");
    CHECK(a_q[0] == q.steady_sliding(vq).area);
    CHECK(a_c[0] == continuum::steady_sliding(s.interface, vc).area);
    CHECK(a_q[0] < a_c[0]);
    CHECK(a_q[30] == 1.0);  // x = 30: outside the patch, stuck
    CHECK(result_of(all, "quadratic").series.at("max_v") != result_of(all, "continuum").series.at("max_v"));

    // The writer: a group per model, the test law's read back bit for bit.
    testing::TempDir dir("law_seam");
    const fs::path file = dir.path / "results.h5";
    app::write_results(file, s, app::to_toml(s), all.models, app::RunMeta{}, &all.comparison);
    const app::ResultsFile back = app::read_results(file);
    REQUIRE(back.models.size() == 4);
    CHECK(back.models[3].model == "quadratic");
    CHECK(back.models[3].snapshots.at("A") == a_q);
    CHECK(back.comparison.reference == "mean_field");
  }
}

TEST_CASE("law seam: a law without a steady state cannot start a nucleation patch", "[law][models]") {
  // The redrawn-threshold law (tests/laws/redrawn_threshold.hpp) declares no steady_state: a patch is refused,
  // naming the key; without a patch it runs.
  compare::Scene s = seam_scene(core::Integrator::central_difference);
  auto run = [](const compare::Scene& sc) {
    return compare::run_model<testing::RedrawnThresholdLaw>(
        sc, [&](std::size_t n) { return testing::RedrawnThresholdLaw(sc.interface, 0.0, 1, n); }, "redrawn",
        compare::RunControl{});
  };
  CHECK_THROWS_WITH(run(s), Catch::Contains("drive.nucleation_length") && Catch::Contains("no steady state"));
  s.drive.nucleation_length = 0.0;
  CHECK(run(s).status == compare::RunStatus::complete);
}

TEST_CASE("law seam: a steady-front start is the law's own: refused for a law that does not declare it", "[law][models]") {
  // drive.start = "steady_front" puts each site in the continuum's solved front; a law declares that front its own
  // (core::LawHooks::steady_front: the shipped laws, exact at w = 0). The test law's steady state differs (κv²
  // detachment), so its start is refused, naming the key, before the front is solved; the continuum starts from it.
  compare::Scene s = seam_scene(core::Integrator::central_difference);
  s.drive.start = "steady_front";
  s.drive.nucleation_length = 0.0;
  s.drive.front_x = 30.0;
  CHECK_THROWS_WITH(alone(s, "quadratic"), Catch::Contains("drive.start") && Catch::Contains("no steady front"));
  const compare::ModelResult r = alone(s, "continuum");
  CHECK(r.status == compare::RunStatus::complete);
  REQUIRE(r.scalars.count("steady_front_c") == 1);
  CHECK(r.scalars.at("steady_front_c") > 0.0);
}
