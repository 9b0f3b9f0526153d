#include "core/inplane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fftw3.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/LU>
#include <Eigen/SparseCholesky>

#include "core/matrix_free.hpp"

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
  double c = -1.0;
  Eigen::VectorXd w;
};

// The capacitance factors of one stage coefficient c (docs/numerics.md §8.9), with S the separable part of A(c, d_ref):
// the dense capacitance matrix C = D_Q − sᵀ S⁻¹ s of the dofs Q = B and the spring's μ = c K_s bᵀx (sources
// s = [A_IB, b]; D_Q = diag(A_BB, −1/(c K_s))) by its LU; Y = Eᵀ S⁻¹ s, their effect on the interface row's u_x; and
// the interface's Green's function of S, diagonal in cosine modes (gs: with the transforms' scaling).
struct InPlane::Capacitance {
  double c = 0.0, d_ref = 0.0;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  Eigen::MatrixXd Y;
  std::vector<double> gs;
  long long used = 0;
};

// The CG's workspace (docs/model.md §10.6): the transforms, the mode factors, the step's coefficients.
// Modes along x: u_x(i, j) = Σ_k a_jk cos(πik/N), k = 0 … N (N = nx − 1); u_y(i, j) = Σ_k b_jk sin(πik/N),
// k = 1 … N − 1, on the interior columns (the end columns' u_y are outside the separable part). Per mode, the
// rows' (a_j, b_j) solve a 2 × 2-block tridiagonal system T_k; its block LDLᵀ factors are kept: Dinv_j (the
// inverted pivots) and U_j = T_{j,j+1}, 4 doubles each, [(k·rows + j)·4].
struct InPlane::Fast {
  std::size_t nx = 0, rows = 0, N = 0, ns = 0;  // ns = nx − 2 interior columns
  double* bx = nullptr;                         // rows × nx, the cosine transforms (in place)
  double* by = nullptr;                         // rows × ns, the sine transforms (in place)
  fftw_plan dct = nullptr, dst = nullptr;
  std::vector<double> dinv, up;                 // the mode factors
  std::vector<double> ga, gb;                   // modal right-hand sides / solutions, [j·(N+1) + k]
  std::vector<double> kdiag;                    // K's diagonal (dofs)
  std::vector<double> z, tmp;                   // the preconditioner's result, apply_system's held-zeroed copy
  double fact_c = -1.0, fact_d = std::numeric_limits<double>::quiet_NaN();
  // the current system A(c, d) (apply_system, apply_preconditioner)
  double c = 0.0;
  std::vector<double> d;                        // the interface coefficient per site
  std::vector<double> rhs;                      // a copy of the right-hand side (rhs and x may alias)
  Eigen::VectorXd guess;                        // krylov's initial guess (kept for the BiCGSTAB fallback)
  // The end columns' u_y in the preconditioner: their diagonal (the implicit step), or (the adaptive stage solves,
  // docs/numerics.md §8.9) each column's u_y–u_y block, tridiagonal in y, solved exactly (Thomas; end_work: its sweep).
  bool end_columns_tridiagonal = false;
  std::vector<double> end_work;
  // The direct stage solve (docs/numerics.md §8.9). The capacitance dofs B: the end columns' u_y of the rows j ≥ 1
  // (column 0, then column N), bdof; K's entries of their columns on the other, unheld dofs (kcol) and among them
  // (kbb); the one-row cosine transform of the interface (b1, dct1); the factors of the last few c (cache).
  std::vector<std::size_t> bdof;
  std::vector<std::vector<std::pair<std::size_t, double>>> kcol;
  // The band of dofs the end columns touch (u_x of columns 0, 1, N−1, N and u_y of 1, N−1, every row): kband, kcol
  // with the band index (class·rows + j) in place of the dof; phase_in/out[class][k], the modal images of a unit
  // value there (the forward transforms' scaling included) and the node value of a mode (for the capacitance build).
  std::vector<std::vector<std::pair<std::size_t, double>>> kband;
  std::array<std::size_t, 6> band_column{};
  std::vector<double> phase_in, phase_out, zband;
  Eigen::MatrixXd kbb;
  double* b1 = nullptr;
  fftw_plan dct1 = nullptr;
  std::vector<std::unique_ptr<Capacitance>> cache;
  long long clock = 0;
  std::vector<double> t, r2;  // the two separable solves' right-hand side and result

  explicit Fast(const InPlane& b) : nx(b.sites()), rows(b.rows()), N(nx - 1), ns(nx - 2) {
    bx = static_cast<double*>(fftw_malloc(rows * nx * sizeof(double)));
    by = static_cast<double*>(fftw_malloc(rows * ns * sizeof(double)));
    b1 = static_cast<double*>(fftw_malloc(nx * sizeof(double)));
    if (bx == nullptr || by == nullptr || b1 == nullptr) {
      release();
      throw std::bad_alloc();
    }
    std::fill(bx, bx + rows * nx, 0.0);
    std::fill(by, by + rows * ns, 0.0);
    const int lx = static_cast<int>(nx), ly = static_cast<int>(ns), r = static_cast<int>(rows);
    const fftw_r2r_kind kc = FFTW_REDFT00, ks = FFTW_RODFT00;
    {
      const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      // FFTW_ESTIMATE: no timing, so the same sizes and alignment give the same plan (bit-reproducible runs).
      dct = fftw_plan_many_r2r(1, &lx, r, bx, nullptr, 1, lx, bx, nullptr, 1, lx, &kc, FFTW_ESTIMATE);
      dst = fftw_plan_many_r2r(1, &ly, r, by, nullptr, 1, ly, by, nullptr, 1, ly, &ks, FFTW_ESTIMATE);
      dct1 = fftw_plan_r2r_1d(lx, b1, b1, kc, FFTW_ESTIMATE);
    }
    if (dct == nullptr || dst == nullptr || dct1 == nullptr) {
      release();
      throw std::runtime_error("InPlane: FFTW could not plan the cosine and sine transforms");
    }
    dinv.assign((N + 1) * rows * 4, 0.0);
    up.assign((N + 1) * rows * 4, 0.0);
    ga.assign((N + 1) * rows, 0.0);
    gb.assign((N + 1) * rows, 0.0);
    z.assign(b.dofs(), 0.0);
    tmp.assign(b.dofs(), 0.0);
    // K's diagonal, element by element
    kdiag.assign(b.dofs(), 0.0);
    const auto& ke = b.element_stiffness();
    const std::size_t P = b.plane();
    for (std::size_t j = 0; j + 1 < rows; ++j)
      for (std::size_t i = 0; i + 1 < nx; ++i) {
        const std::size_t nd[4] = {j * nx + i, j * nx + i + 1, (j + 1) * nx + i, (j + 1) * nx + i + 1};
        for (std::size_t a = 0; a < 4; ++a) {
          kdiag[nd[a]] += ke[a * 8 + a];
          kdiag[P + nd[a]] += ke[(a + 4) * 8 + a + 4];
        }
      }
  }
  Fast(const Fast&) = delete;
  Fast& operator=(const Fast&) = delete;
  ~Fast() { release(); }
  void release() noexcept {
    {
      const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      if (dct != nullptr) fftw_destroy_plan(dct);
      if (dst != nullptr) fftw_destroy_plan(dst);
      if (dct1 != nullptr) fftw_destroy_plan(dct1);
    }
    dct = dst = dct1 = nullptr;
    if (bx != nullptr) fftw_free(bx);
    if (by != nullptr) fftw_free(by);
    if (b1 != nullptr) fftw_free(b1);
    bx = by = b1 = nullptr;
  }
};

