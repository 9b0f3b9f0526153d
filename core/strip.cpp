#include "core/strip.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fftw3.h>

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <unsupported/Eigen/IterativeSolvers>

#include "core/matrix_free.hpp"

namespace slipfront::core {
namespace {

// The DCT-I of solve_system (FFTW's REDFT00 convention, unnormalised: Y_k = X_0 + (−1)^k X_N +
// 2 Σ_{0<i<N} X_i cos(πik/N), n = N + 1 points) of `rows` rows, computed as FFTW's real-to-complex transform of
// each row's even extension (X_0 … X_N, X_{N−1} … X_1: length 2N; Y_k = Re of its k-th coefficient). FFTW's own
// REDFT00 plan for these sizes (FFTW_ESTIMATE) is a split-radix recursion ending in a padded r2hc that allocates
// its buffers at every execution and copies in and out of another buffer: 2.3× slower at n = 601
// (docs/performance.md §13). Out of place, on buffers owned here: no allocation per transform. FFTW_ESTIMATE:
// the same sizes and alignment give the same plan (bit-reproducible runs). run(in, out) fills the extension
// with in(row, i), i = 0 … N, executes, and hands every Y_k to out(row, k, Y_k).
class CosineTransform {
 public:
  CosineTransform(std::size_t n, std::size_t rows) : N_(n - 1), rows_(rows) {
    const std::size_t len = 2 * N_;
    ext_ = static_cast<double*>(fftw_malloc(len * sizeof(double)));
    spec_ = static_cast<fftw_complex*>(fftw_malloc((N_ + 1) * sizeof(fftw_complex)));
    if (ext_ == nullptr || spec_ == nullptr) {
      release();
      throw std::bad_alloc();
    }
    std::fill(ext_, ext_ + len, 0.0);
    {
      const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      plan_ = fftw_plan_dft_r2c_1d(static_cast<int>(len), ext_, spec_, FFTW_ESTIMATE);
    }
    if (plan_ == nullptr) {
      release();
      throw std::runtime_error("Strip: FFTW could not plan the cosine transform of solve_system");
    }
  }
  CosineTransform(const CosineTransform&) = delete;
  CosineTransform& operator=(const CosineTransform&) = delete;
  ~CosineTransform() { release(); }

  // One row: in(i), i = 0 … N; out(k, Y_k), k = 0 … N.
  template <class In, class Out>
  void row(In&& in, Out&& out) {
    const std::size_t N = N_, len = 2 * N;
    double* e = ext_;
    for (std::size_t i = 0; i <= N; ++i) e[i] = in(i);
    for (std::size_t i = 1; i < N; ++i) e[len - i] = e[i];
    fftw_execute(plan_);
    const fftw_complex* y = spec_;
    for (std::size_t k = 0; k <= N; ++k) out(k, y[k][0]);
  }
  // Every row in order, one at a time through one row's buffers (they stay in the first-level caches).
  template <class In, class Out>
  void run(In&& in, Out&& out) {
    for (std::size_t r = 0; r < rows_; ++r)
      row([&in, r](std::size_t i) { return in(r, i); }, [&out, r](std::size_t k, double v) { out(r, k, v); });
  }

 private:
  void release() noexcept {
    if (plan_ != nullptr) {
      const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      fftw_destroy_plan(plan_);
    }
    plan_ = nullptr;
    if (ext_ != nullptr) fftw_free(ext_);
    if (spec_ != nullptr) fftw_free(spec_);
    ext_ = nullptr;
    spec_ = nullptr;
  }
  std::size_t N_, rows_;
  double* ext_ = nullptr;
  fftw_complex* spec_ = nullptr;
  fftw_plan plan_ = nullptr;
};

// Σ_{a ≤ k < b} r[k] with four partial sums (a serial sum is one add per 4 cycles of latency; the order is fixed,
// so the result is reproducible).
double partial_sum(const double* r, std::size_t a, std::size_t b) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  std::size_t k = a;
  for (; k + 4 <= b; k += 4) {
    s0 += r[k];
    s1 += r[k + 1];
    s2 += r[k + 2];
    s3 += r[k + 3];
  }
  for (; k < b; ++k) s0 += r[k];
  return (s0 + s1) + (s2 + s3);
}

// solve_system's interface system in cosine space (docs/performance.md §12): for ξ = the interface row's
// modes (x₀ = C ξ, C: the DCT-I of one row, C² = 2(nx−1) I),
//   B ξ = Wx ρ₀,   B = Wx diag(p) + Wx C diag(d) C / (2(nx−1))
// (p: the modes' interface pivots, ρ₀: the eliminated right-hand side of row 0; Wx C is symmetric, so B is),
// preconditioned by its diagonal for uniform d = d̄: Wx (p + d̄). Two transforms of one row per product.
struct InterfaceData {
  std::size_t nx = 0;
  std::unique_ptr<CosineTransform> row_dct;  // one row
  std::vector<double> row;       // the product's intermediate (physical space)
  std::vector<double> p;         // the interface pivots p_k = 1/g_k
  std::vector<double> wx;        // interface weights (the modes' too)
  std::vector<double> precond;   // 1/(wx_k (p_k + d̄))
  std::vector<double> out;       // the preconditioner's result
  const double* d = nullptr;     // the current interface coefficients
  double norm = 1.0;             // 1/(2(nx−1))
  mutable int applications = 0;

  // the operator of core::MatrixFree (core/matrix_free.hpp)
  void apply_system(const double* x, double* y) {
    ++applications;
    double* r = row.data();
    const double* dd = d;
    const double nm = norm;
    row_dct->run([x](std::size_t, std::size_t k) { return x[k]; },
                 [r, dd, nm](std::size_t, std::size_t i, double v) { r[i] = v * dd[i] * nm; });
    const double* w = wx.data();
    const double* pp = p.data();
    row_dct->run([r](std::size_t, std::size_t i) { return r[i]; },
                 [x, y, w, pp](std::size_t, std::size_t k, double v) { y[k] = w[k] * (pp[k] * x[k] + v); });
  }
  const double* apply_preconditioner(const double* r) {
    out.resize(nx);
    for (std::size_t k = 0; k < nx; ++k) out[k] = r[k] * precond[k];
    return out.data();
  }
};

}  // namespace

