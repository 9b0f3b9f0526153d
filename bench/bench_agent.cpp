// Agent representation (discrete::AgentLaw, event-driven) against the naive baseline
// (discrete::NaiveAgentLaw, every contact every step), w = 0, paper interface (α = 1.05, κ = 8, η = 0.1):
//
//   steady  64 sites sliding at v = 1 (κv = 8, A = 1/9), started in steady state, dt = 1e-3, 1000
//           steps: the law alone (no bulk). Both laws also report the time-averaged A (mean over the
//           64 independent sites ± SE): they must agree within the combined SE (and ≈ 1/(1+κv)).
//   mixed   the same with 56 of the 64 sites stuck (v = 0, A = 1, σ̄ = 0.5): fig1-like, most of an
//           interface is stuck most of the time.
//   fig1    the fig1 scene (docs/model.md §4: edge loading, L = 300, dx = 0.5, cfl = 0.5) to t_end = 40
//           (through first yield; SLIPFRONT_BENCH_T_END to change), through compare::run_dynamic
//           (bulk and measurements included). The naive law only at N = 100 unless
//           SLIPFRONT_BENCH_NAIVE_FIG1=1 (it takes minutes at N = 10^4).
//
// After the table it prints, measured in the same run, ns per site-step and the ratio naive/agent
// for each case and N, and the statistical check of the steady case. Times are process CPU time
// (single-threaded), so that a loaded machine does not distort the ratios.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <time.h>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/naive_law.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

struct Record {
  double ns_per_site_step = 0.0;
  double mean_area = 0.0, se_area = 0.0;  // steady case only
};
std::map<std::string, Record> results;  // "<case> <law> N=<n>" → measured numbers

const core::InterfaceParams paper = testing::paper_interface();

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

discrete::DiscreteParams params(long n) {
  discrete::DiscreteParams p;
  p.contacts_per_site = n;
  p.seed = 1;
  return p;
}

std::string key(const char* scene, const char* law, long n) {
  return std::string(scene) + " " + law + " N=" + std::to_string(n);
}

// The law alone: 64 sites, `sliding` of them at v = 1 in steady state, the rest stuck.
template <class Law>
void law_only(benchmark::State& state, const char* scene, const char* name, std::size_t sliding) {
  const long n = state.range(0);
  const std::size_t sites = 64, steps = 1000;
  const double dt = 1e-3, v_slide = 1.0;
  const double a_ss = 1.0 / (1.0 + paper.kappa * v_slide);
  Record rec;
  for (auto _ : state) {
    Law law(paper, params(n), sites);
    std::vector<double> v(sites, 0.0);
    for (std::size_t i = 0; i < sites; ++i) {
      if (i < sliding) {
        law.set_site(i, a_ss, paper.alpha * a_ss);
        v[i] = v_slide;
      } else {
        law.set_site(i, 1.0, 0.5);
      }
    }
    std::vector<double> sum(sites, 0.0);
    const double t0 = cpu_seconds();
    for (std::size_t k = 0; k < steps; ++k) {
      law.advance(dt, v);
      const auto a = law.contact_area();
      for (std::size_t i = 0; i < sliding; ++i) sum[i] += a[i];
    }
    const double sec = cpu_seconds() - t0;
    state.SetIterationTime(sec);
    rec.ns_per_site_step = 1e9 * sec / static_cast<double>(sites * steps);
    if (sliding > 1) {  // mean over the sliding sites (independent) of their time averages
      double m = 0.0, s2 = 0.0;
      for (std::size_t i = 0; i < sliding; ++i) m += sum[i] / steps;
      m /= static_cast<double>(sliding);
      for (std::size_t i = 0; i < sliding; ++i) s2 += (sum[i] / steps - m) * (sum[i] / steps - m);
      rec.mean_area = m;
      rec.se_area = std::sqrt(s2 / static_cast<double>(sliding - 1) / static_cast<double>(sliding));
    }
  }
  state.counters["ns_per_site_step"] = rec.ns_per_site_step;
  results[key(scene, name, n)] = rec;
}