BodyShape InPlane::shape(const BulkParams& bulk, const DriveParams&, const GridParams& grid) {
  return {static_cast<std::size_t>(std::llround(bulk.length / grid.dx)) + 1,
          static_cast<std::size_t>(std::llround(bulk.height / grid.row_spacing())) + 1, 2};
}

std::span<const SnapshotField> InPlane::snapshot_fields() {
  static constexpr SnapshotField fields[] = {{"u", 2}, {"sigma_xx", 1}, {"sigma_yy", 1}, {"sigma_xy", 1}};
  return fields;
}

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
      p_(material.normal_load), alpha_(law.alpha) {
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
      spring_K_(o.spring_K_), v_d_(o.v_d_), rear_traction_(o.rear_traction_), stable_dt_(o.stable_dt_), alpha_(o.alpha_),
      ke_(o.ke_),
      force_(o.force_), rhs_(o.rhs_), dstep_(o.dstep_), step_solver_(o.step_solver_),
      stage_solver_(o.stage_solver_), stage_(o.stage_) {}  // the factorisations are made again on first use
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
  double px = 0.0, py = 0.0, ends = 0.0;
  for (std::size_t i = 0; i < nx_; ++i) {
    px += interface_weight(i) * v[top + i];
    py += interface_weight(i) * v[P + top + i];
  }
  for (std::size_t j = 0; j <= ny_; ++j) ends += end_load_y(0, j) * v[P + j * nx_] + end_load_y(nx_ - 1, j) * v[P + j * nx_ + nx_ - 1];
  return sigma_d_ * px - p_ * py + ends;
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
  for (std::size_t i = 0; i < nx_; ++i) out[i] = (force_[P + i] + end_load_y(i, 0)) / interface_weight(i);
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
  const std::size_t P = plane();
  node_forces(edge_force, [&](std::size_t k, std::size_t i, std::size_t j, double fx, double fy) {
    const double wx = interface_weight(i), m = node_mass(i, j);
    if (j == 0) {
      // σ_xy = σ̄ + η v with η v centred: m (v⁺ − v⁻)/dt = f − wx (σ̄ + η (v⁺ + v⁻)/2); u_y held at 0.
      const double damp = 0.5 * wx * eta * dt;
      v_new[k] = (v_old[k] * (m - damp) + dt * (fx - wx * sigma_bar[i])) / (m + damp);
      v_new[P + k] = 0.0;
    } else {
      v_new[k] = v_old[k] + dt * fx / m;
      v_new[P + k] = v_old[P + k] + dt * fy / m;
    }
  });
}

void InPlane::rhs_step(std::span<const double> c0, double t, double dt, std::span<const double> u,
                       std::span<const double> V, std::span<const double> sigma_bar, double* rhs) const {
  const std::size_t nx = nx_, ny = ny_, P = plane();
  elastic_forces(u, force_);
  const double edge = (spring_K_ * (v_d_ * (t + 0.5 * dt) - edge_slip(u)) + rear_traction_) / H_;
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::size_t k = j * nx + i;
      const double wx = interface_weight(i), m = 2.0 * node_mass(i, j) / dt;
      double rx = m * V[k] + force_[k], ry = m * V[P + k] + force_[P + k] + end_load_y(i, j);
      if (i == 0) rx += edge * row_weight(j);
      if (j == 0) rx -= wx * 0.5 * (sigma_bar[i] + c0[i]);
      if (j == ny) {
        rx += wx * sigma_d_;
        ry -= wx * p_;
      }
      rhs[k] = rx;
      rhs[P + k] = j == 0 ? 0.0 : ry;  // u_y of the interface: held
    }
}

void InPlane::solve_step(std::span<const double> c0, std::span<const double> c1, double t, double dt, double eta,
                         std::span<const double> u, std::span<const double> V, std::span<const double> sigma_bar,
                         std::span<double> W) {
  rhs_.resize(dofs());
  rhs_step(c0, t, dt, u, V, sigma_bar, rhs_.data());
  dstep_.resize(nx_);
  for (std::size_t i = 0; i < nx_; ++i) dstep_[i] = eta + 0.5 * c1[i];
  if (step_solver_ == StepSolver::direct) solve_direct(0.5 * dt, dstep_, rhs_.data(), W);
  else solve_system(0.5 * dt, dstep_, rhs_, W);
}

void InPlane::solve_direct(double c, std::span<const double> dd, const double* rhs, std::span<double> W) {
  const std::size_t nx = nx_, ny = ny_, P = plane(), n = dofs();
  if (!direct_) {
    direct_ = std::make_unique<Direct>();
    direct_->K = stiffness_matrix();
  }
  Direct& D = *direct_;
  // The matrix A(c, d): remade when c or the interface coefficients change.
  const std::vector<double> d(dd.begin(), dd.end());
  if (c != D.c || d != D.d) {
    Eigen::SparseMatrix<double> A = c * D.K;
    std::vector<Eigen::Triplet<double>> tr;
    for (std::size_t j = 0; j <= ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        const double m = node_mass(i, j) / c;
        tr.emplace_back(k, k, m + (j == 0 ? interface_weight(i) * d[i] : 0.0));
        tr.emplace_back(P + k, P + k, m);
      }
    for (std::size_t a = 0; a <= ny && spring_K_ > 0.0; ++a)  // c K_s b bᵀ, b_j = wy(j)/H on column 0's u_x
      for (std::size_t b = 0; b <= ny; ++b)
        tr.emplace_back(a * nx, b * nx, c * spring_K_ * row_weight(a) * row_weight(b) / (H_ * H_));
    Eigen::SparseMatrix<double> extra(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
    extra.setFromTriplets(tr.begin(), tr.end());
    A += extra;
    // u_y of row 0 held: its rows and columns replaced by the identity (its W is 0).
    for (Eigen::Index outer = 0; outer < A.outerSize(); ++outer)
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, outer); it; ++it) {
        const auto r = static_cast<std::size_t>(it.row()), col = static_cast<std::size_t>(it.col());
        const bool held_r = r >= P && r < P + nx, held_c = col >= P && col < P + nx;
        if (held_r || held_c) it.valueRef() = (r == col) ? 1.0 : 0.0;
      }
    D.ldlt.compute(A);
    if (D.ldlt.info() != Eigen::Success) throw std::runtime_error("InPlane: the implicit step's matrix is not definite");
    D.c = c;
    D.d = d;
  }
  const Eigen::Map<const Eigen::VectorXd> b(rhs, static_cast<Eigen::Index>(n));
  D.w = D.ldlt.solve(b);
  for (std::size_t k = 0; k < n; ++k) W[k] = D.w[static_cast<Eigen::Index>(k)];
  last_iterations_ = 0;
}

