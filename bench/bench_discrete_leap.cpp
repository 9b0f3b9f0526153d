// The stochastic laws on accuracy-chosen steps (issue 22 item 2, core/leap.hpp, docs/performance.md §16): fig1
// with the discrete model on the step-controlled implicit integrator (time.integrator = adaptive) against the
// fixed-step integrators and against the adaptive continuum, all in this one process run. Per case: the median over
// repetitions of the run's own wall clock (integration and measurements, output excluded), its ratio to the
// adaptive continuum's, the steps and trial solves, and, over seeds, the mean and standard deviation of t^ and
// x_arrest (the accuracy side: a cheaper run must give the same distribution of events).
//
//   build/bench/bench_discrete_leap                 (~2 min on 2 cores)
//   SLIPFRONT_BENCH_SEEDS=16 ...                    seeds per case (default 8)
//   SLIPFRONT_BENCH_QUICK=1 ...                     smoke test (2 seeds, fig1 to t_end = 60)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "tests/scenes.hpp"
#include "bench/scenes.hpp"

using namespace slipfront;

namespace {

using bench::quick;
int seeds() { return bench::seeds(8, 2); }

struct Case {
  const char* label;
  const char* model;  // "continuum" or "discrete"
  const char* rep;
  long n;
  bool noise;
  core::Integrator integ;
  double dt;  // implicit only
};

compare::Scene scene(const Case& c, unsigned seed) {
  compare::Scene s = testing::fig1_scene();
  if (quick()) s.time.t_end = 60.0;
  s.models = {c.model};
  s.output.snapshot_dt = 0.0;
  s.time.integrator = c.integ;
  if (c.integ == core::Integrator::implicit_trapezoidal) s.time.dt = c.dt;
  s.discrete.representation = c.rep;
  s.discrete.contacts_per_site = c.n;
  s.discrete.noise = c.noise;
  s.discrete.threshold = "delta";
  s.discrete.width = 0.0;
  s.discrete.seed = seed;
  s.validate();
  return s;
}

compare::ModelResult run(const compare::Scene& s) {
  auto out = compare::run_scene(s, compare::RunControl{});
  if (out.empty() || out.back().status != compare::RunStatus::complete) {
    std::fprintf(stderr, "run failed: %s\n", out.empty() ? "no result" : out.back().message.c_str());
    std::exit(1);
  }
  return std::move(out.back());
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

struct Stat {
  double mean = 0, sd = 0;
  int n = 0;
};
// Mean and standard deviation over the finite values (a run with no transient, or no arrest by t_end, has NaN),
// and how many there were.
Stat stat(const std::vector<double>& all) {
  std::vector<double> x;
  for (double v : all)
    if (std::isfinite(v)) x.push_back(v);
  Stat s;
  s.n = static_cast<int>(x.size());
  if (x.empty()) return {NAN, NAN, 0};
  for (double v : x) s.mean += v / static_cast<double>(x.size());
  for (double v : x) s.sd += (v - s.mean) * (v - s.mean);
  s.sd = x.size() > 1 ? std::sqrt(s.sd / static_cast<double>(x.size() - 1)) : 0.0;
  return s;
}

}  // namespace

int main() {
  using core::Integrator;
  const int S = seeds();
  const std::vector<Case> cases = {
      {"continuum adaptive (baseline)", "continuum", "count", 1, true, Integrator::adaptive_rosenbrock, 0},
      {"count N=1e3 explicit", "discrete", "count", 1000, true, Integrator::central_difference, 0},
      {"count N=1e3 implicit dt=0.02", "discrete", "count", 1000, true, Integrator::implicit_trapezoidal, 0.02},
      {"count N=1e3 leap", "discrete", "count", 1000, true, Integrator::adaptive_rosenbrock, 0},
      {"count N=1e4 explicit", "discrete", "count", 10000, true, Integrator::central_difference, 0},
      {"count N=1e4 implicit dt=0.02", "discrete", "count", 10000, true, Integrator::implicit_trapezoidal, 0.02},
      {"count N=1e4 leap", "discrete", "count", 10000, true, Integrator::adaptive_rosenbrock, 0},
      {"count noise off leap", "discrete", "count", 1000, false, Integrator::adaptive_rosenbrock, 0},
      {"agent N=1e4 implicit dt=0.02", "discrete", "agent", 10000, true, Integrator::implicit_trapezoidal, 0.02},
      {"agent N=1e4 leap", "discrete", "agent", 10000, true, Integrator::adaptive_rosenbrock, 0},
  };
  std::printf("fig1%s, %d seeds per stochastic case; wall = median over seeds of the run's own clock (output excluded)\n",
              quick() ? " (quick: t_end = 60)" : "", S);
  std::printf("%-30s %10s %12s %8s %8s %10s %8s %10s %8s %6s\n", "case", "wall [s]", "vs continuum", "steps", "solves",
              "t^ mean", "t^ sd", "x_arr mean", "x_arr sd", "runs");
  double base = NAN;
  for (const Case& c : cases) {
    const bool stochastic = std::string(c.model) == "discrete" && c.noise;
    const bool agent = std::string(c.rep) == "agent";
    const int reps = stochastic ? (agent ? std::min(S, 3) : S) : 5;
    std::vector<double> wall, steps, solves, th, xa;
    for (int k = 1; k <= reps; ++k) {
      const auto r = run(scene(c, static_cast<unsigned>(k)));
      wall.push_back(r.wall_seconds);
      steps.push_back(r.scalars.at("steps"));
      solves.push_back(r.scalars.count("trial_solves") ? r.scalars.at("trial_solves") : r.scalars.at("steps"));
      th.push_back(r.events.t_hat);
      xa.push_back(r.events.x_arrest);
    }
    const double w = median(wall);
    if (std::isnan(base)) base = w;
    const Stat t = stat(th), x = stat(xa);
    std::printf("%-30s %10.4f %12.2f %8.0f %8.0f %10.3f %8.3f %10.3f %8.3f %3d/%-2d\n", c.label, w, w / base,
                median(steps), median(solves), t.mean, t.sd, x.mean, x.sd, x.n, reps);
  }
  std::printf("ratios: each case's median wall over the adaptive continuum's, measured in this run; means and sds over\n"
              "the runs with the event (runs: those with an arrest by t_end, of all)\n");
  return 0;
}
