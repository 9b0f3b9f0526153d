// The in-plane strip (core/inplane.hpp, docs/model.md §10): its elastic operator against its own matrix and
// energy and the rigid motions; the discrete free modes with a frictionless base against the symmetric Lamb roots
// of a free plate of thickness 2H (the lowest branch at kH = 0.1 … 5, the k = 0 cut-offs, the Rayleigh limit) at
// the observed order of the grid; the viscous base's damping; the static interface kernels K_t, K_n of an imposed
// base slip; the stuck edge-loaded decay rate; the explicit scheme's stability limit; and a closing energy budget
// with the continuum law.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "continuum/friction_law.hpp"
#include "core/inplane.hpp"
#include "core/stepper.hpp"
#include "inplane_fixtures.hpp"
#include "scenes.hpp"

namespace core = slipfront::core;
using slipfront::testing::observed_order;

namespace {

constexpr double pi = std::numbers::pi;

using Setup = slipfront::testing::InPlaneSetup;
using slipfront::testing::bisect;

// nx columns, ny row intervals; fig1's material, edge or homogeneous loading (slipfront::testing::fig1_inplane).
Setup setup(std::size_t nx, std::size_t ny, double dx, double dy, bool edge = true) {
  return slipfront::testing::fig1_inplane(static_cast<double>(nx - 1) * dx, static_cast<double>(ny) * dy, dx, dy, edge);
}

std::vector<double> random_vector(std::size_t n, std::mt19937& g) { return slipfront::testing::uniform_vector(n, g); }

Eigen::Map<const Eigen::VectorXd> view(const std::vector<double>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size())};
}

// --- Closed forms (docs/model.md §10.3) -------------------------------------------------------------------------

// cosh(qH) and sinh(qH)/q for q² of either sign (real for imaginary q).
double ch(double q2, double H) { return q2 >= 0.0 ? std::cosh(std::sqrt(q2) * H) : std::cos(std::sqrt(-q2) * H); }
double sh(double q2, double H) {
  if (q2 == 0.0) return H;
  return q2 > 0.0 ? std::sinh(std::sqrt(q2) * H) / std::sqrt(q2) : std::sin(std::sqrt(-q2) * H) / std::sqrt(-q2);
}
// The symmetric Rayleigh–Lamb function of a free plate of thickness 2H divided by q_t (real for every ω):
// (k² + q_t²)² cosh(q_l H) sinh(q_t H)/q_t − 4k² q_l² cosh(q_t H) sinh(q_l H)/q_l.
double lamb(double w, double k, double H, double cs, double cp) {
  const double qt2 = k * k - w * w / (cs * cs), ql2 = k * k - w * w / (cp * cp);
  return (k * k + qt2) * (k * k + qt2) * ch(ql2, H) * sh(qt2, H) - 4.0 * k * k * ql2 * ch(qt2, H) * sh(ql2, H);
}
// The lowest symmetric Lamb frequency at wavenumber k: the first sign change above 0.5 c_s k (no root below c_R k).
double lamb_lowest(double k, double H, double cs, double cp) {
  const auto f = [&](double w) { return lamb(w, k, H, cs, cp); };
  const double step = 1e-3 * cs * k;
  for (double w = 0.5 * cs * k; w < 2.0 * cp * k; w += step)
    if (f(w) * f(w + step) < 0.0) return bisect(f, w, w + step);
  FAIL("no Lamb root");
  return 0.0;
}
// c_R/c_s: the root of (2 − ξ²)² = 4 sqrt(1 − ξ²) sqrt(1 − ξ² c_s²/c_p²) in (0, 1).
double rayleigh_ratio(double cs, double cp) {
  const double r = cs * cs / (cp * cp);
  return bisect([&](double x) { return (2 - x * x) * (2 - x * x) - 4 * std::sqrt(1 - x * x) * std::sqrt(1 - x * x * r); },
                0.5, 1.0 - 1e-12);
}
// The static interface kernels of a base slip U e^{ikx} under a free top: σ_xy = K_t U, σ_yy = i r K_t U.
double kernel_t(double k, double H, double mu_p, double nu) {
  const double kh = k * H, s = std::sinh(kh);
  const double D = kh * kh + 4 * (1 - nu) * (1 - nu) + (3 - 4 * nu) * s * s;
  return -2 * mu_p * (1 - nu) * k * (2 * kh + std::sinh(2 * kh)) / D;
}
double kernel_ratio(double k, double H, double nu) {
  const double kh = k * H, s = std::sinh(kh);
  return (kh * kh + (1 - 2 * nu) * s * s) / ((1 - nu) * (2 * kh + std::sinh(2 * kh)));
}