// solve_system's workspace: the factors of P = M/c + c S in cosine space (from the top row down), the
// interface system, the transforms, and the spring's ψ (in cosine space) for the (c, d) it was computed for.
struct Strip::Direct : InterfaceData {
  double c = -1.0;
  std::vector<double> lam;    // λ_k = (2/dx²)(1 − cos(πk/(nx−1)))
  std::vector<double> inv;    // 1/pivot of the top-down elimination, [j·nx + k]
  std::vector<double> f;  // the interface right-hand side
  std::vector<double> psi, psi_d;  // the modes of ψ = A₀⁻¹ b (before the inverse transform), the d they hold for
  std::vector<double> spread;  // b_j = wy(j)/H, the edge column's spread
  std::vector<double> dstep;  // solve_step's d = η + c1/2 (StepSolver::direct)
  std::vector<double> row_a, row_b;  // the mixed representation's one-row buffers (mixed_accelerations)
  double psi_c = -1.0, b_psi = 0.0;
  std::unique_ptr<CosineTransform> bulk_dct;  // every row

  Direct(const Strip& s) {
    nx = s.sites();
    lam.resize(nx);
    const double pi_n = std::numbers::pi / static_cast<double>(nx - 1), two_dx2 = 2.0 / (s.dx() * s.dx());
    for (std::size_t k = 0; k < nx; ++k) lam[k] = two_dx2 * (1.0 - std::cos(pi_n * static_cast<double>(k)));
    inv.assign(s.dofs(), 0.0);
    p.assign(nx, 0.0);
    norm = 1.0 / (2.0 * static_cast<double>(nx - 1));
    precond.assign(nx, 0.0);
    wx.resize(nx);
    for (std::size_t i = 0; i < nx; ++i) wx[i] = s.interface_weight(i);
    f.assign(nx, 0.0);
    spread.resize(s.rows());
    for (std::size_t j = 0; j < s.rows(); ++j) spread[j] = s.row_weight(j) / s.height();
    row.assign(nx, 0.0);
    row_a.assign(nx, 0.0);
    row_b.assign(nx, 0.0);
    row_dct = std::make_unique<CosineTransform>(nx, 1);
    bulk_dct = std::make_unique<CosineTransform>(nx, s.rows());
  }
};


BodyShape Strip::shape(const BulkParams& bulk, const DriveParams&, const GridParams& grid) {
  return {static_cast<std::size_t>(std::llround(bulk.length / grid.dx)) + 1,
          static_cast<std::size_t>(std::llround(bulk.height / grid.row_spacing())) + 1, 1};
}

std::span<const SnapshotField> Strip::snapshot_fields() {
  static constexpr SnapshotField fields[] = {{"u", 1}, {"tau_xz", 1}, {"tau_yz", 1}};
  return fields;
}

double Strip::stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx,
                               double dy) {
  const double K = drive.loading == Loading::edge ? drive.K : 0.0;
  const double omega2 = bulk.mu / bulk.rho * (4.0 / (dx * dx) + 4.0 / (dy * dy)) + 2.0 * K / (bulk.rho * dx) +
                        2.0 * law.alpha * bulk.height / (bulk.rho * dy);
  return 2.0 / std::sqrt(omega2);
}

Strip::Strip(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx, double dy)
    : dx_(dx), dy_(dy), H_(bulk.height), rho_(bulk.rho), mu_(bulk.mu) {
  if (drive.loading != Loading::edge && drive.loading != Loading::homogeneous)
    throw std::invalid_argument("Strip: only edge and homogeneous loading have a strip");
  if (!(H_ > 0.0)) throw std::invalid_argument("Strip: bulk.height must be > 0");
  if (!(dx > 0.0)) throw std::invalid_argument("Strip: dx must be > 0");
  if (!(dy > 0.0)) throw std::invalid_argument("Strip: dy must be > 0");
  const auto cells = static_cast<std::size_t>(std::llround(bulk.length / dx));
  if (cells < 1) throw std::invalid_argument("Strip: bulk.length must hold at least one cell");
  const long long ny = std::llround(H_ / dy);
  if (ny < 1) throw std::invalid_argument("Strip: bulk.height must hold at least one row interval");
  if (std::abs(static_cast<double>(ny) * dy - H_) > 1e-9 * H_)
    throw std::invalid_argument("Strip: dy must divide bulk.height");
  nx_ = cells + 1;
  ny_ = static_cast<std::size_t>(ny);
  x_.resize(nx_);
  for (std::size_t i = 0; i < nx_; ++i) x_[i] = static_cast<double>(i) * dx;
  rho_p_ = rho_ / H_;
  mu_p_ = modulus(bulk);
  if (drive.loading == Loading::edge) {
    spring_K_ = drive.K;
    v_d_ = drive.v_d;
  } else {
    sigma_d_ = drive.sigma_d;
    rear_traction_ = drive.rear_traction;
  }
  stable_dt_ = stable_time_step(bulk, drive, law, dx, dy);

  inv_.assign(dofs(), 0.0);
  rhs_.assign(dofs(), 0.0);
  inv_wx_.resize(nx_);
  for (std::size_t i = 0; i < nx_; ++i)
    inv_wx_[i] = 1.0 / (interface_weight(i) * 2.0 * static_cast<double>(nx_ - 1));
  make_plans();
}

void Strip::make_plans() {
  const std::size_t n = dofs();
  buf_ = static_cast<double*>(fftw_malloc(n * sizeof(double)));
  if (buf_ == nullptr) throw std::bad_alloc();
  std::fill(buf_, buf_ + n, 0.0);
  const int len = static_cast<int>(nx_);
  const fftw_r2r_kind kind = FFTW_REDFT00;
  {
    const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    // Rows contiguous (stride 1, distance nx), in place. FFTW_ESTIMATE: no timing, so the same sizes and
    // alignment always give the same plan (bit-reproducible runs and restarts).
    plan_ = fftw_plan_many_r2r(1, &len, static_cast<int>(rows()), buf_, nullptr, 1, len, buf_, nullptr, 1, len,
                               &kind, FFTW_ESTIMATE);
  }
  if (plan_ == nullptr) {
    fftw_free(buf_);
    buf_ = nullptr;
    throw std::runtime_error("Strip: FFTW could not plan the cosine transform");
  }
}

void Strip::free_plans() noexcept {
  if (plan_ != nullptr) {
    const std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    fftw_destroy_plan(plan_);
  }
  plan_ = nullptr;
  if (buf_ != nullptr) fftw_free(buf_);
  buf_ = nullptr;
}

Strip::Strip(const Strip& o)
    : x_(o.x_), nx_(o.nx_), ny_(o.ny_), dx_(o.dx_), dy_(o.dy_), H_(o.H_), rho_(o.rho_), mu_(o.mu_),
      rho_p_(o.rho_p_), mu_p_(o.mu_p_), sigma_d_(o.sigma_d_), spring_K_(o.spring_K_), v_d_(o.v_d_),
      rear_traction_(o.rear_traction_), stable_dt_(o.stable_dt_), shift_(o.shift_), inv_(o.inv_), rhs_(o.rhs_),
      inv_wx_(o.inv_wx_), fact_dt_(o.fact_dt_), fact_dbar_(o.fact_dbar_), last_iterations_(o.last_iterations_),
      last_residual_(o.last_residual_), step_solver_(o.step_solver_),
      last_interface_iterations_(o.last_interface_iterations_), interface_tolerance_(o.interface_tolerance_),
      stage_(o.stage_) {
  make_plans();  // solve_system's workspace is made again on first use (the same factors, bit for bit)
}

