#pragma once
// The elastic bulk of docs/model.md §1 on a uniform vertex-centred grid (lumped mass, half cells at
// the ends), and the loadings: the one place where the elastic operator, its matrix and the drive are
// written (every stepper, the adaptive Jacobian and the energy budgets use them). Per unit interface
// length, node i obeys
//   ρ a_i = (k (u_{i+1} − 2u_i + u_{i−1}) + F_i) / w_i + σ_d − σ̄_i − η v_i,     k = μ/dx,
// with w_i = dx inside, dx/2 at both ends (free end: the missing neighbour drops out), and the
// drive force F_0 = K (v_d t − u_0) on node 0 for edge loading. The 0D spring block is the same
// equation on one node with w = 1 and no elastic neighbour.
//
// As a matrix: the force on the nodes is −S u + K v_d t e_0 with S symmetric tridiagonal,
// S_ii = k·(neighbours of i) + K δ_i0, S_{i,i±1} = −k (elastic_diagonal, spring_K, stiffness).
//
// The chain is one model of the Body concept (core/body.hpp): every node is an interface site.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "core/body.hpp"
#include "core/params.hpp"

namespace slipfront::core {

class Bulk {
 public:
  /// 1D (edge, homogeneous) or 0D spring block; throws for imposed_rate (no bulk there).
  Bulk(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx);
  Bulk(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, const GridParams& grid)
      : Bulk(bulk, drive, law, grid.dx) {}

  std::size_t nodes() const { return x_.size(); }
  std::size_t sites() const { return x_.size(); }  ///< Body: every node is an interface site
  std::size_t dofs() const { return x_.size(); }
  std::size_t rows() const { return 1; }                 ///< one row: the interface
  double height() const { return 0.0; }                  ///< the thin limit of docs/model.md §9
  double row_height(std::size_t) const { return 0.0; }   ///< y of a row
  double interface_weight(std::size_t i) const { return node_weight(i); }
  double edge_mass() const { return rho_ * node_weight(0); }  ///< the inertia the drive spring pulls
  double dx() const { return dx_; }
  const std::vector<double>& x() const { return x_; }
  double rho() const { return rho_; }
  double stiffness() const { return k_; }         ///< μ/dx (0 in 0D)
  double node_weight(std::size_t i) const { return (i == 0 || i + 1 == nodes()) ? w_end_ : w_in_; }
  double uniform_stress() const { return sigma_d_; }
  bool has_drive_spring() const { return spring_K_ > 0.0; }
  double spring_K() const { return spring_K_; }
  double driver_velocity() const { return v_d_; }

  /// F(t) = K (v_d t − u_0) + F_r: the force on node 0 — the drive spring of edge loading and of the
  /// spring block, and the rear traction F_r of a steady-front start (0 otherwise).
  double drive_force(double t, double u0) const { return spring_K_ * (v_d_ * t - u0) + rear_traction_; }
  double rear_traction() const { return rear_traction_; }
  double edge_slip(std::span<const double> u) const { return u[0]; }
  double drive_force(double t, std::span<const double> u) const { return drive_force(t, u[0]); }

  /// Calls f(i, F_i) for every node, F_i = the elastic force of its neighbours plus `edge` on node 0
  /// (the drive force; force units, as the implicit step assembles its rows).
  template <class F>
  void forces(std::span<const double> u, double edge, F&& f) const {
    const std::size_t n = u.size();
    if (n == 1) {
      f(std::size_t{0}, edge);
      return;
    }
    f(std::size_t{0}, k_ * (u[1] - u[0]) + edge);
    for (std::size_t i = 1; i + 1 < n; ++i) f(i, k_ * (u[i + 1] - 2.0 * u[i] + u[i - 1]));
    f(n - 1, k_ * (u[n - 2] - u[n - 1]));
  }
  /// Calls f(i, F_i / w_i) for every node: the same force per unit interface length, as it enters the
  /// equation of motion (the explicit kick and the adaptive right-hand side). Inside, (k/w) times the
  /// difference: one multiplication less per node.
  template <class F>
  void forces_per_length(std::span<const double> u, double edge, F&& f) const {
    const std::size_t n = u.size();
    if (n == 1) {
      f(std::size_t{0}, edge / w_end_);
      return;
    }
    const double inv_w_end = 1.0 / w_end_, kw = k_ / w_in_;
    f(std::size_t{0}, (k_ * (u[1] - u[0]) + edge) * inv_w_end);
    for (std::size_t i = 1; i + 1 < n; ++i) f(i, kw * (u[i + 1] - 2.0 * u[i] + u[i - 1]));
    f(n - 1, k_ * (u[n - 2] - u[n - 1]) * inv_w_end);
  }
  /// Elastic part of S_ii: k times the number of neighbours of node i (0 in 0D). S_00 adds spring_K().
  double elastic_diagonal(std::size_t i) const {
    const std::size_t n = nodes();
    return n == 1 ? 0.0 : k_ * ((i == 0 || i + 1 == n) ? 1.0 : 2.0);
  }
  /// S as a sparse matrix (tests check the steppers' own tridiagonal solves against Eigen's).
  Eigen::SparseMatrix<double> stiffness_matrix() const;

