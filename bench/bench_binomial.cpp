// The count representation's binomial draws (discrete/binomial.hpp) against boost's binomial_distribution built
// per draw, the baseline, in one process: the draw pattern of one disordered site-step with fresh renewal, 64 bins
// (discrete/count_law.cpp: step_contacts_sampled) — k = 32 overloaded bins lose contacts at one shared rate, then
// the new attachments are spread over the bins by successive binomials 1/(B − b) — at the rates and steps of
// validity_friction's sweep, N = 10^3 … 10^5 contacts per site.
// Both draw the same numbers (tests/test_discrete_count.cpp); the ratio is the cost of boost's set-up (its pow)
// per draw.
//
//   ./bench_binomial          prints, per N, ns per site-step of each and the ratios to the baseline
#include <benchmark/benchmark.h>

#include <algorithm>
#include <boost/random/binomial_distribution.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <vector>

#include "discrete/binomial.hpp"
#include "discrete/streams.hpp"

using namespace slipfront;

namespace {

constexpr std::size_t B = 64, k = 32;  // bins, overloaded bins (τ inside g's support)
std::map<std::pair<int, int>, double> ns_per_step;

double boost_draw(discrete::Engine& e, double n, double p) {
  if (n <= 0.0 || p <= 0.0) return 0.0;
  if (p >= 1.0) return n;
  boost::random::binomial_distribution<std::int64_t, double> d(static_cast<std::int64_t>(n), p);
  return static_cast<double>(d(e));
}

template <int mode>  // 0 boost per draw, 1 cached rates, 2 cached rates and the sparse spread by placement
void BM_site_step(benchmark::State& state) {
  constexpr bool cached = mode >= 1;
  // validity_friction's sweep (configs/studies/validity_friction.toml): 13 rates v = 0.02 … 10 (log), each with its
  // step dt = (t_end + slip_end/v)/steps = (20 + 40/v)/3000 and the steady state A = 1/(1 + κv) (κ = 8); an
  // iteration is one site-step at each of the 13 rates
  const double N = static_cast<double>(state.range(0)), kappa = 8.0;
  struct Rate {
    double leave_p, attach_p, area;
  };
  std::vector<Rate> rates;
  for (int j = 0; j < 13; ++j) {
    const double v = 0.02 * std::pow(500.0, j / 12.0), dt = (20.0 + 40.0 / v) / 3000.0, d = kappa * v, r = 1.0 + d;
    rates.push_back({d * -std::expm1(-r * dt) / r, -std::expm1(-dt), 1.0 / r});
  }
  discrete::Engine e = discrete::site_engine(3, 0);
  std::vector<discrete::detail::BinomialRate> share(B + 1);
  for (std::size_t m = 2; m <= B; ++m) share[m] = discrete::detail::BinomialRate(1.0 / static_cast<double>(m));
  std::vector<double> at(B);
  std::int64_t steps = 0;
  for (auto _ : state) {
    double lost = 0.0;
    for (const Rate& rt : rates) {
      std::fill(at.begin(), at.end(), std::floor(rt.area * N / B));
      const discrete::detail::BinomialRate leave(rt.leave_p);
      for (std::size_t b = 0; b < k; ++b) {
        const double x = cached ? discrete::detail::binomial(e, at[b], leave) : boost_draw(e, at[b], rt.leave_p);
        at[b] -= x;
        lost += x;
      }
      double n_det = N;
      for (double v : at) n_det -= v;
      double x = cached ? discrete::detail::binomial(e, n_det, rt.attach_p) : boost_draw(e, n_det, rt.attach_p);
      if (mode == 2 && x < 8.0 * B) {  // count_law.cpp spread_uniform: each contact's bin drawn
        for (auto j = static_cast<std::int64_t>(x); j > 0; --j) at[discrete::detail::uniform_below(e, B)] += 1.0;
        x = 0.0;
      }
      for (std::size_t b = 0; b < B && x > 0.0; ++b) {
        const std::size_t left = B - b;
        const double y = left == 1 ? x : cached ? discrete::detail::binomial(e, x, share[left])
                                                : boost_draw(e, x, 1.0 / static_cast<double>(left));
        at[b] += y;
        x -= y;
      }
    }
    benchmark::DoNotOptimize(lost);
    ++steps;
  }
  state.SetItemsProcessed(steps);
}
BENCHMARK_TEMPLATE(BM_site_step, 0)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_TEMPLATE(BM_site_step, 1)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_TEMPLATE(BM_site_step, 2)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000);

class Collect : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      const std::string name = r.benchmark_name();
      const int mode = name.find("<2>") != std::string::npos ? 2 : name.find("<1>") != std::string::npos ? 1 : 0;
      const int n = std::stoi(name.substr(name.rfind('/') + 1));
      ns_per_step[{n, mode}] = r.GetAdjustedRealTime();
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  Collect reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  std::printf("\none disordered site-step at each of the 13 rates (64 bins, 32 overloaded): boost per draw (the baseline), "
              "cached rates, cached rates + the sparse spread by placement (count_law.cpp)\n");
  for (const int n : {100, 1000, 10000, 100000}) {
    const auto a = ns_per_step.find({n, 0}), b = ns_per_step.find({n, 1}), c = ns_per_step.find({n, 2});
    if (a == ns_per_step.end() || b == ns_per_step.end() || c == ns_per_step.end()) continue;
    std::printf("N = %6d: boost %8.1f ns, cached %8.1f ns (ratio %.2f), + placement %8.1f ns (ratio %.2f)\n", n,
                a->second, b->second, a->second / b->second, c->second, a->second / c->second);
  }
}
