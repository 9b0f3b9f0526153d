// The antiplane strip (core/strip.hpp, docs/model.md §9): its elastic operator against its own matrix and
// energy, the implicit step's matrix-free preconditioned CG against a direct sparse solve of the assembled
// system, the preconditioner as the exact inverse of the separable part (the DCT's scaling and
// eigenvalues), the explicit stability bound, the H → 0 limit (the chain, core::Bulk), bit-reproducible
// copies, and an iteration count that does not grow with the grid.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "core/bulk.hpp"
#include "core/strip.hpp"

namespace core = slipfront::core;

namespace {

struct Setup {
  core::BulkParams bulk;
  core::DriveParams drive;
  core::InterfaceParams law;
  double dx = 0.5, dy = 0.25;
};

// A strip of nx columns and `rows` rows; edge (K = 2.5, v_d = 0.3) or homogeneous (σ_d = 0.5, F_r = 0.7).
Setup setup(std::size_t nx, std::size_t rows, bool edge, double dx = 0.5, double dy = 0.25) {
  Setup s;
  s.dx = dx;
  s.dy = dy;
  s.bulk.rho = 0.01;
  s.bulk.mu = 300.0;
  s.bulk.length = static_cast<double>(nx - 1) * dx;
  s.bulk.height = static_cast<double>(rows - 1) * dy;
  s.drive.loading = edge ? core::Loading::edge : core::Loading::homogeneous;
  s.drive.K = 2.5;
  s.drive.v_d = 0.3;
  s.drive.sigma_d = 0.5;
  s.drive.rear_traction = 0.7;
  s.law.alpha = 1.05;
  s.law.eta = 0.1;
  return s;
}
core::Strip make(const Setup& s) { return core::Strip(s.bulk, s.drive, s.law, s.dx, s.dy); }

std::vector<double> random_vector(std::size_t n, std::mt19937& g, double lo = -1.0, double hi = 1.0) {
  std::uniform_real_distribution<double> d(lo, hi);
  std::vector<double> v(n);
  for (auto& x : v) x = d(g);
  return v;
}

Eigen::Map<const Eigen::VectorXd> view(const std::vector<double>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size())};
}

// The edge column's spread vector b (b_0j = wy(j)/H).
Eigen::VectorXd spread(const core::Strip& s) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(s.dofs()));
  for (std::size_t j = 0; j < s.rows(); ++j) b[static_cast<Eigen::Index>(j * s.sites())] = s.row_weight(j) / s.height();
  return b;
}

// The implicit step's system, assembled from S and the definitions (not from the solver's own code).
struct Assembled {
  Eigen::SparseMatrix<double> A;
  Eigen::VectorXd rhs;
};
Assembled assemble(const core::Strip& s, const std::vector<double>& c0, const std::vector<double>& c1, double t,
                   double dt, double eta, const std::vector<double>& u, const std::vector<double>& V,
                   const std::vector<double>& sb) {
  const auto n = static_cast<Eigen::Index>(s.dofs());
  const std::size_t nx = s.sites();
  const Eigen::SparseMatrix<double> S = s.stiffness_matrix();
  const Eigen::VectorXd b = spread(s);
  Eigen::SparseMatrix<double> D(n, n);
  std::vector<Eigen::Triplet<double>> tr;
  Eigen::VectorXd rhs = -(S * view(u));
  for (std::size_t j = 0; j < s.rows(); ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const auto k = static_cast<Eigen::Index>(j * nx + i);
      const double m = s.node_mass(i, j), wx = s.interface_weight(i);
      double d = 2.0 * m / dt;
      rhs[k] += 2.0 * m * V[static_cast<std::size_t>(k)] / dt;
      if (j == 0) {
        d += wx * (eta + 0.5 * c1[i]);
        rhs[k] -= wx * 0.5 * (sb[i] + c0[i]);
      }
      if (j + 1 == s.rows()) rhs[k] += wx * s.uniform_stress();
      tr.emplace_back(k, k, d);
    }
  D.setFromTriplets(tr.begin(), tr.end());
  const double ubar0 = b.dot(view(u));
  rhs += b * (s.spring_K() * (s.driver_velocity() * (t + 0.5 * dt) - ubar0) + s.rear_traction());
  Eigen::SparseMatrix<double> bb = (b * b.transpose()).sparseView();
  Eigen::SparseMatrix<double> A = D + 0.5 * dt * S + (0.5 * dt * s.spring_K()) * bb;
  return {A, rhs};
}

double rel_diff(const std::vector<double>& a, const Eigen::VectorXd& b) {
  return (view(a) - b).norm() / b.norm();
}

}  // namespace

