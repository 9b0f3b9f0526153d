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
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/SparseCore>

#include "core/params.hpp"

namespace slipfront::core {

class Bulk {
 public:
  /// 1D (edge, homogeneous) or 0D spring block; throws for imposed_rate (no bulk there).
  Bulk(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx);

  std::size_t nodes() const { return x_.size(); }
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

  /// Largest stable step of the explicit scheme: 2/ω_max with the Gershgorin bound
  /// ω_max² = 4μ/(ρ dx²) + 2K/(ρ dx) + α/ρ   (1D; 0D: (K + α)/ρ).
  double stable_dt() const { return stable_dt_; }

 private:
  std::vector<double> x_;
  double dx_ = 1.0, rho_ = 1.0, k_ = 0.0, w_in_ = 1.0, w_end_ = 1.0;
  double sigma_d_ = 0.0, spring_K_ = 0.0, v_d_ = 0.0, rear_traction_ = 0.0, stable_dt_ = 0.0;
};

}  // namespace slipfront::core