Strip::Strip(Strip&& o) noexcept
    : x_(std::move(o.x_)), nx_(o.nx_), ny_(o.ny_), dx_(o.dx_), dy_(o.dy_), H_(o.H_), rho_(o.rho_), mu_(o.mu_),
      rho_p_(o.rho_p_), mu_p_(o.mu_p_), sigma_d_(o.sigma_d_), spring_K_(o.spring_K_), v_d_(o.v_d_),
      rear_traction_(o.rear_traction_), stable_dt_(o.stable_dt_), shift_(o.shift_), buf_(std::exchange(o.buf_, nullptr)),
      plan_(std::exchange(o.plan_, nullptr)), inv_(std::move(o.inv_)), rhs_(std::move(o.rhs_)),
      inv_wx_(std::move(o.inv_wx_)), fact_dt_(o.fact_dt_), fact_dbar_(o.fact_dbar_),
      last_iterations_(o.last_iterations_), last_residual_(o.last_residual_), step_solver_(o.step_solver_),
      direct_(std::move(o.direct_)), last_interface_iterations_(o.last_interface_iterations_),
      interface_tolerance_(o.interface_tolerance_), stage_(std::move(o.stage_)) {}

Strip& Strip::operator=(const Strip& o) {
  if (this != &o) {
    Strip copy(o);
    *this = std::move(copy);
  }
  return *this;
}

Strip& Strip::operator=(Strip&& o) noexcept {
  if (this != &o) {
    free_plans();
    x_ = std::move(o.x_);
    nx_ = o.nx_;
    ny_ = o.ny_;
    dx_ = o.dx_;
    dy_ = o.dy_;
    H_ = o.H_;
    rho_ = o.rho_;
    mu_ = o.mu_;
    rho_p_ = o.rho_p_;
    mu_p_ = o.mu_p_;
    sigma_d_ = o.sigma_d_;
    spring_K_ = o.spring_K_;
    v_d_ = o.v_d_;
    rear_traction_ = o.rear_traction_;
    stable_dt_ = o.stable_dt_;
    shift_ = o.shift_;
    buf_ = std::exchange(o.buf_, nullptr);
    plan_ = std::exchange(o.plan_, nullptr);
    inv_ = std::move(o.inv_);
    rhs_ = std::move(o.rhs_);
    inv_wx_ = std::move(o.inv_wx_);
    fact_dt_ = o.fact_dt_;
    fact_dbar_ = o.fact_dbar_;
    last_iterations_ = o.last_iterations_;
    last_residual_ = o.last_residual_;
    step_solver_ = o.step_solver_;
    direct_ = std::move(o.direct_);
    last_interface_iterations_ = o.last_interface_iterations_;
    interface_tolerance_ = o.interface_tolerance_;
    stage_ = std::move(o.stage_);
  }
  return *this;
}

Strip::~Strip() { free_plans(); }

std::size_t Strip::workspace_bytes() const {
  return (dofs() * 3 + nx_) * sizeof(double);  // buf_, inv_, rhs_, inv_wx_
}

double Strip::kinetic_energy(std::span<const double> V) const {
  double e = 0.0;
  for (std::size_t j = 0; j <= ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i) e += node_mass(i, j) * V[j * nx_ + i] * V[j * nx_ + i];
  return 0.5 * e;
}

double Strip::elastic_energy(std::span<const double> u) const {
  double ex = 0.0, ey = 0.0;
  for (std::size_t j = 0; j <= ny_; ++j) {
    const double* r = u.data() + j * nx_;
    double s = 0.0;
    for (std::size_t i = 0; i + 1 < nx_; ++i) s += (r[i + 1] - r[i]) * (r[i + 1] - r[i]);
    ex += row_weight(j) * s;
    if (j < ny_) {
      const double* up = r + nx_;
      for (std::size_t i = 0; i < nx_; ++i) ey += interface_weight(i) * (up[i] - r[i]) * (up[i] - r[i]);
    }
  }
  return 0.5 * mu_p_ * (ex / dx_ + ey / dy_);
}

double Strip::spring_energy(double t, std::span<const double> u) const {
  if (!(spring_K_ > 0.0)) return 0.0;
  const double stretch = v_d_ * t - edge_slip(u);
  return 0.5 * spring_K_ * stretch * stretch;
}

double Strip::uniform_power(std::span<const double> v) const {
  if (sigma_d_ == 0.0) return 0.0;
  const double* top = v.data() + ny_ * nx_;
  double p = 0.0;
  for (std::size_t i = 0; i < nx_; ++i) p += interface_weight(i) * top[i];
  return sigma_d_ * p;
}

