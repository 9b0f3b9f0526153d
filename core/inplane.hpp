#pragma once
// The in-plane strip of docs/model.md §10: a plane-strain (Lamé) body of height H over the interface,
// u_y = 0 and σ_xy = σ̄ + η v on the interface, discretised by bilinear (Q1) finite elements on the strip's
// vertex-centred grid (nx columns x_i = i dx, the chain's rule; rows = ny + 1 rows y_j = j dy, H = ny dy) with
// the lumped (row-sum) mass ρ' wx(i) wy(j), half cells on every face (§10.4).
//
// Two displacement components per node. Dof layout: u_x of node (i, j) is dof j·nx + i, u_y is plane() + j·nx + i
// (plane() = nx·rows()): the first nx dofs are the interface's slip, the law's sites in order, as on the chain
// and the antiplane strip. u_y of row 0 is held at 0 (the kick keeps its velocity 0); it stays a dof so that the
// two components are two equal grids.
//
// Material: the scene's μ keeps its 1D meaning (the thin strip is §1.2's chain with μ = E' H, E' = 2μ'/(1 − ν)
// the plate modulus, §10.2): μ' = μ(1 − ν)/(2H), ρ' = ρ/H, λ' = 2μ'ν/(1 − 2ν).
// Under homogeneous loading the end faces carry the complementary shear σ_xy = σ_top (end_load_y), so that the
// uniformly sheared strip is a stuck state (docs/model.md §10.3).
// Elastic force Fel = −K u, K the assembled Q1 stiffness (2 × 2 Gauss points, exact for Q1):
// E(u) = u·K u / 2 = (1/2) ∫ σ : ε. External forces: interface row u_x −wx(i)(σ̄_i + η v_i); top row u_x
// +wx(i) σ_top (σ_top = σ_d under homogeneous loading, else 0), u_y −wx(i) p (the normal load); edge column u_x
// +F(t) wy(j)/H, F = K (v_d t − ū0) + F_r, ū0 = Σ_j wy(j) u_x(0, j)/H (as core::Strip).
//
// The adaptive integrator's body (core::AdaptiveBody, docs/numerics.md §8.9): the stage representation is the node
// values; the W solve's u system is the implicit step's matrix A(γh, η + q_σ), solved directly (the capacitance method,
// solve_stage_direct; the preconditioned CG of the implicit step as reference and fallback).
//
// Thread safety: an InPlane holds mutable workspace (the force buffer, the factorisation), so one object serves
// one thread at a time; copies are independent.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "core/body.hpp"
#include "core/params.hpp"

namespace slipfront::core {

/// What the in-plane strip adds to a scene's parameters (docs/model.md §10.1): Poisson's ratio ν ∈ (−1, ½) and
/// the normal load p ≥ 0 on the top face (σ_yy(x, H) = −p).
struct InPlaneParams {
  double poisson = 1.0 / 3.0;
  double normal_load = 0.0;
};

class InPlane {
 public:
  /// Edge or homogeneous loading (throws std::invalid_argument for the others, height ≤ 0, dx or dy ≤ 0,
  /// dy not dividing H, fewer than one cell in x or y, ν outside (−1, ½), p < 0).
  InPlane(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, const InPlaneParams& material,
          double dx, double dy);
  /// A scene's body (core::RunBody): ν and p from bulk.poisson and bulk.normal_load, dy = grid.row_spacing().
  InPlane(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, const GridParams& grid)
      : InPlane(bulk, drive, law, material_of(bulk), grid.dx, grid.row_spacing()) {}
  InPlane(const InPlane& o);
  InPlane(InPlane&& o) noexcept;
  InPlane& operator=(const InPlane& o);
  InPlane& operator=(InPlane&& o) noexcept;
  ~InPlane();

  // --- The grid -----------------------------------------------------------------------------------------
  std::size_t sites() const { return nx_; }
  std::size_t rows() const { return ny_ + 1; }
  std::size_t plane() const { return nx_ * (ny_ + 1); }  ///< dofs of one component; u_y of node k is plane() + k
  std::size_t dofs() const { return 2 * plane(); }
  double dx() const { return dx_; }
  double dy() const { return dy_; }
  double height() const { return H_; }
  double row_height(std::size_t j) const { return static_cast<double>(j) * dy_; }  ///< y_j
  const std::vector<double>& x() const { return x_; }
  double interface_weight(std::size_t i) const { return (i == 0 || i + 1 == nx_) ? 0.5 * dx_ : dx_; }
  double row_weight(std::size_t j) const { return (j == 0 || j == ny_) ? 0.5 * dy_ : dy_; }
  double node_mass(std::size_t i, std::size_t j) const { return rho_p_ * interface_weight(i) * row_weight(j); }

