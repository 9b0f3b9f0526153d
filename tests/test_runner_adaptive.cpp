// time.integrator = "adaptive" through the runner and the config (issue 5): the adaptive continuum
// integrator gives the explicit reference's fig1 events within 1%, records at exact cadence times
// from its dense output, and bad integrator settings are refused with their key.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/runner.hpp"

using namespace slipfront;

namespace {
compare::Scene fig1(std::vector<std::string> extra) {
  std::vector<std::string> o{"models=[\"continuum\"]"};
  o.insert(o.end(), extra.begin(), extra.end());
  return app::load_scene(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1.toml", o);
}
}  // namespace

TEST_CASE("runner: the adaptive integrator reproduces fig1's events within 1% in far fewer steps", "[adaptive]") {
  // Tolerance 1% on t*, t^, c_transient, x_arrest against the explicit reference scheme (cfl 0.5),
  // whose own distance to the converged solution is ~1e-4 (docs/performance.md).
  const auto ex = compare::run_scene(fig1({}), {});
  const auto ad = compare::run_scene(fig1({"time.integrator=adaptive", "time.rtol=1e-2"}), {});
  REQUIRE(ex.at(0).status == slipfront::compare::RunStatus::complete);
  REQUIRE(ad.at(0).status == slipfront::compare::RunStatus::complete);
  CHECK(ad[0].labels.at("integrator") == "adaptive");
  const auto& a = ad[0].events;
  const auto& e = ex[0].events;
  CHECK(a.t_star == Approx(e.t_star).epsilon(0.01));
  CHECK(a.t_hat == Approx(e.t_hat).epsilon(0.01));
  CHECK(a.c_transient == Approx(e.c_transient).epsilon(0.01));
  CHECK(a.x_arrest == Approx(e.x_arrest).epsilon(0.01));
  CHECK(ad[0].scalars.at("steps") * 50 < ex[0].scalars.at("steps"));
  // series and snapshots at the exact cadence times (dense output), with the same layout
  const auto& t = ad[0].series.at("t");
  REQUIRE(t.size() == ex[0].series.at("t").size());
  for (std::size_t k = 0; k < t.size(); ++k) REQUIRE(t[k] == Approx(static_cast<double>(k) * 0.05).margin(1e-9));
  REQUIRE(ad[0].snapshot_t.size() == ex[0].snapshot_t.size());
  REQUIRE(ad[0].snapshots.at("A").size() == ex[0].snapshots.at("A").size());
  for (double x : ad[0].snapshots.at("A")) REQUIRE((x >= 0.0 && x <= 1.0));
}

TEST_CASE("runner: with the adaptive continuum, both models still run and are compared", "[adaptive]") {
  // No common step (the continuum on Rosenbrock steps, the discrete model on leap steps, core/leap.hpp): the
  // models run one after the other; the end-of-run comparison is still written.
  auto s = fig1({"models=[\"continuum\",\"discrete\"]", "time.integrator=adaptive", "time.t_end=40",
                 "bulk.length=100", "grid.dx=1", "discrete.contacts_per_site=1000"});
  const auto r = compare::run_scene_alongside(s, {});
  REQUIRE(r.models.size() == 2);
  CHECK(r.models[0].labels.at("integrator") == "adaptive");
  CHECK(r.models[1].labels.at("integrator") == "leap");  // core/leap.hpp
  CHECK(std::abs(r.comparison.metrics.at("t_star_rel_diff")) < 0.01);
  CHECK(r.comparison.fields.empty());
}

TEST_CASE("config: bad integrator settings are refused with their key", "[adaptive]") {
  const auto refused = [](std::vector<std::string> o, const std::string& key) {
    try {
      (void)fig1(std::move(o));
      FAIL("expected a ConfigError for " << key);
    } catch (const app::ConfigError& e) {
      CHECK(std::string(e.what()).find(key) != std::string::npos);
    }
  };
  refused({"time.integrator=implicit"}, "time.integrator");
  refused({"time.integrator=adaptive", "time.rtol=0"}, "time.rtol");
  refused({"time.integrator=adaptive", "time.atol=-1"}, "time.atol");
  refused({"time.integrator=adaptive", "time.dt_max=0"}, "time.dt_max");
}

TEST_CASE("runner: time.stop_at_arrest ends fig1 at the arrest with the events of the whole run", "[adaptive]") {
  // The run stops at t_arrest (docs/cli.md time.stop_at_arrest); every event up to it is the whole run's,
  // bit for bit (the same steps up to the stop), and the run is shorter than t_end by what follows the arrest.
  const auto whole = compare::run_scene(fig1({"time.integrator=adaptive"}), {});
  const auto cut = compare::run_scene(fig1({"time.integrator=adaptive", "time.stop_at_arrest=true"}), {});
  REQUIRE(whole.at(0).status == compare::RunStatus::complete);
  REQUIRE(cut.at(0).status == compare::RunStatus::complete);
  const auto& w = whole[0].events;
  const auto& c = cut[0].events;
  REQUIRE(std::isfinite(w.t_arrest));
  CHECK(c.t_arrest == w.t_arrest);
  CHECK(c.t_star == w.t_star);
  CHECK(c.t_hat == w.t_hat);
  CHECK(c.c_transient == w.c_transient);
  const auto& ca = cut[0].events_alt;
  CHECK(ca.c_slow == whole[0].events_alt.c_slow);
  CHECK(ca.x_arrest == whole[0].events_alt.x_arrest);
  CHECK(c.x_arrest == w.x_arrest);
  const double reached = cut[0].scalars.at("t_reached");
  CHECK(reached >= w.t_arrest);
  CHECK(reached < w.t_arrest + 2.0);  // the step after the arrest (dt_max = 1 and the tracker's sub-intervals)
  CHECK(reached < 0.9 * whole[0].scalars.at("t_reached"));
}

TEST_CASE("config: time.stop_at_arrest is noted as ignored and reset where there is no arrest to stop at", "[adaptive]") {
  // Like every key a scene does not use (docs/cli.md): a note naming the key and when it is used, and the
  // value reset to its default, so that the homogeneous front still runs to t_end.
  std::vector<std::string> notes;
  const auto s = app::load_scene(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/homogeneous_front.toml",
                                 {"time.stop_at_arrest=true"}, &notes);
  CHECK_FALSE(s.time.stop_at_arrest);
  bool named = false;
  for (const auto& n : notes)
    named = named || (n.find("time.stop_at_arrest") != std::string::npos && n.find("drive.loading = edge") != std::string::npos);
  CHECK(named);
}
