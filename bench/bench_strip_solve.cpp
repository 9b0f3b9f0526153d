// Cost of the antiplane strip's implicit step solve (core::Strip::implicit_solve, docs/performance.md §12)
// against the number of nodes n = nx·rows, and the alternatives measured in the same run:
//   cg_dct_mean   Eigen CG, matrix-free, preconditioner = exact inverse of the separable part with the
//                 interface shift d̄ = η + mean(c1)/2 (mode factors recomputed per step): the chosen one
//   cg_dct_eta    the same with d̄ = η (factors made once per dt)
//   ldlt          Eigen SimplicialLDLT of the assembled sparse system, numeric refactorisation per step
//                 (c1 changes every step; the symbolic analysis is done once, outside the timing)
//   cg_jacobi     Eigen CG on the assembled matrix with its default diagonal preconditioner
//   cg_ichol      Eigen CG on the assembled matrix with IncompleteCholesky (factorised per step)
//   direct        Strip::solve_step by Strip::solve_system (StepSolver::direct): the capacitance method, a
//                 cosine-space direct solve of the separable part and CG on the interface row only; c1
//                 changes every step, so each step also makes the spring's ψ (one more interface solve)
//   direct_stage  Strip::solve_system with another right-hand side on the same (c, d): what a Rosenbrock
//                 stage costs (docs/performance.md §13); the "iterations" column: interface CG iterations
//   mixed_stage   Strip::solve_stage_mixed: the adaptive integrator's stage solve since its state is mixed (rows
//                 j ≥ 1 in cosine modes, docs/numerics.md §8.6): no transform of the bulk
//   mixed_stage_run  the same at the interface tolerance the adaptive integrator uses (1e-6 at rtol 1e-2)
//   stream        the memory traffic of mixed_stage's sweeps as plain streaming loops: the baseline whose ratio to
//                 mixed_stage_run divides the memory hierarchy out of the exponent
// Each solve starts from W = 0 with random u, V, σ̄, c0 and c1 ∈ [0, 2] (η = 0.1, dt = 0.02, dx = dy = 0.5,
// fig1's ρ = 0.01, μ = 300, edge loading K = 2.5): a cold start with high-frequency data, the hardest case
// (a time step warm-starts from the previous W).
//
//   build/bench/bench_strip_solve                          all sizes, up to 1.06e6 nodes (a few minutes)
//   SLIPFRONT_BENCH_QUICK=1 build/bench/bench_strip_solve  up to 2.7e5 nodes (smoke test)
//
// After Google Benchmark's table it prints one line per candidate and size (ms per solve, CG iterations,
// ns per node and iteration, the Strip's bytes per node), the fitted exponent of time vs n (must be ≤ 1.1
// for the chosen solver), and the ratio of each alternative to it.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include "core/strip.hpp"
#include "bench/scenes.hpp"

namespace core = slipfront::core;

