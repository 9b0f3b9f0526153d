// The agent representation of the microcontact ensemble (discrete/agent_law.hpp), docs/model.md §2:
//   - one step: the end-of-step state of every contact has the exact two_state_transition()
//     probabilities (the event-driven chain inside the step is exact), w = 0 and w > 0;
//   - hierarchy item 3: agent, naive (every contact every step) and count representations sample the
//     same process — two-sample KS tests over seeds on A and σ at fixed times, on the steady friction
//     (0D imposed v) and on a short 1D edge-loading run; and the same test DOES see a 10 % error in
//     the detach rate (power);
//   - cost: idle contacts are not touched (a stuck site draws no random number);
//   - reproducibility: same seed, bit-identical; a site's history does not depend on the others;
//   - contact statistics reach the runner's ModelResult.
// False-alarm rates: each two-sample KS at 1e-3 (asymptotic p-value; conservative for the discrete
// values of A = n/N), each mean check at 4 SE (6e-5). The seeds are fixed, so the outcome is too.
// Independent samples: the two representations compared use disjoint seed ranges.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/params.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/count_law.hpp"
#include "discrete/naive_law.hpp"
#include "discrete_agent_helpers.hpp"
#include "scenes.hpp"

using namespace slipfront;
using testing::compare_0d;
using testing::Comparison;
using testing::ks_two_sample;
using testing::paper_interface;
using testing::run_0d;