namespace {

// A 2 × 2 block [[xx, xy], [yx, yy]], row-major.
using Block = std::array<double, 4>;
Block inverse(const Block& m) {
  const double det = m[0] * m[3] - m[1] * m[2];
  return {m[3] / det, -m[1] / det, -m[2] / det, m[0] / det};
}
Block product(const Block& a, const Block& b) {
  return {a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3], a[2] * b[0] + a[3] * b[2], a[2] * b[1] + a[3] * b[3]};
}
Block transposed_product(const Block& a, const Block& b) {  // aᵀ b
  return {a[0] * b[0] + a[2] * b[2], a[0] * b[1] + a[2] * b[3], a[1] * b[0] + a[3] * b[2], a[1] * b[1] + a[3] * b[3]};
}

}  // namespace

// The mode factors of the separable part of A(coef, dbar) (solve_system: coef = dt/2 for the trapezoidal step)
// (docs/model.md §10.6). Per mode θ = πk/N the Q1 operator is, with κ = (2 − 2cos θ)/dx, m = dx (2 + cos θ)/3
// (the 1D stiffness and consistent mass along x on cos θi), s = sin θ, and the 1D matrices along y
// (K1: stiffness, M1: consistent mass, G[c][d] = ∫ψ_c' ψ_d):
//   T_xx = (λ'+2μ') κ M1 + μ' m K1,   T_xy = s (μ' G − λ' Gᵀ),   T_yx = T_xyᵀ,   T_yy = μ' κ M1 + (λ'+2μ') m K1,
// times coef, plus the lumped mass ρ' dx wy(j)/coef on both components and dx dbar on u_x of row 0. u_y of row 0, and
// every b of the modes k = 0, N (sin θi ≡ 0 on the grid), are held: identity rows. Block LDLᵀ from row 0 up.
void InPlane::factorise_modes(double coef, double dbar) const {
  Fast& f = *fast_;
  const std::size_t N = f.N, R = f.rows, ny = ny_;
  const double lam = lambda_p_, mu = mu_p_, h = coef, dy = dy_;
  const auto K1 = [&](std::size_t c, std::size_t d) {
    if (c == d) return (c == 0 || c == ny ? 1.0 : 2.0) / dy;
    return -1.0 / dy;
  };
  const auto M1 = [&](std::size_t c, std::size_t d) {
    if (c == d) return dy / 6.0 * (c == 0 || c == ny ? 2.0 : 4.0);
    return dy / 6.0;
  };
  const auto G = [&](std::size_t c, std::size_t d) {
    if (c == d) return (c == 0 ? -0.5 : 0.0) + (c == ny ? 0.5 : 0.0);
    return d > c ? -0.5 : 0.5;
  };
  for (std::size_t k = 0; k <= N; ++k) {
    const double th = std::numbers::pi * static_cast<double>(k) / static_cast<double>(N);
    const double kap = (2.0 - 2.0 * std::cos(th)) / dx_, m = dx_ * (2.0 + std::cos(th)) / 3.0;
    const double s = (k == 0 || k == N) ? 0.0 : std::sin(th);
    const bool b_free = k != 0 && k != N;
    // T_{c,d}, d ∈ {c, c + 1}
    const auto block = [&](std::size_t c, std::size_t d) {
      Block t{h * ((lam + 2 * mu) * kap * M1(c, d) + mu * m * K1(c, d)), h * s * (mu * G(c, d) - lam * G(d, c)),
              h * s * (mu * G(d, c) - lam * G(c, d)), h * (mu * kap * M1(c, d) + (lam + 2 * mu) * m * K1(c, d))};
      if (c == d) {
        const double mass = rho_p_ * dx_ * row_weight(c) / h;
        t[0] += mass + (c == 0 ? dx_ * dbar : 0.0);
        t[3] += mass;
      }
      const bool held_c = c == 0 || !b_free, held_d = d == 0 || !b_free;
      if (held_c) t[2] = 0.0;  // the held b row: no coupling
      if (held_d) t[1] = 0.0;  // the held b column
      if (held_c || held_d) t[3] = (c == d) ? 1.0 : 0.0;
      return t;
    };
    Block dprev{}, uprev{};
    for (std::size_t j = 0; j < R; ++j) {
      Block dj = block(j, j);
      if (j > 0) {
        const Block c = transposed_product(uprev, product(dprev, uprev));  // U_{j−1}ᵀ D_{j−1}⁻¹ U_{j−1}
        for (int q = 0; q < 4; ++q) dj[static_cast<std::size_t>(q)] -= c[static_cast<std::size_t>(q)];
      }
      dprev = inverse(dj);
      uprev = j + 1 < R ? block(j, j + 1) : Block{};
      for (std::size_t q = 0; q < 4; ++q) {  // planes [(q·R + j)·(N+1) + k]: the sweeps run along k
        f.dinv[(q * R + j) * (N + 1) + k] = dprev[q];
        f.up[(q * R + j) * (N + 1) + k] = uprev[q];
      }
    }
  }
  f.fact_c = coef;
  f.fact_d = dbar;
}

