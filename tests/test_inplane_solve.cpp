// The in-plane strip's implicit step solve (core/inplane.hpp, docs/model.md §10.6): the preconditioner is the exact
// inverse of the separable part (u_x in cosine modes, u_y in sine modes, 2 × 2-block tridiagonal in y); the
// preconditioned CG agrees with the sparse direct solve of the assembled system, with a non-uniform interface
// coefficient and the drive spring; its iteration counts as the grid grows.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "core/inplane.hpp"
#include "inplane_fixtures.hpp"

namespace core = slipfront::core;

namespace {

// fig1's material on nx columns and ny row intervals (dx = dy = d), ν = 1/3, normal load 0.2; edge or homogeneous.
core::InPlane strip(std::size_t nx, std::size_t ny, double d, bool edge) {
  slipfront::testing::InPlaneSetup s =
      slipfront::testing::fig1_inplane(static_cast<double>(nx - 1) * d, static_cast<double>(ny) * d, d, d, edge);
  s.drive.sigma_d = 0.4;
  s.material.normal_load = 0.2;
  return s.make();
}

std::vector<double> random_vector(std::size_t n, std::mt19937& g, double lo = -1.0, double hi = 1.0) {
  return slipfront::testing::uniform_vector(n, g, lo, hi);
}

struct Step {
  std::vector<double> c0, c1, u, V, sb;
  double t = 1.3, dt = 0.01, eta = 0.1;
};
Step random_step(const core::InPlane& b, std::mt19937& g, bool uniform_c1) {
  Step s;
  s.c0 = random_vector(b.sites(), g);
  s.c1 = uniform_c1 ? std::vector<double>(b.sites(), 0.0) : random_vector(b.sites(), g, 0.0, 50.0);
  s.u = random_vector(b.dofs(), g);
  s.V = random_vector(b.dofs(), g);
  for (std::size_t i = 0; i < b.sites(); ++i) s.u[b.plane() + i] = s.V[b.plane() + i] = 0.0;  // held
  s.sb = random_vector(b.sites(), g);
  return s;
}

double max_rel(const std::vector<double>& a, const std::vector<double>& b) {
  double e = 0.0, m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    e = std::max(e, std::abs(a[i] - b[i]));
    m = std::max(m, std::abs(b[i]));
  }
  return e / m;
}

}  // namespace

TEST_CASE("inplane solve: the preconditioner inverts the separable part exactly", "[inplane][solve]") {
  // Homogeneous loading (no spring), c1 = 0 (the interface coefficient uniform, η): the system restricted to the
  // separable dofs (u_y of the end columns and of the interface zero) is the separable operator, so
  // P⁻¹(A x) = x there. A from the assembled stiffness and the definitions, not from the solver.
  std::mt19937 g(7);
  for (const auto& [nx, ny] : {std::pair<std::size_t, std::size_t>{9, 4}, {17, 7}}) {
    core::InPlane b = strip(nx, ny, 0.5, false);
    Step s = random_step(b, g, true);
    std::vector<double> W(b.dofs(), 0.0);
    b.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, W);  // sets up the factors for (dt, η)
    const std::size_t P = b.plane();
    std::vector<double> x = random_vector(b.dofs(), g);
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i)
        if (j == 0 || i == 0 || i + 1 == nx) x[P + j * nx + i] = 0.0;
    const Eigen::SparseMatrix<double> K = b.stiffness_matrix();
    const Eigen::Map<const Eigen::VectorXd> xv(x.data(), static_cast<Eigen::Index>(x.size()));
    Eigen::VectorXd y = 0.5 * s.dt * (K * xv);
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        y[static_cast<Eigen::Index>(k)] += 2.0 * b.node_mass(i, j) / s.dt * x[k] + (j == 0 ? b.interface_weight(i) * s.eta * x[k] : 0.0);
        y[static_cast<Eigen::Index>(P + k)] += 2.0 * b.node_mass(i, j) / s.dt * x[P + k];
      }
    for (std::size_t i = 0; i < nx; ++i) y[static_cast<Eigen::Index>(P + i)] = 0.0;  // held rows: identity on x = 0
    const double* z = b.apply_preconditioner(y.data());
    double e = 0.0, m = 0.0;
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        e = std::max(e, std::abs(z[k] - x[k]));
        if (j > 0 && i > 0 && i + 1 < nx) e = std::max(e, std::abs(z[P + k] - x[P + k]));
        m = std::max(m, std::abs(x[k]));
      }
    INFO("nx = " << nx << ", ny = " << ny);
    CHECK(e < 1e-12 * m);
  }
}

