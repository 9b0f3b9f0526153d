// The step-controlled integrator of the stochastic and mean-field laws (core/leap.hpp, docs/numerics.md §9),
// which time.integrator = adaptive runs them on:
//   - quiet stretches cost a few steps: fig1 up to t = 20 (the stuck phase) in under 50 steps (the fixed implicit
//     step of 0.02 takes 1000, the explicit scheme 14 000);
//   - the located onset: the first yield t* of the count law is the adaptive continuum's to 1e-4 (the explicit
//     scheme's is late by up to its step, 1.5e-3 here);
//   - deterministic accuracy: the noise-off count law at w = 0 is the continuum law (docs/model.md §2 item 1), so
//     on leap steps its fig1 events must be the continuum's on Rosenbrock steps: within 0.5 %; and, having no count
//     noise, it does not pay the noisy law's short steps at sliding sites (fewer than half the noisy run's steps);
//   - statistical accuracy: fig1 events of the count law at N = 10⁴ over 12 seeds on leap steps against the
//     explicit reference scheme's over 12 other seeds (two-sample KS on t^ and x_arrest, each at α = 0.01: a
//     false alarm rate of 2 % for the pair).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/leap.hpp"
#include "discrete/count_law.hpp"
#include "tests/discrete_agent_helpers.hpp"
#include "tests/leap_scenes.hpp"

using namespace slipfront;