  /// Elastic energy Σ k (u_{i+1} − u_i)²/2 of a slip field (energy budgets of every stepper).
  double elastic_energy(std::span<const double> u) const {
    double e = 0.0;
    for (std::size_t i = 0; i + 1 < u.size(); ++i) e += 0.5 * k_ * (u[i + 1] - u[i]) * (u[i + 1] - u[i]);
    return e;
  }
  /// Energy K (v_d t − u_0)²/2 stored in the drive spring (0 without one).
  double spring_energy(double t, double u0) const {
    const double stretch = v_d_ * t - u0;
    return spring_K_ > 0.0 ? 0.5 * spring_K_ * stretch * stretch : 0.0;
  }
  double spring_energy(double t, std::span<const double> u) const { return spring_energy(t, u[0]); }
  /// Kinetic energy Σ ρ w_i V_i²/2 of node velocities V.
  double kinetic_energy(std::span<const double> V) const {
    double e = 0.0;
    for (std::size_t i = 0; i < V.size(); ++i) e += 0.5 * rho_ * node_weight(i) * V[i] * V[i];
    return e;
  }
  /// Power Σ w_i σ_d v_i of the uniform stress (homogeneous loading; 0 otherwise).
  double uniform_power(std::span<const double> v) const {
    double p = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) p += node_weight(i) * sigma_d_ * v[i];
    return p;
  }

  /// The explicit scheme's kick (core/stepper.hpp), node by node:
  ///   v^{n+1/2} (ρ + η Δt/2) = v^{n−1/2} (ρ − η Δt/2) + Δt (F_i / w_i + σ_d − σ̄_i)
  /// with `edge` the drive force F at t^n.
  void kick(double dt, double eta, double edge, std::span<const double> u, std::span<const double> sigma_bar,
            std::span<const double> v_old, std::span<double> v_new) const {
    const double damp = rho_ - 0.5 * eta * dt, inv = 1.0 / (rho_ + 0.5 * eta * dt), sd = sigma_d_;
    const double* sb = sigma_bar.data();
    const double* vo = v_old.data();
    double* vn = v_new.data();
    forces_per_length(u, edge, [&](std::size_t i, double f) { vn[i] = (vo[i] * damp + dt * (f + sd - sb[i])) * inv; });
  }

