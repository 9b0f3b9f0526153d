// discrete::CountLaw (docs/model.md §2, count representation): one-step transition laws against the exact
// two-state probabilities, the noise-off closed forms, draws only where needed, reproducible random
// streams, parameter checks, and the mean-field steady state at imposed v.
//
// Statistical tests use fixed seeds (so each run is deterministic) and are sized so that, for a
// correct implementation, the chance that a fresh seed fails them is the stated false-alarm rate.
#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/random/binomial_distribution.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/exact_update.hpp"
#include "continuum/friction_law.hpp"
#include "discrete/binomial.hpp"
#include "discrete/count_law.hpp"
#include "discrete_agent_helpers.hpp"
#include "discrete/streams.hpp"
#include "scenes.hpp"

using namespace slipfront;
using discrete::CountLaw;
using discrete::DiscreteParams;

namespace {

const core::InterfaceParams paper = testing::paper_interface();

DiscreteParams params(long n, const std::string& threshold = "delta", double w = 0.0, bool noise = true) {
  DiscreteParams p;
  p.contacts_per_site = n;
  p.threshold = threshold;
  p.width = w;
  p.noise = noise;
  p.seed = 20240611;
  return p;
}

std::vector<double> binomial_pmf(double n, double p) {
  const auto nn = static_cast<long>(n);
  std::vector<double> f(static_cast<std::size_t>(nn) + 1);
  if (nn == 0) { f[0] = 1.0; return f; }
  const boost::math::binomial_distribution<double> b(static_cast<double>(nn), p);
  for (long x = 0; x <= nn; ++x) f[static_cast<std::size_t>(x)] = boost::math::pdf(b, static_cast<double>(x));
  return f;
}

std::vector<double> convolve(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> c(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j) c[i + j] += a[i] * b[j];
  return c;
}

// Pearson chi-square of observed counts per outcome against a pmf; adjacent outcomes are pooled
// (left to right) until each cell expects at least 5 events. Critical value at `alpha` for
// df = cells − 1 (the pmf is fully specified, nothing is fitted).
struct ChiSquare {
  double stat = 0.0, critical = 0.0;
  int df = 0;
};
ChiSquare chi_square(const std::vector<long>& observed, const std::vector<double>& pmf, double trials, double alpha) {
  REQUIRE(observed.size() == pmf.size());
  std::vector<double> o_cells, e_cells;
  double o = 0.0, e = 0.0;
  for (std::size_t x = 0; x < pmf.size(); ++x) {
    o += static_cast<double>(observed[x]);
    e += pmf[x] * trials;
    if (e >= 5.0) { o_cells.push_back(o); e_cells.push_back(e); o = e = 0.0; }
  }
  if (e > 0.0 || o > 0.0) {  // leftover tail joins the last cell
    REQUIRE(!o_cells.empty());
    o_cells.back() += o;
    e_cells.back() += e;
  }
  ChiSquare c;
  for (std::size_t k = 0; k < o_cells.size(); ++k) c.stat += (o_cells[k] - e_cells[k]) * (o_cells[k] - e_cells[k]) / e_cells[k];
  c.df = static_cast<int>(o_cells.size()) - 1;
  REQUIRE(c.df >= 1);
  c.critical = boost::math::quantile(boost::math::complement(boost::math::chi_squared(c.df), alpha));
  return c;
}

// Repeat one step from the same start state `trials` times; histogram of the attached count of
// bin `bin` (or of the site when bin < 0) after the step.
std::vector<long> one_step_histogram(CountLaw& law, double area, double sigma_bar, double v, double dt, int bin,
                                     int trials) {
  const auto n = static_cast<std::size_t>(law.contacts_per_site());
  std::vector<long> h(n + 1, 0);
  const double vv[1] = {v};
  for (int t = 0; t < trials; ++t) {
    law.set_site(0, area, sigma_bar);
    law.advance(dt, vv);
    const double x = bin < 0 ? law.attached_total(0) : law.attached(0)[static_cast<std::size_t>(bin)];
    ++h[static_cast<std::size_t>(x)];
  }
  return h;
}

void report(const char* what, const ChiSquare& c, double alpha) {
  std::printf("chi-square %-44s X2 = %7.2f  df = %2d  critical(%g) = %6.2f\n", what, c.stat, c.df, alpha, c.critical);
}

}  // namespace