  // --- The material (docs/model.md §10.2) -------------------------------------------------------------------
  double rho() const { return rho_; }                ///< the scene's ρ (thickness-integrated)
  double mu() const { return mu_; }                  ///< the scene's μ = E' H (thickness-integrated plate stiffness)
  double rho_prime() const { return rho_p_; }        ///< ρ' = ρ/H
  double mu_prime() const { return mu_p_; }          ///< μ' = μ(1 − ν)/(2H)
  double lambda_prime() const { return lambda_p_; }  ///< λ' = 2μ'ν/(1 − 2ν)
  double poisson() const { return nu_; }
  double normal_load() const { return p_; }
  double shear_speed() const;     ///< c_s = sqrt(μ'/ρ')
  double pressure_speed() const;  ///< c_p = sqrt((λ' + 2μ')/ρ')
  double plate_speed() const;     ///< c_0 = sqrt(μ/ρ) = c_s sqrt(2/(1 − ν)), the 1D sound speed

  // --- The loading --------------------------------------------------------------------------------------
  double uniform_stress() const { return sigma_d_; }  ///< σ_top: σ_d (homogeneous loading), else 0
  /// The end faces' complementary shear under homogeneous loading (docs/model.md §10.3): σ_xy = σ_top on x = 0 and
  /// x = L, the nodal force on u_y of node (i, j): −σ_top wy(j) on column 0, +σ_top wy(j) on column nx − 1, else 0.
  /// With it the uniformly sheared strip is a stuck state of the body (a piece of the infinite strip under σ_top).
  double end_load_y(std::size_t i, std::size_t j) const {
    const double s = i == 0 ? -sigma_d_ : i + 1 == nx_ ? sigma_d_ : 0.0;
    return s * row_weight(j);
  }
  bool has_drive_spring() const { return spring_K_ > 0.0; }
  double spring_K() const { return spring_K_; }
  double driver_velocity() const { return v_d_; }
  double rear_traction() const { return rear_traction_; }
  /// Mass of the loaded edge column's u_x, Σ_j M_0j = ρ' wx(0) H = ρ dx/2.
  double edge_mass() const { return rho_ * interface_weight(0); }
  /// ū0 = Σ_j wy(j) u_x(0, j) / H (u: all dofs).
  double edge_slip(std::span<const double> u) const;
  /// F(t) = K (v_d t − ū0) + F_r.
  double drive_force(double t, std::span<const double> u) const {
    return spring_K_ * (v_d_ * t - edge_slip(u)) + rear_traction_;
  }

  // --- Energies ----------------------------------------------------------------------------------------
  double kinetic_energy(std::span<const double> V) const;
  double elastic_energy(std::span<const double> u) const;  ///< u·K u / 2
  double spring_energy(double t, std::span<const double> u) const;
  /// The power of the top face's tractions: Σ_i wx(i) (σ_top v_x(i, ny) − p v_y(i, ny)).
  double uniform_power(std::span<const double> v) const;

  // --- The elastic operator --------------------------------------------------------------------------------
  /// f = −K u (all dofs, both components; the interface's u_y reaction included, nothing held).
  void elastic_forces(std::span<const double> u, std::span<double> f) const;
  /// K (elastic only, dofs × dofs, u_y of row 0 not eliminated).
  Eigen::SparseMatrix<double> stiffness_matrix() const;
  /// The Q1 element's stiffness, 8 × 8, local nodes (0,0), (1,0), (0,1), (1,1), dofs u_x of the four then u_y.
  const std::array<double, 64>& element_stiffness() const { return ke_; }

  // --- Stresses (docs/model.md §10.4) ----------------------------------------------------------------------
  /// σ_yy(x_i, 0) for every interface site: the reaction that holds u_y = 0, per interface length,
  /// (−K u)_{y,i0} / wx(i) (the discrete form of the interface's normal traction; out: sites()).
  void interface_normal_stress(std::span<const double> u, std::span<double> out) const;
  /// The three stresses at node (i, j) from second-order differences of the node field (central inside,
  /// one-sided (−3u₀ + 4u₁ − u₂)/(2h) on the faces; first order when a direction has only two nodes).
  void stresses(std::span<const double> u, std::size_t i, std::size_t j, double& sxx, double& syy,
                double& sxy) const;