namespace {

// Per mode k of the factors (dinv, up: four planes, [(q·R + j)·(N+1) + k] for the block's entry q), the 2 × 2-block
// tridiagonal solve in y in place on the modal values a, b ([j·(N+1) + k]): forward y_j = Dinv_j (r_j − U_{j−1}ᵀ y_{j−1}),
// back x_j = y_j − Dinv_j U_j x_{j+1}; every mode at once, row by row (contiguous in k).
void solve_modes(const double* dinv, const double* up, std::size_t N, std::size_t R, double* ga, double* gb) {
  const std::size_t M = N + 1, Q = R * M;
  for (std::size_t j = 0; j < R; ++j) {
    double* a = ga + j * M;
    double* b = gb + j * M;
    const double *D0 = dinv + j * M, *D1 = D0 + Q, *D2 = D1 + Q, *D3 = D2 + Q;
    if (j > 0) {
      const double *U0 = up + (j - 1) * M, *U1 = U0 + Q, *U2 = U1 + Q, *U3 = U2 + Q;
      const double *ya = a - M, *yb = b - M;
      for (std::size_t k = 0; k < M; ++k) {
        const double ra = a[k] - (U0[k] * ya[k] + U2[k] * yb[k]), rb = b[k] - (U1[k] * ya[k] + U3[k] * yb[k]);
        a[k] = D0[k] * ra + D1[k] * rb;
        b[k] = D2[k] * ra + D3[k] * rb;
      }
    } else {
      for (std::size_t k = 0; k < M; ++k) {
        const double ra = a[k], rb = b[k];
        a[k] = D0[k] * ra + D1[k] * rb;
        b[k] = D2[k] * ra + D3[k] * rb;
      }
    }
  }
  for (std::size_t j = R - 1; j-- > 0;) {
    double* a = ga + j * M;
    double* b = gb + j * M;
    const double *xa = a + M, *xb = b + M;
    const double *D0 = dinv + j * M, *D1 = D0 + Q, *D2 = D1 + Q, *D3 = D2 + Q;
    const double *U0 = up + j * M, *U1 = U0 + Q, *U2 = U1 + Q, *U3 = U2 + Q;
    for (std::size_t k = 0; k < M; ++k) {
      const double ua = U0[k] * xa[k] + U1[k] * xb[k], ub = U2[k] * xa[k] + U3[k] * xb[k];
      a[k] -= D0[k] * ua + D1[k] * ub;
      b[k] -= D2[k] * ua + D3[k] * ub;
    }
  }
}

}  // namespace

// z = S⁻¹ r, S the separable part of the factorised A(c, dbar): u_x of every node and u_y of the interior columns in
// their modes; the end columns' u_y (outside the sine modes) get 0 (row 0: held, their r; the interior columns' held
// u_y come back from their identity rows through the sine transforms).
void InPlane::separable_solve(const double* r, double* z) const {
  Fast& f = *fast_;
  const std::size_t nx = nx_, N = f.N, R = f.rows, ns = f.ns, P = plane();
  const double inv2N = 1.0 / (2.0 * static_cast<double>(N)), invN = 1.0 / static_cast<double>(N);
  // 1. modal right-hand sides: ĝ_x = c_k DCT(r_x/Wn)/(2N), ĝ_y = DST(r_y interior)/N
  for (std::size_t j = 0; j < R; ++j)
    for (std::size_t i = 0; i < nx; ++i) f.bx[j * nx + i] = r[j * nx + i] * dx_ / interface_weight(i);
  fftw_execute(f.dct);
  for (std::size_t j = 0; j < R; ++j)
    for (std::size_t i = 1; i < N; ++i) f.by[j * ns + i - 1] = r[P + j * nx + i];
  if (ns > 0) fftw_execute(f.dst);
  for (std::size_t j = 0; j < R; ++j)
    for (std::size_t k = 0; k <= N; ++k) {
      f.ga[j * (N + 1) + k] = f.bx[j * nx + k] * ((k == 0 || k == N) ? inv2N : 2.0 * inv2N);
      f.gb[j * (N + 1) + k] = (k == 0 || k == N) ? 0.0 : f.by[j * ns + k - 1] * invN;
    }
  // 2. per mode, the block tridiagonal solve in y
  solve_modes(f.dinv.data(), f.up.data(), N, R, f.ga.data(), f.gb.data());
  // 3. back to the nodes: u_x = Σ a_k cos (REDFT00 of a with the interior modes halved), u_y = Σ b_k sin
  for (std::size_t j = 0; j < R; ++j) {
    for (std::size_t k = 0; k <= N; ++k) f.bx[j * nx + k] = f.ga[j * (N + 1) + k] * ((k == 0 || k == N) ? 1.0 : 0.5);
    for (std::size_t k = 1; k < N; ++k) f.by[j * ns + k - 1] = 0.5 * f.gb[j * (N + 1) + k];
  }
  fftw_execute(f.dct);
  if (ns > 0) fftw_execute(f.dst);
  for (std::size_t j = 0; j < R; ++j) {
    for (std::size_t i = 0; i < nx; ++i) z[j * nx + i] = f.bx[j * nx + i];
    for (std::size_t i = 1; i < N; ++i) z[P + j * nx + i] = f.by[j * ns + i - 1];
    for (const std::size_t i : {std::size_t{0}, N}) z[P + j * nx + i] = j == 0 ? r[P + i] : 0.0;  // row 0: held
  }
}

const double* InPlane::apply_preconditioner(const double* r) const {
  Fast& f = *fast_;
  const std::size_t nx = nx_, N = f.N, R = f.rows, P = plane();
  double* z = f.z.data();
  separable_solve(r, z);
  // the end columns' u_y: their diagonal (row 0: held, identity)
  for (std::size_t j = 1; j < R; ++j)
    for (const std::size_t i : {std::size_t{0}, N}) {
      const std::size_t q = P + j * nx + i;
      z[q] = r[q] / (node_mass(i, j) / f.c + f.c * f.kdiag[q]);
    }
  if (f.end_columns_tridiagonal) end_columns_exact(r, z);
  return z;
}

// The end columns' u_y (rows j ≥ 1; row 0 held) by their own block of A(c, ·): M/c + c K restricted to the column,
// tridiagonal in y (the one element beside the column couples (i, j) to (i, j + 1): K_e's u_y entries of its nodes on
// that side), solved exactly by the Thomas algorithm. Replaces their diagonal in z.
void InPlane::end_columns_exact(const double* r, double* z) const {
  Fast& f = *fast_;
  const std::size_t nx = nx_, R = f.rows, P = plane(), N = f.N;
  f.end_work.resize(R);
  double* cp = f.end_work.data();
  for (const std::size_t i : {std::size_t{0}, N}) {
    const double off = f.c * (i == 0 ? ke_[4 * 8 + 6] : ke_[5 * 8 + 7]);  // K(u_y(i, j), u_y(i, j + 1))
    double prev = 0.0, cprev = 0.0;
    for (std::size_t j = 1; j < R; ++j) {  // forward sweep
      const std::size_t q = P + j * nx + i;
      const double diag = node_mass(i, j) / f.c + f.c * f.kdiag[q] - (j > 1 ? off * cprev : 0.0);
      cprev = off / diag;
      cp[j] = cprev;
      prev = (r[q] - (j > 1 ? off * prev : 0.0)) / diag;
      z[q] = prev;
    }
    for (std::size_t j = R - 1; j-- > 1;) z[P + j * nx + i] -= cp[j] * z[P + (j + 1) * nx + i];  // back substitution
  }
}

