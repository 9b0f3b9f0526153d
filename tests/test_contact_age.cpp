// docs/model.md §7 (docs/contacts.md §1): the mean contact age ā of the continuum law and of the agent.
//
// Continuum. The age mass M = A ā obeys dM/dt = A − Θκ|v| M (attachment at unit rate with age 0,
// age-independent detachment of overloaded contacts at rate κ|v|), so dā/dt = 1 − ā (1 − A)/A. Checked
// against closed forms: the steady value ā_ss = 1/(κv); the relaxation after a velocity step (M is
// the sum of two exponentials, rates κv₂ and 1 + κv₂; the update is second order in Δt); the rest
// state (A = 1: ā grows at unit rate; A < 1: new contacts rejuvenate the mean); and compared with the
// aging law of rate-and-state friction, dθ/dt = 1 − vθ/D_c with D_c = 1/κ: same steady value, but ā
// starts flat after a step (it sees v only through A) where θ moves at once.
// The adaptive integrator's age hook (integrate_age_mass on the step's dense output): observed order
// 2 on smooth synthetic A(t), v(t); fig1 ages agree with the explicit scheme's away from the transient.
//
// Agent. The exact mean age of the attached contacts (Σ t_attach per site), 0D imposed v with α = 2 so
// that every attached contact is overloaded whenever v ≠ 0 (asserted): the contacts are then
// independent two-state chains with deterministic rates, the mean of the agent's ā given n ≥ 1 is
// exactly the continuum's M/A (up to the continuum's O(Δt²) step error, ~1e-5 here) and its mean A is
// the continuum's A. Test: at 14 times, z = (mean over 200 seeds − continuum)/SE for ā, M and A;
// family-wise false-alarm rate 1e-3 (Bonferroni over the 42 z-values, two-sided, normal quantile from
// Boost.Math). Power: the agent with κ × 1.2 is rejected by the same test.
#include <catch2/catch.hpp>

#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "compare/alongside.hpp"
#include "core/adaptive.hpp"
#include "continuum/friction_law.hpp"
#include "core/law.hpp"
#include "discrete/agent_law.hpp"
#include "discrete_agent_helpers.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

// One continuum site at imposed v for a time T in steps dt; returns ā at the end.
struct Site0D {
  continuum::FrictionLaw law;
  double t = 0.0;
  Site0D(const core::InterfaceParams& p, double area, double sigma_bar, double mean_age) : law(p, 1) {
    law.track_ages(true);
    law.set_site(0, area, sigma_bar);
    law.set_site_age(0, mean_age);
  }
  void run(double v, double T, double dt) {
    const auto n = static_cast<long>(std::llround(T / dt));
    const double vv[1] = {v};
    for (long k = 0; k < n; ++k) law.advance(dt, vv);
    t += T;
  }
  double area() const { return law.contact_area()[0]; }
  double mass() const { return law.age_mass()[0]; }
  double age() const { return mass() / area(); }
};

// Closed form after a step v1 → v2 from steady sliding at v1 (docs/contacts.md §1.3), Θ = 1 throughout:
// A(t) = A2 + (A1 − A2) e^{−rt}, r = 1 + κv2;  M(t) = A2/(κv2) − (A1 − A2) e^{−rt} + C e^{−κv2 t},
// C = A1/(κv1) − A2/(κv2) + (A1 − A2).
struct StepClosedForm {
  double kappa, v1, v2;
  double a1() const { return 1.0 / (1.0 + kappa * v1); }
  double a2() const { return 1.0 / (1.0 + kappa * v2); }
  double area(double t) const { return a2() + (a1() - a2()) * std::exp(-(1.0 + kappa * v2) * t); }
  double mass(double t) const {
    const double c = a1() / (kappa * v1) - a2() / (kappa * v2) + (a1() - a2());
    return a2() / (kappa * v2) - (a1() - a2()) * std::exp(-(1.0 + kappa * v2) * t) + c * std::exp(-kappa * v2 * t);
  }
  double age(double t) const { return mass(t) / area(t); }
  // The aging law with D_c = 1/κ from its steady state at v1: θ(t) = 1/(κv2) + (1/(κv1) − 1/(κv2)) e^{−κv2 t}.
  double theta(double t) const {
    return 1.0 / (kappa * v2) + (1.0 / (kappa * v1) - 1.0 / (kappa * v2)) * std::exp(-kappa * v2 * t);
  }
};

