#pragma once
// The antiplane strip of docs/model.md §9: a body of height H over the
// interface, discretised on a uniform vertex-centred grid of nx columns (x_i = i dx, the chain's rule) and
// rows = ny + 1 rows (y_j = j dy, H = ny dy), lumped mass, half cells on every face. One scalar unknown per
// node (the antiplane displacement), dof index j·nx + i, row j = 0 the interface (the first nx dofs are the
// interface sites, in order).
//
// Per unit height μ' = μ/H, ρ' = ρ/H (μ, ρ: the scene's thickness-integrated values, so the shear wave
// speed is the chain's and H → 0 is the chain). Weights wx(i) = dx inside, dx/2 at i = 0, nx−1;
// wy(j) = dy inside, dy/2 at j = 0, ny. Node mass M_ij = ρ' wx(i) wy(j).
//   E(u) = (μ'/2) [ Σ_j wy(j) Σ_{i<nx−1} (u_{i+1,j} − u_ij)²/dx + Σ_i wx(i) Σ_{j<ny} (u_{i,j+1} − u_ij)²/dy ]
// and Fel = −∇E = −S u (5-point, free faces: missing neighbours drop out). External forces on node (i, j):
// interface row −wx(i)(σ̄_i + η v_i0); top row +wx(i) σ_d (homogeneous loading); edge column
// +F(t) wy(j)/H, F = K (v_d t − ū0) + F_r, ū0 = Σ_j wy(j) u_0j / H (K, v_d: edge loading; F_r, σ_d:
// homogeneous loading, as core::Bulk sets them). Summing a column over j gives the chain's equation.
//
// The implicit step's system (trapezoidal rule, like core/implicit.hpp) is solved by Eigen's conjugate
// gradient, matrix-free, preconditioned by the exact inverse of its separable part (a cosine transform
// along x, FFTW REDFT00, and one tridiagonal solve per mode along y): O(n log n) per iteration and an
// iteration count that does not grow with the grid (docs/performance.md §12).
//
// Thread safety: a Strip holds mutable workspace, so one object serves one thread at a time; copies are
// independent (own buffers and FFTW plans) and may run concurrently. Results are bit-reproducible
// (FFTW_ESTIMATE plans on aligned buffers of the same sizes; fixed operation order).
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "core/body.hpp"
#include "core/params.hpp"

struct fftw_plan_s;  // FFTW's plan (fftw3.h stays out of this header)

namespace slipfront::core {

class Strip {
 public:
  /// How the preconditioner's interface shift d̄ is chosen (docs/performance.md §12).
  enum class Shift {
    mean_c1,  ///< d̄ = η + mean(c1)/2 of the step: the mode factors are recomputed when it changes (default)
    eta,      ///< d̄ = η: factors recomputed only when dt or η change
  };

  /// Edge or homogeneous loading (throws std::invalid_argument for the others, for height ≤ 0, dy ≤ 0,
  /// dy not dividing H, fewer than one cell in x or y).
  Strip(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx, double dy);
  /// The same with dy = grid.row_spacing().
  Strip(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, const GridParams& grid)
      : Strip(bulk, drive, law, grid.dx, grid.row_spacing()) {}
  Strip(const Strip& o);
  Strip(Strip&& o) noexcept;
  Strip& operator=(const Strip& o);
  Strip& operator=(Strip&& o) noexcept;
  ~Strip();

