#include "core/inplane.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

namespace slipfront::core {
namespace {

// λ' and μ' of docs/model.md §10.2 from the scene's μ (its 1D meaning, μ = E' H) and ν.
double mu_prime_of(double mu, double nu, double H) { return mu * (1.0 - nu) / (2.0 * H); }
double lambda_prime_of(double mu_p, double nu) { return 2.0 * mu_p * nu / (1.0 - 2.0 * nu); }

// The plane-strain Q1 element's stiffness on a dx × dy cell (docs/model.md §10.4): ∫ Bᵀ D B over the cell by the
// 2 × 2 Gauss rule (exact: the integrand is a polynomial of degree ≤ 2 in each variable). Local nodes (0,0), (1,0),
// (0,1), (1,1); dofs u_x of the four, then u_y. D = [[λ+2μ, λ, 0], [λ, λ+2μ, 0], [0, 0, μ]] on (ε_xx, ε_yy, γ_xy).
std::array<double, 64> q1_stiffness(double dx, double dy, double lam, double mu) {
  std::array<double, 64> k{};
  const double g = 1.0 / std::sqrt(3.0);
  const double pts[2] = {0.5 * (1.0 - g), 0.5 * (1.0 + g)};  // on [0, 1]
  const double w = 0.25 * dx * dy;                          // each point's weight
  for (double xi : pts)
    for (double et : pts) {
      const double nx[4] = {-(1.0 - et) / dx, (1.0 - et) / dx, -et / dx, et / dx};  // ∂N_a/∂x
      const double ny[4] = {-(1.0 - xi) / dy, -xi / dy, (1.0 - xi) / dy, xi / dy};  // ∂N_a/∂y
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          k[a * 8 + b] += w * ((lam + 2.0 * mu) * nx[a] * nx[b] + mu * ny[a] * ny[b]);              // x–x
          k[(a + 4) * 8 + b + 4] += w * ((lam + 2.0 * mu) * ny[a] * ny[b] + mu * nx[a] * nx[b]);  // y–y
          k[a * 8 + b + 4] += w * (lam * nx[a] * ny[b] + mu * ny[a] * nx[b]);                     // x–y
          k[(b + 4) * 8 + a] += w * (lam * nx[a] * ny[b] + mu * ny[a] * nx[b]);                   // y–x
        }
    }
  return k;
}

// The largest eigenvalue of the element's stiffness over its lumped mass ρ' dx dy/4 per node (§10.5).
double element_omega2(const std::array<double, 64>& ke, double rho_p, double dx, double dy) {
  Eigen::Matrix<double, 8, 8> m;
  for (int a = 0; a < 8; ++a)
    for (int b = 0; b < 8; ++b) m(a, b) = ke[static_cast<std::size_t>(a * 8 + b)];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 8, 8>> es(m, Eigen::EigenvaluesOnly);
  return es.eigenvalues().maxCoeff() / (0.25 * rho_p * dx * dy);
}

void check_material(const InPlaneParams& m) {
  if (!(m.poisson > -1.0 && m.poisson < 0.5))
    throw std::invalid_argument("InPlane: Poisson's ratio must lie in (-1, 1/2), got " + std::to_string(m.poisson));
  if (!(m.normal_load >= 0.0))
    throw std::invalid_argument("InPlane: the normal load must be >= 0, got " + std::to_string(m.normal_load));
}

}  // namespace

// The implicit step's sparse factorisation (solve_step), remade when its coefficients change.
struct InPlane::Direct {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  Eigen::SparseMatrix<double> K;
  std::vector<double> d;  // η + c1/2 of the factorisation
  double dt = -1.0;
  Eigen::VectorXd rhs, w;
};

double InPlane::stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                                 const InPlaneParams& material, double dx, double dy) {
  check_material(material);
  const double H = bulk.height, nu = material.poisson;
  const double mu_p = mu_prime_of(bulk.mu, nu, H), rho_p = bulk.rho / H;
  const double K = drive.loading == Loading::edge ? drive.K : 0.0;
  const double omega2 = element_omega2(q1_stiffness(dx, dy, lambda_prime_of(mu_p, nu), mu_p), rho_p, dx, dy) +
                        2.0 * K / (bulk.rho * dx) + 2.0 * law.alpha * H / (bulk.rho * dy);
  return 2.0 / std::sqrt(omega2);
}