// Largest |ā − closed form| over t = 0.05, 0.1, ..., 2 after the step, with step dt.
double step_error(const core::InterfaceParams& p, const StepClosedForm& cf, double dt) {
  const continuum::SteadyState ss = continuum::steady_sliding(p, cf.v1);
  Site0D s(p, ss.area, ss.sigma_bar, 1.0 / (p.kappa * cf.v1));
  double err = 0.0;
  for (int k = 1; k <= 40; ++k) {
    s.run(cf.v2, 0.05, dt);
    err = std::max(err, std::abs(s.age() - cf.age(s.t)));
  }
  return err;
}

}  // namespace

TEST_CASE("contact age: steady sliding gives the aging law's steady state, mean age 1/(kappa v)", "[age][continuum]") {
  const auto p = testing::paper_interface();
  for (const double v : {0.05, 0.3, 1.0, 5.0}) {
    const continuum::SteadyState ss = continuum::steady_sliding(p, v);
    Site0D s(p, ss.area, ss.sigma_bar, 0.0);  // M = 0: ages start at 0 and relax at rate κv
    s.run(v, 45.0 / (p.kappa * v), 1e-3 / (p.kappa * v));
    INFO("v = " << v << ": mean age " << s.age() << ", 1/(kappa v) = " << 1.0 / (p.kappa * v));
    CHECK(s.area() == Approx(ss.area).epsilon(1e-12));
    CHECK(s.age() == Approx(1.0 / (p.kappa * v)).epsilon(1e-9));
    CHECK(s.mass() == Approx(ss.area / (p.kappa * v)).epsilon(1e-9));  // M_ss = A_ss θ_ss
  }
}

TEST_CASE("contact age: relaxation after a velocity step, closed form and second order in dt", "[age][continuum]") {
  const auto p = testing::paper_interface();
  // Steps up only: after a step up Θ stays 1 (A falls, |σ|/A grows); a step down re-sticks the site
  // (A heals faster than σ̄ relaxes, |σ|/A < 1: Θ = 0, the rest equation, until it yields again), for
  // which there is no such closed form.
  for (const auto& [v1, v2] : {std::pair{0.5, 5.0}, std::pair{1.0, 3.0}, std::pair{0.2, 1.0}}) {
    const StepClosedForm cf{p.kappa, v1, v2};
    const double e1 = step_error(p, cf, 2e-3), e2 = step_error(p, cf, 1e-3);
    const double order = testing::observed_order(e1, e2);
    std::printf("age step %g -> %g: max error %.3e (dt 2e-3), %.3e (dt 1e-3), order %.2f\n", v1, v2, e1, e2, order);
    CHECK(e2 < 1e-4 * cf.age(0.0));
    CHECK(order > 1.8);
    CHECK(order < 2.2);
  }
}

TEST_CASE("contact age against the aging law: same steady state, two rates instead of one, flat start", "[age][continuum]") {
  const auto p = testing::paper_interface();
  const StepClosedForm cf{p.kappa, 0.5, 5.0};
  const continuum::SteadyState ss = continuum::steady_sliding(p, cf.v1);
  Site0D s(p, ss.area, ss.sigma_bar, 1.0 / (p.kappa * cf.v1));
  // Just after the step: dā/dt(0+) = 1 − ā (1 − A)/A = 0 (ā and A are still steady at v1), while the
  // aging law moves at once, dθ/dt(0+) = 1 − v2/v1 = −9.
  const double delta = 0.002;
  s.run(cf.v2, delta, 1e-5);
  const double age_change = s.age() - cf.age(0.0), theta_change = cf.theta(delta) - cf.theta(0.0);
  std::printf("age vs aging law: after %.3g: d(age) = %.3e, d(theta) = %.3e; ", delta, age_change, theta_change);
  CHECK(std::abs(age_change) < 0.05 * std::abs(theta_change));
  // The transient: the largest |ā − θ| relative to the new steady value, and the same steady state.
  double gap = 0.0;
  for (int k = 1; k <= 100; ++k) {
    s.run(cf.v2, 0.01, 1e-4);
    gap = std::max(gap, std::abs(s.age() - cf.theta(s.t)) * p.kappa * cf.v2);
  }
  s.run(cf.v2, 2.0, 1e-3);
  std::printf("largest |age - theta| = %.3f of the new steady value; at t = %.1f age = %.6f, theta = %.6f\n", gap, s.t,
              s.age(), cf.theta(s.t));
  CHECK(gap > 0.2);
  CHECK(s.age() == Approx(cf.theta(s.t)).epsilon(1e-9));
  // M is exactly two exponentials: the fast one (rate 1 + κv2, amplitude −(A1 − A2)) is the area's.
  CHECK(std::abs(cf.a1() - cf.a2()) > 0.1);
}