  std::size_t sites() const { return nx_; }
  std::size_t rows() const { return ny_ + 1; }
  std::size_t dofs() const { return nx_ * (ny_ + 1); }
  double dx() const { return dx_; }
  double dy() const { return dy_; }
  double height() const { return H_; }
  double row_height(std::size_t j) const { return static_cast<double>(j) * dy_; }  ///< y_j
  const std::vector<double>& x() const { return x_; }
  double rho() const { return rho_; }
  double interface_weight(std::size_t i) const { return (i == 0 || i + 1 == nx_) ? 0.5 * dx_ : dx_; }
  double row_weight(std::size_t j) const { return (j == 0 || j == ny_) ? 0.5 * dy_ : dy_; }
  double node_mass(std::size_t i, std::size_t j) const { return rho_p_ * interface_weight(i) * row_weight(j); }
  /// Mass of the loaded edge column, Σ_j M_0j = ρ' wx(0) H = ρ dx/2.
  double edge_mass() const { return rho_ * interface_weight(0); }
  /// 2/ω, ω² = c_s²(4/dx² + 4/dy²) + 2K/(ρ dx) + 2αH/(ρ dy): Gershgorin bound of M⁻¹(S + interface α + spring).
  double stable_dt() const { return stable_dt_; }
  /// The same bound from the scene's parameters, without building the grid (compare::estimate).
  static double stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx,
                                 double dy);
  double uniform_stress() const { return sigma_d_; }
  bool has_drive_spring() const { return spring_K_ > 0.0; }
  double spring_K() const { return spring_K_; }
  double driver_velocity() const { return v_d_; }
  double rear_traction() const { return rear_traction_; }

  /// ū0 = Σ_j wy(j) u_0j / H (u: all dofs).
  double edge_slip(std::span<const double> u) const {
    return edge_slip_of([u](std::size_t k) { return u[k]; });
  }
  /// F(t) = K (v_d t − ū0) + F_r.
  double drive_force(double t, std::span<const double> u) const {
    return spring_K_ * (v_d_ * t - edge_slip(u)) + rear_traction_;
  }
  double kinetic_energy(std::span<const double> V) const;
  double elastic_energy(std::span<const double> u) const;
  /// K (v_d t − ū0)²/2 (0 without a spring).
  double spring_energy(double t, std::span<const double> u) const;
  /// σ_d Σ_i wx(i) v_{i,ny}: the power of the uniform stress on the top face (0 for edge loading).
  double uniform_power(std::span<const double> v) const;
  /// The two shear stresses at node (i, j) (u: all dofs): τ_xz = μ' ∂u/∂x, τ_yz = μ' ∂u/∂y by second-order
  /// differences, central inside and one-sided (−3u₀ + 4u₁ − u₂)/(2h) on the faces (first order when a
  /// direction has only two nodes). Exact for u quadratic in x and y (the homogeneous stuck state,
  /// docs/model.md §9.4: τ_yz = σ_d, τ_xz = 0).
  void shear_stresses(std::span<const double> u, std::size_t i, std::size_t j, double& txz, double& tyz) const;
  /// S (elastic only), dofs × dofs.
  Eigen::SparseMatrix<double> stiffness_matrix() const;