TEST_CASE("discrete count: the cached-rate binomial draws are boost's, draw for draw", "[discrete][count]") {
  // discrete/binomial.hpp: boost's inversion with (1 − p')^n from a cached log, BTRD above its threshold. Against
  // boost::random::binomial_distribution on the same engine: 10^6 draws over the count law's ranges (n up to 10^5,
  // p from 1e-6 to 1 − 1e-6, both sides of 1/2 and of the inversion threshold (n + 1) p' = 11), the same values and
  // the engines in the same state after them. The two (1 − p')^n differ by ~1e-15 relatively: a draw could differ
  // when its uniform falls that close to a boundary (probability ~1e-15 per draw; 10^6 draws all equal).
  discrete::Engine a = discrete::site_engine(11, 0), b = discrete::site_engine(11, 0);
  const double ns[] = {0, 1, 2, 7, 40, 255, 1000, 4096, 30000, 100000};
  const double ps[] = {0, 1e-6, 1e-4, 3e-3, 1.0 / 64, 0.05, 0.2, 0.5, 0.7, 0.99, 1 - 1e-6, 1};
  std::size_t draws = 0, inversion = 0, differ = 0;
  for (int round = 0; round < 8334; ++round)  // 120 (n, p) pairs a round
    for (const double n : ns)
      for (const double p : ps) {
        const discrete::detail::BinomialRate r(p);
        const double x = discrete::detail::binomial(a, n, r);
        double y = 0.0;
        if (n > 0 && p > 0) {
          if (p >= 1) {
            y = n;
          } else {
            boost::random::binomial_distribution<std::int64_t, double> d(static_cast<std::int64_t>(n), p);
            y = static_cast<double>(d(b));
            inversion += static_cast<std::int64_t>((n + 1) * std::min(p, 1 - p)) < 11 ? 1 : 0;
          }
        }
        differ += x != y ? 1 : 0;
        ++draws;
      }
  std::printf("cached-rate binomial: %zu draws (%zu by inversion), %zu differ from boost's\n", draws, inversion, differ);
  CHECK(draws >= 1000000);
  CHECK(inversion > draws / 3);  // both paths exercised
  CHECK(differ == 0);
  CHECK(a == b);  // the same uniforms consumed
}

TEST_CASE("discrete count: the sparse spread's uniform bins (uniform_below) are uniform", "[discrete][count]") {
  // discrete/binomial.hpp uniform_below: Lemire's multiply-and-reject. For m = 3, 7, 64 and 63 (the spread's bin
  // ranges), 64 000 draws per bin: Pearson chi-square against the uniform pmf at alpha = 1e-3 per m (family 4e-3;
  // fixed seed); every draw in [0, m); and m = 1 always 0.
  discrete::Engine e = discrete::site_engine(5, 0);
  for (const std::uint64_t m : {3u, 7u, 63u, 64u}) {
    INFO("m = " << m);
    const double trials = 64000.0 * static_cast<double>(m);
    std::vector<long> h(m, 0);
    bool in_range = true;
    for (long k = 0; k < static_cast<long>(trials); ++k) {
      const std::size_t b = discrete::detail::uniform_below(e, m);
      in_range = in_range && b < m;
      if (b < m) ++h[b];
    }
    CHECK(in_range);
    const auto c = chi_square(h, std::vector<double>(m, 1.0 / static_cast<double>(m)), trials, 1e-3);
    CHECK(c.stat < c.critical);
  }
  for (int k = 0; k < 100; ++k) CHECK(discrete::detail::uniform_below(e, 1) == 0);
}