  // --- The explicit scheme (docs/model.md §10.5) -----------------------------------------------------------
  /// 2/ω_max with ω_max² = ω_e² + 2αH/(ρ dy) + 2K/(ρ dx), ω_e² the largest eigenvalue of the Q1 element's
  /// stiffness over its lumped mass ρ' dx dy/4 (a bound on the grid's, docs/model.md §10.5).
  double stable_dt() const { return stable_dt_; }
  /// The same bound from the scene's parameters without building the grid.
  static double stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                                 const InPlaneParams& material, double dx, double dy);
  /// Central-difference kick v^{n−1/2} → v^{n+1/2} of every dof, forces at u^n, η v centred on the interface
  /// row's u_x, u_y of row 0 held at 0; edge_force = F(t^n).
  void kick(double dt, double eta, double edge_force, std::span<const double> u, std::span<const double> sigma_bar,
            std::span<const double> v_old, std::span<double> v_new) const;

  // --- core::RunBody (core/body.hpp): what the run layer asks of a body ---------------------------------------
  static InPlaneParams material_of(const BulkParams& bulk) { return {bulk.poisson, bulk.normal_load}; }
  /// round(L/dx) + 1 sites, round(H/dy) + 1 rows (dy = grid.row_spacing()), two components (u_x, u_y).
  static BodyShape shape(const BulkParams& bulk, const DriveParams& drive, const GridParams& grid);
  static double stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                                 const GridParams& grid) {
    return stable_time_step(bulk, drive, law, material_of(bulk), grid.dx, grid.row_spacing());
  }
  BodyShape shape() const { return {nx_, ny_ + 1, 2}; }
  /// Component planes: u_x of node (i, j) is dof j·nx + i, u_y is plane() + j·nx + i.
  std::size_t dof(std::size_t i, std::size_t j, std::size_t c) const { return c * plane() + j * nx_ + i; }
  /// The stuck state of docs/model.md §10.3 lifted into column i: every row carries the uniform shear σ_d and, under
  /// the normal load, the laterally confined compression σ_yy = −p (σ_xx = −νp/(1 − ν)):
  ///   u_x(x_i, y) = u + σ_d y/μ',   u_y(x_i, y) = −p y/(λ' + 2μ'),   moving with the interface's slip rate v (u_x).
  /// Exact inside the strip; the free end faces carry neither the shear nor σ_xx, so within ~H of the ends the
  /// body relaxes from it (§10.3, finding 2).
  template <class Set>
  void lift(std::size_t i, double u, double v, double sigma_d, Set&& set) const {
    const double squeeze = p_ / (lambda_p_ + 2.0 * mu_p_);
    for (std::size_t j = 0; j <= ny_; ++j) {
      const double y = row_height(j);
      set(dof(i, j, 0), u + (j == 0 ? 0.0 : sigma_d * y / mu_p_), v);
      set(dof(i, j, 1), -squeeze * y, 0.0);
    }
  }
  /// ū0 = Σ_j wy(j) value(dof(0, j, 0)) / H.
  template <class Value>
  double edge_slip_of(Value&& value) const {
    double s = 0.0;
    for (std::size_t j = 0; j <= ny_; ++j) s += row_weight(j) * value(j * nx_);
    return s / H_;
  }
  /// F(t) = K (v_d t − ū0) + F_r for a given ū0.
  double drive_force_at(double t, double edge_slip) const { return spring_K_ * (v_d_ * t - edge_slip) + rear_traction_; }
  /// u (u_x, u_y: two components), sigma_xx, sigma_yy, sigma_xy (stresses()).
  static std::span<const SnapshotField> snapshot_fields();
  void snapshot_values(std::span<const double> u, std::size_t i, std::size_t j, std::span<double> out) const {
    out[0] = u[dof(i, j, 0)];
    out[1] = u[dof(i, j, 1)];
    stresses(u, i, j, out[2], out[3], out[4]);
  }

  // --- The implicit (trapezoidal) step (core/implicit.hpp) -------------------------------------------------
  /// The system of core::Strip::implicit_solve with two components per node and u_y of row 0 held at 0:
  ///   A W = [2M/dt + (dt/2)(K + K_s b bᵀ) + E diag(wx (η + c1/2)) Eᵀ] W
  ///       = 2M V/dt − K u + b (K_s (v_d (t + dt/2) − ū0(u)) + F_r) + E wx (−(σ̄ + c0)/2) + top loads.
  /// Solved (docs/model.md §10.6) by Eigen's conjugate gradient, matrix-free, preconditioned by the exact inverse of
  /// the separable part (u_x in cosine modes, FFTW's DCT-I; u_y in sine modes, DST-I; one 2 × 2-block tridiagonal
  /// solve in y per mode; the interface coefficient at its mean; the end columns' u_y by their diagonal), to a
  /// relative residual of 1e-12 within 500 iterations (else std::runtime_error); or, as a reference, by Eigen's
  /// SimplicialLDLT of the assembled matrix (StepSolver::direct, refactorised whenever dt or c1 change).
  template <class Lin>
  void implicit_solve(const Lin& lin, std::span<const double> w_prev, std::span<double> c0, std::span<double> c1,
                      double t, double dt, double eta, std::span<const double> u, std::span<const double> V,
                      std::span<const double> sigma_bar, std::span<double> W) {
    for (std::size_t i = 0; i < nx_; ++i) lin(i, w_prev[i], c0[i], c1[i]);
    solve_step(c0, c1, t, dt, eta, u, V, sigma_bar, W);
  }
  void solve_step(std::span<const double> c0, std::span<const double> c1, double t, double dt, double eta,
                  std::span<const double> u, std::span<const double> V, std::span<const double> sigma_bar,
                  std::span<double> W);
  enum class StepSolver { cg, direct };
  void set_step_solver(StepSolver s) { step_solver_ = s; }
  StepSolver step_solver() const { return step_solver_; }
  /// CG iterations of the last solve (0 for the direct solve).
  int last_iterations() const { return last_iterations_; }

  /// The step matrix with coefficient c and interface coefficients d (as core::Strip::solve_system), for any
  /// right-hand side: A(c, d) x = rhs, A(c, d) = M/c + c (K + K_s b bᵀ) + E diag(wx d) Eᵀ, u_y of row 0 held
  /// (identity rows). The trapezoidal step's is A(dt/2, η + c1/2). By the preconditioned CG above (x on entry: the
  /// guess; rhs and x may alias); throws std::runtime_error when it does not converge.
  void solve_system(double c, std::span<const double> d, std::span<const double> rhs, std::span<double> x);

  // Internal to the CG (inplane.cpp): y = A x of the current step, z = P⁻¹ r (held dofs: identity).
  void apply_system(const double* x, double* y) const;
  const double* apply_preconditioner(const double* r) const;

  // --- The adaptive integrator's body (core::AdaptiveBody, core/body.hpp; docs/numerics.md §8.9) -----------------
  // The stage representation is the node values (both components, the dof layout above: the interface slips first).
  // v' of every dof is the explicit scheme's force over the lumped mass with σ̄ + η v on the interface (u_y of row 0
  // held: its v' is 0 and its u enters no force). The W solve leaves for x_u (docs/numerics.md §8.5, §8.9)
  //   A(c, d) x_u = M b_v + (M/c) b_u + E wx (d b_u0 − c p_σ),   d = η + q_σ,   then x_v = (x_u − b_u)/c,
  // the held dofs x_u = b_u + c b_v, solved directly (solve_stage_direct, docs/numerics.md §8.9: two separable solves,
  // the capacitance factors of the end columns' u_y and the spring cached per c, the interface coefficient's spread
  // about d_ref = η + c α by an nx-sized system to a relative residual of kStageSolveTolerance · rtol); when that
  // system fails, or with set_stage_solver(krylov), by solve_system's preconditioned CG (BiCGSTAB when the CG fails)
  // from the integrator's guess (BulkStage: the last accepted step's same stage, k1 and k2) or else b_u + c b_v.
  std::size_t components() const { return 2; }
  static constexpr bool stage_is_nodes = true;
  const char* stage_archive_tag() const { return "adaptive_inplane"; }
  void to_stage(std::span<const double> u, std::span<double> z) const {
    if (z.data() != u.data()) std::copy_n(u.data(), u.size(), z.data());
  }
  void from_stage(std::span<const double> z, std::span<double> u) const { to_stage(z, u); }
  double stage_value(const double* z, std::size_t i) const { return z[i]; }
  double stage_drive_force(double t, std::span<const double> u) const { return drive_force(t, u); }
  /// a = M⁻¹ (−K u + F(t) b + top and end loads − E wx (σ̄ + η v)) on every dof, 0 on the held u_y of row 0.
  void stage_accelerations(double t, std::span<const double> u, const double* v, const double* sigma_bar, double eta,
                           std::span<double> a);
  /// The stage solves' CG stops at a relative residual of 1e-3 rtol (floor 1e-13; docs/numerics.md §8.9).
  static constexpr double kStageSolveTolerance = 1e-3;
  void set_stage_tolerance(double rtol);
  template <class SiteQ>
  void stage_factor(double c, double eta, SiteQ&& q_sigma) {
    stage_.c = c;
    stage_.eta = eta;
    stage_.d.resize(nx_);
    for (std::size_t i = 0; i < nx_; ++i) stage_.d[i] = eta + q_sigma(i);
  }
  /// The sites' right-hand side (with their p_σ, in order), the rest from `in` (stage_bulk_rhs), the solve, the
  /// sites' x_v handed back in order, the rest completed (stage_bulk_finish).
  template <class SiteP, class SiteBack>
  void stage_solve(const BulkStage& in, SiteP&& p_sigma, SiteBack&& back, double* xu, double* xv) {
    const std::size_t m = nx_;
    const double c = stage_.c, inv_c = 1.0 / c;
    stage_.r.resize(dofs());
    stage_.bu.resize(dofs());
    stage_.x.resize(dofs());
    double *r = stage_.r.data(), *bu = stage_.bu.data(), *x = stage_.x.data();
    const double* d = stage_.d.data();
    for (std::size_t i = 0; i < m; ++i) {
      const double ps = p_sigma(i);
      r[i] = node_mass(i, 0) * (xv[i] + inv_c * xu[i]) + interface_weight(i) * (d[i] * xu[i] - c * ps);
      bu[i] = xu[i];
      x[i] = xu[i] + c * xv[i];  // the guess: x_u of W = I
    }
    stage_bulk_rhs(in);
    if (in.guess_u != nullptr)
      for (std::size_t k = 0, n = dofs(); k < n; ++k)
        x[k] = in.guess_scale * in.guess_u[k] - (in.guess_sub_u ? in.guess_sub_u[k] : 0.0);
    solve_stage_system();
    for (std::size_t i = 0; i < m; ++i) {
      xu[i] = x[i];
      xv[i] = (x[i] - bu[i]) * inv_c;
      back(i, xv[i]);
    }
    stage_bulk_finish(in, xu, xv);
  }
  /// The step sizes the integrator may take on this body (core::AdaptiveSimulation asks when the body has this member):
  /// h rounded to the nearest of the geometric grid 2^(m/kStepLevels), m an integer (up to 4.4 % either way; the error
  /// test still decides), so that the stage matrix A(γh, ·) takes few distinct values and its capacitance factors
  /// (solve_stage_direct) are reused from a cache (docs/numerics.md §8.9).
  static constexpr int kStepLevels = 8;
  static double quantized_step(double h) {
    if (!(h > 0.0) || !std::isfinite(h)) return h;
    return std::exp2(std::round(std::log2(h) * kStepLevels) / kStepLevels);
  }
  /// The stage solve: direct (the capacitance method of docs/numerics.md §8.9, the default) or the preconditioned
  /// Krylov solve (the reference it replaced; also the direct solve's fallback when its interface system fails).
  enum class StageSolver { direct, krylov };
  void set_stage_solver(StageSolver s) { stage_solver_ = s; }
  /// 0: stage_error's scale is taken over every node value already.
  double stage_scale(const double*) const { return 0.0; }
  /// The field norm's parts over every dof (node values, both components).
  StageError stage_error(const double* y, const double* yn, const double* k1, const double* k2, const double* k3) const;
  /// Krylov iterations of every stage solve so far, and how many of them fell back to BiCGSTAB.
  long long stage_iterations() const { return stage_.iterations; }
  long long stage_fallbacks() const { return stage_.fallbacks; }
  /// Capacitance factorisations made (one per distinct stage coefficient c not in the cache) and interface iterations
  /// of the direct stage solves (docs/numerics.md §8.9).
  long long stage_capacitance_builds() const { return stage_.builds; }
  long long stage_interface_iterations() const { return stage_.interface_iterations; }
  /// Direct stage solves whose interface system did not converge (then solved by the Krylov solve).
  long long stage_direct_failures() const { return stage_.direct_failures; }

 private:
  struct Direct;  // the direct solve's factorisation (inplane.cpp)
  struct Fast;    // the CG's transforms, mode factors and step coefficients (inplane_solve.cpp)
  void rhs_step(std::span<const double> c0, double t, double dt, std::span<const double> u, std::span<const double> V,
                std::span<const double> sigma_bar, double* rhs) const;
  void solve_direct(double c, std::span<const double> d, const double* rhs, std::span<double> W);
  void factorise_modes(double c, double dbar) const;
  // Calls f(k, i, j, fx, fy) for every node k = (i, j), rows in order: force_ (−K u, the caller's) with the edge force
  // F wy(j)/H on column 0's u_x, the top's tractions and the end faces' shear; the interface traction is the caller's.
  template <class F>
  void node_forces(double edge_force, F&& f) const {
    const std::size_t nx = nx_, ny = ny_, P = plane();
    const double edge_per_height = edge_force / H_;
    for (std::size_t j = 0; j <= ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) {
        const std::size_t k = j * nx + i;
        const double wx = interface_weight(i);
        double fx = force_[k], fy = force_[P + k] + end_load_y(i, j);
        if (i == 0) fx += edge_per_height * row_weight(j);
        if (j == ny) {
          fx += wx * sigma_d_;
          fy -= wx * p_;
        }
        f(k, i, j, fx, fy);
      }
  }
  // The preconditioned Krylov solve of A(c, d) x = rhs (f.rhs, f.c, f.d set; x on entry the guess) to relative
  // residual tol: CG, and BiCGSTAB from the same guess when the CG fails. Returns the iterations.
  int krylov(std::span<double> x, double tol, bool& fell_back);
  // The adaptive stage solve's parts beyond the sites (docs/numerics.md §8.9).
  void stage_bulk_rhs(const BulkStage& in);
  void solve_stage_system();
  void stage_bulk_finish(const BulkStage& in, double* xu, double* xv) const;
  void end_columns_exact(const double* r, double* z) const;
  // The direct stage solve (docs/numerics.md §8.9): z = S⁻¹ r for the separable part S of A(c, d_ref) (the end
  // columns' u_y excluded: z there 0; held dofs identity), the capacitance factors of c (cached), the solve.
  void separable_solve(const double* r, double* z) const;
  struct Capacitance;
  static constexpr std::size_t kCapacitanceCache = 32;  // the factors of this many stage coefficients c are kept
  Capacitance& capacitance(double c, double d_ref);
  void setup_end_columns();
  bool solve_stage_direct();

  std::vector<double> x_;
  std::size_t nx_ = 0, ny_ = 0;
  double dx_ = 1.0, dy_ = 1.0, H_ = 1.0, rho_ = 1.0, mu_ = 1.0, nu_ = 0.0, p_ = 0.0;
  double rho_p_ = 1.0, mu_p_ = 1.0, lambda_p_ = 0.0;
  double sigma_d_ = 0.0, spring_K_ = 0.0, v_d_ = 0.0, rear_traction_ = 0.0, stable_dt_ = 0.0;
  double alpha_ = 1.0;  // the law's α: the stage solve's reference interface coefficient d_ref = η + c α (stuck, A = 1)
  std::array<double, 64> ke_{};
  mutable std::vector<double> force_;  // the kick's −K u
  std::vector<double> rhs_, dstep_;    // the implicit step's right-hand side and interface coefficients
  std::unique_ptr<Direct> direct_;
  std::unique_ptr<Fast> fast_;
  StepSolver step_solver_ = StepSolver::cg;
  StageSolver stage_solver_ = StageSolver::direct;
  int last_iterations_ = 0;
  struct AdaptiveStage {  // the adaptive stage solve: c, d, the right-hand side, b_u, the solution, the CG's tolerance
    double c = 0.0, eta = 0.0, tolerance = 1e-12;
    std::vector<double> d, r, bu, x, u_free;  // u_free: stage_accelerations' u with the held dofs zeroed
    long long iterations = 0, fallbacks = 0, builds = 0, interface_iterations = 0, direct_failures = 0;
  } stage_;
};

static_assert(Body<InPlane>);
static_assert(RunBody<InPlane>);
static_assert(AdaptiveBody<InPlane>);

}  // namespace slipfront::core
