// The accuracy-stepped integrator on the antiplane strip (issue 19, docs/numerics.md §8, docs/performance.md
// §12–§13): the strip's direct solve of its step matrix (core::Strip::solve_system, the capacitance method)
// against a sparse direct factorisation of the assembled matrix; the adaptive Rosenbrock integrator on the
// strip against the explicit reference on fig1_strip's events; checkpoint/restart; the energy budget.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "core/strip.hpp"

namespace core = slipfront::core;

namespace {

struct Setup {
  core::BulkParams bulk;
  core::DriveParams drive;
  core::InterfaceParams law;
  double dx = 0.5, dy = 0.25;
};

// A strip of nx columns and `rows` rows; edge (K = 2.5, v_d = 0.3) or homogeneous loading (K = 0).
Setup setup(std::size_t nx, std::size_t rows, bool edge) {
  Setup s;
  s.bulk.rho = 0.01;
  s.bulk.mu = 300.0;
  s.bulk.length = static_cast<double>(nx - 1) * s.dx;
  s.bulk.height = static_cast<double>(rows - 1) * s.dy;
  s.drive.loading = edge ? core::Loading::edge : core::Loading::homogeneous;
  s.drive.K = 2.5;
  s.drive.v_d = 0.3;
  s.drive.sigma_d = 0.5;
  s.law.alpha = 1.05;
  s.law.eta = 0.1;
  return s;
}

std::vector<double> random_vector(std::size_t n, std::mt19937& g, double lo, double hi) {
  std::uniform_real_distribution<double> d(lo, hi);
  std::vector<double> v(n);
  for (auto& x : v) x = d(g);
  return v;
}

Eigen::Map<const Eigen::VectorXd> view(const std::vector<double>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size())};
}

// A(c, d) = M/c + c (S + K b bᵀ) + E diag(wx d) Eᵀ, assembled from S and the definitions (docs/model.md §9).
Eigen::SparseMatrix<double> assemble(const core::Strip& s, double c, const std::vector<double>& d) {
  const auto n = static_cast<Eigen::Index>(s.dofs());
  const std::size_t nx = s.sites();
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  for (std::size_t j = 0; j < s.rows(); ++j) b[static_cast<Eigen::Index>(j * nx)] = s.row_weight(j) / s.height();
  std::vector<Eigen::Triplet<double>> tr;
  for (std::size_t j = 0; j < s.rows(); ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const auto k = static_cast<Eigen::Index>(j * nx + i);
      double a = s.node_mass(i, j) / c;
      if (j == 0) a += s.interface_weight(i) * d[i];
      tr.emplace_back(k, k, a);
    }
  Eigen::SparseMatrix<double> D(n, n);
  D.setFromTriplets(tr.begin(), tr.end());
  const Eigen::SparseMatrix<double> bb = (b * b.transpose()).sparseView();
  return D + c * s.stiffness_matrix() + (c * s.spring_K()) * bb;
}

}  // namespace

TEST_CASE("strip: solve_system (capacitance) matches a sparse LDLT of the assembled step matrix", "[strip][adaptive]") {
  std::mt19937 g(19);
  struct Shape {
    std::size_t nx, rows;
  };
  int indefinite_d = 0;
  for (const Shape sh : {Shape{17, 5}, Shape{33, 9}, Shape{101, 2}, Shape{2, 3}, Shape{3, 2}, Shape{64, 17}})
    for (const bool edge : {true, false})
      for (const double c : {0.004, 0.3})
        for (const bool negative : {false, true}) {
          INFO("nx " << sh.nx << " rows " << sh.rows << (edge ? " edge" : " homogeneous") << " c " << c
                     << (negative ? " some d < 0" : " d >= 0"));
          core::Strip s(setup(sh.nx, sh.rows, edge).bulk, setup(sh.nx, sh.rows, edge).drive,
                        setup(sh.nx, sh.rows, edge).law, 0.5, 0.25);
          const std::size_t n = s.dofs(), nx = s.sites();
          std::vector<double> d = random_vector(nx, g, 0.0, 2.0);
          if (negative)  // weakening sites: d < 0 on a third of them, bounded so that A stays definite
            for (std::size_t i = 0; i < nx; i += 3) d[i] = -0.5 * s.rho() / c * std::uniform_real_distribution<>(0.0, 1.0)(g);
          Eigen::SparseMatrix<double> A = assemble(s, c, d);
          Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
          // Definite: the case the method is stated for (the negative d halved until it is).
          for (int k = 0; k < 30 && !(ldlt.info() == Eigen::Success && ldlt.vectorD().minCoeff() > 0.0); ++k) {
            for (auto& di : d) di = di < 0.0 ? 0.5 * di : di;
            A = assemble(s, c, d);
            ldlt.compute(A);
          }
          REQUIRE(ldlt.info() == Eigen::Success);
          REQUIRE(ldlt.vectorD().minCoeff() > 0.0);
          if (negative && *std::min_element(d.begin(), d.end()) < 0.0) ++indefinite_d;
          const auto rhs = random_vector(n, g, -1.0, 1.0);
          std::vector<double> x(n, 0.0);
          s.solve_system(c, d, rhs, x);
          const Eigen::VectorXd ref = ldlt.solve(view(rhs));
          CHECK((view(x) - ref).norm() / ref.norm() < 1e-12);
          CHECK((A * view(x) - view(rhs)).norm() / view(rhs).norm() < 1e-12);
          CHECK(s.last_interface_iterations() >= 1);
          CHECK(s.last_interface_iterations() < 60);
          // A second right-hand side on the same (c, d), in place (rhs and x alias): the cached factors and ψ.
          auto y = random_vector(n, g, -1.0, 1.0);
          const Eigen::VectorXd ref2 = ldlt.solve(view(y));
          s.solve_system(c, d, y, y);
          CHECK((view(y) - ref2).norm() / ref2.norm() < 1e-12);
        }
  CHECK(indefinite_d > 0);
}

TEST_CASE("strip: the trapezoidal step by the direct solve is the CG's step", "[strip][adaptive]") {
  std::mt19937 g(7);
  for (const bool edge : {true, false}) {
    const Setup st = setup(41, 9, edge);
    core::Strip cg(st.bulk, st.drive, st.law, st.dx, st.dy), direct(st.bulk, st.drive, st.law, st.dx, st.dy);
    direct.set_step_solver(core::Strip::StepSolver::direct);
    const std::size_t n = cg.dofs(), nx = cg.sites();
    const auto u = random_vector(n, g, -1, 1), V = random_vector(n, g, -1, 1), sb = random_vector(nx, g, -1, 1);
    const auto c0 = random_vector(nx, g, -1, 1), c1 = random_vector(nx, g, 0.0, 3.0);
    std::vector<double> w_cg(n, 0.0), w_direct(n, 0.0);
    cg.solve_step(c0, c1, 1.3, 0.02, 0.1, u, V, sb, w_cg);
    direct.solve_step(c0, c1, 1.3, 0.02, 0.1, u, V, sb, w_direct);
    CHECK((view(w_cg) - view(w_direct)).norm() / view(w_cg).norm() < 1e-10);
  }
}
