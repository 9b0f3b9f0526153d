#pragma once
// Helpers of the agent-representation tests (test_discrete_agent, test_discrete_renewal,
// test_slow_agent): Kolmogorov–Smirnov one- and two-sample statistics with asymptotic p-values,
// mean / standard error, and a 0D imposed-rate sampler over seeds for any interface law.
// Each test states its false-alarm rate in terms of these p-values.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/params.hpp"
#include "discrete/params.hpp"

namespace slipfront::testing {

/// P(K > λ) of the Kolmogorov distribution: 2 Σ_{k≥1} (−1)^{k−1} e^{−2k²λ²}.
inline double kolmogorov_tail(double lambda) {
  if (lambda < 0.2) return 1.0;
  double p = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * lambda * lambda);
    p += (k % 2 ? 2.0 : -2.0) * term;
    if (term < 1e-16) break;
  }
  return std::clamp(p, 0.0, 1.0);
}

struct KsResult {
  double d = 0.0;  ///< KS statistic
  double p = 1.0;  ///< asymptotic p-value (Stephens' small-sample correction)
};

/// One-sample KS test of `x` against the continuous CDF F.
inline KsResult ks_one_sample(std::vector<double> x, const std::function<double(double)>& cdf) {
  if (x.empty()) throw std::invalid_argument("ks_one_sample: no data");
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, static_cast<double>(i + 1) / n - f, f - static_cast<double>(i) / n});
  }
  const double sn = std::sqrt(n);
  return {d, kolmogorov_tail((sn + 0.12 + 0.11 / sn) * d)};
}

/// Two-sample KS test. With ties (e.g. A = n/N) the asymptotic p-value is conservative.
inline KsResult ks_two_sample(std::vector<double> a, std::vector<double> b) {
  if (a.empty() || b.empty()) throw std::invalid_argument("ks_two_sample: no data");
  const auto nan = [](double x) { return std::isnan(x); };  // (the merge below would not end on one)
  if (std::any_of(a.begin(), a.end(), nan) || std::any_of(b.begin(), b.end(), nan))
    throw std::invalid_argument("ks_two_sample: NaN in the data (map a missing event to a value first)");
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  std::size_t i = 0, j = 0;
  double d = 0.0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / na - static_cast<double>(j) / nb));
  }
  const double ne = std::sqrt(na * nb / (na + nb));
  return {d, kolmogorov_tail((ne + 0.12 + 0.11 / ne) * d)};
}

struct MeanSe {
  double mean = 0.0, se = 0.0;
};
inline MeanSe mean_se(std::span<const double> x) {
  if (x.size() < 2) throw std::invalid_argument("mean_se: need two values");
  double m = 0.0;
  for (double v : x) m += v;
  m /= static_cast<double>(x.size());
  double s2 = 0.0;
  for (double v : x) s2 += (v - m) * (v - m);
  s2 /= static_cast<double>(x.size() - 1);
  return {m, std::sqrt(s2 / static_cast<double>(x.size()))};
}


// 0D imposed slip rate v from the stuck state (A = 1, σ̄ = 0), dt = 0.01: A and σ at t = 2.5, 5, 20
// and the time averages of σ and A over [20, 120], one value per seed seed0, seed0 + 1, ...
struct Sample0D {
  std::vector<double> area[3], sigma[3];  // at t = 2.5, 5, 20
  std::vector<double> steady_sigma, steady_area;  // time averages over [20, 120]
};

template <class Law>
Sample0D run_0d(const discrete::DiscreteParams& base, core::InterfaceParams ip, double v, std::uint64_t seed0, int seeds) {
  Sample0D out;
  const double dt = 0.01;
  const int at[3] = {250, 500, 2000}, steps = 12000;
  for (int k = 0; k < seeds; ++k) {
    auto dp = base;
    dp.seed = seed0 + static_cast<std::uint64_t>(k);
    Law law(ip, dp, 1);
    const double vv[1] = {v};
    double sum_s = 0.0, sum_a = 0.0;
    for (int n = 1; n <= steps; ++n) {
      law.advance(dt, vv);
      const double a = law.contact_area()[0], s = law.sigma_bar()[0] + ip.eta * v;
      for (int j = 0; j < 3; ++j)
        if (n == at[j]) {
          out.area[j].push_back(a);
          out.sigma[j].push_back(s);
        }
      if (n > at[2]) {
        sum_s += s;
        sum_a += a;
      }
    }
    out.steady_sigma.push_back(sum_s / (steps - at[2]));
    out.steady_area.push_back(sum_a / (steps - at[2]));
  }
  return out;
}

struct Comparison {
  std::vector<std::string> names;
  std::vector<KsResult> ks;
  double min_p() const {
    double p = 1.0;
    for (const auto& r : ks) p = std::min(p, r.p);
    return p;
  }
};

inline Comparison compare_0d(const Sample0D& a, const Sample0D& b, const char* label) {
  Comparison c;
  const char* times[3] = {"2.5", "5", "20"};
  for (int j = 0; j < 3; ++j) {
    c.names.push_back(std::string("A(t=") + times[j] + ")");
    c.ks.push_back(ks_two_sample(a.area[j], b.area[j]));
    c.names.push_back(std::string("sigma(t=") + times[j] + ")");
    c.ks.push_back(ks_two_sample(a.sigma[j], b.sigma[j]));
  }
  c.names.push_back("steady sigma");
  c.ks.push_back(ks_two_sample(a.steady_sigma, b.steady_sigma));
  c.names.push_back("steady A");
  c.ks.push_back(ks_two_sample(a.steady_area, b.steady_area));
  std::printf("%s:", label);
  for (std::size_t k = 0; k < c.ks.size(); ++k) std::printf(" %s D=%.3f p=%.2g;", c.names[k].c_str(), c.ks[k].d, c.ks[k].p);
  std::printf("\n");
  return c;
}

}  // namespace slipfront::testing
