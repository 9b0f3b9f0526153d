// The count representation's binomial draws (discrete/binomial.hpp) against boost's binomial_distribution built
// per draw, the baseline, in one process: the draw pattern of one disordered site-step with fresh renewal, 64 bins
// (discrete/count_law.cpp: step_contacts_sampled, as it was written for τ inside g's support; the study's sites turned
// out to sit at k = B, see the law below) — k = 32 overloaded bins lose contacts at one shared rate, then
// the new attachments are spread over the bins by successive binomials 1/(B − b) — at the rates and steps of
// validity_friction's sweep, N = 10^3 … 10^5 contacts per site.
// Both draw the same numbers (tests/test_discrete_count.cpp); the ratio is the cost of boost's set-up (its pow)
// per draw.
//
// Second, the count law itself (discrete::CountLaw) on the same sweep with uniform thresholds w = 0.05 (64 bins,
// fresh renewal, α = 1.05): one step at each of the 13 rates from the steady state, with the unspread arrivals
// (docs/discrete.md: a sliding site has every bin overloaded, k = B, and its new attachments wait unspread) against
// the baseline of the same law with its bins read after every step, which spreads them at every step as the law did
// before. What each costs per step is what validity_friction's disordered group spends.
//
//   ./bench_binomial          prints, per N, ns per site-step of each and the ratios to the baseline
//   SLIPFRONT_BENCH_QUICK=1 ./bench_binomial    the same tables, each case timed for 10 ms (the default test tier)
#include <benchmark/benchmark.h>

#include <algorithm>
#include <boost/random/binomial_distribution.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#include "discrete/binomial.hpp"
#include "discrete/count_law.hpp"
#include "discrete/streams.hpp"

using namespace slipfront;

namespace {

constexpr std::size_t B = 64, k = 32;  // bins, overloaded bins (τ inside g's support)
std::map<std::pair<int, int>, double> ns_per_step;  // (N, mode): 0–2 the draws, 3 the law settled each step, 4 unspread

double boost_draw(discrete::Engine& e, double n, double p) {
  if (n <= 0.0 || p <= 0.0) return 0.0;
  if (p >= 1.0) return n;
  boost::random::binomial_distribution<std::int64_t, double> d(static_cast<std::int64_t>(n), p);
  return static_cast<double>(d(e));
}

// validity_friction's sweep (configs/studies/validity_friction.toml): 13 rates v = 0.02 … 10 (log), each with its
// step dt = (t_end + slip_end/v)/steps = (20 + 40/v)/3000
struct SweepPoint {
  double v, dt;
};
std::vector<SweepPoint> validity_friction_sweep() {
  std::vector<SweepPoint> out;
  for (int j = 0; j < 13; ++j) {
    const double v = 0.02 * std::pow(500.0, j / 12.0);
    out.push_back({v, (20.0 + 40.0 / v) / 3000.0});
  }
  return out;
}

template <int mode>  // 0 boost per draw, 1 cached rates, 2 cached rates and the sparse spread by placement
void BM_site_step(benchmark::State& state) {
  constexpr bool cached = mode >= 1;
  // validity_friction_sweep(), each rate from the steady state A = 1/(1 + κv) (κ = 8); an iteration is one site-step
  // at each of the 13 rates
  const double N = static_cast<double>(state.range(0)), kappa = 8.0;
  struct Rate {
    double leave_p, attach_p, area;
  };
  std::vector<Rate> rates;
  for (const auto [v, dt] : validity_friction_sweep()) {
    const double d = kappa * v, r = 1.0 + d;
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

template <bool unspread>  // false: the bins read (so spread) after every step, the baseline
void BM_count_law(benchmark::State& state) {
  core::InterfaceParams ip;
  ip.alpha = 1.05;
  ip.kappa = 8.0;
  ip.eta = 0.1;
  discrete::DiscreteParams p;
  p.contacts_per_site = state.range(0);
  p.threshold = "uniform";
  p.width = 0.05;
  p.bins = 64;
  p.seed = 7;
  struct Point {
    discrete::CountLaw law;
    double v, dt;
  };
  std::vector<Point> points;
  for (const auto [v, dt] : validity_friction_sweep()) {  // each from its steady state
    const double a = 1.0 / (1.0 + ip.kappa * v);
    points.push_back({discrete::CountLaw(ip, p, 1), v, dt});
    points.back().law.set_site(0, a, ip.alpha * a);
  }
  auto step = [&] {
    double area = 0.0;
    for (Point& pt : points) {
      const double vv[1] = {pt.v};
      pt.law.advance(pt.dt, vv);
      if (!unspread) benchmark::DoNotOptimize(pt.law.attached(0).data());
      area += pt.law.contact_area()[0];
    }
    return area;
  };
  for (int n = 0; n < 300; ++n) step();  // settle into the steady state
  std::int64_t steps = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(step());
    ++steps;
  }
  state.SetItemsProcessed(steps);
}
BENCHMARK_TEMPLATE(BM_count_law, false)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_TEMPLATE(BM_count_law, true)->Arg(100)->Arg(1000)->Arg(10000)->Arg(100000);

class Collect : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      const std::string name = r.benchmark_name();
      const bool law = name.find("BM_count_law") != std::string::npos;
      const int mode = law ? (name.find("<true>") != std::string::npos ? 4 : 3)
                       : name.find("<2>") != std::string::npos ? 2
                       : name.find("<1>") != std::string::npos ? 1
                                                                 : 0;
      const int n = std::stoi(name.substr(name.rfind('/') + 1));
      ns_per_step[{n, mode}] = r.GetAdjustedRealTime();
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  // SLIPFRONT_BENCH_QUICK=1 (the default test tier): each case timed for 10 ms instead of 0.5 s, a smoke test of the tables
  std::vector<char*> args(argv, argv + argc);
  char quick_time[] = "--benchmark_min_time=0.01";
  if (std::getenv("SLIPFRONT_BENCH_QUICK") != nullptr) args.push_back(quick_time);
  int nargs = static_cast<int>(args.size());
  benchmark::Initialize(&nargs, args.data());
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
  std::printf("\nthe count law, one step at each of the 13 rates (w = 0.05, 64 bins, fresh): bins spread at every step "
              "(the baseline) against the unspread arrivals\n");
  for (const int n : {100, 1000, 10000, 100000}) {
    const auto a = ns_per_step.find({n, 3}), b = ns_per_step.find({n, 4});
    if (a == ns_per_step.end() || b == ns_per_step.end()) continue;
    std::printf("N = %6d: spread each step %8.1f ns, unspread %8.1f ns (ratio %.2f)\n", n, a->second, b->second,
                a->second / b->second);
  }
}