TEST_CASE("strip: the elastic force is -S u and the elastic energy u'Su/2", "[strip]") {
  std::mt19937 g(1);
  for (const bool edge : {true, false}) {
    const Setup st = setup(7, 4, edge);
    const core::Strip s = make(st);
    REQUIRE(s.sites() == 7);
    REQUIRE(s.rows() == 4);
    REQUIRE(s.dofs() == 28);
    const auto u = random_vector(s.dofs(), g);
    const Eigen::SparseMatrix<double> S = s.stiffness_matrix();
    const Eigen::VectorXd f_ref = -(S * view(u));
    std::vector<double> f(s.dofs(), 0.0);
    s.elastic_forces(u, [&](std::size_t j, std::size_t i, double F) { f[j * s.sites() + i] = F; });
    CHECK(rel_diff(f, f_ref) < 1e-14);
    const double e_ref = 0.5 * view(u).dot(S * view(u));
    CHECK(std::abs(s.elastic_energy(u) - e_ref) < 1e-13 * e_ref);
    // S is symmetric, rows sum to 0 (free faces), positive semi-definite.
    CHECK((Eigen::MatrixXd(S) - Eigen::MatrixXd(S).transpose()).norm() == 0.0);
    CHECK((Eigen::MatrixXd(S) * Eigen::VectorXd::Ones(28)).norm() < 1e-12 * S.norm());
    // The kick without friction, drive or damping: v_new − v_old = dt (−S u)/M, except the top row of
    // homogeneous loading, which adds wx σ_d.
    const double dt = 1e-3;
    const std::vector<double> zeros(s.sites(), 0.0), v_old = random_vector(s.dofs(), g);
    std::vector<double> v_new(s.dofs());
    s.kick(dt, 0.0, 0.0, u, zeros, v_old, v_new);
    double worst = 0.0;
    for (std::size_t j = 0; j < s.rows(); ++j)
      for (std::size_t i = 0; i < s.sites(); ++i) {
        const std::size_t k = j * s.sites() + i;
        double F = f_ref[static_cast<Eigen::Index>(k)];
        if (j + 1 == s.rows()) F += s.interface_weight(i) * s.uniform_stress();
        const double a = (v_new[k] - v_old[k]) / dt, a_ref = F / s.node_mass(i, j);
        worst = std::max(worst, std::abs(a - a_ref) / (std::abs(a_ref) + 1.0));
      }
    CHECK(worst < 1e-10);
    // Energies of the drive and the masses.
    CHECK(s.kinetic_energy(v_old) > 0.0);
    CHECK(s.spring_energy(2.0, u) == (edge ? Approx(0.5 * 2.5 * std::pow(0.3 * 2.0 - s.edge_slip(u), 2)) : Approx(0.0)));
    CHECK(s.uniform_power(std::vector<double>(s.dofs(), 1.0)) == Approx(edge ? 0.0 : 0.5 * 3.0));
  }
}

TEST_CASE("strip: implicit_solve matches a direct solve of the assembled system", "[strip]") {
  std::mt19937 g(2);
  struct Shape {
    std::size_t nx, rows;
  };
  for (const Shape sh : {Shape{17, 5}, Shape{33, 9}, Shape{101, 2}, Shape{2, 3}, Shape{3, 2}})
    for (const bool edge : {true, false})
      for (const auto shift : {core::Strip::Shift::mean_c1, core::Strip::Shift::eta}) {
        INFO("nx " << sh.nx << " rows " << sh.rows << (edge ? " edge" : " homogeneous") << " shift "
                   << static_cast<int>(shift));
        const Setup st = setup(sh.nx, sh.rows, edge);
        core::Strip s = make(st);
        s.set_shift(shift);
        const std::size_t n = s.dofs(), nx = s.sites();
        const auto u = random_vector(n, g), V = random_vector(n, g), sb = random_vector(nx, g);
        const auto c0_in = random_vector(nx, g), c1_in = random_vector(nx, g, 0.0, 3.0), w_prev = random_vector(nx, g);
        std::vector<double> c0(nx), c1(nx), W(n, 0.0);
        std::vector<double> seen(nx, 0.0);
        const auto lin = [&](std::size_t i, double w, double& a, double& b) {
          seen[i] = w;
          a = c0_in[i];
          b = c1_in[i];
        };
        const double t = 1.3, dt = 0.02, eta = 0.1;
        s.implicit_solve(lin, w_prev, c0, c1, t, dt, eta, u, V, sb, W);
        CHECK(seen == w_prev);
        CHECK(c1 == c1_in);
        const Assembled a = assemble(s, c0, c1, t, dt, eta, u, V, sb);
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a.A);
        REQUIRE(ldlt.info() == Eigen::Success);
        const Eigen::VectorXd ref = ldlt.solve(a.rhs);
        CHECK(rel_diff(W, ref) < 1e-10);
        CHECK(s.last_iterations() >= 1);
        CHECK(s.last_iterations() < 60);
        // Warm start from the solution: converged at once (or after one correcting iteration).
        s.implicit_solve(lin, w_prev, c0, c1, t, dt, eta, u, V, sb, W);
        CHECK(s.last_iterations() <= 1);
        CHECK(rel_diff(W, ref) < 1e-10);
      }
}