TEST_CASE("inplane solve: the preconditioned CG agrees with the direct solve", "[inplane][solve]") {
  // Random states, a non-uniform interface coefficient (c1 ∈ [0, 50], the law's linearisation when sites slide), the
  // drive spring (edge loading) or the top loads (homogeneous), the normal load: relative difference ≤ 1e-10.
  std::mt19937 g(9);
  for (const bool edge : {true, false})
    for (const bool uniform : {true, false}) {
      core::InPlane b = strip(33, 8, 0.5, edge);
      const Step s = random_step(b, g, uniform);
      std::vector<double> w_cg(b.dofs(), 0.0), w_direct(b.dofs(), 0.0);
      b.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, w_cg);
      const int iterations = b.last_iterations();
      b.set_step_solver(core::InPlane::StepSolver::direct);
      b.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, w_direct);
      const double e = max_rel(w_cg, w_direct);
      std::printf("inplane solve (%s, c1 %s): CG %d iterations, relative difference %.2e\n",
                  edge ? "edge" : "homogeneous", uniform ? "0" : "random", iterations, e);
      CHECK(e < 1e-10);
      CHECK(iterations > 0);
      for (std::size_t i = 0; i < b.sites(); ++i) CHECK(w_cg[b.plane() + i] == 0.0);  // held
    }
}

TEST_CASE("inplane solve: CG iterations as the grid grows in x and in y", "[inplane][solve]") {
  // The separable part is exact except on the two end columns' u_y (rank ≤ 2 ny), the spring (rank 1) and the
  // interface coefficient's spread. With a uniform coefficient (c1 = 0) the iterations must not grow with nx; with
  // c1 random per site in [0, 50] (harsher than a law's: it jumps from site to site) they grow slowly (printed).
  std::mt19937 g(13);
  auto iterations = [&](std::size_t nx, std::size_t ny, bool uniform) {
    core::InPlane b = strip(nx, ny, 0.5, true);
    const Step s = random_step(b, g, uniform);
    std::vector<double> w(b.dofs(), 0.0);
    b.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, w);
    return b.last_iterations();
  };
  for (const bool uniform : {true, false}) {
    std::vector<int> by_x, by_y;
    for (const std::size_t nx : {65u, 129u, 257u}) by_x.push_back(iterations(nx, 16, uniform));
    for (const std::size_t ny : {8u, 16u, 32u}) by_y.push_back(iterations(129, ny, uniform));
    std::printf("inplane CG iterations (c1 %s): nx = 65, 129, 257 (ny = 16): %d %d %d; ny = 8, 16, 32 (nx = 129): "
                "%d %d %d\n", uniform ? "0" : "random", by_x[0], by_x[1], by_x[2], by_y[0], by_y[1], by_y[2]);
    if (uniform) CHECK(by_x[2] <= by_x[0] + 3);
  }
}

TEST_CASE("inplane solve: copies are independent and solve bit for bit alike", "[inplane][solve]") {
  std::mt19937 g(17);
  core::InPlane a = strip(33, 6, 0.5, true);
  const Step s = random_step(a, g, false);
  std::vector<double> wa(a.dofs(), 0.0), wb(a.dofs(), 0.0), wc(a.dofs(), 0.0);
  a.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, wa);  // a holds its factors
  core::InPlane b = a;                                              // made again on first use
  b.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, wb);
  core::InPlane c = std::move(a);
  c.solve_step(s.c0, s.c1, s.t, s.dt, s.eta, s.u, s.V, s.sb, wc);
  CHECK(wa == wb);
  CHECK(wa == wc);
}