namespace {

compare::ModelResult run_one(compare::Scene s) {
  s.validate();
  auto out = compare::run_scene(s, compare::RunControl{});
  REQUIRE(!out.empty());
  REQUIRE(out.back().status == compare::RunStatus::complete);
  return std::move(out.back());
}

compare::Scene count_fig1(core::Integrator integ, long n, unsigned seed) { return testing::count_fig1_scene(integ, n, seed); }

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

TEST_CASE("leap: the stuck phase of fig1 costs a few steps", "[leap]") {
  compare::Scene s = count_fig1(core::Integrator::adaptive_rosenbrock, 1000, 1);
  s.time.t_end = 20.0;  // before t* = 25.66: no contact is overloaded
  const auto r = run_one(s);
  CHECK(r.labels.at("integrator") == "leap");
  CHECK(r.scalars.at("t_reached") == 20.0);
  WARN("fig1 stuck phase [0, 20] on leap steps: " << r.scalars.at("steps") << " steps, "
                                                  << r.scalars.at("trial_solves") << " trial solves");
  CHECK(r.scalars.at("steps") < 50);
}

TEST_CASE("leap: the onset of yield is located (t* of the count law against the adaptive continuum)", "[leap]") {
  compare::Scene c = testing::fig1_scene();
  c.models = {"continuum"};
  c.time.integrator = core::Integrator::adaptive_rosenbrock;
  c.time.t_end = 40.0;
  c.output.snapshot_dt = 0.0;
  const auto cont = run_one(c);
  compare::Scene d = count_fig1(core::Integrator::adaptive_rosenbrock, 10000, 3);
  d.time.t_end = 40.0;
  const auto leap = run_one(d);
  WARN("t*: continuum (Rosenbrock) " << cont.events.t_star << ", count N = 1e4 (leap) " << leap.events.t_star);
  CHECK(rel(leap.events.t_star, cont.events.t_star) < 1e-4);
  CHECK(leap.scalars.at("located_onsets") > 0);
}

TEST_CASE("leap: the noise-off count law at w = 0 gives the continuum's fig1 events", "[leap]") {
  compare::Scene c = testing::fig1_scene();
  c.models = {"continuum"};
  c.time.integrator = core::Integrator::adaptive_rosenbrock;
  c.output.snapshot_dt = 0.0;
  const auto cont = run_one(c);
  compare::Scene d = count_fig1(core::Integrator::adaptive_rosenbrock, 1000, 1);
  d.discrete.noise = false;
  const auto leap = run_one(d);
  WARN("fig1 continuum (Rosenbrock) vs noise-off count (leap, " << leap.scalars.at("steps") << " steps): t^ "
                                                                 << cont.events.t_hat << " / " << leap.events.t_hat
                                                                 << ", c_transient " << cont.events.c_transient << " / "
                                                                 << leap.events.c_transient << ", x_arrest "
                                                                 << cont.events.x_arrest << " / " << leap.events.x_arrest);
  CHECK(rel(leap.events.t_star, cont.events.t_star) < 5e-3);
  CHECK(rel(leap.events.t_hat, cont.events.t_hat) < 5e-3);
  CHECK(rel(leap.events.c_transient, cont.events.c_transient) < 5e-3);
  CHECK(rel(leap.events.x_arrest, cont.events.x_arrest) < 5e-3);
  // A deterministic law has no count fluctuation to watch: its sliding sites keep the share ε of the leap condition
  // (core::LawHooks::count_noise). So do the noisy count law's sites near s_0 where the law watches them (fresh
  // renewal, one threshold: its yield test at every count event, discrete::CountLaw::advance_watched); where it does
  // not (quenched renewal, at w = 0 the same chain), they keep ε/4 (core::LeapSimulation::kSlidingShare).
  const auto watched = run_one(count_fig1(core::Integrator::adaptive_rosenbrock, 1000, 1));
  compare::Scene q = count_fig1(core::Integrator::adaptive_rosenbrock, 1000, 1);
  q.discrete.renewal = "quenched";
  const auto shared = run_one(q);
  WARN("fig1 count N = 1e3 on leap steps: noise off " << leap.scalars.at("steps") << " steps, noise on (watched) "
                                                      << watched.scalars.at("steps") << ", noise on, quenched (not "
                                                      << "watched) " << shared.scalars.at("steps"));
  CHECK(watched.scalars.at("steps") < 1.5 * leap.scalars.at("steps"));
  CHECK(leap.scalars.at("steps") < 0.5 * shared.scalars.at("steps"));
}

TEST_CASE("leap: fig1 events of the count law at N = 1e4 are distributed as on the explicit reference scheme",
          "[leap][statistics]") {
  // 12 seeds each, disjoint (1..12 leap, 101..112 explicit): two independent samples.
  std::vector<double> th_l, th_e, xa_l, xa_e;
  // a missing event (no transient, no arrest by t_end) counts as beyond every one measured
  const auto or_beyond = [](double x) { return std::isfinite(x) ? x : 1e9; };
  for (unsigned k = 1; k <= 12; ++k) {
    const auto l = run_one(count_fig1(core::Integrator::adaptive_rosenbrock, 10000, k));
    const auto e = run_one(count_fig1(core::Integrator::central_difference, 10000, 100 + k));
    th_l.push_back(or_beyond(l.events.t_hat));
    th_e.push_back(or_beyond(e.events.t_hat));
    xa_l.push_back(or_beyond(l.events.x_arrest));
    xa_e.push_back(or_beyond(e.events.x_arrest));
  }
  const auto ks_t = testing::ks_two_sample(th_l, th_e), ks_x = testing::ks_two_sample(xa_l, xa_e);
  const auto list = [](const std::vector<double>& x) {
    std::string s;
    for (double v : x) s += " " + std::to_string(v);
    return s;
  };
  WARN("t^ leap:" << list(th_l) << "\nt^ explicit:" << list(th_e));
  WARN("count N = 1e4, 12 + 12 seeds, leap vs explicit: t^ KS D = " << ks_t.d << " p = " << ks_t.p
                                                                    << "; x_arrest KS D = " << ks_x.d << " p = " << ks_x.p);
  CHECK(ks_t.p > 0.01);
  CHECK(ks_x.p > 0.01);
}

TEST_CASE("leap: a site hovering at its threshold does not stall the run (fig1, alpha = 1.03, N = 100, seed 2)", "[leap]") {
  // This run once took 7e5 located onsets in 2.5e4 steps (the floor of a located step shrank with the trial) and
  // did not finish in minutes; a located step is now at least 1 % of the step the leap condition allows.
  compare::Scene s = count_fig1(core::Integrator::adaptive_rosenbrock, 100, 2);
  s.interface.alpha = 1.03;
  const auto r = run_one(s);
  WARN("alpha = 1.03, N = 100, seed 2: " << r.scalars.at("steps") << " steps, " << r.scalars.at("trial_solves")
                                         << " solves, " << r.scalars.at("located_onsets") << " located onsets");
  CHECK(r.scalars.at("t_reached") == 140.0);
  CHECK(r.scalars.at("trial_solves") < 4.0 * r.scalars.at("steps"));
  CHECK(r.scalars.at("located_onsets") < r.scalars.at("steps"));
  CHECK(r.scalars.at("forced_steps") == 0.0);  // no step was taken on a failed test after the 40 trials
}

TEST_CASE("leap: a step that would fall below dt_min fails the run, as on the adaptive integrator", "[leap]") {
  // With dt_min = dt_initial = dt_max = 0.5 every trial that is shortened (the located first yield near t* = 25.7,
  // a halving or a leap rejection) is below dt_min: a NumericalError naming the step and time, never a step
  // taken on a test it failed.
  compare::Scene s = count_fig1(core::Integrator::adaptive_rosenbrock, 1000, 1);
  s.time.t_end = 40.0;
  s.validate();
  core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const std::size_t n = bulk.nodes();
  core::AdaptiveOptions o = core::AdaptiveOptions::from(s.time);
  o.dt_min = o.dt_initial = o.dt_max = 0.5;
  core::LeapSimulation<discrete::CountLaw> sim(std::move(bulk), discrete::CountLaw(s.interface, s.discrete, n), o);
  sim.set_stop_time(s.time.t_end);
  bool failed = false;
  try {
    while (sim.time() < s.time.t_end) sim.step();
  } catch (const core::NumericalError& e) {
    failed = true;
    CHECK(std::string(e.what()).find("leap step below dt_min") != std::string::npos);
    WARN(e.what());
  }
  CHECK(failed);
  CHECK(sim.time() < s.time.t_end);
  // the same run with the default dt_min reaches t_end
  core::Bulk bulk2(s.bulk, s.drive, s.interface, s.grid.dx);
  core::LeapSimulation<discrete::CountLaw> ok(std::move(bulk2), discrete::CountLaw(s.interface, s.discrete, n),
                                              core::AdaptiveOptions::from(s.time));
  ok.set_stop_time(s.time.t_end);
  while (ok.time() < s.time.t_end) ok.step();
  CHECK(ok.time() == s.time.t_end);
  CHECK(ok.stats().forced == 0);
}