namespace {

using slipfront::bench::quick;

// Two series: "long", one body (H = 32, rows = 65) made longer (nx 1025 → 16385): n grows at fixed
// physics; "diag", nx and rows both doubled (H grows 8 → 128, which changes the system: the interface
// row's mass term ρ' dy/dt falls as 1/H, so the spread of c1 counts more, see §12).
struct Size {
  std::size_t nx, rows;
  const char* series;
};
const std::vector<Size>& sizes() {
  static const std::vector<Size> full{{1025, 65, "long"},  {2049, 65, "long"},  {4097, 65, "long"},
                                      {8193, 65, "long"},  {16385, 65, "long"}, {257, 17, "diag"},
                                      {513, 33, "diag"},   {2049, 129, "diag"}, {4097, 257, "diag"}};
  static const std::vector<Size> small{{1025, 65, "long"}, {2049, 65, "long"}, {4097, 65, "long"},
                                       {129, 9, "diag"},   {257, 17, "diag"},  {513, 33, "diag"}};
  return quick() ? small : full;
}
// The assembled direct and Jacobi/IC candidates stop earlier (fill-in and time).
constexpr std::size_t assembled_max_nodes = 300000;

constexpr double dt = 0.02, eta = 0.1, dx = 0.5, dy = 0.5;

struct Problem {
  core::Strip strip;
  std::vector<double> u, V, sb, c0, c1, w_prev;
  explicit Problem(Size s) : strip(make(s)) {
    std::mt19937 g(42);
    std::uniform_real_distribution<double> d(-1.0, 1.0), c(0.0, 2.0);
    const std::size_t n = strip.dofs(), nx = strip.sites();
    u.resize(n);
    V.resize(n);
    for (auto& x : u) x = d(g);
    for (auto& x : V) x = d(g);
    sb.resize(nx);
    c0.resize(nx);
    c1.resize(nx);
    for (auto& x : sb) x = d(g);
    for (auto& x : c0) x = d(g);
    for (auto& x : c1) x = c(g);
    w_prev.assign(nx, 0.0);
  }
  static core::Strip make(Size s) {
    core::BulkParams b;
    b.rho = 0.01;
    b.mu = 300.0;
    b.length = static_cast<double>(s.nx - 1) * dx;
    b.height = static_cast<double>(s.rows - 1) * dy;
    core::DriveParams d;
    d.loading = core::Loading::edge;
    core::InterfaceParams l;
    return core::Strip(b, d, l, dx, dy);
  }
  auto lin() const {
    return [this](std::size_t i, double, double& a, double& b) {
      a = c0[i];
      b = c1[i];
    };
  }
  // The assembled system (the same as tests/test_strip_body.cpp's), for the assembled candidates.
  std::pair<Eigen::SparseMatrix<double>, Eigen::VectorXd> assembled() {
    std::vector<double> W(strip.dofs(), 0.0), cc0(strip.sites()), cc1(strip.sites());
    strip.implicit_solve(lin(), w_prev, cc0, cc1, 0.0, dt, eta, u, V, sb, W);  // also: the reference
    const auto n = static_cast<Eigen::Index>(strip.dofs());
    const std::size_t nx = strip.sites();
    Eigen::SparseMatrix<double> S = strip.stiffness_matrix();
    std::vector<Eigen::Triplet<double>> tr;
    for (std::size_t j = 0; j < strip.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const auto k = static_cast<Eigen::Index>(j * nx + i);
        double d = 2.0 * strip.node_mass(i, j) / dt;
        if (j == 0) d += strip.interface_weight(i) * (eta + 0.5 * c1[i]);
        tr.emplace_back(k, k, d);
      }
    // The spring's rank one couples the edge column: (dt/2) K b bᵀ.
    for (std::size_t a = 0; a < strip.rows(); ++a)
      for (std::size_t b = 0; b < strip.rows(); ++b)
        tr.emplace_back(static_cast<Eigen::Index>(a * nx), static_cast<Eigen::Index>(b * nx),
                        0.5 * dt * strip.spring_K() * strip.row_weight(a) * strip.row_weight(b) /
                            (strip.height() * strip.height()));
    Eigen::SparseMatrix<double> D(n, n);
    D.setFromTriplets(tr.begin(), tr.end());
    Eigen::SparseMatrix<double> A = D + 0.5 * dt * S;
    // A W = rhs for the W just solved: the right-hand side the assembled candidates solve for.
    const Eigen::VectorXd rhs = A * Eigen::Map<const Eigen::VectorXd>(W.data(), n);
    return {std::move(A), rhs};
  }
};

struct Record {
  double seconds = 0.0, iterations = 0.0, bytes_per_node = 0.0;
  std::size_t nodes = 0;
};
std::map<std::string, std::map<std::size_t, Record>>& records() {
  static std::map<std::string, std::map<std::size_t, Record>> r;
  return r;
}

using Clock = std::chrono::steady_clock;

void bm_cg_dct(benchmark::State& state, core::Strip::Shift shift, const char* name) {
  Problem p(sizes()[static_cast<std::size_t>(state.range(0))]);
  p.strip.set_shift(shift);
  const std::size_t n = p.strip.dofs(), nx = p.strip.sites();
  std::vector<double> W(n), c0(nx), c1(nx);
  double total = 0.0, its = 0.0;
  std::int64_t count = 0;
  for (auto _ : state) {
    std::fill(W.begin(), W.end(), 0.0);
    // A new step: force the mode factors to be remade as a changing dt or mean c1 would.
    p.c1[0] += 1e-12;
    const auto t0 = Clock::now();
    p.strip.implicit_solve(p.lin(), p.w_prev, c0, c1, 0.0, dt, eta, p.u, p.V, p.sb, W);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    its += p.strip.last_iterations();
    ++count;
    benchmark::DoNotOptimize(W.data());
  }
  state.counters["iterations"] = its / static_cast<double>(count);
  state.counters["nodes"] = static_cast<double>(n);
  Record& r = records()[std::string(name) + "/" + sizes()[static_cast<std::size_t>(state.range(0))].series][n];
  r = {total / static_cast<double>(count), its / static_cast<double>(count),
       static_cast<double>(p.strip.workspace_bytes() + p.strip.solver_temporary_bytes()) / static_cast<double>(n), n};
}

// The direct solve: `stage` = false, a trapezoidal step with new c1 (ψ remade); true, another right-hand
// side on the same coefficients.
void bm_direct(benchmark::State& state, bool stage, const char* name) {
  Problem p(sizes()[static_cast<std::size_t>(state.range(0))]);
  p.strip.set_step_solver(core::Strip::StepSolver::direct);
  const std::size_t n = p.strip.dofs(), nx = p.strip.sites();
  std::vector<double> W(n), c0(nx), c1(nx), d(nx), rhs(n);
  for (std::size_t i = 0; i < nx; ++i) d[i] = eta + 0.5 * p.c1[i];
  for (std::size_t k = 0; k < n; ++k) rhs[k] = p.u[k];
  if (stage) p.strip.solve_system(0.5 * dt, d, rhs, W);  // factors and ψ made outside the timing
  double total = 0.0, its = 0.0;
  std::int64_t count = 0;
  for (auto _ : state) {
    p.c1[0] += 1e-12;
    const auto t0 = Clock::now();
    if (stage) p.strip.solve_system(0.5 * dt, d, rhs, W);
    else p.strip.implicit_solve(p.lin(), p.w_prev, c0, c1, 0.0, dt, eta, p.u, p.V, p.sb, W);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    its += p.strip.last_interface_iterations();
    ++count;
    benchmark::DoNotOptimize(W.data());
  }
  state.counters["iterations"] = its / static_cast<double>(count);
  state.counters["nodes"] = static_cast<double>(n);
  Record& r = records()[std::string(name) + "/" + sizes()[static_cast<std::size_t>(state.range(0))].series][n];
  r = {total / static_cast<double>(count), its / static_cast<double>(count),
       // solve_system's own: the mode factors and ψ (n each; the transforms' buffers are one row long)
       static_cast<double>(p.strip.workspace_bytes() + 2 * n * sizeof(double)) / static_cast<double>(n), n};
}
// The adaptive integrator's stage solve in the mixed representation (Strip::solve_stage_mixed, docs/numerics.md
// §8.6): the rhs of the rows j ≥ 1 formed from (xu, xv) in their modes, no transform but row 0's.
void bm_mixed_stage_at(benchmark::State& state, double interface_tolerance, const char* name) {
  Problem p(sizes()[static_cast<std::size_t>(state.range(0))]);
  p.strip.set_interface_tolerance(interface_tolerance);
  const std::size_t n = p.strip.dofs(), nx = p.strip.sites();
  std::vector<double> d(nx), r0(nx), xu0(n), xv0(n), xu(n), xv(n);
  for (std::size_t i = 0; i < nx; ++i) {
    d[i] = eta + 0.5 * p.c1[i];
    r0[i] = p.u[i];
  }
  p.strip.to_mixed(p.u, xu0);
  p.strip.to_mixed(p.V, xv0);
  xu = xu0;
  xv = xv0;
  p.strip.solve_stage_mixed(0.5 * dt, d, r0.data(), xu.data(), xv.data());  // factors and ψ outside the timing
  double total = 0.0, its = 0.0;
  std::int64_t count = 0;
  for (auto _ : state) {
    std::copy(xu0.begin(), xu0.end(), xu.begin());
    std::copy(xv0.begin(), xv0.end(), xv.begin());
    const auto t0 = Clock::now();
    p.strip.solve_stage_mixed(0.5 * dt, d, r0.data(), xu.data(), xv.data());
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    its += p.strip.last_interface_iterations();
    ++count;
    benchmark::DoNotOptimize(xu.data());
  }
  state.counters["iterations"] = its / static_cast<double>(count);
  state.counters["nodes"] = static_cast<double>(n);
  Record& r = records()[std::string(name) + "/" + sizes()[static_cast<std::size_t>(state.range(0))].series][n];
  r = {total / static_cast<double>(count), its / static_cast<double>(count),
       static_cast<double>(p.strip.workspace_bytes() + 2 * n * sizeof(double)) / static_cast<double>(n), n};
}
// As the adaptive integrator runs it: the interface iterations stop at 10⁻⁴ rtol (1e-6 at the default rtol 1e-2,
// Strip::kStageSolveTolerance, docs/numerics.md §8.5) instead of 1e-13.
void bm_mixed_stage(benchmark::State& s) { bm_mixed_stage_at(s, 1e-13, "mixed_stage"); }
void bm_mixed_stage_run(benchmark::State& s) { bm_mixed_stage_at(s, 1e-6, "mixed_stage_run"); }
// The memory traffic of mixed_stage's three sweeps without their arithmetic dependencies (the baseline its cost per
// node is measured against, docs/performance.md §12): forward 3 reads + 1 write, back 2 + 1, final 3 + 2 of
// dofs-long arrays, as independent streaming loops.
void bm_stream(benchmark::State& state) {
  Problem p(sizes()[static_cast<std::size_t>(state.range(0))]);
  const std::size_t n = p.strip.dofs();
  std::vector<double> bu(p.u), bv(p.V), inv(n, 0.5), z(n, 0.0), psi(n, 0.25), xu(n), xv(n);
  double total = 0.0;
  std::int64_t count = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < n; ++k) z[k] = 0.3 * (bv[k] + 2.0 * bu[k]) - 0.1 * inv[k];
    for (std::size_t k = 0; k < n; ++k) z[k] = (z[k] - 0.2) * inv[k];
    for (std::size_t k = 0; k < n; ++k) {
      const double x = z[k] - 0.1 * psi[k];
      xv[k] = (x - bu[k]) * 3.0;
      xu[k] = x;
    }
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    ++count;
    benchmark::DoNotOptimize(xu.data());
    benchmark::DoNotOptimize(xv.data());
  }
  state.counters["nodes"] = static_cast<double>(n);
  records()[std::string("stream/") + sizes()[static_cast<std::size_t>(state.range(0))].series][n] = {
      total / static_cast<double>(count), 0.0, 7.0 * sizeof(double), n};
}
void bm_direct_step(benchmark::State& s) { bm_direct(s, false, "direct"); }
void bm_direct_stage(benchmark::State& s) { bm_direct(s, true, "direct_stage"); }

