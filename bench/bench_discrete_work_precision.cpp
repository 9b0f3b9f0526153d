// Discrete work-precision (issue 5, item 1, discrete part; docs/scaling.md §4): error against the
// continuum vs whole-run wall time as N grows, for the count, agent and naive representations, on
// friction_law and fig1, over several seeds, all measured in one run.
//
//   build/bench/bench_discrete_work_precision [--csv FILE]      (~4 min on 2 cores)
//   SLIPFRONT_BENCH_SEEDS=8 ...        seeds per case (default 4)
//   SLIPFRONT_BENCH_QUICK=1 ...        smoke test (2 seeds, small N, fig1 to t_end 60)
//   /usr/bin/python3 scripts/plot_discrete_work_precision.py FILE   the plot
//
// friction_law (docs/model.md §4: 41 rates, 1e-3..1e2, 4000 exact steps per rate): error = RMS over the rates
//   of (σ_discrete − σ_ss)/σ_ss against the closed form the continuum reproduces to 1e-13.
// fig1 (docs/model.md §4, t_end = 140): errors |t^_d − t^_c|/t^_c and |c_d − c_c|/c_c against the continuum
//   on the explicit reference scheme (a run with no transient counts as error 1); the count
//   representation also on the implicit integrator at dt = 0.02 (docs/numerics.md §7).
// Per case: the mean wall time over seeds (the run's own clock, output excluded) and the mean error
// with its standard error over seeds. The naive baseline visits every contact every step; on fig1 it
// runs one seed at N = 1000 (40 s).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
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
int seeds() { return bench::seeds(4, 1); }

compare::Scene friction_law() {
  compare::Scene s = testing::imposed_rate_scene();
  s.drive.v_min = 1e-3;
  s.drive.v_max = 1e2;
  s.drive.sweep_points = quick() ? 11 : 41;
  s.time.t_end = 10.0;
  s.output.snapshot_dt = 0.0;
  return s;
}

compare::Scene fig1() {
  compare::Scene s = testing::fig1_scene();
  if (quick()) s.time.t_end = 60.0;
  return s;
}

compare::ModelResult run(compare::Scene s, const std::string& model, const std::string& rep = "count", long n = 0,
                         unsigned seed = 1, const std::string& integrator = "explicit") {
  s.models = {model};
  s.discrete.representation = rep;
  s.discrete.contacts_per_site = n > 0 ? n : 1;
  s.discrete.threshold = "delta";
  s.discrete.width = 0.0;
  s.discrete.seed = seed;
  if (integrator == "implicit") {
    s.time.integrator = core::Integrator::implicit_trapezoidal;
    s.time.dt = 0.02;
  }
  s.validate();
  auto out = compare::run_scene(s, compare::RunControl{});
  if (out.empty() || out.back().status != slipfront::compare::RunStatus::complete) {
    std::fprintf(stderr, "run %s/%s N=%ld failed: %s\n", model.c_str(), rep.c_str(), n,
                 out.empty() ? "no result" : out.back().message.c_str());
    std::exit(1);
  }
  return std::move(out.back());
}

struct MeanSe {
  double mean = 0, se = NAN;
};
MeanSe mean_se(const std::vector<double>& x) {
  MeanSe m;
  const double n = static_cast<double>(x.size());
  for (double v : x) m.mean += v / n;
  if (x.size() > 1) {
    double ss = 0;
    for (double v : x) ss += (v - m.mean) * (v - m.mean);
    m.se = std::sqrt(ss / (n - 1) / n);
  }
  return m;
}

double rel_err(double d, double c) { return std::isfinite(d) ? std::abs(d - c) / std::abs(c) : 1.0; }

struct Row {
  std::string scene, rep, integrator;
  long n;
  std::vector<double> wall, err1, err2;  // per seed; friction_law: err1 = RMS rel. error, err2 unused
};

// --- the stages of main ----------------------------------------------------------------------------