  // --- core::RunBody (core/body.hpp): what the run layer asks of a body ------------------------------
  /// round(L/dx) + 1 sites, round(H/dy) + 1 rows (dy = grid.row_spacing()), one component (antiplane).
  static BodyShape shape(const BulkParams& bulk, const DriveParams& drive, const GridParams& grid);
  static double stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                                 const GridParams& grid) {
    return stable_time_step(bulk, drive, law, grid.dx, grid.row_spacing());
  }
  BodyShape shape() const { return {nx_, ny_ + 1, 1}; }
  /// Row-major: dof j·nx + i (one component).
  std::size_t dof(std::size_t i, std::size_t j, std::size_t) const { return j * nx_ + i; }
  /// μ' = μ/H, the shear modulus per unit height (docs/model.md §9): of the parameters (the one formula), of this strip.
  static double modulus(const BulkParams& bulk) { return bulk.mu / bulk.height; }
  double modulus() const { return mu_p_; }
  /// docs/model.md §9.4: every row above the interface carries the uniform shear σ_d, u(x, y) = u(x, 0) + σ_d y/μ',
  /// moving with the interface's slip rate.
  template <class Set>
  void lift(std::size_t i, double u, double v, double sigma_d, Set&& set) const {
    for (std::size_t j = 0; j <= ny_; ++j) set(j * nx_ + i, u + (j == 0 ? 0.0 : sigma_d * row_height(j) / mu_p_), v);
  }
  /// ū0 = Σ_j wy(j) value(dof(0, j)) / H.
  template <class Value>
  double edge_slip_of(Value&& value) const {
    double s = 0.0;
    for (std::size_t j = 0; j <= ny_; ++j) s += row_weight(j) * value(j * nx_);
    return s / H_;
  }
  /// u, tau_xz, tau_yz (shear_stresses).
  static std::span<const SnapshotField> snapshot_fields();
  void snapshot_values(std::span<const double> u, std::size_t i, std::size_t j, std::span<double> out) const {
    out[0] = u[j * nx_ + i];
    shear_stresses(u, i, j, out[1], out[2]);
  }

  /// Calls f(j, i, F) for every node with F = (−S u)_ij, rows in order, i inner.
  template <class F>
  void elastic_forces(std::span<const double> u, F&& f) const;

  /// Explicit central-difference kick v^{n−1/2} → v^{n+1/2} of every dof, forces at u^n, η v centred on
  /// the interface row; edge_force = F(t^n). Allocation-free, O(dofs).
  void kick(double dt, double eta, double edge_force, std::span<const double> u, std::span<const double> sigma_bar,
            std::span<const double> v_old, std::span<double> v_new) const;

  /// One implicit (trapezoidal) step's system for W (all dofs), t → t + dt:
  ///   [2M/dt + (dt/2)(S + K b bᵀ) + E diag(wx (η + c1/2)) Eᵀ] W
  ///       = 2M V/dt + Fel(u) + b (K (v_d (t + dt/2) − ū0(u)) + F_r) + E wx (−(σ̄ + c0)/2) + top wx σ_d,
  /// b the edge column's spread vector (b_0j = wy(j)/H), E the interface row. First calls
  /// lin(i, w_prev[i], c0[i], c1[i]) for every site (c1 ≥ 0), then solves; W on entry is the initial guess.
  /// Relative residual ≤ 1e-12 within 200 iterations, else std::runtime_error.
  template <class Lin>
  void implicit_solve(const Lin& lin, std::span<const double> w_prev, std::span<double> c0, std::span<double> c1,
                      double t, double dt, double eta, std::span<const double> u, std::span<const double> V,
                      std::span<const double> sigma_bar, std::span<double> W) {
    for (std::size_t i = 0; i < nx_; ++i) lin(i, w_prev[i], c0[i], c1[i]);
    solve_step(c0, c1, t, dt, eta, u, V, sigma_bar, W);
  }
  /// The solve of implicit_solve with c0, c1 given.
  void solve_step(std::span<const double> c0, std::span<const double> c1, double t, double dt, double eta,
                  std::span<const double> u, std::span<const double> V, std::span<const double> sigma_bar,
                  std::span<double> W);
  /// CG iterations of the last solve (0: the guess already met the tolerance).
  int last_iterations() const { return last_iterations_; }
  /// Relative residual the last solve reached.
  double last_residual() const { return last_residual_; }

  /// The step matrix with coefficient c and interface coefficients d, solved directly for any right-hand side:
  ///   A(c, d) x = rhs,   A(c, d) = M/c + c (S + K b bᵀ) + E diag(wx d) Eᵀ   (all dofs; c > 0; d per site).
  /// The trapezoidal step's matrix is A(dt/2, η + c1/2); the adaptive integrator's u system is A(γh, η + q_σ)
  /// (core/adaptive.hpp). d may be of either sign as long as A is definite (the interface Schur complement
  /// below is then definite too). The capacitance method (docs/performance.md §12): P = M/c + c S is
  /// diagonalised by the DCT-I along x (FFTW REDFT00), per mode a tridiagonal T_k in y, factorised from the
  /// top row down so that its last pivot p_k gives the interface's Green's function G = Eᵀ P⁻¹ E, diagonal in
  /// cosine space (1/p_k); the interface unknowns solve (G⁻¹ + Wx diag(d)) x₀ = Wx C ρ₀ (ρ₀: the eliminated
  /// right-hand side of row 0) by Eigen's CG (MINRES when the CG fails: indefinite), preconditioned by the
  /// cosine-diagonal G⁻¹ + d̄ Wx, d̄ = max(mean d, 0), to interface_tolerance(); the rows above follow by back
  /// substitution in cosine space. The transforms are FFTW's real-to-complex transforms of the rows' even
  /// extensions on buffers owned by the object. The spring's rank one by Sherman–Morrison with ψ = A₀⁻¹ b kept in
  /// cosine space (remade whenever c or d change: one more interface solve, no transform; bᵀx from the modes).
  /// One solve costs two transforms of every row plus nx-sized interface iterations (two one-row transforms each).
  /// rhs and x may alias. Throws std::runtime_error when the interface solve does not converge.
  void solve_system(double c, std::span<const double> d, std::span<const double> rhs, std::span<double> x);

  // --- The mixed representation of the adaptive integrator (docs/numerics.md §8.6) -------------------------
  // A field of all dofs whose row 0 (the interface) holds node values and every row j ≥ 1 its cosine modes
  // ẑ_j = C u_j / (2(nx−1)), so that u_j = C ẑ_j (C: the DCT-I of solve_system). M/c + c S is diagonal in these
  // modes along x, so the bulk's right-hand side and solves need no transform of the rows j ≥ 1; only the interface
  // row (where the law acts, site by site) is kept in node values, joined to row 1 by one-row transforms.
  /// u (all dofs, node values) → z (mixed); may alias.
  void to_mixed(std::span<const double> u, std::span<double> z) const;
  /// z (mixed) → u (node values); may alias.
  void from_mixed(std::span<const double> z, std::span<double> u) const;
  /// The node value at column i of a row given by its modes (O(nx); i = 0: the sum without cosines).
  double mode_row_value(const double* modes, std::size_t i) const;
  /// ū0 of a mixed field.
  double mixed_edge_slip(std::span<const double> z) const;
  /// F(t) = K (v_d t − ū0) + F_r for a given ū0.
  double drive_force_at(double t, double edge_slip) const { return spring_K_ * (v_d_ * t - edge_slip) + rear_traction_; }
  /// a = M⁻¹ (−S u + F b + top wx σ_d − E wx traction) for u mixed, a mixed (F: the drive force F(t);
  /// traction_i = σ̄_i + η v_i0 on the interface sites). Two one-row transforms; a and u must not alias.
  void mixed_accelerations(std::span<const double> u, double drive_force, const double* traction,
                           std::span<double> a) const;
  /// The adaptive integrator's stage solve in the mixed representation, fused (Strip::stage_solve): the
  /// rhs of rows j ≥ 1 formed here, ρ' wy(j) (xv_j + xu_j/c) (the modes of (M xv + M xu/c)/wx), row 0's given as
  /// r0 (node values, sites()); then x = A(c, d)⁻¹ r and xu ← x, xv ← (x − xu)/c (mixed, dofs() each).
  void solve_stage_mixed(double c, std::span<const double> d, const double* r0, double* xu, double* xv);
  /// The same with the stage's right-hand side of the rows j ≥ 1 given apart (the Rosenbrock stages' arithmetic fused
  /// into the sweeps): b_u = bu − sub_u, b_v = bv − sub_v + shift_v (sub_* may be null), and after the solve
  /// xu ← x + add_u, xv ← (x − b_u)/c + add_v on the rows j ≥ 1 (add_* may be null). Row 0 as above: xu, xv hold its
  /// b_u, b_v on entry and x, (x − b_u)/c on return (no add). xu, xv may alias bu, bv.
  struct StageInput {
    const double* bu;
    const double* bv;
    const double* sub_u = nullptr;
    const double* sub_v = nullptr;
    double shift_v = 0.0;
    const double* add_u = nullptr;
    const double* add_v = nullptr;
  };
  void solve_stage_mixed(double c, std::span<const double> d, const double* r0, const StageInput& in, double* xu,
                         double* xv);

  // --- The adaptive integrator's body (core::AdaptiveBody, core/body.hpp; docs/numerics.md §8.8) -----------------
  // The stage representation is the mixed one above; the stage solve is solve_stage_mixed with the interface row's
  // right-hand side formed from the sites' p_σ, d_i = η + q_σ,i (docs/numerics.md §8.5).
  std::size_t components() const { return 1; }
  static constexpr bool stage_is_nodes = false;
  const char* stage_archive_tag() const { return "adaptive_strip_mixed"; }
  void to_stage(std::span<const double> u, std::span<double> z) const { to_mixed(u, z); }
  void from_stage(std::span<const double> z, std::span<double> u) const { from_mixed(z, u); }
  double stage_value(const double* z, std::size_t i) const {
    const std::size_t j0 = (i / nx_) * nx_;
    return j0 == 0 ? z[i] : mode_row_value(z + j0, i - j0);
  }
  double stage_drive_force(double t, std::span<const double> u) const { return drive_force_at(t, mixed_edge_slip(u)); }
  /// mixed_accelerations with the traction σ̄_i + η v_i of the sites.
  void stage_accelerations(double t, std::span<const double> u, const double* v, const double* sigma_bar, double eta,
                           std::span<double> a);
  /// The interface iterations of the stage solves stop at a relative residual of 1e-4 rtol (docs/numerics.md §8.5).
  static constexpr double kStageSolveTolerance = 1e-4;
  void set_stage_tolerance(double rtol);
  template <class SiteQ>
  void stage_factor(double c, double eta, SiteQ&& q_sigma) {
    stage_.c = c;
    stage_.d.resize(nx_);
    for (std::size_t i = 0; i < nx_; ++i) stage_.d[i] = eta + q_sigma(i);
  }
  /// Row 0's right-hand side M b_v + (M/c) b_u + E wx (d b_u0 − c p_σ) from the sites, then solve_stage_mixed.
  template <class SiteP, class SiteBack>
  void stage_solve(const BulkStage& in, SiteP&& p_sigma, SiteBack&& back, double* xu, double* xv) {
    const std::size_t m = nx_;
    const double c = stage_.c, inv_c = 1.0 / c;
    stage_.r.resize(m);
    double* r = stage_.r.data();
    const double* d = stage_.d.data();
    for (std::size_t i = 0; i < m; ++i) {
      const double ps = p_sigma(i);
      r[i] = node_mass(i, 0) * (xv[i] + inv_c * xu[i]) + interface_weight(i) * (d[i] * xu[i] - c * ps);
    }
    solve_stage_mixed(c, stage_.d, r, stage_input(in), xu, xv);
    for (std::size_t i = 0; i < m; ++i) back(i, xv[i]);
  }
  /// The rows' end values of a u or v block (the field norm's scale, docs/numerics.md §8.6).
  double stage_scale(const double* y) const;
  /// Row 0 exactly; each row j ≥ 1 by |ê_0| + |ê_N| + 2 Σ_{0<k<N} |ê_k| ≥ its largest node error (§8.6).
  StageError stage_error(const double* y, const double* yn, const double* k1, const double* k2, const double* k3) const;

  /// Relative residual at which solve_system's interface iterations stop (default 1e-13: the solve then agrees
  /// with a sparse LDLT to ~1e-13). The adaptive integrator loosens it with its rtol (docs/numerics.md §8.5).
  /// Throws std::invalid_argument outside [1e-13, 1).
  void set_interface_tolerance(double tol);
  double interface_tolerance() const { return interface_tolerance_; }
  /// Interface iterations of the last solve_system (the ψ solve not counted).
  int last_interface_iterations() const { return last_interface_iterations_; }
  /// How solve_step solves the trapezoidal step: the preconditioned CG over all dofs (default) or
  /// solve_system (docs/performance.md §12).
  enum class StepSolver { cg, direct };
  void set_step_solver(StepSolver s) { step_solver_ = s; }
  StepSolver step_solver() const { return step_solver_; }

  void set_shift(Shift s) { shift_ = s; }
  Shift shift() const { return shift_; }
  /// Bytes of workspace the object holds (FFT buffer, mode factors, right-hand side), and the bytes Eigen's
  /// CG allocates per solve (four vectors, the product temporary, the guess copy).
  std::size_t workspace_bytes() const;
  std::size_t solver_temporary_bytes() const { return 6 * dofs() * sizeof(double); }

  // Internal to the CG (strip.cpp): y = A x of the step system, z = P⁻¹ r, both on the current step's
  // coefficients.
  void apply_system(const double* x, double* y) const;
  const double* apply_preconditioner(const double* r) const;

 private:
  void make_plans();
  void free_plans() noexcept;
  void factorise(double dt, double dbar) const;
  struct Direct;  // solve_system's workspace (strip.cpp), made on first use
  Direct& direct();
  void direct_factorise(double c);
  struct StageRhs;  // solve_stage_mixed's rows j ≥ 1 (strip.cpp)
  double direct_modes(std::span<const double> d, const double* rhs, double* z, const StageRhs* stage = nullptr);
  void prepare_psi(double c, std::span<const double> d);
  StageInput stage_input(const BulkStage& in) const;

  std::vector<double> x_;
  std::size_t nx_ = 0, ny_ = 0;
  double dx_ = 1.0, dy_ = 1.0, H_ = 1.0, rho_ = 1.0, mu_ = 1.0, rho_p_ = 1.0, mu_p_ = 1.0;
  double sigma_d_ = 0.0, spring_K_ = 0.0, v_d_ = 0.0, rear_traction_ = 0.0, stable_dt_ = 0.0;
  Shift shift_ = Shift::mean_c1;

  // Workspace (mutable: the solve is logically const on the body).
  double* buf_ = nullptr;        // fftw_malloc'd, dofs(): the transform buffer (the preconditioner's result)
  fftw_plan_s* plan_ = nullptr;  // REDFT00 of every row of buf_, in place
  mutable std::vector<double> inv_;   // Thomas factors of the modes: 1/pivot, [j·nx + k]
  mutable std::vector<double> rhs_;   // the step's right-hand side
  mutable std::vector<double> inv_wx_;  // 1/(wx(i) · 2(nx−1)): the row scaling and the DCT's normalisation
  mutable double fact_dt_ = -1.0, fact_dbar_ = -1.0;  // what inv_ was computed for
  // The current step's coefficients (apply_system).
  mutable const double* c1_ = nullptr;
  mutable double dt_ = 0.0, eta_ = 0.0;
  mutable int applications_ = 0;
  int last_iterations_ = 0;
  double last_residual_ = 0.0;
  StepSolver step_solver_ = StepSolver::cg;
  std::unique_ptr<Direct> direct_;
  int last_interface_iterations_ = 0;
  double interface_tolerance_ = 1e-13;
  struct AdaptiveStage {  // the adaptive stage solve's c, d and row 0's right-hand side, the sites' traction
    double c = 0.0;
    std::vector<double> d, r, traction;
  } stage_;
};