void InPlane::apply_system(const double* x, double* y) const {
  Fast& f = *fast_;
  const std::size_t nx = nx_, P = plane(), n = dofs();
  std::copy(x, x + n, f.tmp.begin());
  std::fill(f.tmp.begin() + static_cast<std::ptrdiff_t>(P), f.tmp.begin() + static_cast<std::ptrdiff_t>(P + nx), 0.0);
  elastic_forces(f.tmp, force_);
  const double h = f.c;
  for (std::size_t j = 0; j <= ny_; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const std::size_t k = j * nx + i;
      const double m = node_mass(i, j) / h;
      y[k] = m * f.tmp[k] - h * force_[k];
      y[P + k] = m * f.tmp[P + k] - h * force_[P + k];
    }
  for (std::size_t i = 0; i < nx; ++i) {
    y[i] += interface_weight(i) * f.d[i] * x[i];
    y[P + i] = x[P + i];  // held
  }
  if (spring_K_ > 0.0) {
    double s = 0.0;
    for (std::size_t j = 0; j <= ny_; ++j) s += row_weight(j) * x[j * nx];
    const double c = h * spring_K_ * s / (H_ * H_);
    for (std::size_t j = 0; j <= ny_; ++j) y[j * nx] += c * row_weight(j);
  }
}

void InPlane::solve_system(double c, std::span<const double> d, std::span<const double> rhs, std::span<double> x) {
  const std::size_t nx = nx_;
  if (nx < 3) {  // no interior column: no sine modes
    const std::vector<double> r(rhs.begin(), rhs.end());
    solve_direct(c, d, r.data(), x);
    return;
  }
  if (!fast_) fast_ = std::make_unique<Fast>(*this);
  Fast& f = *fast_;
  f.d.assign(d.begin(), d.end());
  f.rhs.assign(rhs.begin(), rhs.end());
  double mean = 0.0;
  for (double v : f.d) mean += v;
  const double dbar = std::max(mean / static_cast<double>(nx), 0.0);
  if (c != f.fact_c || dbar != f.fact_d) factorise_modes(c, dbar);
  f.c = c;
  f.end_columns_tridiagonal = false;
  bool fell_back = false;
  last_iterations_ = krylov(x, 1e-12, fell_back);
}

int InPlane::krylov(std::span<double> x, double tol, bool& fell_back) {
  Fast& f = *fast_;
  const std::size_t n = dofs();
  const MatrixFree<const InPlane> A(*this, n);
  Eigen::ConjugateGradient<MatrixFree<const InPlane>, Eigen::Lower | Eigen::Upper, MatrixFreePreconditioner<const InPlane>> cg;
  cg.setTolerance(tol);
  cg.setMaxIterations(500);
  cg.compute(A);
  const Eigen::Map<const Eigen::VectorXd> b(f.rhs.data(), static_cast<Eigen::Index>(n));
  Eigen::Map<Eigen::VectorXd> w(x.data(), static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < nx_; ++i) x[plane() + i] = 0.0;  // the held dofs' guess
  f.guess = w;
  w = cg.solveWithGuess(b, f.guess);
  int iterations = static_cast<int>(cg.iterations());
  fell_back = false;
  if (cg.info() == Eigen::Success && std::isfinite(cg.error())) return iterations;
  // Indefinite (weakening sites, d < 0, at a large step): BiCGSTAB with the same preconditioner, from the same guess.
  Eigen::BiCGSTAB<MatrixFree<const InPlane>, MatrixFreePreconditioner<const InPlane>> bicg;
  bicg.setTolerance(tol);
  bicg.setMaxIterations(500);
  bicg.compute(A);
  w = bicg.solveWithGuess(b, f.guess);
  iterations += static_cast<int>(bicg.iterations());
  fell_back = true;
  if (bicg.info() != Eigen::Success || !std::isfinite(bicg.error()))
    throw std::runtime_error("InPlane: the conjugate gradient did not converge (relative residual " +
                             std::to_string(cg.error()) + "), nor BiCGSTAB after it: " +
                             std::to_string(bicg.iterations()) + " iterations, relative residual " +
                             std::to_string(bicg.error()));
  return iterations;
}

// --- The adaptive integrator's body (core::AdaptiveBody; docs/numerics.md §8.9) -----------------------------------

void InPlane::stage_accelerations(double t, std::span<const double> u, const double* v, const double* sigma_bar,
                                  double eta, std::span<double> a) {
  const std::size_t nx = nx_, P = plane();
  // u_y of row 0 is held (0 in every run): a value there enters no force, so that J's column of it is 0 as the
  // stage solve's identity row has it.
  std::span<const double> uf = u;
  if (std::any_of(u.begin() + static_cast<std::ptrdiff_t>(P), u.begin() + static_cast<std::ptrdiff_t>(P + nx),
                  [](double z) { return z != 0.0; })) {
    stage_.u_free.assign(u.begin(), u.end());
    std::fill_n(stage_.u_free.begin() + static_cast<std::ptrdiff_t>(P), nx, 0.0);
    uf = stage_.u_free;
  }
  elastic_forces(uf, force_);
  node_forces(drive_force(t, uf), [&](std::size_t k, std::size_t i, std::size_t j, double fx, double fy) {
    const double inv_m = 1.0 / node_mass(i, j);
    if (j == 0) {
      a[k] = (fx - interface_weight(i) * (sigma_bar[i] + eta * v[i])) * inv_m;
      a[P + k] = 0.0;
    } else {
      a[k] = fx * inv_m;
      a[P + k] = fy * inv_m;
    }
  });
}

void InPlane::set_stage_tolerance(double rtol) { stage_.tolerance = std::clamp(kStageSolveTolerance * rtol, 1e-13, 1e-3); }