template <class Solve>
void bm_assembled(benchmark::State& state, const char* name, Solve&& solve_once) {
  Problem p(sizes()[static_cast<std::size_t>(state.range(0))]);
  const std::size_t n = p.strip.dofs();
  if (n > assembled_max_nodes) {
    state.SkipWithError("too large for the assembled candidates");
    for (auto _ : state) {
    }
    return;
  }
  auto [A, rhs] = p.assembled();
  double total = 0.0, its = 0.0, bytes = 0.0;
  std::int64_t count = 0;
  auto setup = solve_once(A, rhs, true, its, bytes);  // symbolic analysis, outside the timing
  (void)setup;
  its = 0.0;
  for (auto _ : state) {
    A.valuePtr()[0] *= 1.0 + 1e-15;  // a new step: new values, same pattern
    const auto t0 = Clock::now();
    solve_once(A, rhs, false, its, bytes);
    total += std::chrono::duration<double>(Clock::now() - t0).count();
    ++count;
  }
  state.counters["iterations"] = its / static_cast<double>(count);
  state.counters["nodes"] = static_cast<double>(n);
  records()[std::string(name) + "/" + sizes()[static_cast<std::size_t>(state.range(0))].series][n] = {total / static_cast<double>(count), its / static_cast<double>(count),
                        bytes / static_cast<double>(n), n};
}