TEST_CASE("strip: with uniform c1 and no spring the preconditioner is the exact inverse (one CG iteration)", "[strip]") {
  std::mt19937 g(3);
  struct Case {
    std::size_t nx, rows;
    core::Strip::Shift shift;
    double c1;
  };
  for (const Case c : {Case{17, 5, core::Strip::Shift::mean_c1, 1.7}, Case{64, 7, core::Strip::Shift::mean_c1, 0.3},
                       Case{2, 4, core::Strip::Shift::mean_c1, 0.5}, Case{129, 2, core::Strip::Shift::eta, 0.0},
                       Case{45, 12, core::Strip::Shift::eta, 0.0}}) {
    INFO("nx " << c.nx << " rows " << c.rows);
    const Setup st = setup(c.nx, c.rows, false);  // homogeneous: K = 0
    core::Strip s = make(st);
    s.set_shift(c.shift);
    const std::size_t n = s.dofs(), nx = s.sites();
    const auto u = random_vector(n, g), V = random_vector(n, g), sb = random_vector(nx, g);
    const auto c0_in = random_vector(nx, g);
    std::vector<double> c0(nx), c1(nx), W(n, 0.0), w_prev(nx, 0.0);
    const auto lin = [&](std::size_t i, double, double& a, double& b) {
      a = c0_in[i];
      b = c.c1;
    };
    s.implicit_solve(lin, w_prev, c0, c1, 0.0, 0.05, 0.1, u, V, sb, W);
    CHECK(s.last_iterations() == 1);
    CHECK(s.last_residual() < 1e-13);
    const Assembled a = assemble(s, c0, c1, 0.0, 0.05, 0.1, u, V, sb);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(a.A);
    CHECK(rel_diff(W, ldlt.solve(a.rhs)) < 1e-12);
  }
}

TEST_CASE("strip: stable_dt is a true bound of the explicit scheme, within 25% of the exact limit", "[strip]") {
  for (const bool edge : {true, false})
    for (const double dy : {0.25, 0.5, 1.0}) {
      INFO((edge ? "edge" : "homogeneous") << " dy " << dy);
      Setup st = setup(13, 5, edge, 0.5, dy);
      st.law.alpha = 50.0;  // a stiff interface, so that its term counts
      st.drive.K = 40.0;
      const core::Strip s = make(st);
      const auto n = static_cast<Eigen::Index>(s.dofs());
      Eigen::MatrixXd K = Eigen::MatrixXd(s.stiffness_matrix());
      const Eigen::VectorXd b = spread(s);
      K += s.spring_K() * b * b.transpose();
      Eigen::VectorXd m_isqrt(n);
      for (std::size_t j = 0; j < s.rows(); ++j)
        for (std::size_t i = 0; i < s.sites(); ++i) {
          const auto k = static_cast<Eigen::Index>(j * s.sites() + i);
          if (j == 0) K(k, k) += st.law.alpha * s.interface_weight(i);
          m_isqrt[k] = 1.0 / std::sqrt(s.node_mass(i, j));
        }
      const Eigen::MatrixXd sym = m_isqrt.asDiagonal() * K * m_isqrt.asDiagonal();
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym);
      const double exact = 2.0 / std::sqrt(es.eigenvalues().maxCoeff());
      CHECK(exact >= s.stable_dt());
      CHECK(exact <= 1.25 * s.stable_dt());
    }
}

