// The discrete count representation against the continuum on fig1 (issue 5 target: count, N = 1000,
// w = 0, at most 3x the continuum's wall time), everything measured in one run (docs/scaling.md).
//
//   build/bench/bench_discrete_implicit [--csv FILE]
//   SLIPFRONT_BENCH_SEEDS=24 build/bench/bench_discrete_implicit     more seeds (default 12)
//   SLIPFRONT_BENCH_QUICK=1  build/bench/bench_discrete_implicit     smoke test (3 seeds, t_end 60)
//   SLIPFRONT_BENCH_DTS=0.0014,0.005 ...                             other implicit steps
//   SLIPFRONT_BENCH_N=10000 ...                                      other contacts per site
//
// Rows (whole fig1, t_end = 140, wall = the run's own clock, output excluded):
//   continuum  adaptive rtol 1e-2  the cheapest continuum within 1% of the reference (docs/performance.md)
//   continuum  explicit cfl 0.5    the reference scheme (dt = 0.0014)
//   continuum  implicit dt         time.integrator = implicit at dt = 0.01, 0.02, 0.05
//   count N=1000 explicit cfl 0.5 and implicit dt = 0.01, 0.02, 0.05, over S seeds each
// For the discrete rows: mean wall, mean t^ and c_transient with their standard errors over seeds, and
// the time-step bias = mean(implicit) − mean(explicit) over the same seeds in units of its standard
// error (z); the continuum rows give the continuum's own time-step error at the same dt for scale.
// Continuum walls are the minimum of 3 repetitions (the machine is shared); discrete walls are means.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "core/implicit.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "tests/scenes.hpp"
#include "bench/scenes.hpp"

using namespace slipfront;

namespace {

using bench::quick;
long contacts() { return std::getenv("SLIPFRONT_BENCH_N") ? std::atol(std::getenv("SLIPFRONT_BENCH_N")) : 1000; }

bool beyond_guard(const compare::Scene& s) {
  const core::Bulk b(s.bulk, s.drive, s.interface, s.grid.dx);
  return !core::implicit_resolution(b, s.interface, s.measure.v_event, s.time.dt).ok();
}

compare::Scene fig1(const std::string& integrator, double dt) {
  compare::Scene s = testing::fig1_scene();
  if (quick()) s.time.t_end = 60.0;
  s.models = {"continuum"};
  s.time.integrator = core::integrator_from_string(integrator);
  if (integrator == "implicit") {
    s.time.dt = dt;
    // Steps beyond the implicit accuracy guard (docs/robustness.md §7; fig1: dt <= 0.0316, the drive
    // spring) are run anyway, with the guard off, to show what the step does; the table marks them.
    if (beyond_guard(s)) s.time.implicit_resolution_check = false;
  }
  if (integrator == "adaptive") s.time.rtol = 1e-2;
  s.discrete.contacts_per_site = contacts();
  s.discrete.threshold = "delta";
  s.discrete.width = 0.0;
  s.discrete.representation = "count";
  s.validate();
  return s;
}

compare::ModelResult run(compare::Scene s, const std::string& model, unsigned seed = 1) {
  s.models = {model};
  s.discrete.seed = seed;
  auto out = compare::run_scene(s, compare::RunControl{});
  if (out.empty() || out.back().status != slipfront::compare::RunStatus::complete) {
    std::fprintf(stderr, "run failed: %s\n", out.empty() ? "no result" : out.back().message.c_str());
    std::exit(1);
  }
  return std::move(out.back());
}

// Over the finite values (a run with no transient before t_end has t^ = c_transient = NaN).
struct Stats {
  double mean = 0, se = NAN, median = NAN;
  int missing = 0;
};
Stats stats(const std::vector<double>& all) {
  std::vector<double> x;
  for (double v : all) (std::isfinite(v) ? x.push_back(v) : void());
  Stats s;
  s.missing = static_cast<int>(all.size() - x.size());
  if (x.empty()) return s;
  const double n = static_cast<double>(x.size());
  for (double v : x) s.mean += v / n;
  double ss = 0;
  for (double v : x) ss += (v - s.mean) * (v - s.mean);
  if (x.size() > 1) s.se = std::sqrt(ss / (n - 1) / n);
  std::sort(x.begin(), x.end());
  s.median = x.size() % 2 ? x[x.size() / 2] : 0.5 * (x[x.size() / 2 - 1] + x[x.size() / 2]);
  return s;
}

// Mann–Whitney U of b against a, as a z score (normal approximation with ties averaged; NaN = later
// than everything when nan_high, else dropped): > 0 when b tends to be larger. Rank-based, so a
// bimodal sample (N = 1000: re-stuck fronts) does not fool it the way a mean does.
double mann_whitney_z(std::vector<double> a, std::vector<double> b, bool nan_high) {
  auto clean = [&](std::vector<double>& v) {
    std::vector<double> out;
    for (double x : v)
      if (std::isfinite(x)) out.push_back(x);
      else if (nan_high) out.push_back(INFINITY);
    v = out;
  };
  clean(a);
  clean(b);
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  if (a.empty() || b.empty()) return NAN;
  double u = 0;
  for (double y : b)
    for (double x : a) u += y > x ? 1.0 : (y == x ? 0.5 : 0.0);
  return (u - na * nb / 2) / std::sqrt(na * nb * (na + nb + 1) / 12);
}

struct Row {
  std::string model, integrator;
  double dt;
  double wall;
  std::vector<double> t_hat, c_tr, walls;
};

// --- the stages of main ----------------------------------------------------------------------------

struct Options {
  std::string csv;              ///< --csv FILE (none when empty)
  int seeds = 0;                ///< discrete seeds 1..seeds per integrator
  std::vector<double> dts;      ///< the implicit steps
};

// The command line (--csv) and the environment (SLIPFRONT_BENCH_QUICK, _SEEDS, _DTS).
Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--csv") == 0) o.csv = argv[i + 1];
  o.seeds = quick() ? 3 : (std::getenv("SLIPFRONT_BENCH_SEEDS") ? std::atoi(std::getenv("SLIPFRONT_BENCH_SEEDS")) : 12);
  o.dts = {0.01, 0.02, 0.05};
  if (const char* e = std::getenv("SLIPFRONT_BENCH_DTS")) {  // e.g. "0.0014,0.005"
    o.dts.clear();
    for (const char* p = e; *p;) {
      char* end = nullptr;
      o.dts.push_back(std::strtod(p, &end));
      p = *end ? end + 1 : end;
    }
  }
  return o;
}