void bm_ldlt(benchmark::State& state) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  Eigen::VectorXd x;
  bm_assembled(state, "ldlt", [&](const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, bool setup,
                                  double&, double& bytes) {
    if (setup) {
      ldlt.analyzePattern(A);
      return 0;
    }
    ldlt.factorize(A);
    x = ldlt.solve(b);
    benchmark::DoNotOptimize(x.data());
    bytes = static_cast<double>(ldlt.matrixL().nestedExpression().nonZeros()) * (sizeof(double) + sizeof(int));
    return 0;
  });
}

template <class Pre>
void bm_cg_assembled(benchmark::State& state, const char* name) {
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Pre> cg;
  Eigen::VectorXd x;
  bm_assembled(state, name, [&](const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, bool setup,
                                double& its, double& bytes) {
    if (setup) {
      cg.setTolerance(1e-12);
      cg.setMaxIterations(5000);
      return 0;
    }
    cg.compute(A);
    x = cg.solve(b);
    benchmark::DoNotOptimize(x.data());
    its += static_cast<double>(cg.iterations());
    bytes = static_cast<double>(A.nonZeros()) * (sizeof(double) + sizeof(int));
    return 0;
  });
}

void bm_cg_dct_mean(benchmark::State& s) { bm_cg_dct(s, core::Strip::Shift::mean_c1, "cg_dct_mean"); }
void bm_cg_dct_eta(benchmark::State& s) { bm_cg_dct(s, core::Strip::Shift::eta, "cg_dct_eta"); }
void bm_cg_jacobi(benchmark::State& s) { bm_cg_assembled<Eigen::DiagonalPreconditioner<double>>(s, "cg_jacobi"); }
void bm_cg_ichol(benchmark::State& s) {
  bm_cg_assembled<Eigen::IncompleteCholesky<double>>(s, "cg_ichol");
}

