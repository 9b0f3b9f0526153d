// Slow tier (label "slow"): the full convergence studies of configs/studies/, run as
// `slipfront study` runs them (every point on a pool, then the analysis), with their fitted rates
// asserted. About 4 minutes on 2 cores. Tolerances are stated per case; seeds are fixed, so the
// outcomes are deterministic (the false-alarm rates quoted are those of a fresh set of seeds).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "apps/config.hpp"
#include "apps/study.hpp"
#include "compare/alongside.hpp"
#include "compare/pool.hpp"
#include "compare/study.hpp"

using namespace slipfront;

namespace {

compare::StudyReport run(const std::string& name) {
  const auto spec = app::load_study(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/studies/" + name + ".toml");
  const auto runs = compare::expand(spec);
  std::vector<compare::Scene> scenes;
  for (const auto& r : runs) scenes.push_back(app::load_scene(spec.scene_file, r.overrides));
  std::vector<std::vector<compare::ModelResult>> results(runs.size());
  compare::run_pool(runs.size(), std::max(1u, std::thread::hardware_concurrency()), [&](std::size_t i) {
    auto sr = compare::run_scene_alongside(scenes[i], {});
    for (auto& m : sr.models) m.snapshots.clear();
    results[i] = std::move(sr.models);
  });
  auto rep = compare::analyse_study(spec, runs, scenes, results);
  for (const auto& [k, v] : rep.scalars) WARN(name << ": " << k << " = " << v);
  return rep;
}

double get(const compare::StudyReport& r, const std::string& k) { return r.scalars.at(k); }

}  // namespace

TEST_CASE("slow studies: friction law, random error ~ N^(-1/2) in the mean-field regime", "[slow][studies]") {
  // Fit over N >= 1e4 (study key fit_from): exponent within 0.15 of -1/2, 95% interval covering -1/2
  // (5% false-alarm rate for a correct model); bias below the random part there.
  const auto r = run("friction_law_N");
  CHECK(std::abs(get(r, "friction_law_random_exponent_from") + 0.5) < 0.15);
  CHECK(get(r, "friction_law_random_exponent_from_ci_low") <= -0.5);
  CHECK(get(r, "friction_law_random_exponent_from_ci_high") >= -0.5);
}

TEST_CASE("slow studies: threshold disorder, distance to the continuum ~ w^1", "[slow][studies]") {
  // Noise off (deterministic): yield smoothed over a threshold range of width w shifts the static
  // peak and the history by O(w). Asserted: exponents in [0.7, 1.3] with intervals covering 1.
  const auto r = run("threshold_width");
  for (const char* k : {"threshold_width_exponent", "threshold_width_peak_exponent"}) {
    CHECK(get(r, k) > 0.7);
    CHECK(get(r, k) < 1.3);
    CHECK(get(r, std::string(k) + "_ci_low") <= 1.0);
    CHECK(get(r, std::string(k) + "_ci_high") >= 1.0);
  }
}

TEST_CASE("slow studies: transient friction after velocity steps converges like N^(-1/2)", "[slow][studies]") {
  const auto r = run("velocity_step_N");
  CHECK(std::abs(get(r, "transient_distance_exponent_from") + 0.5) < 0.2);
}

TEST_CASE("slow studies: spring-block stick-slip history converges as N grows", "[slow][studies]") {
  // Stick-slip accumulates phase drift over cycles, so the rate is noisy; asserted: it converges
  // (exponent < -0.3) and the distance at the largest N is below 1%.
  const auto r = run("spring_block_N");
  CHECK(get(r, "transient_distance_exponent_from") < -0.3);
  CHECK(r.tables.at("transient_friction").at("distance_mean").back() < 0.01);
}

TEST_CASE("slow studies: fig1 front speeds of the discrete model at the largest N within 2% of the continuum",
          "[slow][studies]") {
  const auto r = run("front_speeds_N");
  const auto& t = r.tables.at("front_speeds");
  for (const char* o : {"t_star", "t_hat", "c_slow_alt", "c_transient", "x_arrest"}) {
    INFO(o);
    CHECK(std::abs(t.at(std::string(o) + "_rel_diff").back()) < 0.02);
  }
  // and the seed spread of t^ and c_transient shrinks with N over the mean-field range
  CHECK(get(r, "front_t_hat_sd_exponent_from") < -0.2);
  CHECK(get(r, "front_c_transient_sd_exponent_from") < -0.2);
}

TEST_CASE("slow studies: Fig. 2 (right), c_transient collapses on sqrt(mu alpha/(eta kappa))", "[slow][studies]") {
  // The paper: a line with a slope of order one. Asserted: overall slope in [0.5, 2] for both models,
  // and each parameter's slope within 25% of the overall one (the collapse).
  const auto r = run("fig2_sweep");
  for (const char* m : {"continuum", "discrete"}) {
    const double all = get(r, std::string("fig2_slope_all_") + m);
    CHECK(all > 0.5);
    CHECK(all < 2.0);
    for (const char* p : {"mu", "alpha", "eta", "kappa"}) {
      INFO(m << " " << p);
      CHECK(std::abs(get(r, std::string("fig2_slope_") + p + "_" + m) / all - 1.0) < 0.25);
    }
  }
}

TEST_CASE("slow studies: the front spectrum of homogeneous loading starts at a finite speed", "[slow][studies]") {
  // No steady front below sigma_d = 0.35 (the nucleation patch re-sticks); the slowest steady front
  // runs at a finite speed well above zero (the 'forbidden gap'); discrete (N = 1e4) within 2%.
  const auto r = run("front_spectrum");
  const auto& t = r.tables.at("front_spectrum");
  for (std::size_t k = 0; k < t.at("sigma_d").size(); ++k) {
    const double sd = t.at("sigma_d")[k], cc = t.at("c_front_continuum")[k], cd = t.at("c_front_discrete")[k];
    INFO("sigma_d = " << sd);
    if (sd <= 0.3) CHECK(std::isnan(cc));
    if (sd >= 0.4) {
      CHECK(cc > 20.0);
      CHECK(std::abs(cd / cc - 1.0) < 0.02);
    }
  }
  CHECK(get(r, "spectrum_slowest_front") > 20.0);
}