TEST_CASE("contact age at rest: unit growth with A = 1, rejuvenation by new contacts with A < 1", "[age][continuum]") {
  const auto p = testing::paper_interface();
  {
    Site0D s(p, 1.0, 0.0, 3.0);
    s.run(0.0, 5.0, 1e-2);
    CHECK(s.age() == Approx(8.0).epsilon(1e-12));  // as the aging law at v = 0: dθ/dt = 1
  }
  // A site left with few old contacts (a fast front removed 80 % of them at random: ā unchanged):
  // A0 = 0.2, ā0 = 10. At rest A = 1 − (1 − A0) e^{−t}, M = A0 ā0 + t − (1 − A0)(1 − e^{−t}).
  const double a0 = 0.2, age0 = 10.0;
  Site0D s(p, a0, 0.0, age0);
  double min_age = age0;
  for (int k = 1; k <= 300; ++k) {
    s.run(0.0, 0.01, 1e-3);
    const double area = 1.0 - (1.0 - a0) * std::exp(-s.t);
    const double mass = a0 * age0 + s.t - (1.0 - a0) * (1.0 - std::exp(-s.t));
    REQUIRE(s.age() == Approx(mass / area).epsilon(1e-7));
    min_age = std::min(min_age, s.age());
  }
  std::printf("rejuvenation at rest: age from %.3g down to %.3g (t = 3: %.3g); the aging law would grow to 13\n", age0,
              min_age, s.age());
  CHECK(min_age < 0.5 * age0);
}

