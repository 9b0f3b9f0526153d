// Slow tier (label "slow"): larger-sample versions of the agent-representation checks.
//   - hierarchy item 3 with 1000 seeds per representation (0D imposed v, N = 50): agent vs naive and
//     agent vs count (w = 0), agent vs naive (uniform w = 0.3, fresh); the 10 % detach-rate error is
//     now seen at fixed times too;
//   - hierarchy item 5 pooled over 10 seeds (~2.5e5 lifetimes per κv): KS against Exp(κv) / Exp(1);
//   - the paper's fig1 scene (docs/model.md §4, L = 300, dx = 0.5, t_end = 140) with N = 100: agent vs count
//     over 12 seeds each on the instability time, the transient front speed and the arrest position.
// False-alarm rates as in the default tier: each KS at 1e-3, each mean at 4 SE.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compare/measure.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/count_law.hpp"
#include "discrete/naive_law.hpp"
#include "discrete_agent_helpers.hpp"
#include "scenes.hpp"

using namespace slipfront;
using testing::compare_0d;
using testing::ks_one_sample;
using testing::ks_two_sample;
using testing::run_0d;

namespace {

constexpr double ks_alpha = 1e-3;

discrete::DiscreteParams params(long n, const std::string& threshold = "delta", double width = 0.0) {
  discrete::DiscreteParams dp;
  dp.contacts_per_site = n;
  dp.threshold = threshold;
  dp.width = width;
  return dp;
}

void require_agree(const testing::Comparison& c) {
  for (std::size_t k = 0; k < c.ks.size(); ++k) {
    INFO(c.names[k] << ": KS D = " << c.ks[k].d << ", p = " << c.ks[k].p);
    CHECK(c.ks[k].p > ks_alpha);
  }
}

}  // namespace

TEST_CASE("slow: agent, naive and count agree over 1000 seeds (0D)", "[discrete][agent][slow]") {
  const auto ip = testing::paper_interface();
  const auto agent = run_0d<discrete::AgentLaw>(params(50), ip, 0.5, 1, 1000);
  const auto naive = run_0d<discrete::NaiveAgentLaw>(params(50), ip, 0.5, 100001, 1000);
  const auto count = run_0d<discrete::CountLaw>(params(50), ip, 0.5, 200001, 1000);
  require_agree(compare_0d(agent, naive, "slow 0D agent vs naive"));
  require_agree(compare_0d(agent, count, "slow 0D agent vs count"));
  const auto agent_w = run_0d<discrete::AgentLaw>(params(50, "uniform", 0.3), ip, 0.5, 1, 1000);
  const auto naive_w = run_0d<discrete::NaiveAgentLaw>(params(50, "uniform", 0.3), ip, 0.5, 100001, 1000);
  require_agree(compare_0d(agent_w, naive_w, "slow 0D agent vs naive, uniform w = 0.3"));
  // power at fixed times and in the steady state
  auto wrong = ip;
  wrong.kappa *= 1.1;
  const auto agent_wrong = run_0d<discrete::AgentLaw>(params(50), wrong, 0.5, 1, 1000);
  const auto c = compare_0d(agent_wrong, count, "slow 0D agent(kappa x 1.1) vs count");
  CHECK(c.ks[3].p < ks_alpha);  // σ(t = 5)
  CHECK(c.ks[6].p < ks_alpha);  // steady σ
  CHECK(c.ks[7].p < ks_alpha);  // steady A
}