// The right-hand side of every dof beyond the sites: b_u = bu − sub_u, b_v = bv − sub_v (+ hdT on the edge column's
// u_x: the spring's ∂f/∂t, K v_d/(ρ wx(0)) on every node of it, as on the site), r = M (b_v + b_u/c); the held dofs
// r = b_u + c b_v (identity rows). The guess b_u + c b_v.
void InPlane::stage_bulk_rhs(const BulkStage& in) {
  const std::size_t nx = nx_, n = dofs(), P = plane();
  const double c = stage_.c, inv_c = 1.0 / c, hdT = has_drive_spring() ? in.hdT : 0.0;
  double *r = stage_.r.data(), *bu = stage_.bu.data(), *x = stage_.x.data();
  for (std::size_t k = nx; k < n; ++k) {  // rows j ≥ 1 of u_x, then every row of u_y (row 0: held)
    const std::size_t node = k < P ? k : k - P, i = node % nx;
    const std::size_t end = std::min(k + (nx - i), n);  // the rest of this row
    const double wy = row_weight(node / nx);
    const bool held = k >= P && node < nx;
    for (; k < end; ++k) {
      const std::size_t ik = k - (end - nx);
      const double u = in.sub_u != nullptr ? in.bu[k] - in.sub_u[k] : in.bu[k];
      double v = in.sub_v != nullptr ? in.bv[k] - in.sub_v[k] : in.bv[k];
      if (k < P && ik == 0) v += hdT;
      bu[k] = u;
      x[k] = u + c * v;
      r[k] = held ? x[k] : rho_p_ * interface_weight(ik) * wy * (v + inv_c * u);  // node_mass(ik, j)
    }
    --k;
  }
}

namespace {

// The interface system of the direct stage solve, (I + G₀ Δ) ξ = ξ₀ on the interface row's u_x (docs/numerics.md
// §8.9): G₀ u = G_S u + Y C⁻¹ Yᵀ u, G_S diagonal in cosine modes (gs, one-row DCT-I both ways, b1 its buffer),
// Δ = diag(wx (d − d_ref)). For Eigen's BiCGSTAB through MatrixFree; no preconditioner (the identity).
struct InterfaceSystem {
  const Eigen::PartialPivLU<Eigen::MatrixXd>* lu;
  const Eigen::MatrixXd* Y;
  const double* gs;
  const double* delta;
  const double* scale_in;  // dx/wx(i)
  double* b1;
  fftw_plan dct1;
  std::size_t nx;
  mutable std::vector<double> z;
  mutable long long applications = 0;
  void apply_system(const double* x, double* y) const {
    ++applications;
    for (std::size_t i = 0; i < nx; ++i) b1[i] = delta[i] * x[i] * scale_in[i];
    fftw_execute(dct1);
    for (std::size_t k = 0; k < nx; ++k) b1[k] *= gs[k];
    fftw_execute(dct1);
    const Eigen::Map<const Eigen::VectorXd> xv(x, static_cast<Eigen::Index>(nx));
    const Eigen::Map<const Eigen::VectorXd> dv(delta, static_cast<Eigen::Index>(nx));
    const Eigen::VectorXd corr = (*Y) * lu->solve(Y->transpose() * dv.cwiseProduct(xv));
    for (std::size_t i = 0; i < nx; ++i) y[i] = x[i] + b1[i] + corr[static_cast<Eigen::Index>(i)];
  }
  const double* apply_preconditioner(const double* r) const {
    z.assign(r, r + nx);
    return z.data();
  }
};

}  // namespace

// The end columns' u_y (the capacitance dofs B) and K's entries of their columns, once.
void InPlane::setup_end_columns() {
  Fast& f = *fast_;
  if (!f.bdof.empty()) return;
  const std::size_t nx = nx_, N = f.N, P = plane(), n = dofs();
  for (const std::size_t i : {std::size_t{0}, N})
    for (std::size_t j = 1; j <= ny_; ++j) f.bdof.push_back(P + j * nx + i);
  const std::size_t nb = f.bdof.size();
  std::vector<long> index(n, -1);
  for (std::size_t q = 0; q < nb; ++q) index[f.bdof[q]] = static_cast<long>(q);
  // K's columns of B from the elements beside the end columns (cells 0 and N − 1 of every row), not the whole matrix
  f.kbb = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(nb), static_cast<Eigen::Index>(nb));
  std::vector<std::vector<std::pair<std::size_t, double>>> entries(nb);
  for (const std::size_t ic : {std::size_t{0}, N - 1})
    for (std::size_t j = 0; j < ny_; ++j) {
      const std::size_t nd[4] = {j * nx + ic, j * nx + ic + 1, (j + 1) * nx + ic, (j + 1) * nx + ic + 1};
      std::size_t d[8];
      for (std::size_t a = 0; a < 4; ++a) {
        d[a] = nd[a];
        d[a + 4] = P + nd[a];
      }
      for (std::size_t b = 0; b < 8; ++b) {
        if (index[d[b]] < 0) continue;
        const auto q = static_cast<std::size_t>(index[d[b]]);
        for (std::size_t a = 0; a < 8; ++a) {
          if (d[a] >= P && d[a] < P + nx) continue;  // held
          if (index[d[a]] >= 0) f.kbb(index[d[a]], static_cast<Eigen::Index>(q)) += ke_[a * 8 + b];
          else entries[q].emplace_back(d[a], ke_[a * 8 + b]);
        }
      }
    }
  f.kcol.assign(nb, {});
  for (std::size_t q = 0; q < nb; ++q) {  // merge each column's entries by dof
    std::stable_sort(entries[q].begin(), entries[q].end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [p, v] : entries[q]) {
      if (!f.kcol[q].empty() && f.kcol[q].back().first == p) f.kcol[q].back().second += v;
      else f.kcol[q].emplace_back(p, v);
    }
  }
  // the band's classes: 0–3 u_x of columns 0, 1, N − 1, N; 4–5 u_y of columns 1, N − 1
  f.band_column = {0, 1, N - 1, N, 1, N - 1};
  const std::size_t M = N + 1, R = f.rows;
  f.phase_in.assign(6 * M, 0.0);
  f.phase_out.assign(6 * M, 0.0);
  const double pi_N = std::numbers::pi / static_cast<double>(N), invN = 1.0 / static_cast<double>(N);
  for (std::size_t cl = 0; cl < 6; ++cl) {
    const std::size_t i = f.band_column[cl];
    for (std::size_t k = 0; k <= N; ++k) {
      const auto ik = static_cast<double>((i * k) % (2 * N));  // cos, sin of π i k/N, the argument reduced
      const bool end_mode = k == 0 || k == N;
      if (cl < 4) {
        const double cs = std::cos(pi_N * ik);
        f.phase_out[cl * M + k] = cs;
        f.phase_in[cl * M + k] = ((i == 0 || i == N) ? 1.0 : 2.0) * cs * dx_ / interface_weight(i) * (end_mode ? 0.5 * invN : invN);
      } else if (!end_mode) {
        const double sn = std::sin(pi_N * ik);
        f.phase_out[cl * M + k] = sn;
        f.phase_in[cl * M + k] = 2.0 * sn * invN;
      }
    }
  }
  const auto band_of = [&](std::size_t p) -> std::size_t {
    const std::size_t comp = p >= P ? 1 : 0, node = p - comp * P, i = node % nx, j = node / nx;
    for (std::size_t cl = comp == 0 ? 0 : 4; cl < (comp == 0 ? 4u : 6u); ++cl)
      if (f.band_column[cl] == i) return cl * R + j;
    throw std::logic_error("InPlane: an end column's stencil reaches outside the band");
  };
  f.kband.assign(nb, {});
  for (std::size_t q = 0; q < nb; ++q)
    for (const auto& [p, k] : f.kcol[q]) f.kband[q].emplace_back(band_of(p), k);
  f.zband.assign(6 * R, 0.0);
}