TEST_CASE("discrete count: one step, w = 0: attached counts follow the exact two-state transition", "[discrete][count]") {
  // Single site, N = 40, imposed v = 1 (d = κv = 8), Δt = 0.05; 20000 independent steps from the same
  // state. Each distribution is a chi-square test at false-alarm rate 1e-3.
  const double alpha = 1e-3, v = 1.0, dt = 0.05, d = paper.kappa * v;
  const int trials = 20000;
  CountLaw law(paper, params(40), 1);
  const auto over = core::two_state_transition(1.0, d, dt);
  const auto free = core::two_state_transition(1.0, 0.0, dt);

  SECTION("all attached, overloaded: pure detachment, n' ~ Bin(40, P(att→att))") {
    // σ̄ = 2, A = 1: τ = 2.1 > 1
    const auto h = one_step_histogram(law, 1.0, 2.0, v, dt, -1, trials);
    const auto c = chi_square(h, binomial_pmf(40, over.stay_attached), trials, alpha);
    report("detachment Bin(40, P(att->att))", c, alpha);
    CHECK(c.stat < c.critical);
  }
  SECTION("half attached, not overloaded: pure attachment, n' − 20 ~ Bin(20, P(det→att), d = 0)") {
    // σ̄ = 0: τ = ηv/A = 0.2 < 1; longer step so that P(det→att) ≈ 0.39
    const double dt2 = 0.5;
    const auto free2 = core::two_state_transition(1.0, 0.0, dt2);
    const auto h = one_step_histogram(law, 0.5, 0.0, v, dt2, -1, trials);
    std::vector<double> pmf(41, 0.0);
    const auto b = binomial_pmf(20, free2.become_attached);
    for (std::size_t x = 0; x < b.size(); ++x) pmf[20 + x] = b[x];
    const auto c = chi_square(h, pmf, trials, alpha);
    report("attachment 20 + Bin(20, P(det->att))", c, alpha);
    CHECK(c.stat < c.critical);
    (void)free;
  }
  SECTION("half attached, overloaded: n' ~ Bin(20, P(att→att)) + Bin(20, P(det→att))") {
    // σ̄ = 1, A = 0.5: τ = 2.2 > 1
    const auto h = one_step_histogram(law, 0.5, 1.0, v, dt, -1, trials);
    const auto pmf = convolve(binomial_pmf(20, over.stay_attached), binomial_pmf(20, over.become_attached));
    const auto c = chi_square(h, pmf, trials, alpha);
    report("both Bin(20,P(a->a)) + Bin(20,P(d->a))", c, alpha);
    CHECK(c.stat < c.critical);
  }
}

TEST_CASE("discrete count: one step, w > 0: every bin's marginal law (fresh and quenched renewal)", "[discrete][count]") {
  // Uniform thresholds, w = 0.2, B = 4 bins (s_b ≈ 0.74, 0.91, 1.09, 1.26); N = 80, A = 0.5 (10 attached
  // per bin), τ = 1 so bins 0, 1 are overloaded. v = 1, Δt = 0.05, 20000 steps. Four bins tested at
  // 1e-3/4 each (Bonferroni): false-alarm rate ≤ 1e-3 per renewal.
  //   fresh:    n_b' ~ Bin(10, P_b(att→att)) + Bin(40, P_b(det→att)/B)   (40 detached, each in bin b w.p. 1/B)
  //   quenched: n_b' ~ Bin(10, P_b(att→att)) + Bin(10, P_b(det→att))
  const double alpha = 1e-3 / 4, v = 1.0, dt = 0.05, d = paper.kappa * v;
  const int trials = 20000;
  const std::string renewal = GENERATE(std::string("fresh"), std::string("quenched"));
  auto p = params(80, "uniform", 0.2);
  p.bins = 4;
  p.renewal = renewal;
  CountLaw law(paper, p, 1);
  REQUIRE(law.bins() == 4);
  const double area = 0.5, sigma_bar = 1.0 * area - paper.eta * v;  // τ = (σ̄ + ηv)/A = 1
  law.set_site(0, area, sigma_bar);
  REQUIRE(law.overloaded_fraction(0, v) == 0.5);
  const auto over = core::two_state_transition(1.0, d, dt);
  const auto free = core::two_state_transition(1.0, 0.0, dt);
  for (int b = 0; b < 4; ++b) {
    const auto& tr = b < 2 ? over : free;
    const auto h = one_step_histogram(law, area, sigma_bar, v, dt, b, trials);
    const auto pmf = renewal == "fresh"
                         ? convolve(binomial_pmf(10, tr.stay_attached), binomial_pmf(40, tr.become_attached / 4.0))
                         : convolve(binomial_pmf(10, tr.stay_attached), binomial_pmf(10, tr.become_attached));
    std::vector<double> full(81, 0.0);
    std::copy(pmf.begin(), pmf.end(), full.begin());
    const auto c = chi_square(h, full, trials, alpha);
    const std::string what = renewal + " bin " + std::to_string(b) + (b < 2 ? " (overloaded)" : " (holding)");
    report(what.c_str(), c, alpha);
    CHECK(c.stat < c.critical);
  }
}