  /// The implicit step's system for the slip rates W frozen over [t, t + Δt] (core/implicit.hpp), multiplied
  /// through by the node weights: symmetric tridiagonal,
  ///   [w_i (2ρ/Δt + η + c1_i/2) + Δt S_ii/2] W_i − (Δt k/2)(W_{i−1} + W_{i+1})
  ///       = w_i (2ρ V_i/Δt + σ_d − (σ̄_i + c0_i)/2) + F_i(u)        (F with the drive at t + Δt/2),
  /// each site's linearisation lin(i, w_prev_i, c0_i, c1_i) computed inside the elimination loop (Thomas),
  /// then back substitution into W. The forces go into the work array first: as a callback of forces()
  /// the elimination was not inlined (a call per node, 15% of the fig1 run at dt = 0.02); with the
  /// linearisation in a pass of its own, its cost added to the latency of the elimination's chain of
  /// divisions instead of hiding behind it (15% again).
  template <class Lin>
  void implicit_solve(const Lin& lin, std::span<const double> w_prev, std::span<double> c0, std::span<double> c1,
                      double t, double dt, double eta, std::span<const double> u, std::span<const double> V,
                      std::span<const double> sigma_bar, std::span<double> W) {
    const std::size_t n = nodes();
    rhs_.resize(n);
    cp_.resize(n);
    const double m = 2.0 * rho_ / dt + eta, off = -0.5 * dt * k_, mass = 2.0 * rho_ / dt, sd = sigma_d_;
    const double drive = spring_K_ * (v_d_ * (t + 0.5 * dt) - u[0]) + rear_traction_;  // F at t + Δt/2
    const double half_dt = 0.5 * dt, spring = half_dt * spring_K_;
    double* r = rhs_.data();
    forces(u, drive, [r](std::size_t i, double force) { r[i] = force; });
    double* cp = cp_.data();
    const double* sb = sigma_bar.data();
    for (std::size_t i = 0; i < n; ++i) {
      lin(i, w_prev[i], c0[i], c1[i]);
      const double w = node_weight(i);
      const double diag = w * (m + 0.5 * c1[i]) + (half_dt * elastic_diagonal(i) + (i == 0 ? spring : 0.0));
      const double rhs = w * (mass * V[i] + sd - 0.5 * (sb[i] + c0[i])) + r[i];
      const double inv = 1.0 / (i == 0 ? diag : diag - off * cp[i - 1]);
      cp[i] = off * inv;
      r[i] = (i == 0 ? rhs : rhs - off * r[i - 1]) * inv;
    }
    W[n - 1] = r[n - 1];
    for (std::size_t i = n - 1; i-- > 0;) W[i] = r[i] - cp[i] * W[i + 1];
  }

  /// Largest stable step of the explicit scheme: 2/ω_max with the Gershgorin bound
  /// ω_max² = 4μ/(ρ dx²) + 2K/(ρ dx) + α/ρ   (1D; 0D: (K + α)/ρ).
  double stable_dt() const { return stable_dt_; }