// --- The column problem --------------------------------------------------------------------------------------------
// For u_x = a_j sin(k x + φ), u_y = b_j cos(k x + φ) the strip's operator at an interior column maps (a, b) to forces
// of the same form: (−K u)_x = −(C z)_x sin, (−K u)_y = −(C z)_y cos, z = (a_0 … a_ny, b_0 … b_ny). C is read off the
// body's own elastic_forces on a 5-column strip at the middle column, with k x_2 + φ = π/4.
struct Column {
  Eigen::MatrixXd C;  // (2 rows) × (2 rows)
  Eigen::VectorXd m;  // the column's lumped masses ρ' dx wy(j), both components
};
std::vector<double> column_field(const core::InPlane& b, double k, const Eigen::VectorXd& z) {
  const std::size_t nx = b.sites(), R = b.rows(), P = b.plane();
  const double phi = pi / 4 - k * b.x()[2];
  std::vector<double> u(b.dofs(), 0.0);
  for (std::size_t j = 0; j < R; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      u[j * nx + i] = z(static_cast<Eigen::Index>(j)) * std::sin(k * b.x()[i] + phi);
      u[P + j * nx + i] = z(static_cast<Eigen::Index>(R + j)) * std::cos(k * b.x()[i] + phi);
    }
  return u;
}
Column column(const core::InPlane& b, double k) {
  REQUIRE(b.sites() == 5);
  const std::size_t R = b.rows(), P = b.plane(), nx = b.sites();
  const auto n = static_cast<Eigen::Index>(2 * R);
  Column c{Eigen::MatrixXd::Zero(n, n), Eigen::VectorXd::Zero(n)};
  const double s = std::sin(pi / 4);  // = cos(π/4)
  std::vector<double> f(b.dofs());
  for (Eigen::Index col = 0; col < n; ++col) {
    const std::vector<double> u = column_field(b, k, Eigen::VectorXd::Unit(n, col));
    b.elastic_forces(u, f);
    for (std::size_t j = 0; j < R; ++j) {
      c.C(static_cast<Eigen::Index>(j), col) = -f[j * nx + 2] / s;
      c.C(static_cast<Eigen::Index>(R + j), col) = -f[P + j * nx + 2] / s;
    }
  }
  for (std::size_t j = 0; j < R; ++j)
    c.m(static_cast<Eigen::Index>(j)) = c.m(static_cast<Eigen::Index>(R + j)) = b.node_mass(2, j);
  return c;
}
// The column with u_y of row 0 removed (the interface's constraint): index R of (a, b) dropped.
Eigen::MatrixXd drop(const Eigen::MatrixXd& A, Eigen::Index r) {
  const Eigen::Index n = A.rows();
  Eigen::MatrixXd B(n - 1, n - 1);
  for (Eigen::Index i = 0, ii = 0; i < n; ++i) {
    if (i == r) continue;
    for (Eigen::Index j = 0, jj = 0; j < n; ++j) {
      if (j == r) continue;
      B(ii, jj++) = A(i, j);
    }
    ++ii;
  }
  return B;
}
// The column's free frequencies with a frictionless base, ascending (the eigenvalues of M⁻¹C are real: checked).
std::vector<double> column_frequencies(const core::InPlane& b, double k) {
  const Column c = column(b, k);
  const auto r = static_cast<Eigen::Index>(b.rows());
  const Eigen::MatrixXd C = drop(c.C, r);
  Eigen::VectorXd m(c.m.size() - 1);
  m << c.m.head(r), c.m.tail(r - 1);
  const Eigen::EigenSolver<Eigen::MatrixXd> es(m.cwiseInverse().asDiagonal() * C, false);
  std::vector<double> w;
  for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
    const std::complex<double> l = es.eigenvalues()(i);
    CHECK(std::abs(l.imag()) <= 1e-9 * std::abs(l) + 1e-12);
    w.push_back(std::sqrt(std::max(l.real(), 0.0)));
  }
  std::sort(w.begin(), w.end());
  return w;
}
// A 5-column strip of height H with ny row intervals, dx = dy = H/ny (fig1's μ, ρ; ν given).
core::InPlane column_strip(double H, std::size_t ny, double nu = 1.0 / 3.0) {
  Setup s = setup(5, ny, H / static_cast<double>(ny), H / static_cast<double>(ny));
  s.material.poisson = nu;
  return s.make();
}

}  // namespace