TEST_CASE("strip: one thin interval is the chain (H -> 0)", "[strip]") {
  std::mt19937 g(5);
  for (const bool edge : {true, false}) {
    const std::size_t nx = 41;
    const double H = 1e-4;
    Setup st = setup(nx, 2, edge, 0.5, H);
    REQUIRE(st.bulk.height == H);
    const core::Strip s = make(st);
    REQUIRE(s.rows() == 2);
    const core::Bulk chain(st.bulk, st.drive, st.law, st.dx);
    REQUIRE(chain.nodes() == nx);
    const auto u1 = random_vector(nx, g), v1 = random_vector(nx, g), sb = random_vector(nx, g);
    std::vector<double> u(2 * nx), v(2 * nx), v_new(2 * nx);
    for (std::size_t j = 0; j < 2; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        u[j * nx + i] = u1[i];
        v[j * nx + i] = v1[i];
      }
    const double t = 0.7, dt = 1e-4;
    const double F = s.drive_force(t, u);
    CHECK(F == Approx(chain.drive_force(t, u1[0])).epsilon(1e-14));
    s.kick(dt, 0.0, F, u, sb, v, v_new);
    // Chain: ρ a_i = F_i/w_i + σ_d − σ̄_i (η = 0).
    std::vector<double> a_chain(nx);
    chain.forces_per_length(u1, chain.drive_force(t, u1[0]), [&](std::size_t i, double f) {
      a_chain[i] = (f + chain.uniform_stress() - sb[i]) / chain.rho();
    });
    double scale = 0.0, worst = 0.0;
    for (std::size_t i = 0; i < nx; ++i) scale = std::max(scale, std::abs(a_chain[i]));
    for (std::size_t i = 0; i < nx; ++i) {
      double p = 0.0;
      for (std::size_t j = 0; j < 2; ++j) p += s.node_mass(i, j) * (v_new[j * nx + i] - v[j * nx + i]) / dt;
      const double a = p / (s.rho() * s.interface_weight(i));
      worst = std::max(worst, std::abs(a - a_chain[i]) / scale);
    }
    CHECK(worst < 1e-12);
    CHECK(s.edge_mass() == Approx(st.bulk.rho * st.dx / 2));
  }
}

TEST_CASE("strip: copies solve bit-identically and outlive the original", "[strip]") {
  std::mt19937 g(6);
  auto original = std::make_unique<core::Strip>(make(setup(48, 7, true)));
  const std::size_t n = original->dofs(), nx = original->sites();
  const auto u = random_vector(n, g), V = random_vector(n, g), sb = random_vector(nx, g);
  const auto c0_in = random_vector(nx, g), c1_in = random_vector(nx, g, 0.0, 2.0);
  const std::vector<double> w_prev(nx, 0.0);
  const auto lin = [&](std::size_t i, double, double& a, double& b) {
    a = c0_in[i];
    b = c1_in[i];
  };
  const auto solve = [&](core::Strip& s) {
    std::vector<double> c0(nx), c1(nx), W(n, 0.0);
    s.implicit_solve(lin, w_prev, c0, c1, 0.4, 0.02, 0.1, u, V, sb, W);
    return W;
  };
  const std::vector<double> W0 = solve(*original);
  core::Strip copy(*original);
  core::Strip assigned = make(setup(5, 3, false));
  assigned = *original;
  core::Strip tmp(*original);
  core::Strip moved(std::move(tmp));
  original.reset();
  CHECK(solve(copy) == W0);  // bit-identical
  CHECK(solve(assigned) == W0);
  CHECK(solve(moved) == W0);
  CHECK(solve(copy) == W0);  // again, with the factors already made
  core::Strip move_assigned = make(setup(5, 3, false));
  move_assigned = std::move(copy);
  CHECK(solve(move_assigned) == W0);
}