namespace {

constexpr double ks_alpha = 1e-3;

discrete::DiscreteParams discrete_params(long n, std::uint64_t seed, const std::string& threshold = "delta",
                                         double width = 0.0, const std::string& renewal = "fresh") {
  discrete::DiscreteParams dp;
  dp.contacts_per_site = n;
  dp.threshold = threshold;
  dp.width = width;
  dp.renewal = renewal;
  dp.seed = seed;
  return dp;
}

// ---- one step ----------------------------------------------------------------------------------

// One step of length dt at slip rate v from (A, σ̄): the attached fraction after the step, and its
// expectation from the exact two-state transition for every contact. g is the threshold CDF (a
// contact is overloaded when s < τ, i.e. with probability G(τ)).
template <class Law>
void check_one_step(const discrete::DiscreteParams& dp, double area, double sigma_bar, double v, double dt) {
  const auto ip = paper_interface();
  Law law(ip, dp, 1);
  law.set_site(0, area, sigma_bar);
  const double n = static_cast<double>(dp.contacts_per_site);
  const double n_att = std::round(area * n);
  const double tau = core::contact_stress(sigma_bar + ip.eta * v, n_att / n);
  const discrete::ThresholdDistribution g(dp.threshold, dp.width);
  const double over = g.degenerate() ? (tau > 1.0 ? 1.0 : 0.0) : g.cdf(tau);
  const auto tr_over = core::two_state_transition(1.0, ip.kappa * std::abs(v), dt);
  const auto tr_free = core::two_state_transition(1.0, 0.0, dt);
  const double expected = n_att * (over * tr_over.stay_attached + (1.0 - over) * tr_free.stay_attached) +
                          (n - n_att) * (over * tr_over.become_attached + (1.0 - over) * tr_free.become_attached);
  const double v1[1] = {v};
  law.advance(dt, v1);
  const double got = law.contact_area()[0] * n;
  const double se = std::sqrt(n * 0.25);  // a sum of N independent Bernoulli variables: var ≤ N/4
  INFO("A = " << area << ", sigma_bar = " << sigma_bar << ", tau = " << tau << ", P(overloaded) = " << over
              << ": attached after the step " << got << ", expected " << expected << " ± " << se);
  CHECK(std::abs(got - expected) < 4.0 * se);
}

template <class Law>
void check_one_step_all(long n) {
  // w = 0: overloaded (τ = 2.05), all detached (τ = ∞), not overloaded (τ = 0.25); κ v Δt = 1
  check_one_step<Law>(discrete_params(n, 5), 1.0, 2.0, 0.25, 0.5);
  check_one_step<Law>(discrete_params(n, 6), 0.0, 0.0, 0.25, 0.5);
  check_one_step<Law>(discrete_params(n, 7), 0.5, 0.1, 0.25, 0.5);
  check_one_step<Law>(discrete_params(n, 8), 0.3, 1.0, 2.0, 0.2);  // r Δt = 3.4: several re-attachments
  // w = 0.3 (uniform, fresh and quenched): τ = 1 exactly, half of the thresholds below it
  check_one_step<Law>(discrete_params(n, 9, "uniform", 0.3), 0.5, 0.475, 0.25, 0.5);
  check_one_step<Law>(discrete_params(n, 10, "uniform", 0.3, "quenched"), 0.5, 0.475, 0.25, 0.5);
  check_one_step<Law>(discrete_params(n, 11, "gaussian", 0.2), 0.4, 0.38, 0.25, 0.3);
}

void require_agree(const Comparison& c) {
  for (std::size_t k = 0; k < c.ks.size(); ++k) {
    INFO(c.names[k] << ": KS D = " << c.ks[k].d << ", p = " << c.ks[k].p);
    CHECK(c.ks[k].p > ks_alpha);
  }
}

// ---- 1D edge loading, short --------------------------------------------------------------------

// Edge loading on a short bar (testing::fig1_scene with L = 20, dx = 1, v_d = 1, t_end = 20): paper
// interface and bulk (ρ = 0.01, μ = 300), K = 2.5, cfl 0.5: first yield at t = 6.5, instability near
// t = 9, then slip over the whole bar and re-sticking; N = 50 contacts per site.
compare::Scene edge_short(const std::string& representation, std::uint64_t seed) {
  compare::Scene s = testing::fig1_scene();
  s.name = "edge_short";
  s.models = {"discrete"};
  s.bulk.length = 20.0;
  s.drive.v_d = 1.0;
  s.grid.dx = 1.0;
  s.time.t_end = 20.0;
  s.output.series_dt = 0.1;
  s.discrete = discrete_params(50, seed);
  s.discrete.representation = representation;
  return s;
}

struct Sample1D {
  std::vector<double> t_hat, force_end, mean_area[3];  // mean over x of A at t = 8, 14, 20
};

Sample1D run_1d(const std::string& representation, std::uint64_t seed0, int seeds) {
  Sample1D out;
  for (int k = 0; k < seeds; ++k) {
    const auto s = edge_short(representation, seed0 + static_cast<std::uint64_t>(k));
    s.validate();
    const auto r = compare::run_scene(s, {}).at(0);
    REQUIRE(r.status == slipfront::compare::RunStatus::complete);
    out.t_hat.push_back(r.events.t_hat);
    out.force_end.push_back(r.series.at("drive_force").back());
    const std::size_t nx = r.x.size();
    const double times[3] = {8.0, 14.0, 20.0};
    for (int j = 0; j < 3; ++j) {
      std::size_t best = 0;
      for (std::size_t m = 0; m < r.snapshot_t.size(); ++m)
        if (std::abs(r.snapshot_t[m] - times[j]) < std::abs(r.snapshot_t[best] - times[j])) best = m;
      double sum = 0.0;
      for (std::size_t i = 0; i < nx; ++i) sum += r.snapshots.at("A")[best * nx + i];
      out.mean_area[j].push_back(sum / static_cast<double>(nx));
    }
  }
  return out;
}

Comparison compare_1d(const Sample1D& a, const Sample1D& b, const char* label) {
  Comparison c;
  c.names = {"t_hat", "F(t=20)", "mean A(t=8)", "mean A(t=14)", "mean A(t=20)"};
  c.ks = {ks_two_sample(a.t_hat, b.t_hat), ks_two_sample(a.force_end, b.force_end),
          ks_two_sample(a.mean_area[0], b.mean_area[0]), ks_two_sample(a.mean_area[1], b.mean_area[1]),
          ks_two_sample(a.mean_area[2], b.mean_area[2])};
  std::printf("%s:", label);
  for (std::size_t k = 0; k < c.ks.size(); ++k) std::printf(" %s D=%.3f p=%.2g;", c.names[k].c_str(), c.ks[k].d, c.ks[k].p);
  std::printf("\n");
  return c;
}

}  // namespace