TEST_CASE("inplane: the elastic force is -K u, the energy u.K u/2, rigid motions are free", "[inplane]") {
  std::mt19937 g(3);
  const Setup st = setup(7, 4, 0.5, 0.25);
  const core::InPlane b = st.make();
  REQUIRE(b.sites() == 7);
  REQUIRE(b.rows() == 5);
  REQUIRE(b.dofs() == 70);
  // the 1D meaning of μ (docs/model.md §10.2): μ' = μ(1 − ν)/(2H), c_0 = sqrt(μ/ρ) = c_s sqrt(2/(1 − ν))
  CHECK(b.mu_prime() == Approx(300.0 * (2.0 / 3.0) / 2.0).epsilon(1e-14));
  CHECK(b.plate_speed() == Approx(b.shear_speed() * std::sqrt(3.0)).epsilon(1e-14));
  CHECK(b.pressure_speed() == Approx(2.0 * b.shear_speed()).epsilon(1e-14));  // ν = 1/3: c_p = 2 c_s
  const auto u = random_vector(b.dofs(), g);
  const Eigen::SparseMatrix<double> K = b.stiffness_matrix();
  std::vector<double> f(b.dofs());
  b.elastic_forces(u, f);
  CHECK((view(f) + K * view(u)).norm() < 1e-13 * (K * view(u)).norm());
  CHECK(b.elastic_energy(u) == Approx(0.5 * view(u).dot(K * view(u))).epsilon(1e-13));
  const Eigen::MatrixXd Kd(K);
  CHECK((Kd - Kd.transpose()).norm() == 0.0);
  // translations and the infinitesimal rotation (u_x = −y, u_y = x) carry no force: three zero modes
  for (int mode = 0; mode < 3; ++mode) {
    std::vector<double> r(b.dofs(), 0.0);
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < b.sites(); ++i) {
        const std::size_t k = j * b.sites() + i;
        r[k] = mode == 0 ? 1.0 : mode == 2 ? -b.row_height(j) : 0.0;
        r[b.plane() + k] = mode == 1 ? 1.0 : mode == 2 ? b.x()[i] : 0.0;
      }
    CHECK((K * view(r)).norm() < 1e-12 * K.norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Kd, Eigen::EigenvaluesOnly);
  CHECK(std::abs(es.eigenvalues()(2)) < 1e-10 * es.eigenvalues().maxCoeff());
  CHECK(es.eigenvalues()(3) > 1e-6 * es.eigenvalues().maxCoeff());
  CHECK(es.eigenvalues()(0) > -1e-10 * es.eigenvalues().maxCoeff());
}

