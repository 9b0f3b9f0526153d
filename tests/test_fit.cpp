// Fits used by the convergence studies (compare/fit.hpp) and the run pool (compare/pool.hpp).
#include <catch2/catch.hpp>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <vector>

#include "compare/fit.hpp"
#include "compare/pool.hpp"

using namespace slipfront::compare;

TEST_CASE("fit_line recovers an exact line with zero standard error", "[fit]") {
  const std::vector<double> x{1, 2, 3, 4, 5}, y{3, 5, 7, 9, 11};
  const LineFit f = fit_line(x, y);
  CHECK(f.slope == Approx(2.0).epsilon(1e-14));
  CHECK(f.intercept == Approx(1.0).epsilon(1e-14));
  CHECK(f.slope_stderr == Approx(0.0).margin(1e-12));
  CHECK(f.r2 == Approx(1.0));
}

TEST_CASE("fit_power_law: the 95% interval covers the true exponent at its nominal rate", "[fit]") {
  // y = 3 N^{-1/2} (1 + 0.1 ε), ε ~ N(0,1): 400 synthetic studies with fixed seed. The interval must
  // cover −1/2 in 95% of them; with 400 trials the count of covers is Binomial(400, 0.95), whose
  // 1e-4 two-sided band is about [355, 394]: the false-alarm rate of this test is < 1e-4.
  boost::random::mt19937_64 rng(12345);
  boost::random::normal_distribution<double> normal;
  const std::vector<double> N{10, 30, 100, 300, 1000, 3000, 10000};
  int covered = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<double> err;
    for (double n : N) err.push_back(3.0 / std::sqrt(n) * std::exp(0.1 * normal(rng)));
    const LineFit f = fit_power_law(N, err);
    covered += (f.slope_ci_low <= -0.5 && -0.5 <= f.slope_ci_high) ? 1 : 0;
  }
  CHECK(covered >= 355);
  CHECK(covered <= 394);
}

TEST_CASE("fit_power_law drops non-positive errors", "[fit]") {
  const std::vector<double> N{10, 100, 1000, 10000}, err{0.1, 0.0, 0.001, 0.0001};
  const LineFit f = fit_power_law(N, err);
  CHECK(f.n == 3);
  CHECK(f.slope == Approx(-1.0).epsilon(1e-12));
}

TEST_CASE("fit_power_law_multi: three exponents of a known law, and their intervals at the nominal rate", "[fit]") {
  // y = 24 a^{-1.5} k^{0.5} e^{-0.5} exp(0.1 ε) on the validity study's grid shape (6 a, 3 k, 3 e, 12 points
  // with one factor off its reference at a time), 400 synthetic studies with a fixed seed: the 95% interval
  // of each exponent covers the truth in Binomial(400, 0.95) of them (1e-4 two-sided band [355, 394], so the
  // false-alarm rate of the three checks together is < 3e-4); exact data give the exponents to 1e-12.
  std::vector<std::vector<double>> f(3);
  for (double a : {0.02, 0.05, 0.1, 0.2, 0.5, 1.0}) f[0].push_back(a), f[1].push_back(8), f[2].push_back(0.1);
  for (double a : {0.05, 0.2})
    for (auto [k, e] : {std::pair{2.0, 0.1}, std::pair{32.0, 0.1}, std::pair{8.0, 0.025}, std::pair{8.0, 0.4}})
      f[0].push_back(a), f[1].push_back(k), f[2].push_back(e);
  const std::size_t n = f[0].size();
  const double truth[3] = {-1.5, 0.5, -0.5};
  auto law = [&](std::size_t i) {
    return 24 * std::pow(f[0][i], truth[0]) * std::pow(f[1][i], truth[1]) * std::pow(f[2][i], truth[2]);
  };
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) y[i] = law(i);
  const PowerLawFit exact = fit_power_law_multi(f, y);
  REQUIRE(exact.exponents.size() == 3);
  for (int c = 0; c < 3; ++c) CHECK(exact.exponents[c] == Approx(truth[c]).margin(1e-12));
  CHECK(exact.prefactor == Approx(24).epsilon(1e-12));
  boost::random::mt19937_64 rng(777);
  boost::random::normal_distribution<double> normal;
  int covered[3] = {0, 0, 0};
  for (int trial = 0; trial < 400; ++trial) {
    for (std::size_t i = 0; i < n; ++i) y[i] = law(i) * std::exp(0.1 * normal(rng));
    const PowerLawFit r = fit_power_law_multi(f, y);
    for (int c = 0; c < 3; ++c) covered[c] += (r.ci_low[c] <= truth[c] && truth[c] <= r.ci_high[c]) ? 1 : 0;
  }
  for (int c = 0; c < 3; ++c) {
    CHECK(covered[c] >= 355);
    CHECK(covered[c] <= 394);
  }
  // a factor that never varies: no fit
  std::vector<std::vector<double>> flat{f[0], std::vector<double>(n, 8.0)};
  CHECK(fit_power_law_multi(flat, y).exponents.empty());
}

TEST_CASE("run_pool: every job runs once and results do not depend on the thread count", "[pool]") {
  for (unsigned threads : {1u, 2u, 5u}) {
    std::vector<int> hits(37, 0);
    run_pool(hits.size(), threads, [&](std::size_t i) { hits[i] += static_cast<int>(i) + 1; });
    for (std::size_t i = 0; i < hits.size(); ++i) CHECK(hits[i] == static_cast<int>(i) + 1);
  }
  CHECK_THROWS_AS(run_pool(4, 2, [](std::size_t i) { if (i == 2) throw std::runtime_error("x"); }), std::runtime_error);
}
