#pragma once
// The elastic bulk of MODEL §1 on a uniform vertex-centred grid (lumped mass, half cells at the
// ends), and the loadings. Per unit interface length, node i obeys
//   ρ a_i = (k (u_{i+1} − 2u_i + u_{i−1}) + F_i) / w_i + σ_d − σ̄_i − η v_i,     k = μ/dx,
// with w_i = dx inside, dx/2 at both ends (free end: the missing neighbour drops out), and the
// drive force F_0 = K (v_d t − u_0) on node 0 for edge loading. The 0D spring block is the same
// equation on one node with w = 1 and no elastic neighbour.
#include <cstddef>
#include <span>
#include <vector>

#include "continuum/params.hpp"

namespace slipfront::continuum {

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

  /// F(t) = K (v_d t − u_0): the drive force of edge loading and of the spring block (0 otherwise).
  double drive_force(double t, double u0) const { return spring_K_ * (v_d_ * t - u0); }

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
  double sigma_d_ = 0.0, spring_K_ = 0.0, v_d_ = 0.0, stable_dt_ = 0.0;
};

}  // namespace slipfront::continuum