TEST_CASE("discrete count: one step with every bin overloaded or none: the unspread arrivals", "[discrete][count]") {
  // Fresh renewal, uniform w = 0.2, B = 4, N = 80, A = 0.5 (10 attached per bin, 40 detached), v = 1, Δt = 0.05,
  // 20000 steps from the same state. With τ above the strongest threshold (k = B) or below the weakest (k = 0) the
  // attaching contacts are not spread over the bins at the step (they wait as unspread arrivals, docs/discrete.md);
  // reading the bins spreads them. The bins read must follow the law of the spread-at-once step:
  //   n_b' ~ Bin(10, P_b(att→att)) + Bin(40, P_b(det→att)/B),
  // rates d = κv in every bin (k = B) or in none (k = 0). Four bins at 1e-3/4 each (Bonferroni): false-alarm rate
  // ≤ 1e-3 per case. Also: the step leaves arrivals unspread, and a read spreads them all, keeping the total.
  const double alpha = 1e-3 / 4, v = 1.0, dt = 0.05, area = 0.5;
  const int trials = 20000;
  const bool all_over = GENERATE(true, false);
  auto p = params(80, "uniform", 0.2);
  p.bins = 4;
  CountLaw law(paper, p, 1);
  REQUIRE(law.bins() == 4);
  // τ = (σ̄ + ηv)/A: 1.5 (above s_3 ≈ 1.26) or 0.5 (below s_0 ≈ 0.74)
  const double tau = all_over ? 1.5 : 0.5, sigma_bar = tau * area - paper.eta * v;
  law.set_site(0, area, sigma_bar);
  REQUIRE(law.overloaded_fraction(0, v) == (all_over ? 1.0 : 0.0));
  const double vv[1] = {v};
  law.advance(dt, vv);
  CHECK(law.unspread(0) > 0.0);
  const double total = law.attached_total(0);
  double read = 0.0;
  for (const double n : law.attached(0)) read += n;
  CHECK(law.unspread(0) == 0.0);
  CHECK(read == total);
  const auto tr = core::two_state_transition(1.0, all_over ? paper.kappa * v : 0.0, dt);
  for (int b = 0; b < 4; ++b) {
    const auto h = one_step_histogram(law, area, sigma_bar, v, dt, b, trials);
    const auto pmf = convolve(binomial_pmf(10, tr.stay_attached), binomial_pmf(40, tr.become_attached / 4.0));
    std::vector<double> full(81, 0.0);
    std::copy(pmf.begin(), pmf.end(), full.begin());
    const auto c = chi_square(h, full, trials, alpha);
    const std::string what = std::string(all_over ? "k = B" : "k = 0") + " bin " + std::to_string(b);
    report(what.c_str(), c, alpha);
    CHECK(c.stat < c.critical);
  }
}

namespace {
// A sliding site from the stuck state: fresh uniform thresholds w = 0.2, B = 8, N = 400, imposed v, Δt = 0.05,
// 200 steps from A = 1, τ = 1.05: the bins part overloaded; then, as contacts detach and τ rises, every bin (k = B,
// arrivals unspread, for ~100 steps); then σ̄ relaxes, k falls below B (the arrivals are spread) and the site
// re-sticks (A grows, k = 0 again with arrivals unspread). `read_every_step` reads the bins after each step, so that no arrival stays unspread
// (the bins then evolve as when every arrival was spread at its step); otherwise they are read once, at the end.
struct SlidingEnd {
  std::vector<double> area, sigma, bin_low, bin_high;
};
SlidingEnd sliding_from_stuck(bool read_every_step, double v, int trials, std::uint64_t seed0) {
  SlidingEnd r;
  for (int t = 0; t < trials; ++t) {
    auto p = params(400, "uniform", 0.2);
    p.bins = 8;
    p.seed = seed0 + static_cast<std::uint64_t>(t);
    CountLaw law(paper, p, 1);
    law.set_site(0, 1.0, 1.05 - paper.eta * v);
    const double vv[1] = {v};
    for (int n = 0; n < 200; ++n) {
      law.advance(0.05, vv);
      if (read_every_step) (void)law.attached(0);
    }
    const auto bins = law.attached(0);
    r.area.push_back(law.contact_area()[0]);
    r.sigma.push_back(law.sigma_bar()[0]);
    r.bin_low.push_back(bins[0]);
    r.bin_high.push_back(bins[7]);
  }
  return r;
}
}  // namespace