TEST_CASE("inplane: the kick is M dv = dt (-K u + loads), u_y of the interface held", "[inplane]") {
  std::mt19937 g(5);
  Setup st = setup(6, 3, 0.5, 0.5, false);  // homogeneous: σ_top = 0.5 on the top
  st.material.normal_load = 0.3;
  const core::InPlane b = st.make();
  const auto u = random_vector(b.dofs(), g), v_old = random_vector(b.dofs(), g), sb = random_vector(b.sites(), g);
  const double dt = 1e-4, eta = 0.1, F = 0.8;
  std::vector<double> v_new(b.dofs()), f(b.dofs());
  b.kick(dt, eta, F, u, sb, v_old, v_new);
  b.elastic_forces(u, f);
  const std::size_t nx = b.sites(), P = b.plane(), top = b.rows() - 1;
  double worst = 0.0;
  for (std::size_t j = 0; j < b.rows(); ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::size_t k = j * nx + i;
      const double m = b.node_mass(i, j), wx = b.interface_weight(i);
      double fx = f[k] + (i == 0 ? F * b.row_weight(j) / b.height() : 0.0), fy = f[P + k];
      fy += (i == 0 ? -0.5 : i + 1 == nx ? 0.5 : 0.0) * b.row_weight(j);  // the end faces' shear σ_xy = σ_top (§10.3)
      if (j == top) {
        fx += wx * 0.5;
        fy -= wx * 0.3;
      }
      if (j == 0) {
        fx -= wx * (sb[i] + eta * 0.5 * (v_old[k] + v_new[k]));
        CHECK(v_new[P + k] == 0.0);
      } else {
        worst = std::max(worst, std::abs(m * (v_new[P + k] - v_old[P + k]) - dt * fy));
      }
      worst = std::max(worst, std::abs(m * (v_new[k] - v_old[k]) - dt * fx));
    }
  CHECK(worst < 1e-15);
  CHECK(b.edge_mass() == Approx(0.01 * 0.25).epsilon(1e-14));
}

TEST_CASE("inplane: hostile construction is refused", "[inplane]") {
  Setup s = setup(5, 2, 1.0, 1.0);
  s.material.poisson = 0.5;
  CHECK_THROWS_AS(s.make(), std::invalid_argument);
  s.material.poisson = -1.0;
  CHECK_THROWS_AS(s.make(), std::invalid_argument);
  s.material.poisson = 0.3;
  s.material.normal_load = -0.1;
  CHECK_THROWS_AS(s.make(), std::invalid_argument);
  s.material.normal_load = 0.0;
  s.dy = 0.7;  // does not divide H = 2
  CHECK_THROWS_AS(s.make(), std::invalid_argument);
  s.dy = 1.0;
  s.drive.loading = core::Loading::spring_block;
  CHECK_THROWS_AS(s.make(), std::invalid_argument);
}

TEST_CASE("inplane: free modes on a frictionless base are the symmetric Lamb modes, second order", "[inplane][lamb]") {
  // docs/model.md §10.3. The lowest branch at ν = 1/3 against the bisected roots, and the roots against the
  // published table (ωH/c_s = 0.17313, 0.85628, 1.63323, 2.48315, 4.74518 at kH = 0.1, 0.5, 1, 2, 5).
  const double H = 2.0;
  const core::InPlane ref = column_strip(H, 4);
  const double cs = ref.shear_speed(), cp = ref.pressure_speed();
  const double kh[5] = {0.1, 0.5, 1.0, 2.0, 5.0}, table[5] = {0.17313, 0.85628, 1.63323, 2.48315, 4.74518};
  for (int n = 0; n < 5; ++n) {
    const double k = kh[n] / H, w = lamb_lowest(k, H, cs, cp);
    CHECK(std::abs(w * H / cs - table[n]) < 6e-6);
    std::vector<double> err;
    for (const std::size_t ny : {8u, 16u, 32u}) {
      const double wd = column_frequencies(column_strip(H, ny), k)[0];
      err.push_back(std::abs(wd / w - 1.0));
    }
    std::printf("inplane Lamb kH = %.1f: relative errors %.3e %.3e %.3e, orders %.3f %.3f\n", kh[n], err[0], err[1],
                err[2], observed_order(err[0], err[1]), observed_order(err[1], err[2]));
    CHECK(observed_order(err[1], err[2]) == Approx(2.0).margin(0.1));
    CHECK(err[2] < 2e-3);
  }
}