void BM_steady_agent(benchmark::State& s) { law_only<discrete::AgentLaw>(s, "steady", "agent", 64); }
void BM_steady_naive(benchmark::State& s) { law_only<discrete::NaiveAgentLaw>(s, "steady", "naive", 64); }
void BM_mixed_agent(benchmark::State& s) { law_only<discrete::AgentLaw>(s, "mixed", "agent", 8); }
void BM_mixed_naive(benchmark::State& s) { law_only<discrete::NaiveAgentLaw>(s, "mixed", "naive", 8); }

template <class Law>
void fig1_run(benchmark::State& state, const char* name) {
  const long n = state.range(0);
  const compare::Scene s = bench::fig1_scene(40.0);
  const core::Bulk probe(s.bulk, s.drive, s.interface, s.grid.dx);
  Record rec;
  for (auto _ : state) {
    const double t0 = cpu_seconds();
    const auto r = compare::run_dynamic<Law>(s, Law(s.interface, params(n), probe.nodes()), name, compare::RunControl{});
    const double sec = cpu_seconds() - t0;
    state.SetIterationTime(sec);
    rec.ns_per_site_step = 1e9 * sec / (r.scalars.at("steps") * static_cast<double>(probe.nodes()));
    state.counters["t_star"] = r.events.t_star;
  }
  state.counters["ns_per_site_step"] = rec.ns_per_site_step;
  results[key("fig1", name, n)] = rec;
}

void BM_fig1_agent(benchmark::State& s) { fig1_run<discrete::AgentLaw>(s, "agent"); }
void BM_fig1_naive(benchmark::State& s) { fig1_run<discrete::NaiveAgentLaw>(s, "naive"); }

}  // namespace

BENCHMARK(BM_steady_agent)->Arg(100)->Arg(1000)->Arg(10000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_steady_naive)->Arg(100)->Arg(1000)->Arg(10000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_mixed_agent)->Arg(100)->Arg(1000)->Arg(10000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_mixed_naive)->Arg(100)->Arg(1000)->Arg(10000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_fig1_agent)->Arg(100)->Arg(1000)->Arg(10000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_fig1_naive)
    ->Apply([](benchmark::internal::Benchmark* b) {
      b->Arg(100);
      const char* all = std::getenv("SLIPFRONT_BENCH_NAIVE_FIG1");
      if (all && std::string(all) == "1") b->Arg(1000)->Arg(10000);
    })
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();

  std::printf("\nns per site-step, and naive/agent (same run):\n");
  std::printf("%-8s %7s %14s %14s %10s\n", "case", "N", "agent", "naive", "ratio");
  for (const char* scene : {"steady", "mixed", "fig1"})
    for (long n : {100L, 1000L, 10000L}) {
      const auto a = results.find(key(scene, "agent", n)), b = results.find(key(scene, "naive", n));
      if (a == results.end()) continue;
      if (b == results.end()) {
        std::printf("%-8s %7ld %14.1f %14s %10s\n", scene, n, a->second.ns_per_site_step, "-", "-");
        continue;
      }
      std::printf("%-8s %7ld %14.1f %14.1f %10.1f\n", scene, n, a->second.ns_per_site_step, b->second.ns_per_site_step,
                  b->second.ns_per_site_step / a->second.ns_per_site_step);
    }
  std::printf("\nsteady A (64 sites x 1000 steps, mean over sites ± SE; 1/(1+kv) = %.5f):\n", 1.0 / 9.0);
  for (long n : {100L, 1000L, 10000L}) {
    const auto a = results.find(key("steady", "agent", n)), b = results.find(key("steady", "naive", n));
    if (a == results.end() || b == results.end()) continue;
    const double z = (a->second.mean_area - b->second.mean_area) /
                     std::sqrt(a->second.se_area * a->second.se_area + b->second.se_area * b->second.se_area);
    std::printf("N=%6ld agent %.5f ± %.5f   naive %.5f ± %.5f   difference %.2f SE %s\n", n, a->second.mean_area,
                a->second.se_area, b->second.mean_area, b->second.se_area, z, std::abs(z) < 4.0 ? "(agree)" : "(DISAGREE)");
  }
  return 0;
}
