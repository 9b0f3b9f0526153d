// docs/model.md §2 hierarchy item 5: contact statistics of the agent representation against renewal theory,
// in steady sliding at imposed v with w = 0 (one site, N = 1000 contacts):
//   lifetimes of completed attachments ~ Exp(κv), detached durations ~ Exp(1),
//   time-averaged A = 1/(1+κv) (and σ̄ = α A), ages of attached contacts ~ Exp(κv).
//
// Conditions. Renewal theory needs every attached contact overloaded at all times (Y = 1): the test
// uses α = 2 (κ = 8, η = 0.1), for which τ = σ̄/A + ηv/A ≈ α stays far above 1, and asserts Y = 1
// (any_yield with w = 0) at every step. The agent simulates each contact's chain in continuous time
// with the rates frozen per step; with v constant and Y = 1 the rates never change, so there is no
// O(Δt) error at all: Δt = 0.01 is used (any Δt would do; the naive law would be O(Δt)).
//
// Samples. Only attachments (detached periods) that start in [t_b, t_e] = [5, 40] are used, and the
// run continues to t_e + 25, so that every one of them is complete (P(censored) ≤ e^{−25}); contacts
// are independent given constant rates, so the samples are i.i.d. Ages are pooled over snapshots
// 5 time units apart (a contact attached at two of them: P ≤ e^{−5κv} ≤ e^{−10}).
//
// False-alarm rates (for a correct implementation and a random seed; the seeds here are fixed):
// each KS test at 1e-3 (asymptotic p-value), each mean within 4 SE (6e-5).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "compare/measure.hpp"
#include "core/params.hpp"
#include "discrete/agent_law.hpp"
#include "discrete_agent_helpers.hpp"

using namespace slipfront;
using testing::ks_one_sample;
using testing::mean_se;

