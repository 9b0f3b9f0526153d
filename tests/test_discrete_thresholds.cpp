// Threshold distributions g of docs/model.md §2 (mean 1, relative width w) and the overloaded fraction of a
// fresh population at contact stress τ, which must be the CDF G(τ): for the distribution object,
// for a CountLaw site (quantile bins: within 1/B), and for sampled thresholds (Kolmogorov–Smirnov).
#include <algorithm>
#include <boost/math/special_functions/gamma.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "discrete/count_law.hpp"
#include "discrete/streams.hpp"
#include "discrete/thresholds.hpp"
#include "scenes.hpp"

using namespace slipfront;
using discrete::ThresholdDistribution;

namespace {

const core::InterfaceParams paper = testing::paper_interface();

// M thresholds drawn by inversion from one stream.
std::vector<double> sample(const ThresholdDistribution& g, std::size_t m, std::uint64_t seed) {
  auto e = discrete::site_engine(seed, 0);
  std::vector<double> s(m);
  for (auto& x : s) x = g.from_uniform(discrete::uniform01(e));
  return s;
}

// Loads τ spread over the body of g (quantiles 0.01 … 0.99) plus both tails.
std::vector<double> loads(const ThresholdDistribution& g) {
  std::vector<double> t{0.0, 0.5 * g.quantile(0.001), 2.0 * g.quantile(0.999)};
  for (int k = 1; k <= 99; k += 7) t.push_back(g.quantile(k / 100.0));
  for (int k = 0; k <= 20; ++k) t.push_back(0.5 + 0.05 * k);
  return t;
}

}  // namespace

TEST_CASE("discrete thresholds: threshold distributions: mean 1 and standard deviation w", "[discrete][thresholds]") {
  const std::string kind = GENERATE(std::string("uniform"), std::string("gaussian"), std::string("weibull"));
  const double w = GENERATE(0.05, 0.2, 0.4);
  INFO(kind << " w = " << w);
  const ThresholdDistribution g(kind, w);
  // by quadrature of the quantile function: tolerance 1e-6
  CHECK(g.mean() == Approx(1.0).margin(1e-6));
  CHECK(g.stddev() == Approx(w).margin(1e-6));
  // sampled: M = 2e5 draws; mean within 5 standard errors s/√M, sd within 5 standard errors
  // sqrt(m4 − s⁴)/(2 s √M) (normal approximation): false-alarm rate ≈ 6e-7 each
  const std::size_t m = 200000;
  const auto s = sample(g, m, 99);
  double mean = 0.0;
  for (double x : s) mean += x;
  mean /= static_cast<double>(m);
  double m2 = 0.0, m4 = 0.0;
  for (double x : s) {
    const double d2 = (x - mean) * (x - mean);
    m2 += d2;
    m4 += d2 * d2;
  }
  m2 /= static_cast<double>(m - 1);
  m4 /= static_cast<double>(m);
  const double sd = std::sqrt(m2);
  const double se_mean = sd / std::sqrt(static_cast<double>(m));
  const double se_sd = std::sqrt(std::max(0.0, m4 - m2 * m2) / static_cast<double>(m)) / (2.0 * sd);
  std::printf("%-8s w = %.2f: sampled mean %.5f (%+.2f SE), sd %.5f (%+.2f SE)\n", kind.c_str(), w, mean,
              (mean - 1.0) / se_mean, sd, (sd - w) / se_sd);
  CHECK(std::abs(mean - 1.0) < 5.0 * se_mean);
  CHECK(std::abs(sd - w) < 5.0 * se_sd);
  CHECK(*std::min_element(s.begin(), s.end()) > 0.0);  // thresholds are positive
}