// --csv FILE: where to write the per-seed CSV (none when absent).
std::string csv_option(int argc, char** argv) {
  std::string csv;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--csv") == 0) csv = argv[i + 1];
  return csv;
}

// friction_law: the continuum (the closed form to 1e-13), then each representation at each N over seeds
// 1..S, error = RMS over the rates of (σ − σ_ss)/σ_ss. Appends its rows; returns the continuum run.
compare::ModelResult run_friction_law(int S, std::vector<Row>& rows) {
  const compare::Scene fl = friction_law();
  auto fl_c = run(fl, "continuum");
  std::fprintf(stderr, "friction_law continuum: %.3f s\n", fl_c.wall_seconds);
  struct Case {
    const char* rep;
    std::vector<long> ns;
  };
  const std::vector<Case> fl_cases =
      quick() ? std::vector<Case>{{"count", {10, 100, 1000}}, {"agent", {10, 100, 1000}}, {"naive", {10, 100}}}
              : std::vector<Case>{{"count", {10, 100, 1000, 10000, 100000}},
                                  {"agent", {10, 100, 1000, 10000}},
                                  {"naive", {10, 100, 1000, 10000}}};
  for (const auto& c : fl_cases)
    for (long n : c.ns) {
      Row r{"friction_law", c.rep, "exact", n, {}, {}, {}};
      for (int k = 1; k <= S; ++k) {
        const auto d = run(fl, "discrete", c.rep, n, static_cast<unsigned>(k));
        const auto& sig = d.friction_law.at("sigma");
        const auto& ref = d.friction_law.at("sigma_closed_form");
        double s2 = 0;
        for (std::size_t j = 0; j < sig.size(); ++j) s2 += std::pow((sig[j] - ref[j]) / ref[j], 2);
        r.wall.push_back(d.wall_seconds);
        r.err1.push_back(std::sqrt(s2 / static_cast<double>(sig.size())));
      }
      std::fprintf(stderr, "friction_law %s N=%ld: %.3f s\n", c.rep, n, mean_se(r.wall).mean);
      rows.push_back(std::move(r));
    }
  return fl_c;
}

// fig1: the continuum on the explicit scheme, then each representation and integrator at each N over
// its seeds, errors of t^ and c_transient against the continuum. Appends its rows; returns the continuum run.
compare::ModelResult run_fig1(int S, std::vector<Row>& rows) {
  const compare::Scene f1 = fig1();
  auto f1_c = run(f1, "continuum");
  const double th = f1_c.events.t_hat, ct = f1_c.events.c_transient;
  std::fprintf(stderr, "fig1 continuum: %.3f s, t_hat %.4f, c_transient %.4f\n", f1_c.wall_seconds, th, ct);
  struct Case1 {
    const char* rep;
    const char* integrator;
    std::vector<long> ns;
    int seeds;
  };
  const std::vector<Case1> f1_cases =
      quick() ? std::vector<Case1>{{"count", "explicit", {100, 1000}, S},
                                   {"count", "implicit", {1000}, S},
                                   {"agent", "explicit", {100}, S},
                                   {"naive", "explicit", {100}, 1}}
              : std::vector<Case1>{{"count", "explicit", {100, 1000, 10000, 100000}, S},
                                   {"count", "implicit", {1000, 10000, 100000}, S},
                                   {"agent", "explicit", {100, 1000, 10000}, S},
                                   {"naive", "explicit", {100}, S},
                                   {"naive", "explicit", {1000}, 1}};
  for (const auto& c : f1_cases)
    for (long n : c.ns) {
      Row r{"fig1", c.rep, c.integrator, n, {}, {}, {}};
      for (int k = 1; k <= c.seeds; ++k) {
        const auto d = run(f1, "discrete", c.rep, n, static_cast<unsigned>(k), c.integrator);
        r.wall.push_back(d.wall_seconds);
        r.err1.push_back(rel_err(d.events.t_hat, th));
        r.err2.push_back(rel_err(d.events.c_transient, ct));
      }
      std::fprintf(stderr, "fig1 %s %s N=%ld: %.3f s\n", c.rep, c.integrator, n, mean_se(r.wall).mean);
      rows.push_back(std::move(r));
    }
  return f1_c;
}