// Continuum rows (adaptive rtol 1e-2, explicit, implicit at each dt): minimum wall over 3 repetitions.
void run_continuum(const Options& o, std::vector<Row>& rows) {
  auto continuum = [&](const std::string& integ, double dt) {
    Row r{"continuum", integ, dt, 1e30, {}, {}, {}};
    for (int k = 0; k < 3; ++k) {
      const auto m = run(fig1(integ, dt), "continuum");
      r.wall = std::min(r.wall, m.wall_seconds);
      if (k == 0) {
        r.t_hat.push_back(m.events.t_hat);
        r.c_tr.push_back(m.events.c_transient);
        if (m.scalars.count("dt")) r.dt = m.scalars.at("dt");
      }
    }
    rows.push_back(r);
    std::fprintf(stderr, "continuum %s dt %g: %.3f s\n", integ.c_str(), r.dt, r.wall);
  };
  continuum("adaptive", 0);
  continuum("explicit", 0);
  for (double dt : o.dts) continuum("implicit", dt);
}

// Discrete rows (count, explicit and implicit at each dt): the same seeds 1..S for every integrator.
void run_count(const Options& o, std::vector<Row>& rows) {
  auto discrete = [&](const std::string& integ, double dt) {
    Row r{"count N=" + std::to_string(contacts()), integ, dt, 0, {}, {}, {}};
    for (int k = 1; k <= o.seeds; ++k) {
      const auto m = run(fig1(integ, dt), "discrete", static_cast<unsigned>(k));
      r.walls.push_back(m.wall_seconds);
      r.t_hat.push_back(m.events.t_hat);
      r.c_tr.push_back(m.events.c_transient);
      if (m.scalars.count("dt")) r.dt = m.scalars.at("dt");
    }
    r.wall = stats(r.walls).mean;
    rows.push_back(r);
    std::fprintf(stderr, "count %s dt %g: %.3f s per run\n", integ.c_str(), r.dt, r.wall);
  };
  discrete("explicit", 0);
  for (double dt : o.dts) discrete("implicit", dt);
}

// The rows the others are measured against.
struct Baselines {
  const Row& adaptive;    ///< continuum, adaptive rtol 1e-2
  const Row& explicit_c;  ///< continuum, explicit
  const Row& explicit_d;  ///< count, explicit
};

