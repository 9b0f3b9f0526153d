#include "continuum/inplane_stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

namespace slipfront::continuum {

namespace {

using Complex = std::complex<double>;

// The strip's stiffness per unit length in x for u_x = X(y) e^{ikx}, u_y = i Y(y) e^{ikx}: the energy density
// ½[(λ'+2μ')(kX)² + 2λ' kX Y' + (λ'+2μ') Y'² + μ'(X' − kY)²] (real in X, Y), linear elements, two Gauss points
// (exact). Dofs: X_0..X_N, then Y_0..Y_N.
Eigen::MatrixXd strip_stiffness(const InPlaneStabilityParams& p, double k) {
  const int N = p.elements, n = 2 * (N + 1);
  const double h = p.height / N, l2 = p.lambda_p + 2.0 * p.mu_p;
  Eigen::Matrix3d D;
  D << l2, p.lambda_p, 0.0, p.lambda_p, l2, 0.0, 0.0, 0.0, p.mu_p;
  Eigen::Matrix4d ke = Eigen::Matrix4d::Zero();
  for (const double xi : {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)}) {
    const double na = 1.0 - xi, nb = xi, da = -1.0 / h, db = 1.0 / h;
    Eigen::Matrix<double, 3, 4> B;
    B << k * na, k * nb, 0.0, 0.0,  // e1 = kX
        0.0, 0.0, da, db,           // e2 = Y'
        da, db, -k * na, -k * nb;   // e3 = X' − kY
    ke += 0.5 * h * B.transpose() * D * B;
  }
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int e = 0; e < N; ++e) {
    const int dof[4] = {e, e + 1, N + 1 + e, N + 2 + e};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) K(dof[a], dof[b]) += ke(a, b);
  }
  return K;
}

// The free dofs (every one but Y_0, held by the interface) and their lumped masses ρ' h (half at the faces).
std::vector<int> free_dofs(int N) {
  std::vector<int> f;
  for (int j = 0; j <= N; ++j) f.push_back(j);
  for (int j = 1; j <= N; ++j) f.push_back(N + 1 + j);
  return f;
}
double lumped_mass(const InPlaneStabilityParams& p, int dof) {
  const int N = p.elements, j = dof % (N + 1);
  const double h = p.height / N;
  return p.rho_p * h * ((j == 0 || j == N) ? 0.5 : 1.0);
}

void check(const InPlaneStabilityParams& p, double k) {
  if (!(k > 0.0) || p.elements < 2 || !(p.height > 0.0) || !(p.mu_p > 0.0) || !(p.rho_p > 0.0) || !(p.p0 > 0.0) ||
      !(p.v0 > 0.0) || !(p.relaxation_length >= 0.0) || !(p.relaxation_speed >= 0.0))
    throw std::invalid_argument("inplane stability: k, H, μ', ρ', p_0, v_0 must be > 0, L, v* >= 0 and elements >= 2");
}

bool regularised(const InPlaneStabilityParams& p) { return p.relaxation_length > 0.0; }

// The first-order system ż = J z, z = [q | q̇ | ℓ | δp_eff]: q the free dofs (X_0..X_N, Y_1..Y_N), ℓ the law's two
// perturbations, δp_eff the regularised load (only with relaxation_length > 0).
Eigen::MatrixXcd growth_matrix(const InPlaneStabilityParams& p, double k) {
  check(p, k);
  const int N = p.elements;
  const Eigen::MatrixXd K = strip_stiffness(p, k);
  const auto f = free_dofs(N);
  const int n = static_cast<int>(f.size()), la = 2 * n, lb = 2 * n + 1, pe = 2 * n + 2;
  const int size = regularised(p) ? 2 * n + 3 : 2 * n + 2;
  const int y0 = N + 1;  // the held dof Y_0: its reaction is the interface normal stress
  // steady sliding at v0 (docs/model.md §1.4): A0 = 1/(1 + κ v0), σ̄0 = α A0
  const double A0 = 1.0 / (1.0 + p.kappa * p.v0), sb0 = p.alpha * A0, r = 1.0 + p.kappa * p.v0;
  const double gain = p.coupled ? p.exponent / p.p0 : 0.0;  // δa = (m/p0) δp
  Eigen::MatrixXcd J = Eigen::MatrixXcd::Zero(size, size);
  for (int a = 0; a < n; ++a) {
    J(a, n + a) = 1.0;  // q̇ = w
    const double m = lumped_mass(p, f[a]);
    for (int b = 0; b < n; ++b) J(n + a, b) = -K(f[a], f[b]) / m;
  }
  // δp = −δσ_yy = i (K q)_{Y0} (u_y = iY: the held dof's reaction G = (Kq)_{Y0} is the traction −σ_yy times −i)
  Eigen::RowVectorXcd dp(size);
  dp.setZero();
  for (int b = 0; b < n; ++b) dp(b) = Complex(0.0, 1.0) * K(y0, f[b]);
  if (regularised(p)) {
    // δṗ_eff = β (δp − δp_eff), β = (v0 + v*)/L (the |v| factor multiplies p_eff − p = 0 at the steady state); the law
    // then sees δp_eff in place of δp
    const double beta = (p.v0 + p.relaxation_speed) / p.relaxation_length;
    J.row(pe) = beta * dp;
    J(pe, pe) = -beta;
    dp.setZero();
    dp(pe) = 1.0;
  }
  // X_0 (free dof 0): m0 Ẍ0 = −(Kq)_{X0} − δτ, δτ = δσ̄ + η δv, δv = w_0
  const double m0 = lumped_mass(p, 0);
  J(n, n) -= p.eta / m0;
  if (!p.instantaneous) {
    // ℓ = [δA, δσ̄]: δȦ = δa − r δA − κ A0 δv, δσ̄̇ = α v0 δA − v0 δσ̄ (the δv terms α A0 − σ̄0 cancel)
    J.row(la) += gain * dp;
    J(la, la) = -r;
    J(la, n) = -p.kappa * A0;
    J(lb, la) = p.alpha * p.v0;
    J(lb, lb) = -p.v0;
    J(n, lb) = -1.0 / m0;
  } else {
    // ℓ = [δφ, δψ], σ̄ = a ψ, A = a φ: δσ̄ = σ̄0 δa + δψ; φ, ψ follow the unloaded law
    J(la, la) = -r;
    J(la, n) = -p.kappa * A0;
    J(lb, la) = p.alpha * p.v0;
    J(lb, lb) = -p.v0;
    J(n, lb) = -1.0 / m0;
    J.row(n) -= (sb0 * gain / m0) * dp;
  }
  return J;
}

}  // namespace