// The capacitance factors of (c, d_ref) from the cache, or made (docs/numerics.md §8.9): per capacitance dof, its
// source s_q (column q of c K on the other dofs, or the spring's b; both in the band of the end columns) put in the
// modes directly, every mode's sweep, and S⁻¹ s_q read at the band and on the interface row: C and Y; the
// interface's Green's function of S from one modal sweep with a unit source on row 0's u_x in every mode.
InPlane::Capacitance& InPlane::capacitance(double c, double d_ref) {
  Fast& f = *fast_;
  for (auto& e : f.cache)
    if (e->c == c && e->d_ref == d_ref) {
      e->used = ++f.clock;
      return *e;
    }
  setup_end_columns();
  if (c != f.fact_c || d_ref != f.fact_d) factorise_modes(c, d_ref);
  const std::size_t nx = nx_, N = f.N, R = f.rows, nb = f.bdof.size();
  const bool spring = spring_K_ > 0.0;
  const auto q = static_cast<Eigen::Index>(nb + (spring ? 1 : 0));
  auto cap = std::make_unique<Capacitance>();
  cap->c = c;
  cap->d_ref = d_ref;
  Eigen::MatrixXd C(q, q);
  cap->Y.resize(static_cast<Eigen::Index>(nx), q);
  const std::size_t M = N + 1;
  double* zb = f.zband.data();
  for (Eigen::Index col = 0; col < q; ++col) {
    // the source's modes, directly (it lives in the band: no transform), then every mode's sweep
    std::fill(f.ga.begin(), f.ga.end(), 0.0);
    std::fill(f.gb.begin(), f.gb.end(), 0.0);
    const auto cb = static_cast<std::size_t>(col);
    const auto add = [&](std::size_t band, double value) {
      const std::size_t cl = band / R, j = band % R;
      double* g = (cl < 4 ? f.ga.data() : f.gb.data()) + j * M;
      const double* ph = f.phase_in.data() + cl * M;
      for (std::size_t k = 0; k < M; ++k) g[k] += value * ph[k];
    };
    if (cb < nb) {
      for (const auto& [band, k] : f.kband[cb]) add(band, c * k);
    } else {
      for (std::size_t j = 0; j < R; ++j) add(j, row_weight(j) / H_);  // b: u_x of column 0 (class 0)
    }
    solve_modes(f.dinv.data(), f.up.data(), N, R, f.ga.data(), f.gb.data());
    // S⁻¹ s at the band's dofs (node values of the modes) and on the interface row (one-row transform)
    for (std::size_t cl = 0; cl < 6; ++cl)
      for (std::size_t j = 0; j < R; ++j) {
        const double* g = (cl < 4 ? f.ga.data() : f.gb.data()) + j * M;
        const double* ph = f.phase_out.data() + cl * M;
        double v = 0.0;
        for (std::size_t k = 0; k < M; ++k) v += g[k] * ph[k];
        zb[cl * R + j] = v;
      }
    for (std::size_t k = 0; k < M; ++k) f.b1[k] = f.ga[k] * ((k == 0 || k == N) ? 1.0 : 0.5);
    fftw_execute(f.dct1);
    for (std::size_t row = 0; row < nb; ++row) {
      double a = 0.0;
      for (const auto& [band, k] : f.kband[row]) a += c * k * zb[band];
      double d = cb < nb ? c * f.kbb(static_cast<Eigen::Index>(row), col) : 0.0;
      if (row == cb) d += node_mass(row < ny_ ? 0 : N, row % ny_ + 1) / c;
      C(static_cast<Eigen::Index>(row), col) = d - a;
    }
    if (spring) {
      double bz = 0.0;
      for (std::size_t j = 0; j < R; ++j) bz += row_weight(j) / H_ * zb[j];
      C(q - 1, col) = -bz - (cb == nb ? 1.0 / (c * spring_K_) : 0.0);
    }
    for (std::size_t i = 0; i < nx; ++i) cap->Y(static_cast<Eigen::Index>(i), col) = f.b1[i];
  }
  cap->lu.compute(C);
  // G_S: the modal solve of a unit source on row 0's u_x in every mode, with the transforms' scalings
  std::fill(f.ga.begin(), f.ga.end(), 0.0);
  std::fill(f.gb.begin(), f.gb.end(), 0.0);
  for (std::size_t k = 0; k <= N; ++k) f.ga[k] = 1.0;
  solve_modes(f.dinv.data(), f.up.data(), N, R, f.ga.data(), f.gb.data());
  cap->gs.resize(nx);
  const double inv2N = 1.0 / (2.0 * static_cast<double>(N));
  for (std::size_t k = 0; k <= N; ++k) cap->gs[k] = f.ga[k] * ((k == 0 || k == N) ? inv2N : 2.0 * inv2N * 0.5);
  ++stage_.builds;
  cap->used = ++f.clock;
  if (f.cache.size() < kCapacitanceCache) {
    f.cache.push_back(std::move(cap));
    return *f.cache.back();
  }
  auto oldest = std::min_element(f.cache.begin(), f.cache.end(), [](const auto& a, const auto& b) { return a->used < b->used; });
  *oldest = std::move(cap);
  return **oldest;
}

