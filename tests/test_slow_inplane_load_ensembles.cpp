// The ensembles on the coupled in-plane strip (issue 40 item 1, "each the limit of the one below it"; docs/model.md §12.7):
// the count ensemble with the noise on converges to the mean field in N on the events t*, t^ and x_arrest, under the
// instantaneous channel with and without the regularisation (nothing is clamped there) and under re-attachment (the
// ensembles' capacity at p_0 clamps a at 1 in both, docs/model.md §12.5). Scene: the small coupled fig1 of
// tests/test_inplane_load.cpp made 200 long (the in-plane strip 200 × 4, dx = dy = 1, p_0 = 10, m = 1, explicit, to
// t = 140; the mean field's t^ = 108, x_arrest = 114 under the instantaneous channel: ~3 CPU-s a run), fig1_inplane_load
// itself being ~3 CPU-min per continuum run (its restart is checked here, on the continuum to t = 36). The noise-off
// identity is in tests/test_inplane_load.cpp (default tier).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/fit.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "identical.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

compare::Scene coupled(const std::string& channel, double length) {
  compare::Scene s = testing::small_strip_scene(core::Integrator::central_difference, "fig1_inplane_load", "inplane");
  s.bulk.normal_load = 10.0;
  s.interface.load_coupling = "sigma_yy";
  s.interface.load_channel = channel;
  s.interface.load_exponent = 1.0;
  s.interface.load_relaxation_length = length;
  s.interface.load_relaxation_speed = length > 0.0 ? 0.1 : 0.0;
  s.bulk.length = 200.0;  // the small strip's 60 arrests nothing: t^ and x_arrest need the front room to stop
  s.time.t_end = 140.0;
  s.limits.min_nodes_per_elastic_length = 0.0;
  s.output.snapshot_dt = 0.0;
  s.discrete.representation = "count";
  return s;
}

double event(const compare::ModelResult& r, int which) {
  return which == 0 ? r.events.t_star : which == 1 ? r.events.t_hat : r.events.x_arrest;
}

}  // namespace

TEST_CASE("inplane load ensembles: the count ensemble converges to the mean field in N on the coupled strip",
          "[inplane_load][slow]") {
  // t* under the instantaneous channel: before first yield every site is at rest with all its contacts attached, and the
  // count law's draws at rest change nothing (no detachment below the threshold, nothing to re-attach): t* is the mean
  // field's exactly, at every N and seed (asserted). Under re-attachment a site below p_0 (a < 1: the tension at the
  // loaded corner) turns its contacts over at rest (docs/model.md §12.2), so t* is random there and fitted as the others.
  // The events: at N = 100, 1000, 10000 (seeds 1..4) the RMS over the seeds of the event minus the mean field's; fitted
  // err ≈ C N^p (compare::fit_power_law over the three N). An RMS of 4 seeds has a log-error of
  // ~1/sqrt(8) = 0.35, so p over ln N = 4.6 .. 9.2 has a standard error of ~0.11: the band |p + 1/2| < 0.3 is ~2.8
  // sigma (false alarm ~0.5 % a fit, ~3 % over the 7 fits; fixed seeds, so a pass is reproducible).
  struct Case {
    const char* channel;
    double length;
  };
  const char* names[] = {"t*", "t^", "x_arrest"};
  for (const Case c : {Case{"instantaneous", 0.0}, Case{"instantaneous", 1.0}, Case{"reattachment", 0.0}}) {
    INFO(c.channel << ", L = " << c.length);
    compare::Scene mf = coupled(c.channel, c.length);
    mf.models = {"mean_field"};
    mf.validate();
    const auto ref = compare::run_scene(mf, {});
    REQUIRE(ref.size() == 1);
    std::printf("%s, L = %g: mean field t* %.4f t^ %.4f x_arrest %.3f\n", c.channel, c.length, ref[0].events.t_star,
                ref[0].events.t_hat, ref[0].events.x_arrest);
    for (int w = 0; w < 3; ++w) REQUIRE(std::isfinite(event(ref[0], w)));
    std::vector<double> ns, err[3];
    for (const long n : {100L, 1000L, 10000L}) {
      double sq[3] = {0, 0, 0};
      const int seeds = 4;
      for (int seed = 1; seed <= seeds; ++seed) {
        compare::Scene s = coupled(c.channel, c.length);
        s.models = {"discrete"};
        s.discrete.contacts_per_site = n;
        s.discrete.seed = static_cast<std::uint64_t>(seed);
        s.validate();
        const auto r = compare::run_scene(s, {});
        REQUIRE(r.size() == 1);
        for (int w = 0; w < 3; ++w) sq[w] += std::pow(event(r[0], w) - event(ref[0], w), 2);
      }
      ns.push_back(static_cast<double>(n));
      for (int w = 0; w < 3; ++w) err[w].push_back(std::sqrt(sq[w] / seeds));
      std::printf("  N = %5ld: RMS t* %.3e, t^ %.3e, x_arrest %.3e\n", n, err[0].back(), err[1].back(), err[2].back());
    }
    const bool exact_start = std::string(c.channel) == "instantaneous";
    if (exact_start)
      for (const double e : err[0]) CHECK(e == 0.0);
    for (int w = exact_start ? 1 : 0; w < 3; ++w) {
      const auto fit = compare::fit_power_law(ns, err[w]);
      std::printf("  %s: p = %.3f (95%% CI %.3f .. %.3f)\n", names[w], fit.slope, fit.slope_ci_low, fit.slope_ci_high);
      INFO(names[w]);
      CHECK(std::abs(fit.slope + 0.5) < 0.3);
    }
  }
}

TEST_CASE("inplane load ensembles: fig1_inplane_load restarted is the uninterrupted run bit for bit, both channels",
          "[inplane_load][checkpoint][slow]") {
  // configs/fig1_inplane_load.toml itself (the continuum, H = 17, p_0 = 10) to t = 36 (past first yield, t* = 28.5 under
  // re-attachment, 33.1 under the instantaneous channel), under re-attachment, the instantaneous channel and the
  // regularised one (L = 1, v* = 0.1): the run with checkpoints every 16 and the run restarted from the first checkpoint
  // against the run without: every field exactly (tests/identical.hpp). The small-strip version with the ensembles
  // alongside is in tests/test_inplane_load.cpp.
  struct Case {
    const char* channel;
    double length;
  };
  for (const Case c : {Case{"reattachment", 0.0}, Case{"instantaneous", 0.0}, Case{"instantaneous", 1.0}}) {
    std::vector<std::string> set = {"time.t_end=36", std::string("interface.load_channel=") + c.channel};
    if (c.length > 0.0) {
      set.push_back("interface.load_relaxation_length=1.0");
      set.push_back("interface.load_relaxation_speed=0.1");
    }
    const compare::Scene s = app::load_scene(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1_inplane_load.toml", set);
    INFO(c.channel << ", L = " << c.length);
    const auto whole = compare::run_scene_alongside(s, {});
    REQUIRE(std::isfinite(whole.models[0].events.t_star));
    testing::require_restarts_identical(s, whole, 16.0, false);
  }
}