TEST_CASE("inplane: the k = 0 cut-offs m pi c_s/H and (2m+1) pi c_p/(2H), second order", "[inplane][lamb]") {
  const double H = 1.0;
  const core::InPlane ref = column_strip(H, 4);
  const double cs = ref.shear_speed(), cp = ref.pressure_speed();
  std::vector<double> exact;
  for (int m = 1; m <= 4; ++m) exact.push_back(m * pi * cs / H);
  for (int m = 0; m <= 3; ++m) exact.push_back((2 * m + 1) * pi * cp / (2 * H));
  std::sort(exact.begin(), exact.end());
  exact.resize(4);  // the four lowest non-zero
  std::vector<double> err;
  for (const std::size_t ny : {8u, 16u, 32u}) {
    const std::vector<double> w = column_frequencies(column_strip(H, ny), 0.0);
    CHECK(w[0] < 1e-6 * cs / H);  // rigid sliding on the frictionless base
    double e = 0.0;
    for (std::size_t m = 0; m < 4; ++m) e = std::max(e, std::abs(w[m + 1] / exact[m] - 1.0));
    err.push_back(e);
  }
  std::printf("inplane cut-offs: max relative errors %.3e %.3e %.3e\n", err[0], err[1], err[2]);
  CHECK(observed_order(err[0], err[1]) == Approx(2.0).margin(0.1));
  CHECK(observed_order(err[1], err[2]) == Approx(2.0).margin(0.1));
}

TEST_CASE("inplane: the lowest branch tends to the Rayleigh wave at large kH", "[inplane][lamb]") {
  // c_R/c_s = 0.91940, 0.92741, 0.93253, 0.94220 at ν = 0.25, 0.3, 1/3, 0.4 (docs/model.md §10.3). The Lamb root's
  // phase speed tends to c_R as e^{−2 q_t H} (q_t = k sqrt(1 − c_R²/c_s²)): 1e-4 at kH = 12, 1e-9 at kH = 30. The
  // grid's (dy = H/96) at kH = 12 against the Lamb root there: its O((k dy)²) error.
  const double nus[4] = {0.25, 0.3, 1.0 / 3.0, 0.4}, table[4] = {0.91940, 0.92741, 0.93253, 0.94220};
  for (int n = 0; n < 4; ++n) {
    const core::InPlane b = column_strip(1.0, 96, nus[n]);
    const double cs = b.shear_speed(), cp = b.pressure_speed(), ratio = rayleigh_ratio(cs, cp);
    CHECK(std::abs(ratio - table[n]) < 6e-6);
    CHECK(lamb_lowest(30.0, 1.0, cs, cp) / (30.0 * cs) == Approx(ratio).epsilon(1e-8));
    const double w12 = lamb_lowest(12.0, 1.0, cs, cp), wd = column_frequencies(b, 12.0)[0];
    std::printf("inplane Rayleigh nu = %.3f: c_R/c_s %.6f, Lamb kH = 12 %.6f, grid %.6f\n", nus[n], ratio,
                w12 / (12.0 * cs), wd / (12.0 * cs));
    CHECK(w12 / (12.0 * cs) == Approx(ratio).epsilon(3e-4));
    CHECK(wd / w12 == Approx(1.0).epsilon(3e-3));
  }
}

TEST_CASE("inplane: a viscous base damps the lowest mode at Re s = -eta/(2 rho' H)", "[inplane]") {
  // The quadratic eigenproblem s² M + s C + K of the column, C = η dx on the interface's u_x, by its companion
  // matrix. Thin strip (H = 1, ν = 1/3, ρ = 0.01, μ = 300: c_0 = 173.2), η = 0.02 (−η/(2ρ'H) = −1), kH = 0.05 and
  // 0.025 (underdamped: c_0 k = 8.7, 4.3). The thin-strip value neglects relative terms (kH)² (the Lamb branch's
  // dispersion) and η H |s|/μ' (the shear across the height that the base's drag makes): the tolerance is their sum.
  double prev = 0.0;
  for (const double kh : {0.05, 0.025}) {
    const core::InPlane b = column_strip(1.0, 16);
    const double k = kh, eta = 0.02;
    const Column c = column(b, k);
    const auto R = static_cast<Eigen::Index>(b.rows());
    const Eigen::MatrixXd Kc = drop(c.C, R);
    const Eigen::Index n = Kc.rows();
    Eigen::VectorXd m(n);
    m << c.m.head(R), c.m.tail(R - 1);
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    A.topRightCorner(n, n).setIdentity();
    A.bottomLeftCorner(n, n) = -(m.cwiseInverse().asDiagonal() * Kc);
    A(n, n) = -eta * b.dx() / m(0);  // u_x of row 0 is the first unknown
    const Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
    std::complex<double> low(0.0, 1e300);
    for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i) {
      const std::complex<double> s = es.eigenvalues()(i);
      if (s.imag() > 0.0 && s.imag() < low.imag()) low = s;
    }
    const double expect = -eta / (2.0 * b.rho_prime() * b.height());
    const double dev = std::abs(low.real() / expect - 1.0), tol = kh * kh + eta * b.height() * std::abs(low) / b.mu_prime();
    std::printf("inplane viscous base kH = %.3f: Re s = %.6f (thin strip %.6f; relative %.2e, tolerance %.2e), "
                "Im s = %.4f (c_0 k = %.4f)\n", kh, low.real(), expect, dev, tol, low.imag(), b.plate_speed() * k);
    CHECK(dev < tol);
    if (prev > 0.0) CHECK(dev < prev);  // closer for the thinner strip
    prev = dev;
  }
}