TEST_CASE("discrete count: unspread arrivals leave the law of a sliding site unchanged", "[discrete][count]") {
  // sliding_from_stuck, 1500 seeds each way, v = 0.5: two-sample KS on A, σ̄ and the counts of the weakest and the
  // strongest bin at the end, each at 1e-3/4 (Bonferroni; family false-alarm rate ≤ 1e-3; KS is conservative on the
  // tied counts). Power: the tests on A, σ̄ and the strongest bin reject, at the same level, the run at v = 0.55 (a
  // 10 % change of the detach rate), so they would see an error of that size in the unspread bookkeeping (the
  // weakest bin's end count hardly depends on v: ~7.5 contacts either way).
  const int trials = 1500;
  const double alpha = 1e-3 / 4;
  const auto lazy = sliding_from_stuck(false, 0.5, trials, 1000);
  const auto eager = sliding_from_stuck(true, 0.5, trials, 900000);
  const auto faster = sliding_from_stuck(true, 0.55, trials, 900000);
  const std::pair<const char*, std::vector<double> SlidingEnd::*> what[] = {
      {"A", &SlidingEnd::area}, {"sigma_bar", &SlidingEnd::sigma}, {"bin 0", &SlidingEnd::bin_low},
      {"bin 7", &SlidingEnd::bin_high}};
  for (const auto& [name, field] : what) {
    const auto same = testing::ks_two_sample(lazy.*field, eager.*field);
    const auto other = testing::ks_two_sample(lazy.*field, faster.*field);
    std::printf("unspread vs spread each step, %-9s: KS D = %.4f p = %.3g; vs v x 1.1: D = %.4f p = %.3g\n", name,
                same.d, same.p, other.d, other.p);
    INFO(name);
    CHECK(same.p > alpha);
    if (field != &SlidingEnd::bin_low) CHECK(other.p < alpha);
  }
}

TEST_CASE("discrete count: noise off: one step equals the closed forms", "[discrete][count]") {
  // Exact (bitwise) against relax() of core/exact_update.hpp, which is how the expectation is
  // evaluated; and to 1e-15 relative (a few ulps) against the two-state form
  // n P(att→att) + (T − n) P(det→att), algebraically the same number.
  const double dt = 0.03, v = 0.7, d = paper.kappa * v;
  SECTION("w = 0, overloaded and holding") {
    CountLaw law(paper, params(1000, "delta", 0.0, false), 2);
    law.set_site(0, 0.6, 1.0);   // τ = (1 + 0.07)/0.6 > 1: overloaded
    law.set_site(1, 0.6, 0.3);   // τ = 0.37/0.6 < 1: holding
    const double vv[2] = {v, v};
    const auto info = law.advance(dt, vv);
    CHECK(info.any_yield);
    const double a_over = core::relax(0.6, 1.0, 1.0 + d, dt);
    const double a_free = core::relax(0.6, 1.0, 1.0, dt);
    CHECK(law.contact_area()[0] == a_over);
    CHECK(law.contact_area()[1] == a_free);
    const auto tr = core::two_state_transition(1.0, d, dt);
    CHECK(law.contact_area()[0] == Approx(0.6 * tr.stay_attached + 0.4 * tr.become_attached).epsilon(1e-15));
    CHECK(law.sigma_bar()[0] == core::relax(1.0, paper.alpha * 0.5 * (0.6 + a_over) * v, v, dt));
    CHECK(law.sigma_bar()[1] == 0.3 + paper.alpha * 0.5 * (0.6 + a_free) * v * dt);
    // the continuum law from the same state gives the same numbers
    continuum::FrictionLaw c(paper, 2);
    c.set_site(0, 0.6, 1.0);
    c.set_site(1, 0.6, 0.3);
    c.advance(dt, vv);
    for (std::size_t i = 0; i < 2; ++i) {
      CHECK(c.contact_area()[i] == law.contact_area()[i]);
      CHECK(c.sigma_bar()[i] == law.sigma_bar()[i]);
    }
  }
  SECTION("w > 0, fresh: bin b gets n_b P_b(att→att) + (n_det/B) P_b(det→att); Y = k/B") {
    auto p = params(1000, "uniform", 0.2, false);
    p.bins = 4;
    CountLaw law(paper, p, 1);
    const double area = 0.6, sb = 1.0 * area - paper.eta * v;  // τ = 1: bins 0, 1 overloaded
    law.set_site(0, area, sb);
    const double y = law.overloaded_fraction(0, v), a0 = law.contact_area()[0];
    CHECK(y == Approx(0.5).epsilon(1e-15));
    const double vv[1] = {v};
    law.advance(dt, vv);
    const auto over = core::two_state_transition(1.0, d, dt);
    const auto free = core::two_state_transition(1.0, 0.0, dt);
    double total = 0.0;
    for (std::size_t b = 0; b < 4; ++b) {
      const auto& tr = b < 2 ? over : free;
      const double expect = 0.15 * tr.stay_attached + 0.1 * tr.become_attached;  // fractions of the site
      CHECK(law.attached(0)[b] == Approx(expect).epsilon(1e-15));
      total += expect;
    }
    CHECK(law.contact_area()[0] == Approx(total).epsilon(1e-15));
    CHECK(law.detached(0)[0] == Approx(1.0 - total).epsilon(1e-15));
    CHECK(law.sigma_bar()[0] ==
          core::relax(sb, paper.alpha * 0.5 * (a0 + law.contact_area()[0]) * v, y * v, dt));
  }
}