TEST_CASE("inplane solve: solve_system solves A(c, d) for any right-hand side", "[inplane][solve]") {
  // A(c, d) = M/c + c (K + K_s b bᵀ) + E diag(wx d) Eᵀ, u_y of the interface held, assembled here from the stiffness
  // and the definitions; the residual of solve_system's x relative to rhs ≤ 1e-11, rhs and x aliased.
  std::mt19937 g(19);
  core::InPlane b = strip(41, 6, 0.5, true);
  const std::size_t nx = b.sites(), P = b.plane(), n = b.dofs();
  for (const double c : {1e-3, 0.05}) {
    const std::vector<double> d = random_vector(nx, g, -0.05, 20.0);
    std::vector<double> rhs = random_vector(n, g);
    for (std::size_t i = 0; i < nx; ++i) rhs[P + i] = 0.0;
    std::vector<double> x = rhs;  // aliased
    b.solve_system(c, d, x, x);
    const Eigen::SparseMatrix<double> K = b.stiffness_matrix();
    std::vector<double> xz = x;
    for (std::size_t i = 0; i < nx; ++i) xz[P + i] = 0.0;
    const Eigen::Map<const Eigen::VectorXd> xv(xz.data(), static_cast<Eigen::Index>(n));
    Eigen::VectorXd y = c * (K * xv);
    double ub = 0.0;
    for (std::size_t j = 0; j < b.rows(); ++j) ub += b.row_weight(j) * xz[j * nx] / b.height();
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        const auto e = static_cast<Eigen::Index>(k);
        y[e] += b.node_mass(i, j) / c * xz[k] + (j == 0 ? b.interface_weight(i) * d[i] * xz[k] : 0.0);
        if (i == 0) y[e] += c * b.spring_K() * ub * b.row_weight(j) / b.height();
        y[static_cast<Eigen::Index>(P + k)] += b.node_mass(i, j) / c * xz[P + k];
      }
    double res = 0.0, nr = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const bool held = k >= P && k < P + nx;
      res += held ? x[k] * x[k] : (y[static_cast<Eigen::Index>(k)] - rhs[k]) * (y[static_cast<Eigen::Index>(k)] - rhs[k]);
      nr += rhs[k] * rhs[k];
    }
    std::printf("inplane solve_system c = %g: %d iterations, relative residual %.2e\n", c, b.last_iterations(),
                std::sqrt(res / nr));
    CHECK(std::sqrt(res / nr) < 1e-11);
  }
}

namespace {

// The adaptive stage solve (docs/numerics.md §8.9) checked through the body's own right-hand side: a(t; u, v, σ̄) is
// affine, so J x = a(0; x) − a(0; 0), and x from stage_factor/stage_solve must satisfy x_u − c x_v = b_u and
// x_v − c (a(0; x_u, x_v, x_σ) − a(0; 0)) = b_v with the sites' x_σ = p + q x_v. Returns the larger residual of the
// two rows relative to the largest term in them (c J x included: at c = 3 it is ~1e4 times b, and its round-off with
// it); xu_out the solution's x_u.
double stage_residual(core::InPlane& b, double c, double eta, const std::vector<double>& q, std::mt19937& g,
                      std::vector<double>* xu_out = nullptr) {
  const std::size_t n = b.dofs(), m = b.sites();
  std::vector<double> bu = random_vector(n, g), bv = random_vector(n, g), p = random_vector(m, g);
  for (std::size_t i = 0; i < m; ++i) bu[b.plane() + i] = bv[b.plane() + i] = 0.0;  // held
  b.stage_factor(c, eta, [&](std::size_t i) { return q[i]; });
  std::vector<double> xu(bu), xv(bv), back(m, 0.0);
  b.stage_solve(core::BulkStage{bu.data(), bv.data()}, [&](std::size_t i) { return p[i]; },
                [&](std::size_t i, double v) { back[i] = v; }, xu.data(), xv.data());
  std::vector<double> zero(n, 0.0), a0(n), ax(n), xs(m);
  for (std::size_t i = 0; i < m; ++i) xs[i] = p[i] + q[i] * xv[i];
  b.stage_accelerations(0.0, zero, zero.data(), zero.data(), eta, a0);
  b.stage_accelerations(0.0, xu, xv.data(), xs.data(), eta, ax);
  double res = 0.0, size = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    res = std::max({res, std::abs(xu[k] - c * xv[k] - bu[k]), std::abs(xv[k] - c * (ax[k] - a0[k]) - bv[k])});
    size = std::max({size, std::abs(bu[k]), std::abs(bv[k]), std::abs(xu[k]), std::abs(xv[k]), c * std::abs(ax[k] - a0[k])});
  }
  if (xu_out != nullptr) *xu_out = xu;
  return res / size;
}

}  // namespace