TEST_CASE("agent: one step has the exact two-state transition probabilities", "[discrete][agent]") {
  // N = 200000 contacts on one site: the attached count after one step within 4 SE of its mean.
  check_one_step_all<discrete::AgentLaw>(200000);
}

TEST_CASE("naive agent: one step has the exact two-state transition probabilities", "[discrete][agent]") {
  check_one_step_all<discrete::NaiveAgentLaw>(200000);
}

TEST_CASE("agent and naive sample the same process: 0D imposed v, w = 0", "[discrete][agent]") {
  // N = 50, paper interface, v = 0.5 (κv = 4) from the stuck state; 100 seeds each.
  const auto ip = paper_interface();
  const auto base = discrete_params(50, 0);
  const auto agent = run_0d<discrete::AgentLaw>(base, ip, 0.5, 1, 100);
  const auto naive = run_0d<discrete::NaiveAgentLaw>(base, ip, 0.5, 1001, 100);
  require_agree(compare_0d(agent, naive, "0D agent vs naive"));
}

TEST_CASE("agent and count sample the same process: 0D imposed v, w = 0", "[discrete][agent]") {
  const auto ip = paper_interface();
  const auto base = discrete_params(50, 0);
  const auto agent = run_0d<discrete::AgentLaw>(base, ip, 0.5, 1, 100);
  const auto count = run_0d<discrete::CountLaw>(base, ip, 0.5, 2001, 100);
  require_agree(compare_0d(agent, count, "0D agent vs count"));
}

TEST_CASE("agent power: the same test sees a 10% error in the detach rate", "[discrete][agent]") {
  // The agent run with κ·1.1 against the count representation with κ: the steady friction and the
  // steady area must be rejected at the same 1e-3 level (else the agreement above proves little).
  auto wrong = paper_interface();
  wrong.kappa *= 1.1;
  const auto base = discrete_params(50, 0);
  const auto agent = run_0d<discrete::AgentLaw>(base, wrong, 0.5, 1, 100);
  const auto count = run_0d<discrete::CountLaw>(base, paper_interface(), 0.5, 2001, 100);
  const auto c = compare_0d(agent, count, "0D agent(kappa x 1.1) vs count");
  CHECK(c.ks[6].p < ks_alpha);  // steady sigma
  CHECK(c.ks[7].p < ks_alpha);  // steady A
}

TEST_CASE("agent and naive sample the same process: 0D imposed v, w > 0", "[discrete][agent]") {
  // Thresholds uniform with w = 0.3, fresh and quenched (continuous g in both laws; the count
  // representation, which bins g, is compared at w = 0 only). 100 seeds each.
  const auto ip = paper_interface();
  for (const char* renewal : {"fresh", "quenched"}) {
    const auto base = discrete_params(50, 0, "uniform", 0.3, renewal);
    const auto agent = run_0d<discrete::AgentLaw>(base, ip, 0.5, 1, 100);
    const auto naive = run_0d<discrete::NaiveAgentLaw>(base, ip, 0.5, 1001, 100);
    const std::string label = std::string("0D agent vs naive, uniform w = 0.3, ") + renewal;
    require_agree(compare_0d(agent, naive, label.c_str()));
  }
}

TEST_CASE("agent, count and naive sample the same process: 1D edge loading", "[discrete][agent]") {
  // 40 seeds each; observables: instability time t^, F at t_end, mean A over x at three times.
  const auto agent = run_1d("agent", 1, 40);
  const auto count = run_1d("count", 2001, 40);
  const auto naive = run_1d("naive", 1001, 40);
  require_agree(compare_1d(agent, count, "1D agent vs count"));
  require_agree(compare_1d(agent, naive, "1D agent vs naive"));
}