TEST_CASE("strip: the CG iteration count does not grow with the grid", "[strip]") {
  // With P the system's separable part (d̄ between min and max of d_i = η + c1_i/2), A − P is diagonal on
  // the interface plus the spring's rank one, so wᵀAw/wᵀPw ∈ [(m + d_min)/(m + d̄), (m + d_max)/(m + d̄)],
  // m = ρ' dy/dt the interface row's mass term per unit wx: κ(P⁻¹A) ≤ (m + d_max)/(m + d_min) ≤ d_max/d_min,
  // whatever nx, rows and H. CG reduces the residual by 2 sqrt(κ(A)) ((√κ−1)/(√κ+1))^k, plus one iteration
  // for the rank one: with κ = d_max/d_min the bound grows only with log κ(A) (~ 2 log of the grid's
  // aspect dt c_s/dx, not with the number of nodes). Observed 13, 15, 19, 23, 24 along the diagonal (H grows
  // with rows, m falls, κ rises towards d_max/d_min) and 21 → 24 for 16× the columns at rows = 65 (CG's
  // superlinear phase: a longer interface samples more distinct c1).
  std::mt19937 g(7);
  const double dt = 0.02, eta = 0.1, dx = 0.5, dy = 0.5, c1_max = 2.0;
  const double dmin = eta, dmax = eta + 0.5 * c1_max;
  const double kappa = dmax / dmin;
  const double rate = std::log((std::sqrt(kappa) + 1) / (std::sqrt(kappa) - 1));
  std::vector<int> its;
  for (const auto& [nx, rows] : {std::pair<std::size_t, std::size_t>{65, 9}, {129, 17}, {257, 33}, {513, 65},
                                 {1025, 65}, {65, 65}}) {
    INFO("nx " << nx << " rows " << rows);
    const Setup st = setup(nx, rows, true, dx, dy);
    core::Strip s = make(st);
    const std::size_t n = s.dofs();
    const auto u = random_vector(n, g), V = random_vector(n, g), sb = random_vector(nx, g);
    const auto c0_in = random_vector(nx, g), c1_in = random_vector(nx, g, 0.0, c1_max);
    std::vector<double> c0(nx), c1(nx), W(n, 0.0), w_prev(nx, 0.0);
    const auto lin = [&](std::size_t i, double, double& a, double& b) {
      a = c0_in[i];
      b = c1_in[i];
    };
    s.implicit_solve(lin, w_prev, c0, c1, 0.0, dt, eta, u, V, sb, W);
    // κ(A) ≤ (largest Gershgorin row sum)/(smallest mass term 2M/dt).
    const double mp = st.bulk.rho / st.bulk.height, mup = st.bulk.mu / st.bulk.height;
    const double amax = 2 * mp * dx * dy / dt + dt * (2 * mup * dy / dx + 2 * mup * dx / dy) + dx * dmax +
                        dt * st.drive.K;
    const double amin = 2 * mp * (dx / 2) * (dy / 2) / dt;
    const int bound = 2 + static_cast<int>(std::ceil(std::log(2 * std::sqrt(amax / amin) / 1e-12) / rate));
    INFO("iterations " << s.last_iterations() << " bound " << bound);
    CHECK(s.last_iterations() <= bound);
    CHECK(bound <= 60);  // the bound itself: grid-independent but for the logarithm
    its.push_back(s.last_iterations());
  }
  CHECK(its[4] <= its[5] + 4);  // rows 65: nx 1025 against nx 65
  CHECK(its[4] <= its[3] + 2);  // rows 65: nx 1025 against nx 513
}

// The explicit kick runs the interior of each row in one branch-free (vectorised; on x86-64 an AVX2 clone) loop. It
// must give, bit for bit, what the node-by-node update of the force of elastic_forces gives (the kick before that
// loop): v_new = v_old + dt f/M off the interface row (plus wx σ_d on the top row, the edge force on column 0) and
// (v_old (M − wx η dt/2) + dt (f − wx σ̄))/(M + wx η dt/2) on it. Random states, both loadings, one to several rows.
// (Deterministic.)
TEST_CASE("strip: the explicit kick is the node-by-node update bit for bit", "[strip]") {
  std::mt19937 g(11);
  for (const bool edge : {true, false})
    for (const std::size_t rows : {std::size_t{2}, std::size_t{3}, std::size_t{9}}) {
      INFO("edge " << edge << ", rows " << rows);
      const Setup st = setup(37, rows, edge);
      const core::Strip s = make(st);
      const std::size_t nx = s.sites(), ny = s.rows() - 1;
      const auto u = random_vector(s.dofs(), g), v_old = random_vector(s.dofs(), g);
      const auto sb = random_vector(nx, g, 0.0, 2.0);
      const double dt = 1e-3, eta = 0.1, F = 0.8;
      std::vector<double> v_new(s.dofs()), v_ref(s.dofs());
      s.kick(dt, eta, F, u, sb, v_old, v_new);
      s.elastic_forces(u, [&](std::size_t j, std::size_t i, double f) {
        const std::size_t k = j * nx + i;
        const double wx = s.interface_weight(i), m = s.node_mass(i, j);
        if (i == 0) f += F / s.height() * s.row_weight(j);
        if (j == ny) f += wx * s.uniform_stress();
        if (j == 0) {
          const double damp = wx * (0.5 * eta * dt);
          v_ref[k] = (v_old[k] * (m - damp) + dt * (f - wx * sb[i])) / (m + damp);
        } else {
          v_ref[k] = v_old[k] + dt * f / m;
        }
      });
      std::size_t differ = 0;
      for (std::size_t k = 0; k < v_new.size(); ++k) differ += v_new[k] != v_ref[k];
      CHECK(differ == 0);
    }
}