template <class F>
void Strip::elastic_forces(std::span<const double> u, F&& f) const {
  const std::size_t nx = nx_, ny = ny_;
  const double cx_in = mu_p_ * dy_ / dx_, cy_in = mu_p_ * dx_ / dy_;
  for (std::size_t j = 0; j <= ny; ++j) {
    const double* r = u.data() + j * nx;
    // A missing neighbour row is the row itself: its difference is exactly 0.
    const double* dn = j == 0 ? r : r - nx;
    const double* up = j == ny ? r : r + nx;
    const double cx = (j == 0 || j == ny) ? 0.5 * cx_in : cx_in;
    const double cy_end = 0.5 * cy_in;
    f(j, std::size_t{0}, cx * (r[1] - r[0]) + cy_end * ((dn[0] - r[0]) + (up[0] - r[0])));
    for (std::size_t i = 1; i + 1 < nx; ++i)
      f(j, i, cx * ((r[i - 1] - r[i]) + (r[i + 1] - r[i])) + cy_in * ((dn[i] - r[i]) + (up[i] - r[i])));
    const std::size_t e = nx - 1;
    f(j, e, cx * (r[e - 1] - r[e]) + cy_end * ((dn[e] - r[e]) + (up[e] - r[e])));
  }
}

static_assert(Body<Strip>);
static_assert(RunBody<Strip>);
static_assert(AdaptiveBody<Strip>);

}  // namespace slipfront::core