Eigen::SparseMatrix<double> Strip::stiffness_matrix() const {
  const auto n = static_cast<Eigen::Index>(dofs());
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(5 * dofs());
  const auto id = [this](std::size_t i, std::size_t j) { return static_cast<Eigen::Index>(j * nx_ + i); };
  const auto bond = [&t](Eigen::Index a, Eigen::Index b, double k) {
    t.emplace_back(a, a, k);
    t.emplace_back(b, b, k);
    t.emplace_back(a, b, -k);
    t.emplace_back(b, a, -k);
  };
  for (std::size_t j = 0; j <= ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i) {
      if (i + 1 < nx_) bond(id(i, j), id(i + 1, j), mu_p_ * row_weight(j) / dx_);
      if (j < ny_) bond(id(i, j), id(i, j + 1), mu_p_ * interface_weight(i) / dy_);
    }
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

// x86-64 with GCC or Clang: an AVX2 clone of the kick besides the baseline one, chosen when the program loads (ifunc).
// AVX2 without FMA: the same IEEE operations, four at a time instead of two, so the results are bit for bit the
// baseline's on any machine (strip_height 26.4 -> 23.3 s, docs/performance.md §17).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define SLIPFRONT_AVX2_CLONE __attribute__((target_clones("avx2", "default")))
#else
#define SLIPFRONT_AVX2_CLONE
#endif
namespace {
// v^{n+1/2} of one node from v^{n−1/2}, its force f and mass m: v + dt f/m, and on the interface row (`Interface`)
// η v centred: (v (m − damp) + dt (f − wx σ̄))/(m + damp), damp = wx η dt/2.
template <bool Interface>
inline double kicked(double vo, double f, double m, double dt, double wx, double damp, double sb) {
  if constexpr (Interface) return (vo * (m - damp) + dt * (f - wx * sb)) / (m + damp);
  else return vo + dt * f / m;
}
}  // namespace

SLIPFRONT_AVX2_CLONE void Strip::kick(double dt, double eta, double edge_force, std::span<const double> u,
                 std::span<const double> sigma_bar, std::span<const double> v_old, std::span<double> v_new) const {
  const std::size_t nx = nx_, ny = ny_;
  const double half_eta_dt = 0.5 * eta * dt, edge_per_height = edge_force / H_, sd = sigma_d_;
  const double* vo = v_old.data();
  double* vn = v_new.data();
  const double* sb = sigma_bar.data();
  // One node, the force f of elastic_forces given: the edge force on the column i = 0, the uniform load on the top
  // row, η v centred on the interface row.
  auto node = [&, this](std::size_t j, std::size_t i, double f) {
    const std::size_t k = j * nx + i;
    const double wx = interface_weight(i), m = rho_p_ * wx * row_weight(j);
    if (i == 0) f += edge_per_height * row_weight(j);
    if (j == ny) f += wx * sd;
    const double damp = wx * half_eta_dt;
    vn[k] = j == 0 ? kicked<true>(vo[k], f, m, dt, wx, damp, sb[i]) : kicked<false>(vo[k], f, m, dt, wx, damp, 0.0);
  };
  // The nodes 0 < i < nx − 1 of row j: node()'s arithmetic, operation for operation, in one loop without branches
  // (wx = dx, m = ρ' dx wy(j) for all of them), which the compiler vectorises: the explicit scheme on the strip
  // spent ~75 % of its time here node by node (strip_height, docs/performance.md §17). Bit-identical.
  const double cx_in = mu_p_ * dy_ / dx_, cy_in = mu_p_ * dx_ / dy_;
  auto interior = [&](std::size_t j, const double* r, const double* dn, const double* up, double cx, auto interface,
                      auto top) {
    const double wx = interface_weight(1), m = rho_p_ * wx * row_weight(j), add = wx * sd, damp = wx * half_eta_dt;
    const double* vo_r = vo + j * nx;
    double* vn_r = vn + j * nx;
    for (std::size_t i = 1; i + 1 < nx; ++i) {
      double f = cx * ((r[i - 1] - r[i]) + (r[i + 1] - r[i])) + cy_in * ((dn[i] - r[i]) + (up[i] - r[i]));
      if constexpr (decltype(top)::value) f += add;
      vn_r[i] = kicked<decltype(interface)::value>(vo_r[i], f, m, dt, wx, damp, decltype(interface)::value ? sb[i] : 0.0);
    }
  };
  using yes = std::true_type;
  using no = std::false_type;
  for (std::size_t j = 0; j <= ny; ++j) {  // elastic_forces' rows, ends and interior
    const double* r = u.data() + j * nx;
    const double* dn = j == 0 ? r : r - nx;  // a missing neighbour row is the row itself: its difference is 0
    const double* up = j == ny ? r : r + nx;
    const double cx = (j == 0 || j == ny) ? 0.5 * cx_in : cx_in;
    const double cy_end = 0.5 * cy_in;
    node(j, 0, cx * (r[1] - r[0]) + cy_end * ((dn[0] - r[0]) + (up[0] - r[0])));
    if (j == 0 && j == ny) interior(j, r, dn, up, cx, yes{}, yes{});
    else if (j == 0) interior(j, r, dn, up, cx, yes{}, no{});
    else if (j == ny) interior(j, r, dn, up, cx, no{}, yes{});
    else interior(j, r, dn, up, cx, no{}, no{});
    const std::size_t e = nx - 1;
    node(j, e, cx * (r[e - 1] - r[e]) + cy_end * ((dn[e] - r[e]) + (up[e] - r[e])));
  }
}

// The Thomas factors (1/pivot) of T_k = (2ρ'/dt + (dt/2)μ'λ_k) Wy + (dt/2)μ' Dy + d̄ e0 e0ᵀ for every
// mode k, λ_k = (2/dx²)(1 − cos(πk/(nx−1))); the off-diagonal is the constant o = −(dt/2)μ'/dy.
void Strip::factorise(double dt, double dbar) const {
  if (dt == fact_dt_ && dbar == fact_dbar_) return;
  const std::size_t nx = nx_, ny = ny_;
  const double mass = 2.0 * rho_p_ / dt, half = 0.5 * dt * mu_p_, ky = half / dy_, o = -ky;
  const double pi_n = std::numbers::pi / static_cast<double>(nx - 1), two_dx2 = 2.0 / (dx_ * dx_);
  double* inv = inv_.data();
  // Row j = 0 first (k inner), then each row from the one below.
  for (std::size_t k = 0; k < nx; ++k) {
    const double lam = two_dx2 * (1.0 - std::cos(pi_n * static_cast<double>(k)));
    inv[k] = 1.0 / ((mass + half * lam) * 0.5 * dy_ + ky + dbar);
  }
  for (std::size_t j = 1; j <= ny; ++j) {
    const double wy = row_weight(j), nb = j == ny ? ky : 2.0 * ky;
    double* r = inv + j * nx;
    const double* p = r - nx;
    for (std::size_t k = 0; k < nx; ++k) {
      const double lam = two_dx2 * (1.0 - std::cos(pi_n * static_cast<double>(k)));
      r[k] = 1.0 / ((mass + half * lam) * wy + nb - o * o * p[k]);
    }
  }
  fact_dt_ = dt;
  fact_dbar_ = dbar;
}

const double* Strip::apply_preconditioner(const double* r) const {
  const std::size_t nx = nx_, ny = ny_;
  double* b = buf_;
  const double* iw = inv_wx_.data();
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) b[j * nx + i] = r[j * nx + i] * iw[i];
  fftw_execute(plan_);  // the modes of every row (times 2(nx−1), taken out above)
  const double o = -0.5 * dt_ * mu_p_ / dy_;
  const double* inv = inv_.data();
  for (std::size_t k = 0; k < nx; ++k) b[k] *= inv[k];
  for (std::size_t j = 1; j <= ny; ++j) {
    double* z = b + j * nx;
    const double* zp = z - nx;
    const double* iv = inv + j * nx;
    for (std::size_t k = 0; k < nx; ++k) z[k] = (z[k] - o * zp[k]) * iv[k];
  }
  for (std::size_t j = ny; j-- > 0;) {
    double* z = b + j * nx;
    const double* zn = z + nx;
    const double* iv = inv + j * nx;
    for (std::size_t k = 0; k < nx; ++k) z[k] -= o * iv[k] * zn[k];
  }
  fftw_execute(plan_);  // back to the nodes
  return b;
}

