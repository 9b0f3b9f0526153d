// discrete::CountLaw's watched step (advance_watched: a site near its threshold stepped event by event, its yield test
// after every count event; core/leap.hpp takes its accepted steps by it, docs/numerics.md §9.7), against the exact
// two-state chain of docs/model.md §2:
//   - at a yield state that cannot change over the step (τ far above s_0, or far below), the attached count after
//     one step follows the chain's transition law over dt: its distribution (chi-square), its mean and its variance
//     (z tests against the closed forms), each at a false-alarm rate of 1e-3, so ≤ 3e-3 per case, 6e-3 for both;
//   - where one attachment takes τ below s_0, detachment stops at that event: the mean count after the step is the
//     pure-attachment chain's, not the frozen-yield (binomial) step's (false alarm 1e-3; the two differ by 55 counts,
//     ~450 standard errors);
//   - where the law does not watch (bins > 1, the noise off, past the event cap), advance_watched is advance bit for bit.
// Fixed seeds: each run is deterministic.
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/exact_update.hpp"
#include "core/leap.hpp"
#include "discrete/count_law.hpp"
#include "scenes.hpp"

using namespace slipfront;
using discrete::CountLaw;
using discrete::DiscreteParams;

namespace {

const core::InterfaceParams paper = testing::paper_interface();
constexpr double kZ = 3.2905;  // two-sided normal quantile at 1e-3

DiscreteParams params(long n, unsigned seed) {
  DiscreteParams p;
  p.contacts_per_site = n;
  p.threshold = "delta";
  p.width = 0.0;
  p.seed = seed;
  return p;
}

// The pmf of Bin(n1, p1) + Bin(n2, p2).
std::vector<double> two_binomials(long n1, double p1, long n2, double p2) {
  const auto pmf = [](long n, double p) {
    std::vector<double> f(static_cast<std::size_t>(n) + 1, 0.0);
    const boost::math::binomial_distribution<double> b(static_cast<double>(n), p);
    for (long x = 0; x <= n; ++x) f[static_cast<std::size_t>(x)] = boost::math::pdf(b, static_cast<double>(x));
    return f;
  };
  const auto a = pmf(n1, p1), b = pmf(n2, p2);
  std::vector<double> c(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  return c;
}

// `trials` watched steps of site 0 from the same state (A, σ̄) at rate v over dt: the attached counts after each.
std::vector<double> watched_counts(CountLaw& law, double area, double sigma_bar, double v, double dt, int trials,
                                   double reach) {
  const double vv[1] = {v};
  law.set_site(0, area, sigma_bar);
  REQUIRE(law.watches(0, v, dt, reach));
  std::vector<double> out;
  for (int t = 0; t < trials; ++t) {
    law.set_site(0, area, sigma_bar);
    law.advance_watched(dt, vv, reach);
    out.push_back(law.attached_total(0));
  }
  return out;
}

// The counts against a pmf: chi-square (cells of expectation ≥ 5), mean and variance z tests (the variance's standard
// error from the pmf's fourth central moment), each at 1e-3.
void check_against_pmf(const std::vector<double>& counts, const std::vector<double>& pmf, const char* what) {
  const double trials = static_cast<double>(counts.size());
  double mu = 0.0, var = 0.0, m4 = 0.0;
  for (std::size_t x = 0; x < pmf.size(); ++x) mu += pmf[x] * static_cast<double>(x);
  for (std::size_t x = 0; x < pmf.size(); ++x) {
    const double d = static_cast<double>(x) - mu;
    var += pmf[x] * d * d;
    m4 += pmf[x] * d * d * d * d;
  }
  std::vector<double> hist(pmf.size(), 0.0);
  double mean = 0.0;
  for (double c : counts) {
    REQUIRE(c >= 0.0);
    REQUIRE(c < static_cast<double>(pmf.size()));
    hist[static_cast<std::size_t>(c)] += 1.0;
    mean += c / trials;
  }
  double s2 = 0.0;
  for (double c : counts) s2 += (c - mean) * (c - mean) / (trials - 1.0);
  double stat = 0.0, o = 0.0, e = 0.0;
  int cells = 0;
  for (std::size_t x = 0; x < pmf.size(); ++x) {
    o += hist[x];
    e += pmf[x] * trials;
    if (e >= 5.0 || x + 1 == pmf.size()) {
      stat += (o - e) * (o - e) / e;
      ++cells;
      o = e = 0.0;
    }
  }
  const double critical = boost::math::quantile(boost::math::complement(boost::math::chi_squared(cells - 1), 1e-3));
  const double z_mean = (mean - mu) / std::sqrt(var / trials), z_var = (s2 - var) / std::sqrt((m4 - var * var) / trials);
  std::printf("watched %-36s mean %.3f (exact %.3f, z %.2f), variance %.3f (exact %.3f, z %.2f), X2 %.1f (critical %.1f)\n",
              what, mean, mu, z_mean, s2, var, z_var, stat, critical);
  CHECK(std::abs(z_mean) < kZ);
  CHECK(std::abs(z_var) < kZ);
  CHECK(stat < critical);
}

// Two laws built alike, one stepped by advance and one by advance_watched: the same state and streams, bit for bit.
void check_unwatched(const core::InterfaceParams& ip, const DiscreteParams& p, double area, double sigma_bar,
                     std::vector<double> v, double dt) {
  CountLaw a(ip, p, v.size()), b(ip, p, v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    a.set_site(i, area, sigma_bar);
    b.set_site(i, area, sigma_bar);
    CHECK_FALSE(b.watches(i, v[i], dt, 1e9));
  }
  for (int k = 0; k < 20; ++k) {
    const bool ya = a.advance(dt, v).any_yield, yb = b.advance_watched(dt, v, 1e9).any_yield;
    CHECK(ya == yb);
  }
  CHECK(a.save_state() == b.save_state());
}

}  // namespace

TEST_CASE("watched count step at a fixed yield state is the exact two-state chain", "[discrete][count][watched]") {
  // N = 40, A = 0.5 (20 attached), 20000 steps from the same state; a large reach, so that the site is watched far from
  // s_0 too (the cap: N (1 + κv) dt ≤ 18 here).
  const int trials = 20000;
  const double reach = 1e3, v = 1.0;
  SECTION("overloaded throughout: n' ~ Bin(20, P(att→att)) + Bin(20, P(det→att)), d = κv") {
    // σ̄ = 2: σ̄ ≥ 2 e^{−v dt} > 1.9 over the step, so τ = (σ̄ + ηv) N/n > 2 at every count n ≤ N
    const double dt = 0.05;
    CountLaw law(paper, params(40, 7), 1);
    const auto tr = core::two_state_transition(1.0, paper.kappa * v, dt);
    check_against_pmf(watched_counts(law, 0.5, 2.0, v, dt, trials, reach),
                      two_binomials(20, tr.stay_attached, 20, tr.become_attached), "overloaded, d = 8, dt = 0.05");
  }
  SECTION("stuck throughout: n' − 20 ~ Bin(20, P(det→att)), d = 0") {
    // σ̄ = 0: no detachment, so A only grows and σ̄ ≤ α v A t: τ ≤ α v dt + ηv/A_0 = 0.725 < 1 over the step
    const double dt = 0.5;
    CountLaw law(paper, params(40, 8), 1);
    const auto tr = core::two_state_transition(1.0, 0.0, dt);
    auto pmf = two_binomials(20, 1.0, 20, tr.become_attached);
    check_against_pmf(watched_counts(law, 0.5, 0.0, v, dt, trials, reach), pmf, "stuck, dt = 0.5");
  }
}

TEST_CASE("watched count step stops detaching at the event that takes tau below the threshold",
          "[discrete][count][watched]") {
  // N = 1000, n = 500, σ̄ + ηv = 0.5005: τ = 1.001 overloaded, and one attachment (n = 501) takes it to 0.999. At
  // v = 0.01 (detach rate κv = 0.08 per contact, 40 in all, against 500 attachments) the first event is an attachment
  // with probability 0.93, and from there on the site is stuck: n only grows (σ̄ grows by ≤ αv = 0.0105 per unit time,
  // n by ~500: τ falls). Over dt = 2 the watched step is the pure-attachment chain from n = 500,
  //   E n' = 500 + 500 (1 − e^{−dt}) = 932.3 (sd 7.6; the few detachments before the crossing lower it by ~0.01),
  // where the binomial step, its yield state frozen at the start, keeps detaching: E n' = 500 P(att→att) + 500
  // P(det→att) = 876.8 at d = 0.08. The leap's own reach (core::LeapSimulation::kNoiseReach) watches this site.
  const double v = 0.01, dt = 2.0, area = 0.5, sigma_bar = 0.5005 - paper.eta * v;
  const double reach = core::LeapSimulation<CountLaw>::kNoiseReach / std::sqrt(1000.0);
  const int trials = 4000;
  CountLaw law(paper, params(1000, 11), 1);
  law.set_site(0, area, sigma_bar);
  REQUIRE(law.overloaded_fraction(0, v) == 1.0);
  const auto counts = watched_counts(law, area, sigma_bar, v, dt, trials, reach);
  double mean = 0.0;
  for (double c : counts) mean += c / trials;
  const double p_free = 1.0 - std::exp(-dt), watched = 500.0 + 500.0 * p_free;
  const double se = std::sqrt(500.0 * p_free * (1.0 - p_free) / trials);
  const auto tr = core::two_state_transition(1.0, paper.kappa * v, dt);
  const double frozen = 500.0 * tr.stay_attached + 500.0 * tr.become_attached;
  std::printf("watched crossing: mean n' %.2f, pure attachment %.2f (se %.3f), frozen yield %.2f\n", mean, watched, se,
              frozen);
  CHECK(std::abs(mean - watched) < kZ * se + 0.02);  // (+0.02: the detachments before the crossing, ~0.01)
  CHECK(frozen < watched - 100.0 * se);              // the two hypotheses apart: the check can tell them
  // and the binomial step of the same state (advance) is the frozen one
  const double vv[1] = {v};
  double binomial_mean = 0.0;
  for (int t = 0; t < trials; ++t) {
    law.set_site(0, area, sigma_bar);
    law.advance(dt, vv);
    binomial_mean += law.attached_total(0) / trials;
  }
  const double se_frozen = std::sqrt((500.0 * tr.stay_attached * (1.0 - tr.stay_attached) +
                                      500.0 * tr.become_attached * (1.0 - tr.become_attached)) / trials);
  CHECK(std::abs(binomial_mean - frozen) < kZ * se_frozen);  // (false alarm 1e-3 more)
  CHECK(binomial_mean < watched - 100.0 * se);
}

TEST_CASE("watched count step is the binomial step bit for bit where the law does not watch",
          "[discrete][count][watched]") {
  // Sliding sites (τ = 1.02, A = 0.8) at rates around the fig1 slow front, 20 steps of 0.01: states and streams equal.
  const double area = 0.8, sigma_bar = 1.02 * area - 0.1 * paper.eta, dt = 0.01;
  const std::vector<double> v = {0.1, 0.12, 0.08, 0.1};
  SECTION("binned thresholds (w = 0.2, 4 bins)") {
    auto p = params(1000, 3);
    p.threshold = "uniform";
    p.width = 0.2;
    p.bins = 4;
    check_unwatched(paper, p, area, sigma_bar, v, dt);
  }
  SECTION("quenched renewal") {
    auto p = params(1000, 4);
    p.renewal = "quenched";
    check_unwatched(paper, p, area, sigma_bar, v, dt);
  }
  SECTION("noise off") {
    auto p = params(1000, 5);
    p.noise = false;
    check_unwatched(paper, p, area, sigma_bar, v, dt);
  }
  SECTION("past the event cap: N (1 + κv) dt > kWatchCap") {
    const double n = std::ceil(CountLaw::kWatchCap / ((1.0 + paper.kappa * 0.08) * dt)) + 1.0;
    check_unwatched(paper, params(static_cast<long>(n), 6), area, sigma_bar, v, dt);
  }
}