// The stage system A(c, d) x = r solved directly (docs/numerics.md §8.9): S the separable part of A(c, d_ref),
// d_ref = η + c α (a stuck site's); the capacitance dofs w = (x_B, μ) and the interface's force f = Δ ξ,
// Δ = diag(wx (d − d_ref)), ξ = Eᵀ x:
//   t = S⁻¹ r_I,   ρ = [r_B; 0] − sᵀ t,   ξ₀ = Eᵀ t − Y C⁻¹ ρ,   (I + G₀ Δ) ξ = ξ₀,   f = Δ ξ,
//   w = C⁻¹ (ρ + Yᵀ f),   x_I = S⁻¹ (r_I − E f − s w),   x_B = w_B.
// Two separable solves and an interface system of nx unknowns (BiCGSTAB on one-row transforms, to the stage
// tolerance; none when every site has d = d_ref). Returns false when that system does not converge.
bool InPlane::solve_stage_direct() {
  Fast& f = *fast_;
  const double c = stage_.c, d_ref = stage_.eta + c * alpha_;
  const Capacitance& cap = capacitance(c, d_ref);
  if (c != f.fact_c || d_ref != f.fact_d) factorise_modes(c, d_ref);
  const std::size_t nx = nx_, n = dofs(), nb = f.bdof.size(), R = f.rows;
  const bool spring = spring_K_ > 0.0;
  const Eigen::Index q = cap.Y.cols(), m = static_cast<Eigen::Index>(nx);
  const double* r = stage_.r.data();
  f.r2.assign(r, r + n);
  f.t.resize(n);
  for (const std::size_t b : f.bdof) f.r2[b] = 0.0;
  separable_solve(f.r2.data(), f.t.data());
  Eigen::VectorXd rho(q);
  for (std::size_t b = 0; b < nb; ++b) {
    double a = 0.0;
    for (const auto& [p, k] : f.kcol[b]) a += c * k * f.t[p];
    rho[static_cast<Eigen::Index>(b)] = r[f.bdof[b]] - a;
  }
  if (spring) {
    double a = 0.0;
    for (std::size_t j = 0; j < R; ++j) a += row_weight(j) / H_ * f.t[j * nx];
    rho[q - 1] = -a;
  }
  const Eigen::VectorXd v0 = cap.lu.solve(rho);
  Eigen::VectorXd force = Eigen::VectorXd::Zero(m), delta(m), scale(m);
  bool varies = false;
  for (std::size_t i = 0; i < nx; ++i) {
    delta[static_cast<Eigen::Index>(i)] = interface_weight(i) * (stage_.d[i] - d_ref);
    scale[static_cast<Eigen::Index>(i)] = dx_ / interface_weight(i);
    varies = varies || delta[static_cast<Eigen::Index>(i)] != 0.0;
  }
  if (varies) {
    const Eigen::VectorXd xi0 = Eigen::Map<const Eigen::VectorXd>(f.t.data(), m) - cap.Y * v0;
    const InterfaceSystem sys{&cap.lu, &cap.Y, cap.gs.data(), delta.data(), scale.data(), f.b1, f.dct1, nx, {}};
    const MatrixFree<const InterfaceSystem> A(sys, nx);
    Eigen::BiCGSTAB<MatrixFree<const InterfaceSystem>, MatrixFreePreconditioner<const InterfaceSystem>> solver;
    solver.setTolerance(stage_.tolerance);
    solver.setMaxIterations(200);
    solver.compute(A);
    const Eigen::VectorXd xi = solver.solveWithGuess(xi0, xi0);
    stage_.interface_iterations += sys.applications;
    if (solver.info() != Eigen::Success || !xi.allFinite()) return false;
    force = delta.cwiseProduct(xi);
  }
  const Eigen::VectorXd w = v0 + cap.lu.solve(cap.Y.transpose() * force);
  for (std::size_t i = 0; i < nx; ++i) f.r2[i] -= force[static_cast<Eigen::Index>(i)];
  for (std::size_t b = 0; b < nb; ++b)
    for (const auto& [p, k] : f.kcol[b]) f.r2[p] -= c * k * w[static_cast<Eigen::Index>(b)];
  if (spring)
    for (std::size_t j = 0; j < R; ++j) f.r2[j * nx] -= w[q - 1] * row_weight(j) / H_;
  double* x = stage_.x.data();
  separable_solve(f.r2.data(), x);
  for (std::size_t b = 0; b < nb; ++b) x[f.bdof[b]] = w[static_cast<Eigen::Index>(b)];
  return w.allFinite();
}

void InPlane::solve_stage_system() {
  const std::size_t nx = nx_;
  if (nx < 3) {  // no interior column: the direct solve (as solve_system)
    solve_direct(stage_.c, stage_.d, stage_.r.data(), stage_.x);
    return;
  }
  if (!fast_) fast_ = std::make_unique<Fast>(*this);
  if (stage_solver_ == StageSolver::direct) {
    if (solve_stage_direct()) return;
    ++stage_.direct_failures;
  }
  Fast& f = *fast_;
  f.d.assign(stage_.d.begin(), stage_.d.end());
  f.rhs.assign(stage_.r.begin(), stage_.r.end());
  double mean = 0.0;
  for (double v : f.d) mean += v;
  const double dbar = std::max(mean / static_cast<double>(nx), 0.0);
  if (stage_.c != f.fact_c || dbar != f.fact_d) factorise_modes(stage_.c, dbar);
  f.c = stage_.c;
  f.end_columns_tridiagonal = true;
  // the held dofs are identity rows: their x is their right-hand side (krylov sets their guess to 0)
  bool fell_back = false;
  stage_.iterations += krylov(stage_.x, stage_.tolerance, fell_back);
  if (fell_back) ++stage_.fallbacks;
}

// After the solve, every dof beyond the sites: x_u ← x + add_u, x_v ← (x − b_u)/c + add_v.
void InPlane::stage_bulk_finish(const BulkStage& in, double* xu, double* xv) const {
  const std::size_t nx = nx_, n = dofs();
  const double inv_c = 1.0 / stage_.c;
  const double *x = stage_.x.data(), *bu = stage_.bu.data();
  for (std::size_t k = nx; k < n; ++k) {
    xu[k] = in.add_u != nullptr ? x[k] + in.add_u[k] : x[k];
    const double v = (x[k] - bu[k]) * inv_c;
    xv[k] = in.add_v != nullptr ? v + in.add_v[k] : v;
  }
}

StageError InPlane::stage_error(const double* y, const double* yn, const double* k1, const double* k2,
                                const double* k3) const {
  StageError r;
  for (std::size_t j = 0, n = dofs(); j < n; ++j) {
    r.scale = std::max(r.scale, std::max(std::abs(y[j]), std::abs(yn[j])));
    const double e = std::abs(k1[j] - 2.0 * k2[j] + k3[j]);
    r.emax = std::max(r.emax, e);
    r.probe += e + yn[j];
  }
  return r;
}

}  // namespace slipfront::core