TEST_CASE("slow: renewal statistics pooled over seeds", "[discrete][agent][slow]") {
  // As test_discrete_renewal (α = 2, κ = 8, η = 0.1, N = 1000, dt = 0.01, starts in [5, 40], run to
  // 65), pooled over 10 seeds.
  for (const double kv : {2.0, 8.0}) {
    std::vector<double> life, det;
    for (std::uint64_t seed = 1; seed <= 10; ++seed) {
      const core::InterfaceParams ip{2.0, 8.0, 0.1};
      auto dp = params(1000);
      dp.seed = seed;
      dp.contact_statistics = true;
      discrete::AgentLaw law(ip, dp, 1);
      law.set_site(0, 1.0 / (1.0 + kv), 2.0 / (1.0 + kv));
      const double v[1] = {kv / 8.0};
      for (int n = 0; n < 6500; ++n) REQUIRE(law.advance(0.01, v).any_yield);
      const auto& st = law.contact_stats();
      REQUIRE(st.lifetimes().size() == st.lifetime_count());
      for (std::size_t k = 0; k < st.lifetimes().size(); ++k)
        if (st.lifetime_starts()[k] >= 5.0 && st.lifetime_starts()[k] <= 40.0) life.push_back(st.lifetimes()[k]);
      for (std::size_t k = 0; k < st.detached_durations().size(); ++k)
        if (st.detached_starts()[k] >= 5.0 && st.detached_starts()[k] <= 40.0) det.push_back(st.detached_durations()[k]);
    }
    const auto ks_l = ks_one_sample(life, [kv](double x) { return x > 0 ? -std::expm1(-kv * x) : 0.0; });
    const auto ks_d = ks_one_sample(det, [](double x) { return x > 0 ? -std::expm1(-x) : 0.0; });
    const auto ml = testing::mean_se(life), md = testing::mean_se(det);
    std::printf("slow renewal kv=%g: lifetimes n=%zu KS D=%.5f p=%.3f mean %.5f (%.2f SE); detached n=%zu KS D=%.5f "
                "p=%.3f mean %.5f (%.2f SE)\n",
                kv, life.size(), ks_l.d, ks_l.p, ml.mean, (ml.mean - 1 / kv) / ml.se, det.size(), ks_d.d, ks_d.p, md.mean,
                (md.mean - 1) / md.se);
    CHECK(ks_l.p > ks_alpha);
    CHECK(ks_d.p > ks_alpha);
    CHECK(std::abs(ml.mean - 1.0 / kv) < 4.0 * ml.se);
    CHECK(std::abs(md.mean - 1.0) < 4.0 * md.se);
  }
}

TEST_CASE("slow: fig1 with N = 100, agent vs count over seeds", "[discrete][agent][slow]") {
  // docs/model.md §4 fig1 (testing::fig1_scene): edge loading, paper parameters, L = 300, dx = 0.5, cfl = 0.5,
  // t_end = 140.
  auto scene = [](const std::string& rep, std::uint64_t seed) {
    compare::Scene s = testing::fig1_scene();
    s.models = {"discrete"};
    s.output.series_dt = 0.5;
    s.output.snapshot_dt = 10.0;
    s.discrete = params(100);
    s.discrete.representation = rep;
    s.discrete.seed = seed;
    s.validate();
    return s;
  };
  std::vector<double> t_hat[2], c_tr[2], x_arr[2];
  const char* reps[2] = {"agent", "count"};
  for (int k = 0; k < 2; ++k)
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
      const auto r = compare::run_scene(scene(reps[k], seed + 1000 * static_cast<std::uint64_t>(k)), {}).at(0);
      REQUIRE(r.status == slipfront::compare::RunStatus::complete);
      t_hat[k].push_back(r.events.t_hat);
      c_tr[k].push_back(r.events.c_transient);
      x_arr[k].push_back(r.events.x_arrest);
    }
  for (int k = 0; k < 2; ++k)
    for (const auto* v : {&t_hat[k], &c_tr[k], &x_arr[k]})
      for (double x : *v) REQUIRE(std::isfinite(x));  // every run had its transient front
  const auto a = ks_two_sample(t_hat[0], t_hat[1]), b = ks_two_sample(c_tr[0], c_tr[1]), c = ks_two_sample(x_arr[0], x_arr[1]);
  const auto ma = testing::mean_se(t_hat[0]), mc = testing::mean_se(t_hat[1]);
  std::printf("slow fig1 N=100 agent vs count: t_hat %.2f±%.2f vs %.2f±%.2f KS D=%.3f p=%.3f; c_transient KS D=%.3f "
              "p=%.3f; x_arrest KS D=%.3f p=%.3f\n",
              ma.mean, ma.se, mc.mean, mc.se, a.d, a.p, b.d, b.p, c.d, c.p);
  CHECK(a.p > ks_alpha);
  CHECK(b.p > ks_alpha);
  CHECK(c.p > ks_alpha);
}