InPlane::InPlane(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                 const InPlaneParams& material, double dx, double dy)
    : dx_(dx), dy_(dy), H_(bulk.height), rho_(bulk.rho), mu_(bulk.mu), nu_(material.poisson),
      p_(material.normal_load) {
  if (drive.loading != Loading::edge && drive.loading != Loading::homogeneous)
    throw std::invalid_argument("InPlane: only edge and homogeneous loading have an in-plane strip");
  check_material(material);
  if (!(H_ > 0.0)) throw std::invalid_argument("InPlane: bulk.height must be > 0");
  if (!(dx > 0.0)) throw std::invalid_argument("InPlane: dx must be > 0");
  if (!(dy > 0.0)) throw std::invalid_argument("InPlane: dy must be > 0");
  const auto cells = static_cast<long long>(std::llround(bulk.length / dx));
  if (cells < 1) throw std::invalid_argument("InPlane: bulk.length must hold at least one cell");
  const long long ny = std::llround(H_ / dy);
  if (ny < 1) throw std::invalid_argument("InPlane: bulk.height must hold at least one row interval");
  if (std::abs(static_cast<double>(ny) * dy - H_) > 1e-9 * H_)
    throw std::invalid_argument("InPlane: dy must divide bulk.height");
  nx_ = static_cast<std::size_t>(cells) + 1;
  ny_ = static_cast<std::size_t>(ny);
  x_.resize(nx_);
  for (std::size_t i = 0; i < nx_; ++i) x_[i] = static_cast<double>(i) * dx;
  rho_p_ = rho_ / H_;
  mu_p_ = mu_prime_of(mu_, nu_, H_);
  lambda_p_ = lambda_prime_of(mu_p_, nu_);
  if (drive.loading == Loading::edge) {
    spring_K_ = drive.K;
    v_d_ = drive.v_d;
  } else {
    sigma_d_ = drive.sigma_d;
    rear_traction_ = drive.rear_traction;
  }
  ke_ = q1_stiffness(dx_, dy_, lambda_p_, mu_p_);
  stable_dt_ = stable_time_step(bulk, drive, law, material, dx, dy);
  force_.assign(dofs(), 0.0);
}

InPlane::InPlane(const InPlane& o)
    : x_(o.x_), nx_(o.nx_), ny_(o.ny_), dx_(o.dx_), dy_(o.dy_), H_(o.H_), rho_(o.rho_), mu_(o.mu_), nu_(o.nu_),
      p_(o.p_), rho_p_(o.rho_p_), mu_p_(o.mu_p_), lambda_p_(o.lambda_p_), sigma_d_(o.sigma_d_),
      spring_K_(o.spring_K_), v_d_(o.v_d_), rear_traction_(o.rear_traction_), stable_dt_(o.stable_dt_), ke_(o.ke_),
      force_(o.force_) {}  // the factorisation is made again on first use
InPlane::InPlane(InPlane&& o) noexcept = default;
InPlane& InPlane::operator=(const InPlane& o) {
  if (this != &o) {
    InPlane copy(o);
    *this = std::move(copy);
  }
  return *this;
}
InPlane& InPlane::operator=(InPlane&& o) noexcept = default;
InPlane::~InPlane() = default;

double InPlane::shear_speed() const { return std::sqrt(mu_p_ / rho_p_); }
double InPlane::pressure_speed() const { return std::sqrt((lambda_p_ + 2.0 * mu_p_) / rho_p_); }
double InPlane::plate_speed() const { return std::sqrt(mu_ / rho_); }

double InPlane::edge_slip(std::span<const double> u) const {
  double s = 0.0;
  for (std::size_t j = 0; j <= ny_; ++j) s += row_weight(j) * u[j * nx_];
  return s / H_;
}

double InPlane::kinetic_energy(std::span<const double> V) const {
  const std::size_t P = plane();
  double e = 0.0;
  for (std::size_t j = 0; j <= ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i) {
      const std::size_t k = j * nx_ + i;
      e += node_mass(i, j) * (V[k] * V[k] + V[P + k] * V[P + k]);
    }
  return 0.5 * e;
}

