// Slow tier (label "slow"): threshold disorder on fig1 (issue 21, docs/studies.md "disorder_limit"), run as
// `slipfront study` runs them. (1) configs/studies/checks/disorder_limit_fig1_N.toml (96 runs, ~90 s CPU): at w = 0.2
// the discrete events converge on mean_field's as N grows; (2) configs/studies/disorder_limit_fig1.toml (~35 s CPU):
// mean_field tends to the continuum as w -> 0, at a fitted rate. Seeds are fixed, so the outcomes are deterministic;
// the false-alarm rates quoted are those of a fresh set of seeds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "apps/config.hpp"
#include "apps/study.hpp"
#include "compare/alongside.hpp"
#include "compare/pool.hpp"
#include "studies/study.hpp"
#include "study_run.hpp"

using namespace slipfront;

namespace {
studies::StudyReport run(const std::string& name) { return testing::run_study(name); }
double get(const studies::StudyReport& r, const std::string& k) { return testing::scalar(r, k); }
}  // namespace

TEST_CASE("slow disorder: fig1 with w = 0.2: discrete events converge to mean_field's with N (fitted exponent with CI)",
          "[slow][studies][disorder]") {
  const auto r = run("checks/disorder_limit_fig1_N");
  // Uniform thresholds, fresh renewal, N = 1e3 .. 3e5, 8 seeds: the spread over seeds of (discrete - mean_field) /
  // mean_field falls like N^-1/2 for t^, c_slow, c_transient, x_arrest (measured -0.51, -0.60, -0.51, -0.52). Asserted:
  // the 95 % interval below zero and containing -1/2: 5 % false alarms per event for a correct model (up to ~19 % for
  // the four, less as they are correlated).
  for (const char* o : {"t_hat", "c_slow", "c_transient", "x_arrest"}) {
    const std::string k = std::string("disorder_N_") + o + "_uniform_fresh_w0.2_sd_exponent";
    INFO(k << " = " << get(r, k) << " (" << get(r, k + "_ci_low") << " .. " << get(r, k + "_ci_high") << ")");
    CHECK(get(r, k + "_ci_high") < 0.0);
    CHECK(get(r, k + "_ci_low") <= -0.5);
    CHECK(get(r, k + "_ci_high") >= -0.5);
  }
  // t* is decided before any contact detaches: identical to mean_field's at every N (no rate)
  CHECK(r.scalars.count("disorder_N_t_star_uniform_fresh_w0.2_sd_exponent") == 0);
  // Gaussian thresholds, quenched renewal (finding, docs/studies.md): the discrete model converges, but slowly and with
  // a bias: its spread falls like N^-0.20 .. -0.26 (intervals below zero, excluding -1/2) and at N = 3e5 its mean t^,
  // c_transient, x_arrest are still 6 %, 10 %, 8 % below mean_field's. Asserted: the interval below zero, and the bias
  // (seed mean) smaller at the largest N than at N = 3e3 by at least a factor 1.5 (measured 2.1, 4.2, 2.6).
  const auto& t = r.tables.at("disorder_limit_N");
  std::size_t lo = 0, hi = 0;
  for (std::size_t k = 0; k < t.at("N").size(); ++k)
    if (t.at("threshold")[k] == 2) {
      if (t.at("N")[k] == 3000) lo = k;
      if (t.at("N")[k] == 300000) hi = k;
    }
  REQUIRE(t.at("N")[lo] == 3000);
  REQUIRE(t.at("N")[hi] == 300000);
  for (const char* o : {"t_hat", "c_transient", "x_arrest"}) {
    const std::string k = std::string("disorder_N_") + o + "_gaussian_quenched_w0.2_sd_exponent";
    INFO(k << " = " << get(r, k) << " (" << get(r, k + "_ci_low") << " .. " << get(r, k + "_ci_high") << ")");
    CHECK(get(r, k + "_ci_high") < 0.0);
    const auto& bias = t.at(std::string(o) + "_mean_rel");
    CHECK(std::abs(bias[hi]) * 1.5 < std::abs(bias[lo]));
  }
}

TEST_CASE("slow disorder: fig1: mean_field tends to the continuum as w -> 0, t* at first order",
          "[slow][studies][disorder]") {
  const auto r = run("disorder_limit_fig1");
  // Deterministic (no seeds). Fitted over w = 0.002 .. 0.05 (w <= alpha - 1) at dt = 0.005, fresh renewal:
  // t* first order (measured 0.993 uniform, 0.998 gaussian; the weakest thresholds yield first), x_arrest 1.18 .. 1.25,
  // c_slow 1.32 .. 1.75, c_transient 1.48 .. 1.71 (wide intervals). Asserted: t*'s rate within 0.1 of 1 with its interval
  // covering 1; x_arrest's and c_slow's intervals above 0.5 (they do vanish as w -> 0); every event within 1 % at
  // w = 0.002 (the largest: t* of gaussian thresholds, 0.51 %).
  for (const char* lr : {"uniform_fresh", "gaussian_fresh"}) {  // (quenched renewal runs at w >= 0.07 only)
    INFO(lr);
    const std::string ts = std::string("disorder_w_t_star_") + lr + "_exponent";
    CHECK(std::abs(get(r, ts) - 1.0) < 0.1);
    CHECK(get(r, ts + "_ci_low") <= 1.0);
    CHECK(get(r, ts + "_ci_high") >= 1.0);
    for (const char* o : {"x_arrest", "c_slow"})
      CHECK(get(r, std::string("disorder_w_") + o + "_" + lr + "_exponent_ci_low") > 0.5);
    // the 1 % crossing of t* at w ~ 0.0036 (gaussian) .. 0.0056 (uniform): about 1 % / (w-slope of t*)
    const double x = get(r, std::string("disorder_w1pct_t_star_") + lr);
    CHECK(x > 0.002);
    CHECK(x < 0.01);
  }
  const auto& t = r.tables.at("disorder_limit_w");
  for (std::size_t k = 0; k < t.at("w").size(); ++k)
    if (t.at("w")[k] == 0.002)
      for (const char* o : {"t_star", "t_hat", "c_slow", "c_transient", "x_arrest"})
        CHECK(t.at(std::string(o) + "_rel_diff")[k] < 0.01);
}