namespace {

struct RenewalRun {
  std::vector<double> lifetimes, detached, ages;
  double area_mean = 0, area_se = 0, sb_mean = 0, sb_se = 0;
  bool always_overloaded = true;
};

RenewalRun run_steady(double kappa_v, std::uint64_t seed) {
  core::InterfaceParams ip;
  ip.alpha = 2.0;
  ip.kappa = 8.0;
  ip.eta = 0.1;
  discrete::DiscreteParams dp;
  dp.contacts_per_site = 1000;
  dp.representation = "agent";
  dp.contact_statistics = true;
  dp.seed = seed;
  const double v = kappa_v / ip.kappa, a_ss = 1.0 / (1.0 + kappa_v);
  discrete::AgentLaw law(ip, dp, 1);
  law.set_site(0, a_ss, ip.alpha * a_ss);

  const double dt = 0.01, t_b = 5.0, t_e = 40.0, t_end = t_e + 25.0;
  const auto steps = static_cast<int>(std::lround(t_end / dt));
  compare::BatchMeans area(t_b, t_e, 20), sb(t_b, t_e, 20);
  RenewalRun r;
  const double vv[1] = {v};
  double next_snapshot = 10.0;
  for (int n = 0; n < steps; ++n) {
    const double t0 = n * dt, t1 = (n + 1) * dt;
    r.always_overloaded &= law.advance(dt, vv).any_yield;
    if (t1 <= t_e + 1e-9) {
      area.add(t0, t1, law.contact_area()[0]);
      sb.add(t0, t1, law.sigma_bar()[0]);
    }
    if (t1 >= next_snapshot - 1e-9 && next_snapshot <= t_e) {
      law.for_each_attached(0, [&](const discrete::AttachedContact& c) { r.ages.push_back(law.time() - c.attached_at); });
      next_snapshot += 5.0;
    }
  }
  const auto& st = law.contact_stats();
  REQUIRE(st.lifetimes().size() == st.lifetime_count());  // raw values kept (below the cap)
  REQUIRE(st.detached_durations().size() == st.detached_count());
  for (std::size_t k = 0; k < st.lifetimes().size(); ++k)
    if (st.lifetime_starts()[k] >= t_b && st.lifetime_starts()[k] <= t_e) r.lifetimes.push_back(st.lifetimes()[k]);
  for (std::size_t k = 0; k < st.detached_durations().size(); ++k)
    if (st.detached_starts()[k] >= t_b && st.detached_starts()[k] <= t_e) r.detached.push_back(st.detached_durations()[k]);
  r.area_mean = area.mean();
  r.area_se = area.stderr_of_mean();
  r.sb_mean = sb.mean();
  r.sb_se = sb.stderr_of_mean();
  return r;
}

void check_renewal(double kappa_v, std::uint64_t seed) {
  const RenewalRun r = run_steady(kappa_v, seed);
  REQUIRE(r.always_overloaded);  // precondition of renewal theory: Y = 1 throughout
  const double d = kappa_v;
  auto exp_cdf = [](double rate) { return [rate](double x) { return x > 0 ? -std::expm1(-rate * x) : 0.0; }; };

  const auto ks_life = ks_one_sample(r.lifetimes, exp_cdf(d));
  const auto ks_det = ks_one_sample(r.detached, exp_cdf(1.0));
  const auto ks_age = ks_one_sample(r.ages, exp_cdf(d));
  const auto life = mean_se(r.lifetimes), det = mean_se(r.detached);
  std::printf("renewal kv=%g: lifetimes n=%zu mean=%.5f (1/kv=%.5f, se %.1e) KS D=%.4f p=%.3f | detached n=%zu "
              "mean=%.5f (se %.1e) KS D=%.4f p=%.3f | ages n=%zu KS D=%.4f p=%.3f | A=%.5f±%.1e (%.5f) "
              "sigma_bar=%.5f±%.1e (%.5f)\n",
              kappa_v, r.lifetimes.size(), life.mean, 1.0 / d, life.se, ks_life.d, ks_life.p, r.detached.size(), det.mean,
              det.se, ks_det.d, ks_det.p, r.ages.size(), ks_age.d, ks_age.p, r.area_mean, r.area_se, 1.0 / (1.0 + d),
              r.sb_mean, r.sb_se, 2.0 / (1.0 + d));

  CHECK(r.lifetimes.size() > 10000);
  CHECK(ks_life.p > 1e-3);
  CHECK(std::abs(life.mean - 1.0 / d) < 4.0 * life.se);
  CHECK(ks_det.p > 1e-3);
  CHECK(std::abs(det.mean - 1.0) < 4.0 * det.se);
  CHECK(r.ages.size() > 500);
  CHECK(ks_age.p > 1e-3);
  CHECK(std::abs(r.area_mean - 1.0 / (1.0 + d)) < 4.0 * r.area_se);
  CHECK(std::abs(r.sb_mean - 2.0 / (1.0 + d)) < 4.0 * r.sb_se);  // σ̄_ss = α A_ss (linear in A)
}

}  // namespace

TEST_CASE("renewal: agent contact statistics in steady sliding, kappa v = 2", "[discrete][agent][renewal]") {
  check_renewal(2.0, 11);
}

TEST_CASE("renewal: agent contact statistics in steady sliding, kappa v = 8", "[discrete][agent][renewal]") {
  check_renewal(8.0, 12);
}

// Power of the same checks: the statistics of a chain with the wrong detach rate (κv·1.1 reported
// against the theory for κv) are rejected. If this fails, the KS tests above could not see a 10 %
// error in the detach rate, and their passing would mean little.
TEST_CASE("renewal: a 10% error in the detach rate is detected", "[discrete][agent][renewal]") {
  const RenewalRun r = run_steady(2.2, 13);
  auto exp_cdf = [](double x) { return x > 0 ? -std::expm1(-2.0 * x) : 0.0; };
  const auto ks = ks_one_sample(r.lifetimes, exp_cdf);
  const auto life = mean_se(r.lifetimes);
  std::printf("renewal power: kv=2.2 tested as 2: KS D=%.4f p=%.2e, mean %.5f vs 0.5 (%.1f SE)\n", ks.d, ks.p, life.mean,
              (life.mean - 0.5) / life.se);
  CHECK(ks.p < 1e-3);
  CHECK(std::abs(life.mean - 0.5) > 4.0 * life.se);
  CHECK(std::abs(r.area_mean - 1.0 / 3.0) > 4.0 * r.area_se);
}