void InPlane::elastic_forces(std::span<const double> u, std::span<double> f) const {
  // Element by element: gather the cell's 8 dofs, f_e = −K_e u_e, scatter (docs/model.md §10.4).
  std::fill(f.begin(), f.end(), 0.0);
  const std::size_t nx = nx_, P = plane();
  const double* k = ke_.data();
  for (std::size_t j = 0; j < ny_; ++j)
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const std::size_t n[4] = {j * nx + i, j * nx + i + 1, (j + 1) * nx + i, (j + 1) * nx + i + 1};
      double ue[8];
      for (int a = 0; a < 4; ++a) {
        ue[a] = u[n[a]];
        ue[a + 4] = u[P + n[a]];
      }
      for (int a = 0; a < 8; ++a) {
        double s = 0.0;
        for (int b = 0; b < 8; ++b) s += k[a * 8 + b] * ue[b];
        f[a < 4 ? n[a] : P + n[a - 4]] -= s;
      }
    }
}

double InPlane::elastic_energy(std::span<const double> u) const {
  std::vector<double> f(dofs());
  elastic_forces(u, f);
  double e = 0.0;
  for (std::size_t k = 0; k < dofs(); ++k) e -= u[k] * f[k];
  return 0.5 * e;
}

double InPlane::spring_energy(double t, std::span<const double> u) const {
  if (!(spring_K_ > 0.0)) return 0.0;
  const double stretch = v_d_ * t - edge_slip(u);
  return 0.5 * spring_K_ * stretch * stretch;
}

double InPlane::uniform_power(std::span<const double> v) const {
  if (sigma_d_ == 0.0 && p_ == 0.0) return 0.0;
  const std::size_t top = ny_ * nx_, P = plane();
  double px = 0.0, py = 0.0;
  for (std::size_t i = 0; i < nx_; ++i) {
    px += interface_weight(i) * v[top + i];
    py += interface_weight(i) * v[P + top + i];
  }
  return sigma_d_ * px - p_ * py;
}

Eigen::SparseMatrix<double> InPlane::stiffness_matrix() const {
  const auto n = static_cast<Eigen::Index>(dofs());
  const std::size_t nx = nx_, P = plane();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(64 * ny_ * (nx - 1));
  for (std::size_t j = 0; j < ny_; ++j)
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const std::size_t nd[4] = {j * nx + i, j * nx + i + 1, (j + 1) * nx + i, (j + 1) * nx + i + 1};
      Eigen::Index d[8];
      for (int a = 0; a < 4; ++a) {
        d[a] = static_cast<Eigen::Index>(nd[a]);
        d[a + 4] = static_cast<Eigen::Index>(P + nd[a]);
      }
      for (int a = 0; a < 8; ++a)
        for (int b = 0; b < 8; ++b) t.emplace_back(d[a], d[b], ke_[static_cast<std::size_t>(a * 8 + b)]);
    }
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

void InPlane::interface_normal_stress(std::span<const double> u, std::span<double> out) const {
  elastic_forces(u, force_);
  const std::size_t P = plane();
  for (std::size_t i = 0; i < nx_; ++i) out[i] = force_[P + i] / interface_weight(i);
}

void InPlane::stresses(std::span<const double> u, std::size_t i, std::size_t j, double& sxx, double& syy,
                       double& sxy) const {
  const std::size_t nx = nx_, P = plane();
  // ∂/∂x or ∂/∂y of component c (0: u_x, 1: u_y) at (i, j), second order where three nodes exist.
  auto diff = [&](std::size_t c, bool along_x) {
    const std::size_t n = along_x ? nx : ny_ + 1, at = along_x ? i : j;
    const double h = along_x ? dx_ : dy_;
    auto val = [&](std::size_t m) { return along_x ? u[c * P + j * nx + m] : u[c * P + m * nx + i]; };
    if (n == 2) return (val(1) - val(0)) / h;
    if (at == 0) return (-3.0 * val(0) + 4.0 * val(1) - val(2)) / (2.0 * h);
    if (at + 1 == n) return (3.0 * val(at) - 4.0 * val(at - 1) + val(at - 2)) / (2.0 * h);
    return (val(at + 1) - val(at - 1)) / (2.0 * h);
  };
  const double exx = diff(0, true), eyy = diff(1, false), gxy = diff(0, false) + diff(1, true);
  sxx = (lambda_p_ + 2.0 * mu_p_) * exx + lambda_p_ * eyy;
  syy = lambda_p_ * exx + (lambda_p_ + 2.0 * mu_p_) * eyy;
  sxy = mu_p_ * gxy;
}