void Strip::apply_system(const double* x, double* y) const {
  ++applications_;
  const std::size_t nx = nx_;
  const double dt = dt_, mass = 2.0 * rho_p_ / dt, half = 0.5 * dt, eta = eta_;
  const double* c1 = c1_;
  elastic_forces(std::span<const double>(x, dofs()), [&, this](std::size_t j, std::size_t i, double f) {
    const std::size_t k = j * nx + i;
    const double wx = interface_weight(i);
    double a = mass * wx * row_weight(j) * x[k] - half * f;
    if (j == 0) a += wx * (eta + 0.5 * c1[i]) * x[k];
    y[k] = a;
  });
  if (spring_K_ > 0.0) {
    const double s = half * spring_K_ * edge_slip(std::span<const double>(x, dofs())) / H_;
    for (std::size_t j = 0; j <= ny_; ++j) y[j * nx] += s * row_weight(j);
  }
}

void Strip::solve_step(std::span<const double> c0, std::span<const double> c1, double t, double dt, double eta,
                       std::span<const double> u, std::span<const double> V, std::span<const double> sigma_bar,
                       std::span<double> W) {
  const std::size_t nx = nx_, ny = ny_, n = dofs();
  // The right-hand side.
  const double mass = 2.0 * rho_p_ / dt, sd = sigma_d_;
  const double edge = (spring_K_ * (v_d_ * (t + 0.5 * dt) - edge_slip(u)) + rear_traction_) / H_;
  double* rhs = rhs_.data();
  const double* Vp = V.data();
  elastic_forces(u, [&, this](std::size_t j, std::size_t i, double f) {
    const std::size_t k = j * nx + i;
    const double wx = interface_weight(i);
    double r = mass * wx * row_weight(j) * Vp[k] + f;
    if (i == 0) r += edge * row_weight(j);
    if (j == 0) r -= wx * 0.5 * (sigma_bar[i] + c0[i]);
    if (j == ny) r += wx * sd;
    rhs[k] = r;
  });
  if (step_solver_ == StepSolver::direct) {
    std::vector<double>& d = direct().dstep;
    d.resize(nx);
    for (std::size_t i = 0; i < nx; ++i) d[i] = eta + 0.5 * c1[i];
    solve_system(0.5 * dt, d, std::span<const double>(rhs, n), W);
    last_iterations_ = 0;
    last_residual_ = 0.0;
    return;
  }
  // The preconditioner's shift and factors.
  double dbar = eta;
  if (shift_ == Shift::mean_c1) {
    double s = 0.0;
    for (std::size_t i = 0; i < nx; ++i) s += c1[i];
    dbar += 0.5 * s / static_cast<double>(nx);
  }
  factorise(dt, dbar);
  dt_ = dt;
  eta_ = eta;
  c1_ = c1.data();

  const MatrixFree<const Strip> A(*this, dofs());
  Eigen::ConjugateGradient<MatrixFree<const Strip>, Eigen::Lower | Eigen::Upper, MatrixFreePreconditioner<const Strip>> cg;
  cg.setTolerance(1e-12);
  cg.setMaxIterations(200);
  cg.compute(A);
  const Eigen::Map<const Eigen::VectorXd> b(rhs, static_cast<Eigen::Index>(n));
  Eigen::Map<Eigen::VectorXd> w(W.data(), static_cast<Eigen::Index>(n));
  applications_ = 0;
  w = cg.solveWithGuess(b, w);
  // Operator applications: one for the initial residual, one per CG iteration.
  last_iterations_ = std::max(0, applications_ - 1);
  last_residual_ = cg.error();
  c1_ = nullptr;
  if (cg.info() != Eigen::Success || !std::isfinite(last_residual_))
    throw std::runtime_error("Strip: the implicit step's conjugate gradient did not converge: " +
                             std::to_string(last_iterations_) + " iterations, relative residual " +
                             format_number(last_residual_));
}

Strip::Direct& Strip::direct() {
  if (!direct_) direct_ = std::make_unique<Direct>(*this);
  return *direct_;
}

void Strip::set_interface_tolerance(double tol) {
  if (!(tol >= 1e-13 && tol < 1.0))
    throw std::invalid_argument("Strip::set_interface_tolerance: the tolerance must be in [1e-13, 1)");
  interface_tolerance_ = tol;
}

// The factors of T_k = (ρ'/c + c μ' λ_k) Wy + c μ' Dy/dy for every mode, eliminated from the top row (j = ny)
// down: inv[j, k] = 1/pivot; the pivot of row 0 is 1/g_k, g_k = e0ᵀ T_k⁻¹ e0 (the interface's Green's function).
void Strip::direct_factorise(double c) {
  Direct& D = direct();
  if (c == D.c) return;
  const std::size_t nx = nx_, ny = ny_;
  const double mass = rho_p_ / c, cm = c * mu_p_, ky = cm / dy_, o2 = ky * ky;
  const double* lam = D.lam.data();
  for (std::size_t j = ny + 1; j-- > 0;) {
    const double wy = row_weight(j), nb = (j == 0 || j == ny) ? ky : 2.0 * ky;
    double* r = D.inv.data() + j * nx;
    if (j == ny) {
      for (std::size_t k = 0; k < nx; ++k) r[k] = 1.0 / ((mass + cm * lam[k]) * wy + nb);
    } else {
      const double* p = r + nx;
      for (std::size_t k = 0; k < nx; ++k) r[k] = 1.0 / ((mass + cm * lam[k]) * wy + nb - o2 * p[k]);
    }
  }
  for (std::size_t k = 0; k < nx; ++k) D.p[k] = 1.0 / D.inv[k];
  D.c = c;
  D.psi_c = -1.0;
}

// z = the modes of A₀⁻¹ r (A₀ = A(c, d) without the spring, the factors of c made), before the inverse
// transform: the rows' DCT (r scaled by 1/(wx 2(nx−1)), the transform's normalisation), the top-down
// elimination, the interface system for row 0, back substitution upwards. rhs = nullptr: r = b, the spring's
// spread, whose rows' DCT is b_j/(wx(0) 2(nx−1)) in every mode (the DCT-I of e_0 is all ones). Returns bᵀ C z
// (bᵀ x for x the inverse transform of z). The rows are transformed one at a time and eliminated while in cache.
// With a stage (solve_stage_mixed) the rows j ≥ 1 are formed in their modes from it, without a transform, and rhs is
// row 0's node values only.
struct Strip::StageRhs {
  const StageInput* in;
  double inv_c;
};

