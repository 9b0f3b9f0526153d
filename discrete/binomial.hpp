#pragma once
// Binomial draws of the count representation (discrete/count_law.hpp), with a probability's set-up computed once.
#include <boost/random/binomial_distribution.hpp>
#include <boost/random/uniform_01.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "discrete/streams.hpp"

namespace slipfront::discrete::detail {

/// A binomial success probability with what the draws need of it, computed once (binomial below).
struct BinomialRate {
  double p = 0.0, small = 0.0, log_q = 0.0;  ///< p, p' = min(p, 1 − p) as boost takes it, log(1 − p')
  BinomialRate() = default;
  explicit BinomialRate(double prob) : p(prob), small(0.5 < prob ? 1 - prob : prob), log_q(std::log(1 - small)) {}
};

// Binomial(n, p) draws from the site's stream, as boost::random::binomial_distribution<int64_t, double> makes them,
// draw for draw: for a small mean ((n + 1) p' < 11, p' = min(p, 1 − p)) its inversion, whose set-up computes
// (1 − p')^n with pow, here exp(n log(1 − p')) with the logarithm computed once per probability (BinomialRate: the
// step's rates are shared by the bins of a site, and 1/(B − b) of the uniform spread by every step); above it,
// boost's own BTRD. The two products differ by ~1e-15 relatively, so a draw differs only when its uniform falls that
// close to a cumulative boundary (never seen: tests/test_discrete_count.cpp compares 10^6 draws with boost's, and the count law's runs are
// bit for bit those before it). Written by hand (boost's inversion loop, copied in its arithmetic): the pow was ~45 % of a disordered count
// run (perf of validity_friction, docs/performance.md §17). No draw when the outcome is certain (n = 0, p = 0 or
// p = 1): a draw is spent only where the scene needs one.
inline double binomial(Engine& e, double n, const BinomialRate& r) {
  if (n <= 0.0 || r.p <= 0.0) return 0.0;
  if (r.p >= 1.0) return n;
  const auto t = static_cast<std::int64_t>(n);
  if (static_cast<std::int64_t>(static_cast<double>(t + 1) * r.small) >= 11) {  // boost's BTRD (use_inversion() is m < 11)
    boost::random::binomial_distribution<std::int64_t, double> dist(t, r.p);
    return static_cast<double>(dist(e));
  }
  // boost's invert(t, p'), with q_n = (1 − p')^t
  const double pp = 0.5 < r.p ? 1 - r.p : r.p;
  const double q = 1 - pp, s = pp / q, a = static_cast<double>(t + 1) * s;
  double rr = std::exp(static_cast<double>(t) * r.log_q);
  double u = boost::random::uniform_01<double>()(e);
  std::int64_t x = 0;
  while (u > rr) {
    u = u - rr;
    ++x;
    const double r1 = ((a / static_cast<double>(x)) - s) * rr;
    if (r1 < std::numeric_limits<double>::epsilon() && r1 < rr) break;
    rr = r1;
  }
  return static_cast<double>(0.5 < r.p ? t - x : x);
}
inline double binomial(Engine& e, double n, double p) { return binomial(e, n, BinomialRate(p)); }

// A uniform integer in [0, m), m ≥ 1, from one engine call (rarely more): Lemire's multiply-and-reject (ACM TOMACS
// 2019), exact for every m. Written by hand: boost's uniform_int_distribution divides twice per draw.
__extension__ using uint128 = unsigned __int128;
inline std::size_t uniform_below(Engine& e, std::uint64_t m) {
  static_assert(Engine::word_size == 64, "a full 64-bit engine: every value of e() equally likely in [0, 2^64)");
  uint128 p = static_cast<uint128>(e()) * m;
  auto low = static_cast<std::uint64_t>(p);
  if (low < m) {
    const std::uint64_t reject_below = (0 - m) % m;  // 2^64 mod m
    while (low < reject_below) {
      p = static_cast<uint128>(e()) * m;
      low = static_cast<std::uint64_t>(p);
    }
  }
  return static_cast<std::size_t>(p >> 64);
}

}  // namespace slipfront::discrete::detail