TEST_CASE("inplane: static interface kernels of a base slip against K_t and K_n/K_t, second order", "[inplane]") {
  // docs/model.md §10.3: u_x(x, 0) = U sin(kx + φ), u_y(x, 0) = 0, free top; σ_xy(x, 0) = K_t U sin,
  // σ_yy(x, 0) = r K_t U cos (K_n = i r K_t). σ_yy read by the body's interface_normal_stress.
  const double H = 1.0, nu = 1.0 / 3.0;
  for (const double kh : {0.1, 1.0, 10.0}) {
    std::vector<double> et, en;
    double mu_p = 0.0;
    // the fields vary across the height over min(H, 1/k): rows scaled with kH at kH = 10 (k dy = 0.16 … 0.04)
    const std::size_t scale = kh > 2.0 ? 4 : 1;
    for (const std::size_t ny : {16 * scale, 32 * scale, 64 * scale}) {
      const core::InPlane b = column_strip(H, ny, nu);
      mu_p = b.mu_prime();
      const double k = kh / H;
      const Column c = column(b, k);
      const auto R = static_cast<Eigen::Index>(b.rows());
      // unknowns: a_1 … a_ny, b_1 … b_ny (a_0 = U = 1, b_0 = 0)
      std::vector<Eigen::Index> fr;
      for (Eigen::Index i = 1; i < R; ++i) fr.push_back(i);
      for (Eigen::Index i = R + 1; i < 2 * R; ++i) fr.push_back(i);
      const auto nf = static_cast<Eigen::Index>(fr.size());
      Eigen::MatrixXd A(nf, nf);
      Eigen::VectorXd rhs(nf);
      for (Eigen::Index i = 0; i < nf; ++i) {
        rhs(i) = -c.C(fr[static_cast<std::size_t>(i)], 0);
        for (Eigen::Index j = 0; j < nf; ++j) A(i, j) = c.C(fr[static_cast<std::size_t>(i)], fr[static_cast<std::size_t>(j)]);
      }
      const Eigen::VectorXd zf = A.partialPivLu().solve(rhs);
      Eigen::VectorXd z = Eigen::VectorXd::Zero(2 * R);
      z(0) = 1.0;
      for (Eigen::Index i = 0; i < nf; ++i) z(fr[static_cast<std::size_t>(i)]) = zf(i);
      const double sxy = -(c.C.row(0).dot(z)) / b.dx();  // σ_xy = (−K u)_x / wx per sin(kx + φ)
      std::vector<double> syy(b.sites());
      b.interface_normal_stress(column_field(b, k, z), syy);
      const double Kt = kernel_t(k, H, mu_p, nu), r = kernel_ratio(k, H, nu);
      et.push_back(std::abs(sxy / Kt - 1.0));
      en.push_back(std::abs(syy[2] / std::cos(pi / 4) / (r * Kt) - 1.0));
    }
    std::printf("inplane kernels kH = %g: K_t errors %.3e %.3e %.3e, K_n errors %.3e %.3e %.3e\n", kh, et[0], et[1],
                et[2], en[0], en[1], en[2]);
    CHECK(observed_order(et[1], et[2]) == Approx(2.0).margin(0.15));
    CHECK(observed_order(en[1], en[2]) == Approx(2.0).margin(0.15));
    CHECK(et[2] < 1e-3);
    CHECK(en[2] < 1e-3);
  }
}