TEST_CASE("agent: idle contacts are not touched", "[discrete][agent]") {
  // Stuck sites (τ < every threshold): no state change, no random number drawn — the engines are
  // exactly where set_site left them after 1000 steps. Site 1 slips slowly but is not overloaded.
  const auto ip = paper_interface();
  for (const auto& dp : {discrete_params(1000, 3), discrete_params(1000, 3, "uniform", 0.3)}) {
    discrete::AgentLaw law(ip, dp, 3);
    for (std::size_t i = 0; i < 3; ++i) law.set_site(i, 1.0, 0.3);  // τ ≤ 0.3 + η·0.01 < 1 − √3·0.3
    std::vector<discrete::Engine> before;
    for (std::size_t i = 0; i < 3; ++i) before.push_back(law.engine(i));
    const double v[3] = {0.0, 0.01, 0.0};
    for (int n = 0; n < 1000; ++n) CHECK_FALSE(law.advance(1e-3, v).any_yield);
    CHECK(law.state_changes() == 0);
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(law.engine(i) == before[i]);
      CHECK(law.contact_area()[i] == 1.0);
    }
  }
  // Stuck with A = 1 and w = 0: not a single draw since construction.
  discrete::AgentLaw law(ip, discrete_params(1000, 3), 1);
  const double v[1] = {0.0};
  for (int n = 0; n < 100; ++n) law.advance(1e-3, v);
  CHECK(law.engine(0) == discrete::site_engine(3, 0));
}

TEST_CASE("agent: same seed bit-identical, and a site does not depend on the others", "[discrete][agent]") {
  const auto s = edge_short("agent", 17);
  const auto r1 = compare::run_scene(s, {}).at(0);
  const auto r2 = compare::run_scene(s, {}).at(0);
  CHECK(r1.snapshots.at("A") == r2.snapshots.at("A"));
  CHECK(r1.snapshots.at("sigma_bar") == r2.snapshots.at("sigma_bar"));
  CHECK(r1.series.at("drive_force") == r2.series.at("drive_force"));
  auto s3 = s;
  s3.discrete.seed = 18;
  CHECK(compare::run_scene(s3, {}).at(0).snapshots.at("A") != r1.snapshots.at("A"));

  // Site 0 of a 3-site law and the only site of a 1-site law, same seed and v history: identical.
  const auto ip = paper_interface();
  for (const auto& dp : {discrete_params(200, 5), discrete_params(200, 5, "weibull", 0.4, "quenched")}) {
    discrete::AgentLaw one(ip, dp, 1), three(ip, dp, 3);
    for (int n = 0; n < 3000; ++n) {
      const double v0 = 0.5 + 0.4 * std::sin(0.01 * n);
      const double v1[1] = {v0}, v3[3] = {v0, 2.0, 0.0};
      one.advance(0.01, v1);
      three.advance(0.01, v3);
    }
    CHECK(one.contact_area()[0] == three.contact_area()[0]);
    CHECK(one.sigma_bar()[0] == three.sigma_bar()[0]);
    CHECK(one.engine(0) == three.engine(0));
  }
}

TEST_CASE("agent: set_site", "[discrete][agent]") {
  const auto ip = paper_interface();
  discrete::AgentLaw law(ip, discrete_params(1001, 2, "gaussian", 0.2), 2);
  law.set_site(1, 0.3, 0.4);
  CHECK(law.attached_count(1) == 300);  // round(0.3 · 1001) = round(300.3)
  CHECK(law.contact_area()[1] == Approx(300.0 / 1001.0));
  CHECK(law.sigma_bar()[1] == 0.4);
  double sum = 0.0, n = 0.0;
  law.for_each_attached(1, [&](const discrete::AttachedContact& c) {
    CHECK(c.attached_at == law.time());  // age 0
    sum += c.threshold;
    n += 1.0;
  });
  // mean of 300 thresholds from g (mean 1, sd 0.2): within 4 SE
  CHECK(std::abs(sum / n - 1.0) < 4.0 * 0.2 / std::sqrt(n));
  std::size_t detached = 0;
  law.for_each_detached(1, [&](const discrete::DetachedContact& c) {
    CHECK(c.detached_at == law.time());
    ++detached;
  });
  CHECK(detached == 701);
  CHECK_THROWS_AS(law.set_site(0, 1.5, 0.0), std::invalid_argument);
  auto dp = discrete_params(10, 1);
  dp.noise = false;
  CHECK_THROWS_AS(discrete::AgentLaw(ip, dp, 1), core::ParamError);
  CHECK_THROWS_AS(discrete::NaiveAgentLaw(ip, dp, 1), core::ParamError);
}