std::vector<Complex> inplane_growth_rates(const InPlaneStabilityParams& p, double k) {
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(growth_matrix(p, k), false);
  if (es.info() != Eigen::Success) throw std::runtime_error("inplane stability: the eigenvalue solver failed");
  return {es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size()};
}

Complex leading_growth_rate(const InPlaneStabilityParams& p, double k, double max_frequency) {
  return leading_mode(p, k, max_frequency).s;
}

InPlaneMode leading_mode(const InPlaneStabilityParams& p, double k, double max_frequency) {
  Eigen::ComplexEigenSolver<Eigen::MatrixXcd> es(growth_matrix(p, k), true);
  if (es.info() != Eigen::Success) throw std::runtime_error("inplane stability: the eigenvalue solver failed");
  const auto& ev = es.eigenvalues();
  // The sliding breaks the symmetry x -> -x, so the modes of e^{ikx} need not come in pairs ±ω: every frequency
  // sign counts; of two with the same rate (to 1e-12 of |s|), the one with Im s >= 0.
  Eigen::Index best = -1;
  for (Eigen::Index a = 0; a < ev.size(); ++a) {
    if (std::abs(ev(a).imag()) > max_frequency) continue;
    const double gain = best < 0 ? 1.0 : ev(a).real() - ev(best).real(), tie = 1e-12 * std::abs(ev(a));
    if (gain > tie || (std::abs(gain) <= tie && ev(a).imag() >= 0.0 && ev(best).imag() < 0.0)) best = a;
  }
  if (best < 0) throw std::runtime_error("inplane stability: no mode below the frequency bound");
  const int N = p.elements, n = 2 * N + 1;
  const auto z = es.eigenvectors().col(best);
  const Complex norm = z(n);  // the interface's slip-rate amplitude δv = 1
  if (std::abs(norm) == 0.0) throw std::runtime_error("inplane stability: the leading mode does not slip the interface");
  InPlaneMode m;
  m.s = ev(best);
  m.ux.assign(N + 1, 0.0);
  m.uy.assign(N + 1, 0.0);
  m.vx.assign(N + 1, 0.0);
  m.vy.assign(N + 1, 0.0);
  for (int j = 0; j <= N; ++j) {
    m.ux[j] = z(j) / norm;
    m.vx[j] = z(n + j) / norm;
  }
  for (int j = 1; j <= N; ++j) {  // u_y = i Y e^{ikx}
    m.uy[j] = Complex(0.0, 1.0) * z(N + j) / norm;
    m.vy[j] = Complex(0.0, 1.0) * z(n + N + j) / norm;
  }
  m.law_a = z(2 * n) / norm;
  m.law_b = z(2 * n + 1) / norm;
  m.p_eff = regularised(p) ? z(2 * n + 2) / norm : Complex(0.0);
  return m;
}

void inplane_static_kernels(const InPlaneStabilityParams& p, double k, Complex& kt, Complex& kn) {
  check(p, k);
  const int N = p.elements, y0 = N + 1;
  const Eigen::MatrixXd K = strip_stiffness(p, k);
  // X_0 = 1, Y_0 = 0 held; the others in equilibrium
  std::vector<int> rest;
  for (int j = 1; j <= N; ++j) rest.push_back(j);
  for (int j = 1; j <= N; ++j) rest.push_back(N + 1 + j);
  const int m = static_cast<int>(rest.size());
  Eigen::MatrixXd A(m, m);
  Eigen::VectorXd b(m);
  for (int a = 0; a < m; ++a) {
    b(a) = -K(rest[a], 0);
    for (int c = 0; c < m; ++c) A(a, c) = K(rest[a], rest[c]);
  }
  const Eigen::VectorXd x = A.ldlt().solve(b);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(2 * (N + 1));
  q(0) = 1.0;
  for (int a = 0; a < m; ++a) q(rest[a]) = x(a);
  const Eigen::VectorXd g = K * q;
  kt = -g(0);                           // σ_xy(x, 0) = −(Kq)_{X0}
  kn = Complex(0.0, -1.0) * g(y0);      // σ_yy(x, 0) = −i (Kq)_{Y0}
}

std::vector<double> inplane_frictionless_frequencies(const InPlaneStabilityParams& p, double k) {
  check(p, k);
  const Eigen::MatrixXd K = strip_stiffness(p, k);
  const auto f = free_dofs(p.elements);
  const int n = static_cast<int>(f.size());
  Eigen::MatrixXd S(n, n);  // M^{-1/2} K M^{-1/2}
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) S(a, b) = K(f[a], f[b]) / std::sqrt(lumped_mass(p, f[a]) * lumped_mass(p, f[b]));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S, Eigen::EigenvaluesOnly);
  std::vector<double> w;
  for (int a = 0; a < n; ++a) w.push_back(std::sqrt(std::max(0.0, es.eigenvalues()(a))));
  return w;
}

}  // namespace slipfront::continuum