void InPlane::kick(double dt, double eta, double edge_force, std::span<const double> u,
                   std::span<const double> sigma_bar, std::span<const double> v_old, std::span<double> v_new) const {
  elastic_forces(u, force_);
  const std::size_t nx = nx_, ny = ny_, P = plane();
  const double edge_per_height = edge_force / H_;
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::size_t k = j * nx + i;
      const double wx = interface_weight(i), m = node_mass(i, j);
      double fx = force_[k], fy = force_[P + k];
      if (i == 0) fx += edge_per_height * row_weight(j);
      if (j == ny) {
        fx += wx * sigma_d_;
        fy -= wx * p_;
      }
      if (j == 0) {
        // σ_xy = σ̄ + η v with η v centred: m (v⁺ − v⁻)/dt = f − wx (σ̄ + η (v⁺ + v⁻)/2); u_y held at 0.
        const double damp = 0.5 * wx * eta * dt;
        v_new[k] = (v_old[k] * (m - damp) + dt * (fx - wx * sigma_bar[i])) / (m + damp);
        v_new[P + k] = 0.0;
      } else {
        v_new[k] = v_old[k] + dt * fx / m;
        v_new[P + k] = v_old[P + k] + dt * fy / m;
      }
    }
}

void InPlane::solve_step(std::span<const double> c0, std::span<const double> c1, double t, double dt, double eta,
                         std::span<const double> u, std::span<const double> V, std::span<const double> sigma_bar,
                         std::span<double> W) {
  const std::size_t nx = nx_, ny = ny_, P = plane(), n = dofs();
  if (!direct_) {
    direct_ = std::make_unique<Direct>();
    direct_->K = stiffness_matrix();
  }
  Direct& D = *direct_;
  // The matrix: remade when dt or the interface coefficients change.
  std::vector<double> d(nx);
  for (std::size_t i = 0; i < nx; ++i) d[i] = eta + 0.5 * c1[i];
  if (dt != D.dt || d != D.d) {
    Eigen::SparseMatrix<double> A = (0.5 * dt) * D.K;
    std::vector<Eigen::Triplet<double>> tr;
    for (std::size_t j = 0; j <= ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        const double m = 2.0 * node_mass(i, j) / dt;
        tr.emplace_back(k, k, m + (j == 0 ? interface_weight(i) * d[i] : 0.0));
        tr.emplace_back(P + k, P + k, m);
      }
    for (std::size_t a = 0; a <= ny && spring_K_ > 0.0; ++a)  // (dt/2) K_s b bᵀ, b_j = wy(j)/H on column 0's u_x
      for (std::size_t b = 0; b <= ny; ++b)
        tr.emplace_back(a * nx, b * nx, 0.5 * dt * spring_K_ * row_weight(a) * row_weight(b) / (H_ * H_));
    Eigen::SparseMatrix<double> extra(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    extra.setFromTriplets(tr.begin(), tr.end());
    A += extra;
    // u_y of row 0 held: its rows and columns replaced by the identity (its W is 0).
    for (Eigen::Index c = 0; c < A.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
        const auto r = static_cast<std::size_t>(it.row()), col = static_cast<std::size_t>(it.col());
        const bool held_r = r >= P && r < P + nx, held_c = col >= P && col < P + nx;
        if (held_r || held_c) it.valueRef() = (r == col) ? 1.0 : 0.0;
      }
    D.ldlt.compute(A);
    if (D.ldlt.info() != Eigen::Success) throw std::runtime_error("InPlane: the implicit step's matrix is not definite");
    D.dt = dt;
    D.d = d;
  }
  // The right-hand side.
  elastic_forces(u, force_);
  D.rhs.resize(static_cast<Eigen::Index>(n));
  const double edge = (spring_K_ * (v_d_ * (t + 0.5 * dt) - edge_slip(u)) + rear_traction_) / H_;
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::size_t k = j * nx + i;
      const double wx = interface_weight(i), m = 2.0 * node_mass(i, j) / dt;
      double rx = m * V[k] + force_[k], ry = m * V[P + k] + force_[P + k];
      if (i == 0) rx += edge * row_weight(j);
      if (j == 0) rx -= wx * 0.5 * (sigma_bar[i] + c0[i]);
      if (j == ny) {
        rx += wx * sigma_d_;
        ry -= wx * p_;
      }
      D.rhs[static_cast<Eigen::Index>(k)] = rx;
      D.rhs[static_cast<Eigen::Index>(P + k)] = j == 0 ? 0.0 : ry;
    }
  D.w = D.ldlt.solve(D.rhs);
  for (std::size_t k = 0; k < n; ++k) W[k] = D.w[static_cast<Eigen::Index>(k)];
}

}  // namespace slipfront::core