TEST_CASE("inplane: the uniform states are exact on the grid, and the normal load makes the strip expand", "[inplane]") {
  // docs/model.md §10.3. (a) Homogeneous stuck state, p = 0: u_x = σ_top/α + σ_top y/μ', u_y = 0 is in equilibrium
  // with σ̄ = σ_top on the interface everywhere but on the two end faces: there σ_xy = σ_top needs the complementary
  // shear traction ∓σ_top on the faces x = 0, L, which a free face does not carry. The grid's residual without it is
  // exactly that missing traction, ±wy(j) σ_top on the end columns' u_y (and the interface's corners would read
  // σ_yy = ±σ_top wy(0)/wx(0)); the body loads the end faces with it under homogeneous loading (end_load_y), and then
  // the state is exact everywhere, σ_yy = −p at the corners too. (b) Normal load p with a frictionless
  // base: u_x = ε_xx x, u_y = ε_yy y, ε_xx = ν p/(2μ'), ε_yy = −(1 − ν) p/(2μ') (plane strain, σ_xx = σ_xy = 0,
  // σ_yy = −p) is in equilibrium and the interface reads σ_yy = −p. So under p a stuck interface (σ̄ = α u_x) cannot
  // hold the uniform state: its slip would grow with x.
  Setup st = setup(9, 4, 0.5, 0.5, false);
  st.drive.sigma_d = 0.4;
  for (const bool normal : {false, true}) {
    st.material.normal_load = normal ? 0.3 : 0.0;
    if (normal) st.drive.sigma_d = 0.0;
    const core::InPlane b = st.make();
    const std::size_t nx = b.sites(), P = b.plane();
    const double mp = b.mu_prime(), nu = b.poisson(), p = b.normal_load(), s = b.uniform_stress();
    std::vector<double> u(b.dofs(), 0.0), v0(b.dofs(), 0.0), v1(b.dofs()), sb(nx, s), syy(nx);
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const double x = b.x()[i], y = b.row_height(j);
        u[j * nx + i] = normal ? nu * p / (2 * mp) * x : s / st.law.alpha + s * y / mp;
        u[P + j * nx + i] = normal ? -(1 - nu) * p / (2 * mp) * y : 0.0;
      }
    const double dt = 1e-3;
    b.kick(dt, 0.0, 0.0, u, sb, v0, v1);  // no edge force
    double worst = 0.0;
    for (std::size_t j = 0; j < b.rows(); ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        const double m = b.node_mass(i, j);
        // the end faces' missing complementary shear (0 under the normal load alone), which end_load_y supplies
        const double missing = i == 0 ? s * b.row_weight(j) : i + 1 == nx ? -s * b.row_weight(j) : 0.0;
        CHECK(b.end_load_y(i, j) + missing == Approx(0.0).margin(1e-15));
        worst = std::max({worst, std::abs(m * v1[k] / dt), std::abs(m * v1[P + k] / dt)});
      }
    CHECK(worst < 1e-12);
    b.interface_normal_stress(u, syy);
    for (std::size_t i = 0; i < nx; ++i) CHECK(syy[i] == Approx(-p).margin(1e-13));
    for (const std::size_t j : {std::size_t{0}, std::size_t{2}, std::size_t{4}})
      for (const std::size_t i : {std::size_t{0}, std::size_t{3}, std::size_t{8}}) {
        double sxx = 0.0, syy_n = 0.0, sxy = 0.0;
        b.stresses(u, i, j, sxx, syy_n, sxy);
        CHECK(sxx == Approx(0.0).margin(1e-12));
        CHECK(syy_n == Approx(-p).margin(1e-12));
        CHECK(sxy == Approx(s).margin(1e-12));
      }
  }
}