void register_all() {
  const auto count = static_cast<std::int64_t>(sizes().size());
  const auto add = [&](const char* name, void (*f)(benchmark::State&)) {
    benchmark::RegisterBenchmark(name, f)->DenseRange(0, count - 1)->Unit(benchmark::kMillisecond)->MinTime(0.3);
  };
  add("cg_dct_mean", bm_cg_dct_mean);
  add("cg_dct_eta", bm_cg_dct_eta);
  add("ldlt", bm_ldlt);
  add("cg_jacobi", bm_cg_jacobi);
  add("cg_ichol", bm_cg_ichol);
  add("direct", bm_direct_step);
  add("direct_stage", bm_direct_stage);
  add("mixed_stage", bm_mixed_stage);
  add("mixed_stage_run", bm_mixed_stage_run);
  add("stream", bm_stream);
}

// Least-squares slope of log t against log n.
double exponent(const std::map<std::size_t, Record>& r) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
  for (const auto& [n, rec] : r) {
    if (!(rec.seconds > 0.0)) continue;
    const double x = std::log(static_cast<double>(n)), y = std::log(rec.seconds);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    m += 1;
  }
  return m < 2 ? std::nan("") : (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

void summary() {
  std::printf("\nstrip implicit solve (cold start W = 0, rel. residual 1e-12)%s\n",
              quick() ? " (SLIPFRONT_BENCH_QUICK=1)" : "");
  std::printf("%-17s %9s %11s %10s %14s %11s\n", "candidate/series", "nodes", "ms/solve", "iterations",
              "ns/node/iter", "bytes/node");
  for (const auto& [name, byn] : records())
    for (const auto& [n, r] : byn)
      std::printf("%-17s %9zu %11.3f %10.1f %14.2f %11.1f\n", name.c_str(), n, 1e3 * r.seconds, r.iterations,
                  r.iterations > 0 ? 1e9 * r.seconds / (static_cast<double>(n) * r.iterations) : std::nan(""),
                  r.bytes_per_node);
  std::printf("\nexponent of time vs nodes (least squares, log-log)\n");
  for (const auto& [name, byn] : records()) std::printf("  %-17s %.3f\n", name.c_str(), exponent(byn));
  for (const char* series : {"long", "diag"}) {
    const auto& chosen = records()[std::string("cg_dct_mean/") + series];
    std::printf("\nratio time(candidate) / time(cg_dct_mean), series %s\n%-17s", series, "nodes");
    for (const auto& [n, r] : chosen) std::printf(" %9zu", n);
    std::printf("\n");
    for (const auto& [name, byn] : records()) {
      if (name.rfind(series) == std::string::npos || name.rfind("cg_dct_mean", 0) == 0) continue;
      std::printf("%-17s", name.c_str());
      for (const auto& [n, r] : chosen) {
        const auto it = byn.find(n);
        if (it == byn.end() || !(it->second.seconds > 0.0))
          std::printf(" %9s", "-");
        else
          std::printf(" %9.2f", it->second.seconds / r.seconds);
      }
      std::printf("\n");
    }
  }
  for (const char* name : {"cg_dct_mean/long", "direct/long", "direct_stage/long", "mixed_stage/long",
                           "mixed_stage_run/long"}) {
    const double e = exponent(records()[name]);
    std::printf("\n%s exponent (one body made longer) %.3f (%s 1.1)", name, e, e <= 1.1 ? "<=" : "ABOVE");
  }
  std::printf("\n");
  // The stage solve's cost against the streaming of the same arrays: the exponent of the ratio is the algorithm's
  // own growth with the nodes, the memory hierarchy divided out.
  for (const char* series : {"long", "diag"}) {
    const auto& a = records()[std::string("mixed_stage_run/") + series];
    const auto& b = records()[std::string("stream/") + series];
    std::map<std::size_t, Record> ratio;
    for (const auto& [n, r] : a)
      if (const auto it = b.find(n); it != b.end() && it->second.seconds > 0.0)
        ratio[n] = {r.seconds / it->second.seconds, 0.0, 0.0, n};
    std::printf("mixed_stage_run / stream, series %s:", series);
    for (const auto& [n, r] : ratio) std::printf(" %zu: %.2f", n, r.seconds);
    std::printf("; exponents: stream %.3f, mixed_stage_run %.3f, their ratio %.3f (%s 0.1 above linear)\n",
                exponent(b), exponent(a), exponent(ratio), exponent(ratio) <= 0.1 ? "<=" : "ABOVE");
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  summary();
  return 0;
}