  // --- core::RunBody (core/body.hpp): what the run layer asks of a body ------------------------------
  /// round(L/dx) + 1 sites in one row (1D), one site (the 0D spring block); one component.
  static BodyShape shape(const BulkParams& bulk, const DriveParams& drive, const GridParams& grid);
  /// stable_dt() of the chain these parameters build (0 for an imposed rate: no body).
  static double stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                                 const GridParams& grid);
  BodyShape shape() const { return {nodes(), 1, 1}; }
  std::size_t dof(std::size_t i, std::size_t, std::size_t) const { return i; }
  /// The chain is its interface: the site's own state.
  template <class Set>
  void lift(std::size_t i, double u, double v, double, Set&& set) const {
    set(i, u, v);
  }
  template <class Value>
  double edge_slip_of(Value&& value) const {
    return value(std::size_t{0});
  }
  double drive_force_at(double t, double edge_slip) const { return drive_force(t, edge_slip); }
  /// None: the chain's fields are the interface's (the snapshots).
  static std::span<const SnapshotField> snapshot_fields() { return {}; }
  void snapshot_values(std::span<const double>, std::size_t, std::size_t, std::span<double>) const {}
  // --- The adaptive integrator's body (core::AdaptiveBody, core/body.hpp; docs/numerics.md §8.8) -----------------
  // The stage representation is the node values; the u system of the W solve is symmetric tridiagonal (Thomas):
  //   (ρ w_i D_i / c²) x_u,i + (S x_u)_i = w_i ((ρ/c) b_v,i − p_σ,i) + (ρ w_i D_i / c²) b_u,i,
  //   D_i = 1 + cη/ρ + (c/ρ) q_σ,i,   S the stiffness (elastic_diagonal, stiffness, spring_K),
  // then x_v = (x_u − b_u)/c. Every node is a site: there is nothing beyond the sites (BulkStage is not read).
  std::size_t components() const { return 1; }
  static constexpr bool stage_is_nodes = true;
  const char* stage_archive_tag() const { return "adaptive"; }
  void to_stage(std::span<const double> u, std::span<double> z) const {
    if (z.data() != u.data()) std::copy_n(u.data(), u.size(), z.data());
  }
  void from_stage(std::span<const double> z, std::span<double> u) const { to_stage(z, u); }
  double stage_value(const double* z, std::size_t i) const { return z[i]; }
  double stage_drive_force(double t, std::span<const double> u) const { return drive_force(t, u[0]); }
  /// v'_i = (F_i/w_i + σ_d − σ̄_i − η v_i)/ρ.
  void stage_accelerations(double t, std::span<const double> u, const double* v, const double* sigma_bar, double eta,
                           std::span<double> a) {
    const double inv_rho = 1.0 / rho_, sd = sigma_d_;
    double* fv = a.data();
    forces_per_length(u, drive_force(t, u[0]),
                      [&](std::size_t i, double force) { fv[i] = (force + sd - sigma_bar[i] - eta * v[i]) * inv_rho; });
  }
  void set_stage_tolerance(double) {}  ///< the Thomas solve is exact
  /// The Thomas factors of the u system, site i's q_σ from the callback inside the elimination.
  template <class SiteQ>
  void stage_factor(double c, double eta, SiteQ&& q_sigma) {
    const std::size_t n = nodes();
    stage_d_.resize(n);
    stage_tc_.resize(n);
    stage_tinv_.resize(n);
    stage_tmp_.resize(n);
    stage_c_ = c;
    const double rho = rho_, K = spring_K_;
    const double base = 1.0 + c * eta / rho, c_rho = c / rho, rho_c2 = rho / (c * c);
    const double off = -k_;
    for (std::size_t i = 0; i < n; ++i) {
      const double qs = q_sigma(i);
      const double w = node_weight(i);
      const double dc = rho_c2 * w * (base + c_rho * qs);
      stage_d_[i] = dc;
      const double diag = dc + elastic_diagonal(i) + (i == 0 ? K : 0.0);
      const double m = i == 0 ? diag : diag - off * stage_tc_[i - 1];
      stage_tinv_[i] = 1.0 / m;
      stage_tc_[i] = off / m;
    }
  }
  /// The W solve: the forward sweep takes each site's p_σ as it goes, the back substitution hands back x_v,i.
  template <class SiteP, class SiteBack>
  void stage_solve(const BulkStage&, SiteP&& p_sigma, SiteBack&& back, double* xu, double* xv) {
    const std::size_t n = nodes();
    const double c = stage_c_, rho_c = rho_ / c, inv_c = 1.0 / c, off = -k_;
    const double* dcoef = stage_d_.data();
    const double* tinv = stage_tinv_.data();
    const double* tc = stage_tc_.data();
    double* d = stage_tmp_.data();
    double prev = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double ps = p_sigma(i);
      const double r = node_weight(i) * (rho_c * xv[i] - ps) + dcoef[i] * xu[i];
      prev = (r - off * prev) * tinv[i];  // forward sweep
      d[i] = prev;
    }
    double next = 0.0;
    for (std::size_t i = n; i-- > 0;) {
      const double ui = d[i] - tc[i] * next;
      next = ui;
      const double vi = (ui - xu[i]) * inv_c;
      xu[i] = ui;
      xv[i] = vi;
      back(i, vi);
    }
  }
  double stage_scale(const double*) const { return 0.0; }  ///< the sites are the whole block
  StageError stage_error(const double* y, const double* yn, const double* k1, const double* k2,
                         const double* k3) const {
    StageError r;
    for (std::size_t j = 0; j < nodes(); ++j) {
      r.scale = std::max(r.scale, std::max(std::abs(y[j]), std::abs(yn[j])));
      const double e = std::abs(k1[j] - 2.0 * k2[j] + k3[j]);
      r.emax = std::max(r.emax, e);
      r.probe += e + yn[j];
    }
    return r;
  }

 private:
  std::vector<double> x_;
  double dx_ = 1.0, rho_ = 1.0, k_ = 0.0, w_in_ = 1.0, w_end_ = 1.0;
  double sigma_d_ = 0.0, spring_K_ = 0.0, v_d_ = 0.0, rear_traction_ = 0.0, stable_dt_ = 0.0;
  std::vector<double> rhs_, cp_;  ///< implicit_solve's work arrays
  double stage_c_ = 0.0;  ///< the adaptive stage solve's c, its coefficients, Thomas factors and sweep
  std::vector<double> stage_d_, stage_tc_, stage_tinv_, stage_tmp_;
};

static_assert(Body<Bulk>);
static_assert(RunBody<Bulk>);
static_assert(AdaptiveBody<Bulk>);

}  // namespace slipfront::core