double Strip::direct_modes(std::span<const double> d, const double* rhs, double* z, const StageRhs* stage) {
  Direct& D = direct();
  const std::size_t nx = nx_, ny = ny_;
  const double* iw = inv_wx_.data();
  const double o = -D.c * mu_p_ / dy_;
  const double* inv = D.inv.data();
  // Row by row from the top: its transform, then its elimination by the row above (still in cache).
  for (std::size_t j = ny + 1; j-- > 0;) {
    double* zj = z + j * nx;
    if (stage != nullptr && j > 0) {  // the row's modes formed from the stage (solve_stage_mixed)
      const StageInput& in = *stage->in;
      const double* bu = in.bu + j * nx;
      const double* bv = in.bv + j * nx;
      const double mj = rho_p_ * row_weight(j), ic = stage->inv_c, sh = in.shift_v;
      const double* iv = inv + (j + 1) * nx;  // (rows j < ny: the row above)
      const double* zn = zj + nx;
      if (in.sub_u != nullptr) {
        const double* su = in.sub_u + j * nx;
        const double* sv = in.sub_v + j * nx;
        if (j == ny) {
          for (std::size_t k = 0; k < nx; ++k) zj[k] = mj * ((bv[k] - sv[k] + sh) + ic * (bu[k] - su[k]));
        } else {
          for (std::size_t k = 0; k < nx; ++k)
            zj[k] = mj * ((bv[k] - sv[k] + sh) + ic * (bu[k] - su[k])) - o * iv[k] * zn[k];
        }
      } else if (j == ny) {
        for (std::size_t k = 0; k < nx; ++k) zj[k] = mj * ((bv[k] + sh) + ic * bu[k]);
      } else {
        for (std::size_t k = 0; k < nx; ++k) zj[k] = mj * ((bv[k] + sh) + ic * bu[k]) - o * iv[k] * zn[k];
      }
    } else if (rhs != nullptr) {  // (with a stage: row 0's node values)
      const double* rj = rhs + j * nx;
      if (j == ny) {
        D.bulk_dct->row([rj, iw](std::size_t i) { return rj[i] * iw[i]; }, [zj](std::size_t k, double v) { zj[k] = v; });
      } else {
        const double* zn = zj + nx;
        const double* iv = inv + (j + 1) * nx;
        D.bulk_dct->row([rj, iw](std::size_t i) { return rj[i] * iw[i]; },
                        [zj, zn, iv, o](std::size_t k, double v) { zj[k] = v - o * iv[k] * zn[k]; });
      }
    } else {
      const double bj = D.spread[j] * iw[0];
      if (j == ny) {
        std::fill(zj, zj + nx, bj);
      } else {
        const double* zn = zj + nx;
        const double* iv = inv + (j + 1) * nx;
        for (std::size_t k = 0; k < nx; ++k) zj[k] = bj - o * iv[k] * zn[k];
      }
    }
  }
  // The interface row's modes ξ: B ξ = Wx ρ₀ (InterfaceData).
  for (std::size_t k = 0; k < nx; ++k) D.f[k] = D.wx[k] * z[k];
  double dbar = 0.0;
  for (std::size_t i = 0; i < nx; ++i) dbar += d[i];
  dbar = std::max(dbar / static_cast<double>(nx), 0.0);
  for (std::size_t k = 0; k < nx; ++k) D.precond[k] = 1.0 / (D.wx[k] * (D.p[k] + dbar));
  D.d = d.data();
  const MatrixFree<InterfaceData> B(D, nx);
  const Eigen::Map<const Eigen::VectorXd> f(D.f.data(), static_cast<Eigen::Index>(nx));
  Eigen::Map<Eigen::VectorXd> xi(z, static_cast<Eigen::Index>(nx));  // row 0: its modes
  D.applications = 0;
  {
    using Interface = MatrixFree<InterfaceData>;
    Eigen::ConjugateGradient<Interface, Eigen::Lower | Eigen::Upper, MatrixFreePreconditioner<InterfaceData>> cg;
    cg.setTolerance(interface_tolerance_);
    cg.setMaxIterations(300);
    cg.compute(B);
    xi = cg.solve(f);
    bool ok = cg.info() == Eigen::Success && std::isfinite(cg.error());
    if (!ok) {  // indefinite (d < 0 somewhere): MINRES, with the same (definite) preconditioner
      Eigen::MINRES<Interface, Eigen::Lower | Eigen::Upper, MatrixFreePreconditioner<InterfaceData>> mr;
      mr.setTolerance(interface_tolerance_);
      mr.setMaxIterations(1000);
      mr.compute(B);
      xi = mr.solve(f);
      ok = mr.info() == Eigen::Success && std::isfinite(mr.error());
      if (!ok)
        throw std::runtime_error("Strip: the interface system of solve_system did not converge (CG and MINRES): " +
                                 std::to_string(D.applications) + " applications, relative residual " +
                                 format_number(mr.error()));
    }
  }
  last_interface_iterations_ = D.applications;
  D.d = nullptr;
  // The rows above, from row 0's modes; bᵀ C z on the way (x_j0 = z_j0 + z_jN + 2 Σ_{0<k<N} z_jk: the DCT-I at
  // i = 0).
  const auto edge = [nx](const double* r) { return r[0] + r[nx - 1] + 2.0 * partial_sum(r, 1, nx - 1); };
  double functional = D.spread[0] * edge(z);
  for (std::size_t j = 1; j <= ny; ++j) {
    double* zj = z + j * nx;
    const double* zp = zj - nx;
    const double* iv = inv + j * nx;
    for (std::size_t k = 0; k < nx; ++k) zj[k] = (zj[k] - o * zp[k]) * iv[k];
    functional += D.spread[j] * edge(zj);
  }
  return functional;
}

// The spring's ψ = A₀⁻¹ b for (c, d), kept as its modes (solve_system, solve_stage_mixed): then A⁻¹ r = A₀⁻¹ r − s ψ,
// s = β bᵀA₀⁻¹r / (1 + β bᵀψ), β = c K (Sherman–Morrison). ψ costs one interface solve and two passes, no transform.
void Strip::prepare_psi(double c, std::span<const double> d) {
  Direct& D = direct();
  if (!(spring_K_ > 0.0)) return;
  if (D.psi_c != c || !std::equal(d.begin(), d.end(), D.psi_d.begin(), D.psi_d.end())) {
    D.psi.resize(dofs());
    D.b_psi = direct_modes(d, nullptr, D.psi.data());
    D.psi_d.assign(d.begin(), d.end());
    D.psi_c = c;
  }
}