TEST_CASE("agent: contact statistics reach the run's result", "[discrete][agent]") {
  // 0D imposed v = 0.5 for 20 time units with snapshots every 1: the tables the writer stores under
  // /discrete/contacts, consistent with each other.
  compare::Scene s = testing::imposed_rate_scene();
  s.name = "contacts";
  s.models = {"discrete"};
  s.drive.v = {0.5};
  s.drive.v_times = {0.0};
  s.time.t_end = 20.0;
  s.time.dt = 0.01;
  s.output.snapshot_dt = 1.0;
  s.discrete = discrete_params(500, 4);
  s.discrete.representation = "agent";
  s.discrete.contact_statistics = true;
  s.validate();
  const auto r = compare::run_scene(s, {}).at(0);
  REQUIRE(r.status == slipfront::compare::RunStatus::complete);
  for (const char* name : {"lifetime_hist_edges", "lifetime_hist_counts", "lifetimes", "detached_hist_counts",
                           "age_hist_edges", "threshold_hist_edges", "snapshot_t", "lifetime_total"})
    CHECK(r.contacts.count(name) == 1);
  const auto& snap_t = r.contacts.at("snapshot_t");
  CHECK(snap_t.size() == 21);  // t = 0, 1, ..., 20
  const auto& ages = r.contacts_2d.at("age_hist_counts");
  const auto& det = r.contacts_2d.at("detachments_per_site");
  CHECK(ages.cols == r.contacts.at("age_hist_edges").size() - 1);
  CHECK(ages.data.size() == snap_t.size() * ages.cols);
  CHECK(det.cols == 1);
  CHECK(det.data.size() == snap_t.size());
  // every attached contact is in the age histogram; the last snapshot is the end state
  double last_row = 0.0;
  for (std::size_t b = 0; b < ages.cols; ++b) last_row += ages.data[(snap_t.size() - 1) * ages.cols + b];
  CHECK(last_row == Approx(r.series.at("A").back() * 500.0));
  double first_row = 0.0;
  for (std::size_t b = 0; b < ages.cols; ++b) first_row += ages.data[b];
  CHECK(first_row == 500.0);  // stuck start: all attached
  // detachments per interval add up to the completed lifetimes
  double total = 0.0;
  for (double x : det.data) total += x;
  CHECK(total == r.contacts.at("lifetime_total")[0]);
  double hist = 0.0;
  for (double x : r.contacts.at("lifetime_hist_counts")) hist += x;
  CHECK(hist == total);
  CHECK(r.contacts.at("lifetimes").size() == static_cast<std::size_t>(total));
  // without contact_statistics nothing is stored
  s.discrete.contact_statistics = false;
  CHECK(compare::run_scene(s, {}).at(0).contacts.empty());

  // 1D (run_dynamic): one contact snapshot per field snapshot, one column per node
  auto s1 = edge_short("agent", 5);
  s1.discrete.contact_statistics = true;
  const auto r1 = compare::run_scene(s1, {}).at(0);
  REQUIRE(r1.status == slipfront::compare::RunStatus::complete);
  CHECK(r1.contacts.at("snapshot_t") == r1.snapshot_t);
  const auto& det1 = r1.contacts_2d.at("detachments_per_site");
  CHECK(det1.cols == r1.x.size());
  CHECK(det1.data.size() == r1.snapshot_t.size() * r1.x.size());
  double total1 = 0.0;
  for (double x : det1.data) total1 += x;
  CHECK(total1 > 0.0);
  CHECK(total1 <= r1.contacts.at("lifetime_total")[0]);  // detachments after the last snapshot are not in a row
}