TEST_CASE("contact age: the adaptive step's age integration is second order on its dense output", "[age][adaptive]") {
  // Smooth A(t), v(t) standing in for a dense output; reference by RK4 with 2e5 steps.
  const double kappa = 2.0, T = 2.0;
  auto area = [](double t) { return 0.5 + 0.3 * std::sin(t); };
  auto speed = [](double t) { return 1.0 + 0.5 * std::cos(2.0 * t); };
  auto f = [&](double t, double m) { return area(t) - kappa * std::abs(speed(t)) * m; };
  double ref = 0.3;
  const int nref = 200000;
  for (int k = 0; k < nref; ++k) {
    const double h = T / nref, t = k * h;
    const double k1 = f(t, ref), k2 = f(t + h / 2, ref + h / 2 * k1), k3 = f(t + h / 2, ref + h / 2 * k2),
                 k4 = f(t + h, ref + h * k3);
    ref += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  std::vector<double> err;
  for (const int n : {10, 20, 40, 80}) {
    double m = 0.3;
    for (int k = 0; k < n; ++k) m = core::integrate_age_mass(m, T * k / n, T * (k + 1) / n, true, kappa, area, speed);
    err.push_back(std::abs(m - ref));
  }
  std::printf("adaptive age integration: errors %.2e %.2e %.2e %.2e, orders %.2f %.2f %.2f\n", err[0], err[1], err[2],
              err[3], testing::observed_order(err[0], err[1]), testing::observed_order(err[1], err[2]),
              testing::observed_order(err[2], err[3]));
  for (std::size_t k = 0; k + 1 < err.size(); ++k) {
    CHECK(testing::observed_order(err[k], err[k + 1]) > 1.8);
    CHECK(testing::observed_order(err[k], err[k + 1]) < 2.3);
  }
  // Θ = 0 and constant A: exact, M grows by A·T.
  auto flat = [](double) { return 0.7; };
  auto never = [](double) -> double { throw std::logic_error("slip rate read with Theta = 0"); };
  CHECK(core::integrate_age_mass(1.0, 0.0, 2.0, false, 8.0, flat, never) == Approx(2.4).epsilon(1e-15));
}

TEST_CASE("contact age on fig1: the adaptive integrator's age map agrees with the explicit scheme's", "[age][adaptive]") {
  auto s = testing::fig1_scene();
  s.output.ages = true;
  const compare::ModelResult ex = testing::run_continuum(s);
  s.time.integrator = core::Integrator::adaptive_rosenbrock;
  const compare::ModelResult ad = testing::run_continuum(s);
  REQUIRE(ex.snapshots.count("age"));
  REQUIRE(ad.snapshots.count("age"));
  REQUIRE(ex.snapshot_t.size() == ad.snapshot_t.size());
  // Away from the transient (t^ = 108.7; its front's position differs between the integrators by their
  // event-time error, 0.03 × 16 length units, and ā jumps across it), before t = 105 and after 120.
  double before = 0.0, after = 0.0;
  const std::size_t nx = ex.x.size();
  for (std::size_t k = 1; k < ex.snapshot_t.size(); ++k) {
    const auto a = testing::snapshot_row(ex, "age", k), b = testing::snapshot_row(ad, "age", k);
    for (std::size_t i = 0; i < nx; ++i) {
      const double rel = std::abs(b[i] - a[i]) / a[i];
      if (ex.snapshot_t[k] < 105.0) before = std::max(before, rel);
      if (ex.snapshot_t[k] > 120.0) after = std::max(after, rel);
    }
  }
  std::printf("fig1 ages, adaptive vs explicit: largest relative difference %.2e (t < 105), %.2e (t > 120)\n", before,
              after);
  CHECK(before < 0.01);
  CHECK(after < 0.06);
  // Before first yield nothing detaches: ā = t at every node (within the snapshot time's rounding).
  const std::size_t k20 = testing::snapshot_index(ex, 20.0);
  for (const auto* r : {&ex, &ad})
    for (double a : testing::snapshot_row(*r, "age", k20)) REQUIRE(a == Approx(r->snapshot_t[k20]).epsilon(1e-9));
}

namespace {

// The agent's (or continuum's) ā, M and A at the check times of an imposed history v = 0.5 (t < 20),
// 5 (20 ≤ t < 30), 0 (t ≥ 30), from the stuck state, dt = 0.01, α = 2, N = 1000.
constexpr double kTimes[] = {5.0, 10.0, 19.9, 20.1, 20.5, 22.0, 25.0, 29.9, 30.1, 30.5, 31.0, 33.0, 40.0, 49.9};
constexpr int kChecks = sizeof(kTimes) / sizeof(kTimes[0]);
struct History {
  std::vector<double> age[kChecks], mass[kChecks], area[kChecks];
  bool always_overloaded = true;
};

template <class Law>
void run_history(Law& law, History& h) {
  const double dt = 0.01;
  const int steps = 5000;
  int next = 0;
  std::vector<double> buf(1);
  for (int n = 1; n <= steps; ++n) {
    const double t0 = (n - 1) * dt, t = n * dt;
    const double v = t0 < 19.9999 ? 0.5 : (t0 < 29.9999 ? 5.0 : 0.0);
    const double vv[1] = {v};
    const bool y = law.advance(dt, vv).any_yield;
    if (v != 0.0 && t0 > 1.0) h.always_overloaded &= y;  // yield at t ≈ 0.5
    if (next < kChecks && std::abs(t - kTimes[next]) < 1e-9) {
      law.mean_age(buf);
      h.age[next].push_back(buf[0]);
      h.area[next].push_back(law.contact_area()[0]);
      h.mass[next].push_back(buf[0] * law.contact_area()[0]);
      ++next;
    }
  }
}

core::InterfaceParams alpha2() {
  auto p = testing::paper_interface();
  p.alpha = 2.0;
  return p;
}

// Smallest two-sided p-value (times the number of tests: Bonferroni) of the agent against the continuum.
double agent_vs_continuum(double kappa_agent, std::uint64_t seed0, bool print) {
  const auto pc = alpha2();
  continuum::FrictionLaw cont(pc, 1);
  cont.track_ages(true);
  History hc;
  run_history(cont, hc);
  auto pa = pc;
  pa.kappa = kappa_agent;
  discrete::DiscreteParams dp;
  dp.contacts_per_site = 1000;
  dp.representation = "agent";
  History ha;
  for (int k = 0; k < 200; ++k) {
    dp.seed = seed0 + static_cast<std::uint64_t>(k);
    discrete::AgentLaw law(pa, dp, 1);
    law.track_ages(true);
    run_history(law, ha);
  }
  REQUIRE(ha.always_overloaded);  // precondition: Y = 1 whenever v ≠ 0
  REQUIRE(hc.always_overloaded);
  double zmax = 0.0;
  for (int j = 0; j < kChecks; ++j) {
    const auto a = testing::mean_se(ha.age[j]), m = testing::mean_se(ha.mass[j]), ar = testing::mean_se(ha.area[j]);
    // (at t = 49.9 every contact of every seed is attached, A = 1 exactly: no spread, no z)
    const double za = (a.mean - hc.age[j][0]) / a.se, zm = (m.mean - hc.mass[j][0]) / m.se,
                 zr = ar.se > 0.0 ? (ar.mean - hc.area[j][0]) / ar.se : 0.0;
    if (ar.se == 0.0) REQUIRE(std::abs(ar.mean - hc.area[j][0]) < 1e-6);
    if (print)
      std::printf("  t = %5.1f: age %.5f vs %.5f (z %+.2f), M z %+.2f, A %.5f vs %.5f (z %+.2f)\n", kTimes[j], a.mean,
                  hc.age[j][0], za, zm, ar.mean, hc.area[j][0], zr);
    zmax = std::max({zmax, std::abs(za), std::abs(zm), std::abs(zr)});
  }
  const boost::math::normal n01;
  const double p = 2.0 * boost::math::cdf(boost::math::complement(n01, zmax));
  std::printf("  agent kappa %g: largest |z| = %.2f over %d z-values\n", kappa_agent, zmax, 3 * kChecks);
  return std::min(1.0, p * 3.0 * kChecks);
}

}  // namespace

TEST_CASE("contact age: the agent's exact mean age agrees with the continuum's in 0D, and a wrong kappa is seen",
          "[age][agent]") {
  std::printf("agent vs continuum mean age (200 seeds, N = 1000):\n");
  const double p_ok = agent_vs_continuum(8.0, 1000, true);
  const double p_wrong = agent_vs_continuum(9.6, 2000, false);
  std::printf("agent vs continuum: Bonferroni p = %.3g (kappa right), %.3g (agent kappa x 1.2)\n", p_ok, p_wrong);
  CHECK(p_ok > 1e-3);
  CHECK(p_wrong < 1e-3);
}

TEST_CASE("contact age through the runner: 0D series/age and 1D snapshots/age for both models", "[age][runner]") {
  auto s = testing::imposed_rate_scene();
  s.models = {"continuum", "discrete"};
  s.interface.alpha = 2.0;
  s.drive.v = {0.5, 5.0};
  s.drive.v_times = {0.0, 5.0};
  s.time.t_end = 8.0;
  s.time.dt = 0.01;
  s.output.series_dt = 0.5;
  s.output.ages = true;
  s.discrete.representation = "agent";
  s.discrete.contacts_per_site = 100000;
  const auto r = compare::run_scene_alongside(s, compare::RunControl{});
  for (const auto& m : r.models) {
    REQUIRE(m.series.count("age"));
    const auto& t = m.series.at("t");
    const auto& age = m.series.at("age");
    // steady at v = 5 by t = 8 (relaxation rates ≥ κv = 40): ā = 1/(κv) = 0.025 (agent: N A = 2400
    // contacts, relative sd 2 %)
    CHECK(t.back() == Approx(8.0));
    CHECK(age.back() == Approx(0.025).epsilon(m.model == "continuum" ? 1e-9 : 0.1));
  }
  auto s1 = testing::fig1_scene();
  s1.bulk.length = 20.0;
  s1.grid.dx = 1.0;
  s1.time.t_end = 5.0;
  s1.models = {"continuum", "discrete"};
  s1.discrete.representation = "agent";
  s1.discrete.contacts_per_site = 10;
  for (const bool on : {false, true}) {
    s1.output.ages = on;
    const auto r1 = compare::run_scene_alongside(s1, compare::RunControl{});
    for (const auto& m : r1.models) {
      CHECK(m.snapshots.count("age") == (on ? 1u : 0u));
      if (on) CHECK(m.snapshots.at("age").size() == m.snapshots.at("A").size());
    }
  }
}