TEST_CASE("discrete count: no random draw on idle sites", "[discrete][count]") {
  // Site 0 holds (τ < 1, A = 1), site 1 slides overloaded, site 2 is overloaded with A = 1 but v = 0,
  // site 3 holds with A = 1 and v < 0. Idle sites must leave their stream untouched.
  const auto p = params(1000);
  CountLaw law(paper, p, 4);
  law.set_site(0, 1.0, 0.2);
  law.set_site(1, 0.5, 1.0);
  law.set_site(2, 1.0, 1.5);
  law.set_site(3, 1.0, -0.2);
  const double v[4] = {0.3, 1.0, 0.0, -0.3};
  bool any = false;
  for (int n = 0; n < 100; ++n) any |= law.advance(0.001, v).any_yield;
  CHECK(any);
  for (std::size_t i : {0u, 2u, 3u}) {
    INFO("site " << i);
    CHECK(law.engine(i) == discrete::site_engine(p.seed, i));
    CHECK(law.contact_area()[i] == 1.0);
  }
  CHECK(law.engine(1) != discrete::site_engine(p.seed, 1));
  CHECK(law.sigma_bar()[2] == 1.5);                                   // v = 0: σ̄ frozen
  CHECK(law.sigma_bar()[0] == Approx(0.2 + 100 * 0.001 * paper.alpha * 0.3).epsilon(1e-12));  // elastic
  // a site overloaded with v = 0 does not count as yielding
  CountLaw still(paper, p, 1);
  still.set_site(0, 1.0, 1.5);
  const double zero[1] = {0.0};
  CHECK_FALSE(still.advance(0.01, zero).any_yield);
}

namespace {

// Short edge-loading scene (testing::fig1_scene, L = 100: 201 sites, > 3 chunks of 64) with noise on.
compare::Scene noisy_edge(std::uint64_t seed, int threads) {
  compare::Scene s = testing::fig1_scene();
  s.name = "count_reproducibility";
  s.models = {"discrete"};
  s.bulk.length = 100.0;
  s.time.t_end = 30.0;
  s.output.series_dt = 0.1;
  s.output.snapshot_dt = 5.0;
  s.discrete.contacts_per_site = 100;
  s.discrete.seed = seed;
  s.discrete.threads = threads;
  s.validate();
  return s;
}

}  // namespace

TEST_CASE("discrete count: reproducibility: seeds, thread counts, saved state", "[discrete][count]") {
  const auto a = compare::run_scene(noisy_edge(11, 1), {}).at(0);
  const auto b = compare::run_scene(noisy_edge(11, 1), {}).at(0);
  const auto c = compare::run_scene(noisy_edge(12, 1), {}).at(0);
  const auto t2 = compare::run_scene(noisy_edge(11, 2), {}).at(0);
  REQUIRE(a.status == slipfront::compare::RunStatus::complete);
  REQUIRE(std::isfinite(a.events.t_star));  // it yielded, so draws happened
  for (const char* f : {"A", "sigma_bar", "u", "v"}) {
    INFO(f);
    CHECK(a.snapshots.at(f) == b.snapshots.at(f));   // same seed: bit-identical
    CHECK(a.snapshots.at(f) == t2.snapshots.at(f));  // 2 threads: bit-identical
    CHECK(a.snapshots.at(f) != c.snapshots.at(f));   // another seed: different
  }
  CHECK(a.series.at("drive_force") == t2.series.at("drive_force"));
  CHECK(a.events.t_star == t2.events.t_star);
}