TEST_CASE("discrete thresholds: overloaded fraction of a fresh population is G(tau)", "[discrete][thresholds]") {
  const std::string kind = GENERATE(std::string("uniform"), std::string("gaussian"), std::string("weibull"));
  const double w = GENERATE(0.05, 0.2, 0.4);
  INFO(kind << " w = " << w);
  const ThresholdDistribution g(kind, w);

  SECTION("(a) the distribution object: G is the inverse of the quantile and has the closed form") {
    // tolerance 1e-12 (root finding inside the Boost quantiles)
    for (int k = 1; k < 100; ++k) CHECK(g.cdf(g.quantile(k / 100.0)) == Approx(k / 100.0).margin(1e-12));
    CHECK(g.cdf(0.0) == 0.0);
    for (double tau : loads(g)) {
      INFO("tau = " << tau);
      if (kind == "uniform") {
        const double a = 1.0 - std::sqrt(3.0) * w, b = 1.0 + std::sqrt(3.0) * w;
        CHECK(g.cdf(tau) == Approx(std::clamp((tau - a) / (b - a), 0.0, 1.0)).margin(1e-14));
      } else if (kind == "weibull") {
        // shape k from the coefficient of variation w (bisection here, independently), scale 1/Γ(1+1/k)
        double lo = 0.5, hi = 200.0;
        for (int it = 0; it < 200; ++it) {
          const double mid = 0.5 * (lo + hi);
          const double g1 = boost::math::tgamma(1.0 + 1.0 / mid), g2 = boost::math::tgamma(1.0 + 2.0 / mid);
          (std::sqrt(g2 / (g1 * g1) - 1.0) > w ? lo : hi) = mid;
        }
        const double shape = 0.5 * (lo + hi), scale = 1.0 / boost::math::tgamma(1.0 + 1.0 / shape);
        CHECK(g.cdf(tau) == Approx(1.0 - std::exp(-std::pow(tau / scale, shape))).margin(1e-9));
      } else {
        // truncated normal: G(τ) = ∫_0^τ density, checked against the numerical derivative
        const double h = 1e-5;
        if (tau > 2 * h) CHECK((g.cdf(tau + h) - g.cdf(tau - h)) / (2 * h) >= 0.0);
      }
    }
  }

  SECTION("(b) a CountLaw site with B = 256 quantile bins: within 1/B (+ 1/N, noise on)") {
    for (const bool noise : {false, true}) {
      discrete::DiscreteParams p;
      p.threshold = kind;
      p.width = w;
      p.bins = 256;
      p.noise = noise;
      p.contacts_per_site = 1000000;
      discrete::CountLaw law(paper, p, 1);
      REQUIRE(law.bins() == 256);
      const double tol = 1.0 / 256 + (noise ? 1e-6 : 1e-12);
      double worst = 0.0;
      for (double tau : loads(g)) {
        law.set_site(0, 1.0, tau);  // A = 1, v = 0: contact stress τ
        const double y = law.overloaded_fraction(0, 0.0);
        worst = std::max(worst, std::abs(y - g.cdf(tau)));
        INFO("tau = " << tau << " noise " << noise);
        CHECK(std::abs(y - g.cdf(tau)) <= tol);
      }
      std::printf("%-8s w = %.2f: CountLaw B = 256 (noise %s): max |Y - G(tau)| = %.2e (1/B = %.2e)\n", kind.c_str(), w,
                  noise ? "on " : "off", worst, 1.0 / 256);
    }
  }

  SECTION("(c) sampled thresholds: Kolmogorov–Smirnov at false-alarm rate 1e-3") {
    // D_M = sup_τ |F_M(τ) − G(τ)|; critical value sqrt(−ln(α/2)/2)/√M (asymptotic, conservative)
    const std::size_t m = 50000;
    auto s = sample(g, m, 4242);
    std::sort(s.begin(), s.end());
    double d = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
      const double gj = g.cdf(s[j]);
      d = std::max({d, static_cast<double>(j + 1) / m - gj, gj - static_cast<double>(j) / m});
    }
    const double critical = std::sqrt(-std::log(1e-3 / 2.0) / 2.0) / std::sqrt(static_cast<double>(m));
    std::printf("%-8s w = %.2f: KS D = %.5f, critical(1e-3) = %.5f\n", kind.c_str(), w, d, critical);
    CHECK(d < critical);
  }
}

TEST_CASE("discrete thresholds: degenerate thresholds: delta (w = 0) gives one bin at s = 1", "[discrete][thresholds]") {
  const ThresholdDistribution g("delta", 0.0);
  CHECK(g.degenerate());
  CHECK(g.cdf(0.999) == 0.0);
  CHECK(g.cdf(1.0) == 1.0);
  discrete::DiscreteParams p;
  discrete::CountLaw law(paper, p, 1);
  REQUIRE(law.bins() == 1);
  CHECK(law.thresholds()[0] == 1.0);
  law.set_site(0, 1.0, 1.0);
  CHECK(law.overloaded_fraction(0, 0.0) == 0.0);   // τ = 1 is not above the threshold (Θ = θ(τ − 1))
  law.set_site(0, 1.0, 1.0 + 1e-12);
  CHECK(law.overloaded_fraction(0, 0.0) == 1.0);
  // a zero width with a non-degenerate kind also collapses to one bin
  p.threshold = "weibull";
  p.width = 0.0;
  CHECK(discrete::CountLaw(paper, p, 1).bins() == 1);
}