TEST_CASE("inplane solve: the direct stage solve (capacitance on the end columns, interface system) is exact",
          "[inplane][solve][adaptive]") {
  // The default stage solve of the adaptive integrator: two separable solves, the capacitance matrix of the end
  // columns' u_y (and the spring), the interface coefficient's spread about d_ref = η + cα by an nx-sized system. Its
  // residual must be round-off at every c (the step's M/c dominant, balanced, c K dominant), edge (spring) and
  // homogeneous loading, q_σ per site random (some d < d_ref) or all at a stuck site's cα (no interface system);
  // the Krylov reference agrees; the factors of a c are made once (cached) and again for a new c.
  std::mt19937 g(41);
  struct Shape {
    std::size_t nx, ny;
  };
  for (const Shape sh : {Shape{33, 8}, Shape{65, 4}, Shape{17, 16}})
    for (const bool edge : {true, false}) {
      core::InPlane b = strip(sh.nx, sh.ny, 0.5, edge);
      b.set_stage_tolerance(1e-12);  // the interface system to 1e-13
      const double eta = 0.1, alpha = 1.05;
      long long builds = 0;
      for (const double c : {0.004, 0.3, 3.0})
        for (const bool uniform : {false, true}) {
          INFO("nx " << sh.nx << " ny " << sh.ny << (edge ? " edge" : " homogeneous") << " c " << c
                     << (uniform ? " q = c alpha" : " q random"));
          const std::vector<double> q = uniform ? std::vector<double>(sh.nx, c * alpha) : random_vector(sh.nx, g, -0.02, 1.0);
          const long long its = b.stage_interface_iterations();
          std::vector<double> xd, xk;
          std::mt19937 g1 = g;
          b.set_stage_solver(core::InPlane::StageSolver::direct);
          const double rd = stage_residual(b, c, eta, q, g, &xd);
          // round-off: ~ε times the system's condition number κ ≈ 1 + (c ω_max)², ω_max = 2/stable_dt (1e-15 κ:
          // 1.6e-14 at c = 0.004, 8.7e-11 at 0.3, 8.7e-9 at 3 on nx 33), or the interface system's 1e-13 (residuals
          // to 1e-12 measured at c = 0.004 with it): bound max(1e-11, 1e-15 κ), for the Krylov reference as well
          const double kappa = 1.0 + std::pow(2.0 * c / b.stable_dt(), 2), bound = std::max(1e-11, 1e-15 * kappa);
          CHECK(rd < bound);
          CHECK(b.stage_direct_failures() == 0);
          CHECK(b.stage_capacitance_builds() == builds + (uniform ? 0 : 1));  // the second solve of c: cached
          builds = b.stage_capacitance_builds();
          if (uniform) CHECK(b.stage_interface_iterations() == its);
          else CHECK(b.stage_interface_iterations() > its);
          b.set_stage_solver(core::InPlane::StageSolver::krylov);
          const double rk = stage_residual(b, c, eta, q, g1, &xk);  // the same input (the generator copied)
          CHECK(rk < bound);
          CHECK(max_rel(xd, xk) < 1e-9);
          std::printf("inplane direct stage solve (nx %zu, ny %zu, %s, c %g, q %s): residual %.1e (Krylov %.1e; "
                      "1e-15 kappa %.1e), interface iterations %lld\n", sh.nx, sh.ny, edge ? "edge" : "homogeneous", c,
                      uniform ? "c alpha" : "random", rd, rk, 1e-15 * kappa, b.stage_interface_iterations() - its);
        }
    }
}