TEST_CASE("discrete count: save_state / load_state continue bit for bit", "[discrete][count]") {
  {
    auto p = params(500, "gaussian", 0.2, GENERATE(true, false));
    p.renewal = GENERATE(std::string("fresh"), std::string("quenched"));
    p.bins = 8;
    CountLaw law(paper, p, 3);
    for (std::size_t i = 0; i < 3; ++i) law.set_site(i, 0.7, 0.9);
    const double v[3] = {0.5, 1.0, 2.0};
    for (int n = 0; n < 50; ++n) law.advance(0.01, v);
    const std::string saved = law.save_state();
    CountLaw other(paper, p, 3);
    other.load_state(saved);
    CHECK(other.save_state() == saved);
    for (int n = 0; n < 50; ++n) {
      law.advance(0.01, v);
      other.advance(0.01, v);
    }
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(law.contact_area()[i] == other.contact_area()[i]);
      CHECK(law.sigma_bar()[i] == other.sigma_bar()[i]);
      CHECK(law.engine(i) == other.engine(i));
    }
    CountLaw wrong(paper, params(400), 3);
    CHECK_THROWS_AS(wrong.load_state(saved), std::invalid_argument);
  }
}

TEST_CASE("discrete count: a saved state keeps the unspread arrivals, and a version-1 state still loads", "[discrete][count]") {
  // Fresh uniform thresholds, B = 8, every bin overloaded (τ ≈ 1.5): after a few steps the site holds unspread
  // arrivals. Saving must not spread them (it would draw), and the loaded law continues bit for bit, spreading them
  // at the same step. A version-1 text (this state with its unspread field removed, settled first) loads.
  auto p = params(400, "uniform", 0.2);
  p.bins = 8;
  CountLaw law(paper, p, 2);
  for (std::size_t i = 0; i < 2; ++i) law.set_site(i, 0.5, 0.7);
  const double v[2] = {1.0, 1.0};
  for (int n = 0; n < 5; ++n) law.advance(0.01, v);
  REQUIRE(law.unspread(0) > 0.0);
  const auto engine_before = law.engine(0);
  const std::string saved = law.save_state();
  CHECK(law.engine(0) == engine_before);  // saving drew nothing
  CHECK(saved.rfind("slipfront-count-law 2 ", 0) == 0);
  CountLaw other(paper, p, 2);
  other.load_state(saved);
  CHECK(other.unspread(0) == law.unspread(0));
  CHECK(other.save_state() == saved);
  const double slow[2] = {0.05, 0.05};  // σ̄ relaxes below the strongest threshold: the arrivals get spread
  bool spread = false;
  for (int n = 0; n < 400; ++n) {
    const bool held = law.unspread(0) > 0.0;
    law.advance(0.01, n < 50 ? v : slow);
    other.advance(0.01, n < 50 ? v : slow);
    spread |= held && law.unspread(0) == 0.0;
  }
  CHECK(spread);
  CHECK(other.save_state() == law.save_state());

  // version 1: every site settled (a read spreads), then each site's unspread field (after its 8 bins) removed
  for (std::size_t i = 0; i < 2; ++i) (void)law.attached(i);
  std::istringstream in(law.save_state());
  std::string header, out;
  std::getline(in, header);
  REQUIRE(header.rfind("slipfront-count-law 2 ", 0) == 0);
  out = "slipfront-count-law 1 " + header.substr(22) + "\n";
  for (std::string numbers, engine; std::getline(in, numbers) && std::getline(in, engine);) {
    std::istringstream tok(numbers);
    std::vector<std::string> t;
    for (std::string x; tok >> x;) t.push_back(x);
    REQUIRE(t.size() == 1 + 8 + 1 + 1);  // σ̄, the bins, unspread, the detached pool
    REQUIRE(std::strtod(t[9].c_str(), nullptr) == 0.0);
    t.erase(t.begin() + 9);
    for (const auto& x : t) out += x + " ";
    out += "\n" + engine + "\n";
  }
  CountLaw old(paper, p, 2);
  old.load_state(out);
  CHECK(old.save_state() == law.save_state());
}