void Strip::solve_system(double c, std::span<const double> d, std::span<const double> rhs, std::span<double> x) {
  if (!(c > 0.0)) throw std::invalid_argument("Strip::solve_system: c must be > 0");
  direct_factorise(c);
  Direct& D = direct();
  const std::size_t nx = nx_;
  double s = 0.0;
  prepare_psi(c, d);
  double* z = buf_;
  const double b_x = direct_modes(d, rhs.data(), z);
  double* xo = x.data();
  if (spring_K_ > 0.0) {
    const double beta = c * spring_K_;
    s = beta * b_x / (1.0 + beta * D.b_psi);
    const double* psi = D.psi.data();
    D.bulk_dct->run([z, psi, s, nx](std::size_t j, std::size_t k) { return z[j * nx + k] - s * psi[j * nx + k]; },
                    [xo, nx](std::size_t j, std::size_t i, double v) { xo[j * nx + i] = v; });
  } else {
    D.bulk_dct->run([z, nx](std::size_t j, std::size_t k) { return z[j * nx + k]; },
                    [xo, nx](std::size_t j, std::size_t i, double v) { xo[j * nx + i] = v; });
  }
}

void Strip::solve_stage_mixed(double c, std::span<const double> d, const double* r0, double* xu, double* xv) {
  solve_stage_mixed(c, d, r0, StageInput{xu, xv}, xu, xv);
}

void Strip::solve_stage_mixed(double c, std::span<const double> d, const double* r0, const StageInput& in, double* xu,
                              double* xv) {
  if (!(c > 0.0)) throw std::invalid_argument("Strip::solve_stage_mixed: c must be > 0");
  direct_factorise(c);
  Direct& D = direct();
  const std::size_t n = dofs(), nx = nx_;
  prepare_psi(c, d);
  double* z = buf_;
  const double inv_c = 1.0 / c;
  const StageRhs stage{&in, inv_c};
  const double b_x = direct_modes(d, r0, z, &stage);
  const double s = spring_K_ > 0.0 ? c * spring_K_ * b_x / (1.0 + c * spring_K_ * D.b_psi) : 0.0;
  const double* psi = spring_K_ > 0.0 ? D.psi.data() : nullptr;
  const double* bu = in.bu;
  const double* su = in.sub_u;
  const double* au = in.add_u;
  const double* av = in.add_v;
  // rows j ≥ 1: x = z − s ψ, xv = (x − b_u)/c (+ add), xu = x (+ add); each element read before it is written
  for (std::size_t k = nx; k < n; ++k) {
    const double x = psi != nullptr ? z[k] - s * psi[k] : z[k];
    const double b = su != nullptr ? bu[k] - su[k] : bu[k];
    const double v = (x - b) * inv_c;
    xv[k] = av != nullptr ? v + av[k] : v;
    xu[k] = au != nullptr ? x + au[k] : x;
  }
  D.row_dct->row([z, psi, s](std::size_t k) { return psi != nullptr ? z[k] - s * psi[k] : z[k]; },
                 [xu, xv, inv_c](std::size_t i, double x) {
                   xv[i] = (x - xu[i]) * inv_c;
                   xu[i] = x;
                 });
}

void Strip::to_mixed(std::span<const double> u, std::span<double> z) const {
  Direct& D = const_cast<Strip*>(this)->direct();
  const std::size_t nx = nx_;
  const double nm = D.norm;
  if (z.data() != u.data()) std::copy_n(u.data(), nx, z.data());
  for (std::size_t j = 1; j <= ny_; ++j) {
    const double* uj = u.data() + j * nx;
    double* zj = z.data() + j * nx;
    D.row_dct->row([uj, nm](std::size_t i) { return uj[i] * nm; }, [zj](std::size_t k, double v) { zj[k] = v; });
  }
}

void Strip::from_mixed(std::span<const double> z, std::span<double> u) const {
  Direct& D = const_cast<Strip*>(this)->direct();
  const std::size_t nx = nx_;
  if (z.data() != u.data()) std::copy_n(z.data(), nx, u.data());
  for (std::size_t j = 1; j <= ny_; ++j) {
    const double* zj = z.data() + j * nx;
    double* uj = u.data() + j * nx;
    D.row_dct->row([zj](std::size_t k) { return zj[k]; }, [uj](std::size_t i, double v) { uj[i] = v; });
  }
}

// (C ẑ)_i = ẑ_0 + (−1)^i ẑ_N + 2 Σ_{0<k<N} ẑ_k cos(πik/N).
double Strip::mode_row_value(const double* modes, std::size_t i) const {
  const std::size_t N = nx_ - 1;
  double inner = 0.0;
  if (i == 0) {
    inner = partial_sum(modes, 1, N);
  } else if (i == N) {  // cos(πk) = (−1)^k
    double e0 = 0.0, e1 = 0.0, o0 = 0.0, o1 = 0.0;  // four partial sums (partial_sum)
    std::size_t k = 1;
    for (; k + 4 <= N; k += 4) {
      o0 += modes[k];
      e0 += modes[k + 1];
      o1 += modes[k + 2];
      e1 += modes[k + 3];
    }
    for (; k < N; ++k) (k % 2 == 0 ? e0 : o0) += modes[k];
    inner = (e0 + e1) - (o0 + o1);
  } else {
    const double w = std::numbers::pi * static_cast<double>(i) / static_cast<double>(N);
    for (std::size_t k = 1; k < N; ++k) inner += modes[k] * std::cos(w * static_cast<double>(k));
  }
  return modes[0] + ((i % 2 == 0) ? modes[N] : -modes[N]) + 2.0 * inner;
}

double Strip::mixed_edge_slip(std::span<const double> z) const {
  double s = row_weight(0) * z[0];
  for (std::size_t j = 1; j <= ny_; ++j) s += row_weight(j) * mode_row_value(z.data() + j * nx_, 0);
  return s / H_;
}