// The table: per case the mean wall and errors with their standard errors, and the wall against the continuum's.
void print_table(const std::vector<Row>& rows, int S, const compare::ModelResult& fl_c, const compare::ModelResult& f1_c) {
  std::printf("discrete work-precision, w = 0, noise on, seeds 1..%d per case (naive fig1 N = 1000: seed 1)\n", S);
  std::printf("continuum: friction_law %.3f s (closed form to 1e-13); fig1 explicit %.3f s, t_hat %.4f, c_transient %.4f\n\n",
              fl_c.wall_seconds, f1_c.wall_seconds, f1_c.events.t_hat, f1_c.events.c_transient);
  std::printf("%-13s %-6s %-9s %7s %5s %9s %10s %9s %10s %9s %8s\n", "scene", "repr", "integ", "N", "seeds", "wall [s]",
              "err 1", "+-se", "err 2", "+-se", "/contin.");
  for (const auto& r : rows) {
    const auto w = mean_se(r.wall), e1 = mean_se(r.err1);
    const double cw = r.scene == "fig1" ? f1_c.wall_seconds : fl_c.wall_seconds;
    std::printf("%-13s %-6s %-9s %7ld %5zu %9.4f %10.3e %9.1e", r.scene.c_str(), r.rep.c_str(), r.integrator.c_str(), r.n,
                r.wall.size(), w.mean, e1.mean, e1.se);
    if (!r.err2.empty()) {
      const auto e2 = mean_se(r.err2);
      std::printf(" %10.3e %9.1e", e2.mean, e2.se);
    } else {
      std::printf(" %10s %9s", "-", "-");
    }
    std::printf(" %8.2f\n", w.mean / cw);
  }
  std::printf("\nerr 1: friction_law RMS_v |sigma - sigma_ss|/sigma_ss; fig1 |t_hat - t_hat_c|/t_hat_c. err 2: fig1 "
              "|c_tr - c_tr_c|/c_tr_c (1 when no transient).\n");
}

// Representation ratios at equal N (same scene, same seeds): the agent's event-driven cost against
// the naive visit of every contact.
void print_ratios(const std::vector<Row>& rows) {
  for (const auto& a : rows)
    for (const auto& b : rows)
      if (a.scene == b.scene && a.n == b.n && a.rep == "agent" && b.rep == "naive" && a.integrator == b.integrator)
        std::printf("%s N=%ld: naive / agent wall = %.1f\n", a.scene.c_str(), a.n, mean_se(b.wall).mean / mean_se(a.wall).mean);
}

// The CSV for scripts/plot_discrete_work_precision.py: one line per run (case and seed).
void write_csv(const std::string& csv, const std::vector<Row>& rows, const compare::ModelResult& fl_c,
               const compare::ModelResult& f1_c) {
  std::ofstream out(csv);
  out << "scene,representation,integrator,N,seed,wall,err1,err2,continuum_wall\n";
  for (const auto& r : rows)
    for (std::size_t k = 0; k < r.wall.size(); ++k)
      out << r.scene << ',' << r.rep << ',' << r.integrator << ',' << r.n << ',' << k + 1 << ',' << r.wall[k] << ','
          << r.err1[k] << ',' << (r.err2.empty() ? NAN : r.err2[k]) << ','
          << (r.scene == "fig1" ? f1_c.wall_seconds : fl_c.wall_seconds) << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  const std::string csv = csv_option(argc, argv);
  const int S = seeds();
  std::vector<Row> rows;
  const auto fl_c = run_friction_law(S, rows);  // the continuum, then the cases
  const auto f1_c = run_fig1(S, rows);
  print_table(rows, S, fl_c, f1_c);
  print_ratios(rows);
  if (!csv.empty()) write_csv(csv, rows, fl_c, f1_c);
  return 0;
}