TEST_CASE("discrete count: bad parameters are refused, naming the key", "[discrete][count]") {
  auto refused_key = [](const DiscreteParams& p) -> std::string {
    try {
      CountLaw law(paper, p, 1);
    } catch (const core::ParamError& e) {
      return e.key;
    }
    return "accepted";
  };
  auto p = params(1000);
  CHECK(refused_key(p) == "accepted");
  p.contacts_per_site = 0;
  CHECK(refused_key(p) == "discrete.contacts_per_site");
  p = params(1000, "uniform", -0.1);
  CHECK(refused_key(p) == "discrete.width");
  p = params(1000, "lognormal", 0.1);
  CHECK(refused_key(p) == "discrete.threshold");
  p = params(1000);
  p.representation = "grid";
  CHECK(refused_key(p) == "discrete.representation");
  p = params(1000);
  p.renewal = "sometimes";
  CHECK(refused_key(p) == "discrete.renewal");
  p = params(1000, "weibull", 0.2);
  p.bins = 0;
  CHECK(refused_key(p) == "discrete.bins");
  // through the scene, before any work
  compare::Scene s = noisy_edge(1, 1);
  s.discrete.contacts_per_site = -5;
  try {
    s.validate();
    FAIL("accepted N < 1");
  } catch (const core::ParamError& e) {
    CHECK(e.key == "discrete.contacts_per_site");
  }
  CountLaw law(paper, params(10), 1);
  CHECK_THROWS_AS(law.set_site(0, 1.5, 0.0), std::invalid_argument);
}

TEST_CASE("discrete count: mean field: steady sliding at imposed v, time-averaged A and sigma_bar", "[discrete][count]") {
  // w = 0, N = 1000, v ∈ {1, 3, 10} (A_ss = 1/(1+κv)): every attached contact stays overloaded
  // (τ ≈ α + ηv/A_ss ≥ 1.95, far above the threshold 1 compared with the O(N^{-1/2}) fluctuations),
  // and the exact two-state chain has the stationary attached fraction a/(a+d) = 1/(1+κv) for any Δt,
  // so E[A] = 1/(1+κv) and E[σ̄] = α E[A] exactly. Tolerance: 4 standard errors from 40 batch means
  // of 50 time units each (≫ the correlation time 1/(1+κv) ≈ 0.11): false-alarm rate ≈ 6e-5 each.
  const double v = GENERATE(1.0, 3.0, 10.0);
  const double dt = 0.01, burn_in = 20.0, batch = 50.0;
  const int batches = 40;
  CountLaw law(paper, params(1000), 1);
  const auto ss = continuum::steady_sliding(paper, v);
  law.set_site(0, ss.area, ss.sigma_bar);
  const double vv[1] = {v};
  for (int n = 0; n < static_cast<int>(burn_in / dt); ++n) law.advance(dt, vv);
  std::vector<double> a_means, s_means;
  const int per_batch = static_cast<int>(std::lround(batch / dt));
  for (int k = 0; k < batches; ++k) {
    double sa = 0.0, ss_ = 0.0;
    for (int n = 0; n < per_batch; ++n) {
      const double a0 = law.contact_area()[0];
      law.advance(dt, vv);
      sa += 0.5 * (a0 + law.contact_area()[0]);
      ss_ += law.sigma_bar()[0];
    }
    a_means.push_back(sa / per_batch);
    s_means.push_back(ss_ / per_batch);
  }
  auto mean_se = [](const std::vector<double>& x) {
    double m = 0.0, s2 = 0.0;
    for (double y : x) m += y;
    m /= static_cast<double>(x.size());
    for (double y : x) s2 += (y - m) * (y - m);
    return std::pair{m, std::sqrt(s2 / static_cast<double>(x.size() - 1) / static_cast<double>(x.size()))};
  };
  const auto [am, ase] = mean_se(a_means);
  const auto [sm, sse] = mean_se(s_means);
  std::printf("mean field v = %5.2f: <A> = %.6f +- %.2g (1/(1+kv) = %.6f, %+.2f SE); <sb> = %.6f +- %.2g (alpha A_ss = %.6f, %+.2f SE)\n",
              v, am, ase, ss.area, (am - ss.area) / ase, sm, sse, ss.sigma_bar, (sm - ss.sigma_bar) / sse);
  CHECK(std::abs(am - ss.area) < 4.0 * ase);
  CHECK(std::abs(sm - ss.sigma_bar) < 4.0 * sse);
  CHECK(ase > 0.0);
}
