// Slow tier (label "slow"): the full convergence studies of configs/studies/, run as
// `slipfront study` runs them (every point on a pool, then the analysis), with their fitted rates
// asserted. About 4 minutes on 2 cores. Tolerances are stated per case; seeds are fixed, so the
// outcomes are deterministic (the false-alarm rates quoted are those of a fresh set of seeds).
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
#include "studies/strip_height.hpp"
#include "studies/study.hpp"
#include "study_run.hpp"
#include "continuum/friction_law.hpp"

using namespace slipfront;

namespace {
studies::StudyReport run(const std::string& name) { return testing::run_study(name); }
double get(const studies::StudyReport& r, const std::string& k) { return testing::scalar(r, k); }
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

TEST_CASE("slow studies: Fig. 2 in the strip, every run has its c_min and H = 2 is the chain run for run", "[slow][studies][strip]") {
  // configs/studies/fig2_strip.toml (docs/fronts.md §10.16): 13 parameter sets on the chain and at H = 2, 17, 100.
  // Asserted: every run measured a transient front and has the c_min of its own scene; c_min of the chain is the
  // 1D branch end (11.2811 at the paper's parameters); H = 2 (H/l <= 0.027) gives the chain's c_transient run for
  // run within 1.5 % (the O(H^2) limit; measured at most 0.94 %, kappa = 4) and c_min within 0.1 %. The 2D
  // results (the ratio below one at H = 100) are findings, reported, not asserted.
  const auto r = run("fig2_strip");
  const auto& a = r.tables.at("fig2_all");
  const auto& H = a.at("H");
  REQUIRE(H.size() == 52);
  for (std::size_t i = 0; i < H.size(); ++i) {
    INFO("run " << i << " H = " << H[i]);
    CHECK(std::isfinite(a.at("c_continuum")[i]));
    CHECK(std::isfinite(a.at("c_min")[i]));
  }
  CHECK(a.at("c_min")[1] == Approx(11.28108382).epsilon(1e-7));  // the chain's base run (mu = 300)
  std::vector<std::size_t> chain, thin;
  for (std::size_t i = 0; i < H.size(); ++i) {
    if (H[i] == 0.0) chain.push_back(i);
    if (H[i] == 2.0) thin.push_back(i);
  }
  REQUIRE(chain.size() == 13);
  REQUIRE(thin.size() == 13);
  for (std::size_t k = 0; k < 13; ++k) {
    INFO("parameter set " << k);
    CHECK(std::abs(a.at("c_continuum")[thin[k]] / a.at("c_continuum")[chain[k]] - 1.0) < 0.015);
    CHECK(std::abs(a.at("c_min")[thin[k]] / a.at("c_min")[chain[k]] - 1.0) < 1e-3);
  }
  REQUIRE(r.tables.at("fig2_heights").at("H").size() == 4);
}

TEST_CASE("slow studies: the discrete ensemble on the strip's fronts converges on the continuum with N", "[slow][studies][strip]") {
  // docs/fronts.md §10.17, configs/studies/checks/ (about 2.5 + 2.5 min on 2 cores). Fixed seeds: deterministic.
  // Steady strip front (H = 17, sigma_d = 0.3, N = 1e2 .. 1e5, 4 seeds): RMS distance to the continuum falls
  // (exponent interval below zero; measured -0.38, CI -0.50 .. -0.25) and is below 2e-4 at N = 1e5 (9.7e-5).
  const auto s = run("checks/steady_front_strip_N");
  CHECK(get(s, "steady_front_speed_exponent_ci_high") < 0.0);
  CHECK(s.tables.at("steady_front_N").at("rms_discrete_vs_continuum").back() < 2e-4);
  // fig1 on the strip H = 100 (N = 1e3 .. 1e5, 4 seeds): the seed spread of c_transient falls (interval below
  // zero; measured -0.49, CI -0.79 .. -0.18), the seed mean within 0.5 % of the continuum at N = 1e5 (0.019 %),
  // t* the continuum's exactly.
  const auto f = run("checks/front_speeds_strip_N");
  CHECK(get(f, "front_c_transient_sd_exponent_ci_high") < 0.0);
  const auto& t = f.tables.at("front_speeds");
  CHECK(std::abs(t.at("c_transient_rel_diff").back()) < 5e-3);
  for (double d : t.at("t_star_rel_diff")) CHECK(d == 0.0);
}

TEST_CASE("slow studies: both models on an in-plane Fig. 2 point, the discrete model converges on the continuum with N",
          "[slow][studies][inplane]") {
  // docs/fronts.md §11.11, configs/studies/checks/front_speeds_inplane_N.toml: fig1_inplane at H = 17 (the crossover
  // point of fig2_inplane, mu = E'H = 300), explicit, dx = dy = 1, stopped at the arrest; the count representation with
  // noise, N = 1e2 .. 1e6 x 6 seeds, 48 runs of both models alongside (measured 1144 s of CPU at measure.sample_dt
  // 0.01, ~10 min on 2 quiet cores; every step a tip sample now). Fixed seeds: deterministic; for a fresh set of seeds
  // a 95 % interval misses -1/2 at 5 %.
  const auto r = run("checks/front_speeds_inplane_N");
  const auto& t = r.tables.at("front_speeds");
  // t* is the continuum's exactly (no draw before first yield)
  for (double d : t.at("t_star_rms_rel_diff")) CHECK(d == 0.0);
  // t^, x_arrest, c_transient and the peak speed: the RMS over seeds of |discrete - continuum|/continuum falls as
  // N^-1/2 over N >= 1e3 (fit_from; measured -0.520, -0.506, -0.486, -0.365): exponent within 0.2 of -1/2, its
  // interval covering -1/2. c_transient's rate holds on tip samples every step (the study's measure.sample_dt = 0.002);
  // at the default 0.01 the samples its window gains or loses gave N^-0.31 (docs/fronts.md §11.11)
  for (const char* o : {"t_hat", "x_arrest", "c_transient", "c_transient_peak"}) {
    INFO(o);
    const std::string k = std::string("front_") + o + "_rms_exponent_from";
    CHECK(std::abs(get(r, k) + 0.5) < 0.2);
    CHECK(get(r, k + "_ci_low") <= -0.5);
    CHECK(get(r, k + "_ci_high") >= -0.5);
  }
  // at N = 1e6: c_transient's RMS 3.9e-4 (was 1.3e-3 on the default samples), the seed mean within 0.01 % (asserted 0.1 %)
  CHECK(t.at("c_transient_rms_rel_diff").back() < 1e-3);
  CHECK(std::abs(t.at("c_transient_rel_diff").back()) < 1e-3);
  REQUIRE(t.at("N").back() == 1e6);
}

TEST_CASE("slow studies: nucleated fronts lie on the solved branch and stop at the nucleation limit", "[slow][studies]") {
  // docs/model.md §6, docs/fronts.md: the nucleation patch (150 long) starts fronts down to sigma_d ~ 0.355 and
  // none at 0.35 or below (its leading edge heals first), although the solved branch runs down to
  // sigma_c^d = 0.2166 with c_min = 11.28. Where a front starts it runs at the solved speed within 4% (a
  // finite, still accelerating run), the discrete model (N = 1e4) with it within 2%; v_behind satisfies
  // sigma_ss(v_behind) = sigma_d to 1e-2 (the rear free edge of the nucleated scene pulls on it).
  const auto r = run("front_spectrum");
  const auto& t = r.tables.at("front_spectrum");
  const core::InterfaceParams p{1.05, 8.0, 0.1};
  for (std::size_t k = 0; k < t.at("sigma_d").size(); ++k) {
    const double sd = t.at("sigma_d")[k], cc = t.at("c_front_continuum")[k], cd = t.at("c_front_discrete")[k];
    INFO("sigma_d = " << sd << ": continuum " << cc << ", discrete " << cd << ", solved " << t.at("c_solved")[k]);
    if (sd <= 0.35) CHECK(std::isnan(cc));
    if (sd >= 0.36) {
      REQUIRE(std::isfinite(cc));
      CHECK(std::abs(cc / t.at("c_solved")[k] - 1.0) < 0.04);
      CHECK(std::abs(cd / cc - 1.0) < 0.02);
      CHECK(std::abs(continuum::steady_sliding(p, t.at("v_behind_continuum")[k]).sigma - sd) < 1e-2);
    }
  }
  CHECK(get(r, "nucleation_limit_sigma_d") > 0.35);
  CHECK(get(r, "nucleation_limit_sigma_d") <= 0.36);
  CHECK(get(r, "branch_c_min") == Approx(11.28108382).epsilon(1e-6));
  CHECK(get(r, "branch_sigma_d_at_c_min") == Approx(0.2166288).epsilon(1e-5));
}

TEST_CASE("slow studies: fronts started from the solved branch keep its speed, kicked or not, both models", "[slow][studies]") {
  // front_branch (docs/model.md §6), on the adaptive integrator at rtol 1e-3 (docs/fronts.md §8a): at sigma_d from
  // 0.22 (just above the branch's end) to 0.7, a run started from the solved front keeps the solved speed — the
  // unkicked continuum within 1e-4 (measured 2e-5: with its switchings located the explicit scheme's first-order
  // switching error of 7e-4..1e-3 is gone), every run within 0.2 % (the discrete model, N = 1e4 on leap steps:
  // 3-8e-4) — and a slip-rate kick of -0.5 or +2 behind the tip changes the measured speed by less than 5e-4
  // (measured 4.0e-4): every part of the branch tried is stable.
  const auto r = run("front_branch");
  const auto& t = r.tables.at("steady_fronts");
  REQUIRE(t.at("sigma_d").size() == 18);
  for (std::size_t k = 0; k < t.at("sigma_d").size(); ++k) {
    INFO("sigma_d = " << t.at("sigma_d")[k] << ", kick " << t.at("kick_dv")[k]);
    CHECK(std::abs(t.at("rel_continuum")[k]) < 2e-3);
    if (t.at("kick_dv")[k] == 0.0) CHECK(std::abs(t.at("rel_continuum")[k]) < 1e-4);
    CHECK(std::abs(t.at("rel_discrete")[k]) < 2e-3);
    CHECK(std::abs(t.at("sigma_ss_error_continuum")[k]) < 1e-3);
  }
  CHECK(get(r, "kick_max_speed_change") < 5e-4);
}

TEST_CASE("slow studies: the discrete front speed converges on the steady front's as N grows", "[slow][studies]") {
  // steady_front_N (docs/model.md §2.1 item 2 on a steady front): started from the solved front at
  // sigma_d = 0.3, below the nucleation limit; every seed's front keeps running at every N; the RMS over 4
  // seeds of c_discrete/c_continuum - 1 falls with N at the mean-field rate: fitted exponent within
  // [-0.9, -0.3] (the -1/2 of the mean-field limit; 4 N values, 95% interval about +-0.35), and below 2e-4
  // at N = 1e5.
  const auto r = run("steady_front_N");
  const auto& n = r.tables.at("steady_front_N");
  for (double f : n.at("fronts")) CHECK(f == 4.0);
  CHECK(n.at("rms_discrete_vs_continuum").back() < 2e-4);
  const double p = get(r, "steady_front_speed_exponent");
  CHECK(p < -0.3);
  CHECK(p > -0.9);
}

TEST_CASE("slow studies: the validity map of the steady law at reduced size, and its collapse", "[slow][studies]") {
  // validity_friction (docs/validity.md) with w = 0 only and 4 seeds: the bias of the discrete steady law falls
  // from a few % to ~1e-4 within one step of the N grid (the re-sticking stops); N* (bias < 1%) grows as alpha
  // - 1 shrinks, fitted exponent within [-1.8, -1.0] (theory -3/2 from the noise-over-margin argument at the
  // worst slip rate of the sweep; the full study measures -1.32, CI -1.51 .. -1.13; the naive N (alpha - 1)^2
  // would give -2); alpha - 1 >= 0.5 holds to 1% at every N of the grid.
  auto spec = app::load_study(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/studies/validity_friction.toml");
  spec.seeds = 4;
  spec.groups.resize(1);  // w = 0
  const auto runs = compare::expand(spec);
  std::vector<compare::Scene> scenes;
  for (const auto& r : runs) scenes.push_back(app::load_scene(spec.scene_file, r.overrides));
  std::vector<std::vector<compare::ModelResult>> results(runs.size());
  compare::run_pool(runs.size(), std::max(1u, std::thread::hardware_concurrency()),
                    [&](std::size_t i) { results[i] = compare::run_scene_alongside(scenes[i], {}).models; });
  const auto r = studies::analyse_study(spec, runs, scenes, results);
  const auto& x = r.tables.at("validity_crossover");
  for (std::size_t k = 0; k < x.at("alpha").size(); ++k) {
    INFO("alpha - 1 = " << x.at("alpha_minus_1")[k] << ": N* = " << x.at("N_star_1")[k]);
    if (x.at("alpha_minus_1")[k] >= 0.5) CHECK(x.at("N_star_1_valid_everywhere")[k] == 1.0);
    else CHECK(std::isfinite(x.at("N_star_1")[k]));
  }
  const double p = get(r, "validity_friction_Nstar1_exponent");
  WARN("collapse exponent " << p);
  CHECK(p > -1.8);
  CHECK(p < -1.0);
}

TEST_CASE("slow studies: fig1 on the in-plane strip tends to the 1D chain as H -> 0 at second order (inplane_height)",
          "[slow][studies][strip][inplane]") {
  // inplane_height (docs/studies.md; issue 38): the in-plane strip and the antiplane strip at H = 0.25 .. 100 and the
  // chain, both models, dx = 1, one step 5e-4. At H = 0.25 every event of both models on either strip within 0.5 % of
  // the chain's (measured: in-plane 0.081 %, the discrete t^); over the thin heights (H/l_e <= 0.35: H = 0.25 .. 5)
  // the in-plane continuum's t*, t^ and x_arrest depart from the chain as H^p with p within 0.3 of 2 (docs/model.md
  // §10.2; measured 2.00, 1.88, 1.96). At H = 17 first yield comes latest on the in-plane strip (its stuck phase decays
  // slowest, docs/model.md §10.3): t* in-plane > antiplane > chain (measured 34.99, 29.00, 25.67).
  const auto r = run("inplane_height");
  for (const char* body : {"inplane_height", "strip_height"}) {
    INFO(body);
    CHECK(get(r, std::string(body) + "_thin_H") == 0.25);
    CHECK(get(r, std::string(body) + "_thin_max_rel_diff") < studies::strip_height_thin_tolerance);
  }
  for (const char* o : {"t_star", "t_hat", "x_arrest"})
    CHECK(std::abs(get(r, std::string("inplane_height_order_") + o + "_continuum") - 2.0) < 0.3);
  const auto at17 = [&](const char* table) {
    const auto& t = r.tables.at(table);
    const auto k = static_cast<std::size_t>(std::find(t.at("H").begin(), t.at("H").end(), 17.0) - t.at("H").begin());
    REQUIRE(k < t.at("H").size());
    return t.at("t_star_continuum")[k];
  };
  CHECK(at17("inplane_height") > at17("strip_height"));
  CHECK(at17("strip_height") > get(r, "inplane_height_1d_t_star_continuum"));
}

TEST_CASE("slow studies: fig1 on the strip tends to the 1D chain as H -> 0 at second order, t* as the series of §9.3",
          "[slow][studies][strip]") {
  // strip_height (docs/studies.md): H = 0.25 .. 100, both models, one fixed dt. At H = 0.25 every event of both
  // models within 0.5 % of the chain's (measured 0.011 %); over the thin heights (H/l_e <= 0.35) the continuum's
  // t*, t^ and x_arrest depart from the chain as H^p with p within 0.3 of 2 (docs/model.md §9.2; measured 2.09,
  // 2.15, 1.94); t*(H) / t*(chain) is the quasi-static series' t*(H) / t*_1D of docs/model.md §9.3 within 0.2 %
  // at H = 5, 17, 34 (the grid's own 0.2 % offset of t* cancels in the ratio; measured within 0.05 %).
  const auto r = run("strip_height");
  CHECK(get(r, "strip_height_thin_H") == 0.25);
  CHECK(get(r, "strip_height_thin_max_rel_diff") < studies::strip_height_thin_tolerance);
  for (const char* o : {"t_star", "t_hat", "x_arrest"})
    CHECK(std::abs(get(r, std::string("strip_height_order_") + o + "_continuum") - 2.0) < 0.3);
  const auto& t = r.tables.at("strip_height");
  const double series_1d = 25.712;
  for (const auto& [H, series] : {std::pair{5.0, 26.086}, std::pair{17.0, 29.039}, std::pair{34.0, 35.619}}) {
    const auto k = static_cast<std::size_t>(std::find(t.at("H").begin(), t.at("H").end(), H) - t.at("H").begin());
    REQUIRE(k < t.at("H").size());
    INFO("H = " << H);
    CHECK(t.at("t_star_continuum")[k] / t.at("t_star_continuum")[0] == Approx(series / series_1d).epsilon(0.002));
  }
}