// Row 0 as the adaptive right-hand side (stage_accelerations) computes it (the elastic forces of elastic_forces, the edge force, the interface traction,
// over the node mass), with row 1 brought to node values; every row j ≥ 1 in its modes:
//   â_kj = (μ'/ρ') (−λ_k ẑ_kj + ((ẑ_k,j−1 − ẑ_kj) + (ẑ_k,j+1 − ẑ_kj))/(dy wy(j))) + F/(H ρ' wx(0)) / (2(nx−1))
// (the edge column's force per unit mass, δ_i0, has the mode 1/(2(nx−1)) in every k), + σ_d/(ρ' wy(ny)) in the
// mode k = 0 of the top row (a uniform traction), row 0's modes taken by one transform.
void Strip::mixed_accelerations(std::span<const double> u, double drive_force, const double* traction,
                                std::span<double> a) const {
  Direct& D = const_cast<Strip*>(this)->direct();
  const std::size_t nx = nx_, ny = ny_, e = nx - 1;
  const double nm = D.norm;
  const double* r = u.data();
  double* u1 = D.row_a.data();  // row 1's node values
  double* m0 = D.row_b.data();  // row 0's modes
  D.row_dct->row([r, nx](std::size_t k) { return r[nx + k]; }, [u1](std::size_t i, double v) { u1[i] = v; });
  D.row_dct->row([r, nm](std::size_t i) { return r[i] * nm; }, [m0](std::size_t k, double v) { m0[k] = v; });
  const double edge = drive_force / H_;
  {  // row 0: node values
    const double cx = 0.5 * mu_p_ * dy_ / dx_, cy_in = mu_p_ * dx_ / dy_, cy_end = 0.5 * cy_in, wy0 = row_weight(0);
    double* a0 = a.data();
    const auto put = [&](std::size_t i, double force) { a0[i] = force * (1.0 / node_mass(i, 0)); };
    put(0, cx * (r[1] - r[0]) + cy_end * (u1[0] - r[0]) + edge * wy0 - interface_weight(0) * traction[0]);
    for (std::size_t i = 1; i < e; ++i)
      put(i, cx * ((r[i - 1] - r[i]) + (r[i + 1] - r[i])) + cy_in * (u1[i] - r[i]) - dx_ * traction[i]);
    put(e, cx * (r[e - 1] - r[e]) + cy_end * (u1[e] - r[e]) - interface_weight(e) * traction[e]);
  }
  const double mr = mu_p_ / rho_p_, load = edge / (rho_p_ * interface_weight(0)) * nm;
  const double* lam = D.lam.data();
  for (std::size_t j = 1; j <= ny; ++j) {
    const double* zj = r + j * nx;
    const double* dn = j == 1 ? m0 : zj - nx;
    double* aj = a.data() + j * nx;
    const double cy = mr / (dy_ * row_weight(j));
    if (j < ny) {
      const double* up = zj + nx;
      for (std::size_t k = 0; k < nx; ++k)
        aj[k] = -mr * lam[k] * zj[k] + cy * ((dn[k] - zj[k]) + (up[k] - zj[k])) + load;
    } else {
      for (std::size_t k = 0; k < nx; ++k) aj[k] = -mr * lam[k] * zj[k] + cy * (dn[k] - zj[k]) + load;
      aj[0] += sigma_d_ / (rho_p_ * row_weight(ny));
    }
  }
}

// --- The adaptive integrator's body (core::AdaptiveBody) ---------------------------------------------------------

void Strip::stage_accelerations(double t, std::span<const double> u, const double* v, const double* sigma_bar,
                                double eta, std::span<double> a) {
  stage_.traction.resize(nx_);
  double* traction = stage_.traction.data();
  for (std::size_t i = 0; i < nx_; ++i) traction[i] = sigma_bar[i] + eta * v[i];
  mixed_accelerations(u, drive_force_at(t, mixed_edge_slip(u)), traction, a);
}

void Strip::set_stage_tolerance(double rtol) {
  set_interface_tolerance(std::clamp(kStageSolveTolerance * rtol, 1e-13, 1e-3));
}

Strip::StageInput Strip::stage_input(const BulkStage& in) const {
  StageInput s{in.bu, in.bv};
  s.sub_u = in.sub_u;
  s.sub_v = in.sub_v;
  s.add_u = in.add_u;
  s.add_v = in.add_v;
  // The spring's ∂f/∂t in the modes of every row j ≥ 1: those of hdT δ_i0 (the edge column), hdT/(2(nx − 1)).
  s.shift_v = has_drive_spring() ? in.hdT / (2.0 * static_cast<double>(nx_ - 1)) : 0.0;
  return s;
}

double Strip::stage_scale(const double* y) const {
  const std::size_t m = nx_, n = dofs(), N = m - 1;
  double sc = 0.0;
  for (std::size_t r = m; r < n; r += m)
    sc = std::max({sc, std::abs(mode_row_value(y + r, 0)), std::abs(mode_row_value(y + r, N))});
  return sc;
}

StageError Strip::stage_error(const double* y, const double* yn, const double* k1, const double* k2,
                              const double* k3) const {
  const std::size_t m = nx_, n = dofs(), N = m - 1;
  StageError out;
  for (std::size_t j = 0; j < m; ++j) {
    out.scale = std::max(out.scale, std::max(std::abs(y[j]), std::abs(yn[j])));
    const double e = std::abs(k1[j] - 2.0 * k2[j] + k3[j]);
    out.emax = std::max(out.emax, e);
    out.probe += e;
  }
  for (std::size_t q = m; q < n; q += m) {  // rows j ≥ 1: modes
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::size_t k = 1;
    for (; k + 4 <= N; k += 4) {
      s0 += std::abs(k1[q + k] - 2.0 * k2[q + k] + k3[q + k]);
      s1 += std::abs(k1[q + k + 1] - 2.0 * k2[q + k + 1] + k3[q + k + 1]);
      s2 += std::abs(k1[q + k + 2] - 2.0 * k2[q + k + 2] + k3[q + k + 2]);
      s3 += std::abs(k1[q + k + 3] - 2.0 * k2[q + k + 3] + k3[q + k + 3]);
    }
    for (; k < N; ++k) s0 += std::abs(k1[q + k] - 2.0 * k2[q + k] + k3[q + k]);
    const double bound = std::abs(k1[q] - 2.0 * k2[q] + k3[q]) + std::abs(k1[q + N] - 2.0 * k2[q + N] + k3[q + N]) +
                         2.0 * ((s0 + s1) + (s2 + s3));
    out.emax = std::max(out.emax, bound);
    out.probe += bound;
  }
  return out;
}

namespace {
// d/ds of the samples f(k) = p[k * step], k = 0 .. n − 1, spacing h, at k: second order (central inside,
// one-sided on the ends; two samples: their difference quotient).
double derivative(const double* p, std::size_t step, std::size_t n, std::size_t k, double h) {
  if (n < 2) return 0.0;
  if (n == 2) return (p[step] - p[0]) / h;
  if (k == 0) return (-3.0 * p[0] + 4.0 * p[step] - p[2 * step]) / (2.0 * h);
  if (k + 1 == n) return (3.0 * p[k * step] - 4.0 * p[(k - 1) * step] + p[(k - 2) * step]) / (2.0 * h);
  return (p[(k + 1) * step] - p[(k - 1) * step]) / (2.0 * h);
}
}  // namespace

void Strip::shear_stresses(std::span<const double> u, std::size_t i, std::size_t j, double& txz, double& tyz) const {
  txz = mu_p_ * derivative(u.data() + j * nx_, 1, nx_, i, dx_);
  tyz = mu_p_ * derivative(u.data() + i, nx_, ny_ + 1, j, dy_);
}

}  // namespace slipfront::core
