// Cost per site-step of the count representation (discrete::CountLaw) against the continuum law on
// the fig1 scene (docs/model.md §4: edge loading, paper parameters, L = 300, dx = 0.5, cfl = 0.5), run through
// compare::run_dynamic like a real run (bulk stepping and measurements included). w = 0, noise on.
//
//   ./bench_discrete_count                        t_end = 80 (through first yield and the slow front)
//   SLIPFRONT_BENCH_T_END=140 ./bench_discrete_count   the whole fig1 sequence
//
// After the table it prints the time per site-step of each case (wall clock, and process CPU time,
// which is the fairer figure on a shared machine for one thread) and its ratio to the continuum.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <ctime>
#include <map>
#include <string>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "discrete/count_law.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

struct Cost {
  double wall_ns, cpu_ns;  // per site-step: wall clock, and process CPU time (robust on a busy machine)
};
std::map<std::string, Cost> cost;  // filled by each benchmark, read by main

compare::Scene fig1() { return bench::fig1_scene(80.0); }  // t_end = 80 unless SLIPFRONT_BENCH_T_END

template <class Law, class Make>
void run(benchmark::State& state, const std::string& label, Make make) {
  const compare::Scene s = fig1();
  const core::Bulk probe(s.bulk, s.drive, s.interface, s.grid.dx);
  double site_steps = 0.0, seconds = 0.0, cpu = 0.0;
  for (auto _ : state) {
    const std::clock_t c0 = std::clock();
    const auto r = compare::run_dynamic<Law>(s, make(probe.nodes()), label, compare::RunControl{});
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    benchmark::DoNotOptimize(r.events.t_star);
    site_steps += r.scalars.at("steps") * static_cast<double>(probe.nodes());
    seconds += r.wall_seconds;
    state.counters["t_star"] = r.events.t_star;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(site_steps));
  state.counters["wall_ns_per_site_step"] = 1e9 * seconds / site_steps;
  state.counters["cpu_ns_per_site_step"] = 1e9 * cpu / site_steps;
  cost[label] = {1e9 * seconds / site_steps, 1e9 * cpu / site_steps};
}

void BM_continuum(benchmark::State& state) {
  const compare::Scene s = fig1();
  run<continuum::FrictionLaw>(state, "continuum", [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); });
}

void BM_count(benchmark::State& state) {
  const compare::Scene s = fig1();
  discrete::DiscreteParams p;
  p.contacts_per_site = state.range(0);
  p.threads = static_cast<int>(state.range(1));
  p.seed = 1;
  const std::string label = "count N=" + std::to_string(p.contacts_per_site) + " threads=" + std::to_string(p.threads);
  run<discrete::CountLaw>(state, label, [&](std::size_t n) { return discrete::CountLaw(s.interface, p, n); });
}

}  // namespace

BENCHMARK(BM_continuum)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_count)
    ->Args({1000, 1})
    ->Args({100, 1})
    ->Args({10000, 1})
    ->Args({100000, 1})
    ->Args({1000, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  const auto c = cost.find("continuum");
  if (c == cost.end()) return 0;
  std::printf("\nfig1, t_end = %g: time per site-step (bulk + law + measurements)\n", fig1().time.t_end);
  std::printf("  %-28s %9s %9s   %s\n", "", "wall ns", "CPU ns", "ratio to continuum (wall, CPU)");
  for (const auto& [label, k] : cost)
    std::printf("  %-28s %9.1f %9.1f   %.2f  %.2f\n", label.c_str(), k.wall_ns, k.cpu_ns, k.wall_ns / c->second.wall_ns,
                k.cpu_ns / c->second.cpu_ns);
  return 0;
}