// The table: per row its wall, t^ and c_transient statistics, the shift against the explicit runs,
// and the wall against the continuum's adaptive one.
void print_table(const std::vector<Row>& rows, const Baselines& base, const Options& o) {
  const Row& adaptive = base.adaptive;
  const Row& explicit_c = base.explicit_c;
  const Row& explicit_d = base.explicit_d;
  std::printf("fig1 (t_end = %g), count representation N = %ld, w = 0, %d seeds; continuum walls: min of 3\n",
              fig1("explicit", 0).time.t_end, contacts(), o.seeds);
  std::printf("(discrete: mean +- standard error over seeds with a transient, median, runs with no transient before\n"
              " t_end; 'shift' = the continuum's error against the explicit reference, or for the discrete rows the\n"
              " Mann-Whitney z of the implicit runs against the explicit runs (|z| > 2.6: 1%% two-sided false alarm))\n");
  std::printf("%-13s %-9s %8s %8s %8s %6s %8s %3s %7s %6s %7s %8s %8s %9s\n", "model", "integ", "dt", "wall [s]", "t^",
              "+-se", "median", "nan", "c_tr", "+-se", "median", "shift t^", "shift c", "/adaptive");
  for (const auto& r : rows) {
    const Stats th = stats(r.t_hat), c = stats(r.c_tr);
    std::printf("%-13s %-9s %8.4g %8.4f %8.3f %6.3f %8.3f %3d %7.3f %6.3f %7.3f", r.model.c_str(), r.integrator.c_str(),
                r.dt, r.wall, th.mean, th.se, th.median, th.missing, c.mean, c.se, c.median);
    if (r.model == "continuum") {
      std::printf(" %7.2f%% %7.2f%%", 100 * (th.mean / explicit_c.t_hat[0] - 1), 100 * (c.mean / explicit_c.c_tr[0] - 1));
    } else if (&r != &explicit_d) {
      std::printf(" %7.2fz %7.2fz", mann_whitney_z(explicit_d.t_hat, r.t_hat, true),
                  mann_whitney_z(explicit_d.c_tr, r.c_tr, false));
    } else {
      std::printf(" %8s %8s", "-", "-");
    }
    std::printf(" %9.2f%s\n", r.wall / adaptive.wall,
                r.integrator == "implicit" && beyond_guard(fig1("implicit", r.dt)) ? "  *" : "");
  }
  std::printf("(* beyond the implicit accuracy guard, docs/robustness.md section 7: run with "
              "time.implicit_resolution_check = false)\n");
}

// The count representation's wall against the continuum: adaptive, the same integrator at the same
// dt, explicit.
void print_ratios(const std::vector<Row>& rows, const Baselines& base) {
  auto continuum_at = [&](const Row& d) -> const Row& {
    for (const auto& r : rows)
      if (r.model == "continuum" && r.integrator == d.integrator && (d.integrator != "implicit" || r.dt == d.dt)) return r;
    return base.explicit_c;
  };
  std::printf("\nratios of the count representation (N = %ld) to the continuum, wall time:\n", contacts());
  for (const auto& r : rows) {
    if (r.model == "continuum") continue;
    const Row& same = continuum_at(r);
    std::printf("  count %-8s dt %-7.4g: %6.2fx continuum adaptive (rtol 1e-2), %6.2fx continuum %s at the same dt, "
                "%6.2fx continuum explicit\n",
                r.integrator.c_str(), r.dt, r.wall / base.adaptive.wall, r.wall / same.wall, same.integrator.c_str(),
                r.wall / base.explicit_c.wall);
  }
}

// The CSV: one line per run (continuum rows: the first repetition, seed 0).
void write_csv(const std::string& csv, const std::vector<Row>& rows) {
  std::ofstream out(csv);
  out << "model,integrator,dt,seed,wall,t_hat,c_transient\n";
  for (const auto& r : rows)
    for (std::size_t k = 0; k < r.t_hat.size(); ++k)
      out << r.model << ',' << r.integrator << ',' << r.dt << ',' << (r.model == "continuum" ? 0 : k + 1) << ','
          << (r.walls.empty() ? r.wall : r.walls[k]) << ',' << r.t_hat[k] << ',' << r.c_tr[k] << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse_options(argc, argv);
  std::vector<Row> rows;
  run_continuum(o, rows);  // rows[0] adaptive, rows[1] explicit, then implicit at each dt
  run_count(o, rows);      // rows[2 + dts] explicit, then implicit at each dt
  const Baselines base{rows[0], rows[1], rows[2 + o.dts.size()]};
  print_table(rows, base, o);
  print_ratios(rows, base);
  if (!o.csv.empty()) write_csv(o.csv, rows);
  return 0;
}
