#include "core/bulk.hpp"

#include <cmath>
#include <stdexcept>

namespace slipfront::core {

BodyShape Bulk::shape(const BulkParams& bulk, const DriveParams& drive, const GridParams& grid) {
  if (!is_one_dimensional(drive.loading)) return {1, 1, 1};
  return {static_cast<std::size_t>(std::llround(bulk.length / grid.dx)) + 1, 1, 1};
}

double Bulk::stable_time_step(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law,
                              const GridParams& grid) {
  // ω_max² = 4μ/(ρ dx²) + 2K/(ρ dx) + α/ρ (1D edge: the drive spring on the half cell of node 0;
  // homogeneous: no spring), (K + α)/ρ for the 0D spring block: the one formula (the constructor, the estimate)
  const double rho = bulk.rho, dx = grid.dx;
  double omega2 = law.alpha / rho;
  switch (drive.loading) {
    case Loading::edge:
      omega2 += 4.0 * bulk.mu / (rho * dx * dx);
      omega2 += drive.K / (rho * (0.5 * dx));
      break;
    case Loading::homogeneous: omega2 += 4.0 * bulk.mu / (rho * dx * dx); break;
    case Loading::spring_block: omega2 += drive.K / rho; break;
    case Loading::imposed_rate: return 0.0;
  }
  return 2.0 / std::sqrt(omega2);
}

Bulk::Bulk(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx)
    : rho_(bulk.rho) {
  switch (drive.loading) {
    case Loading::edge:
    case Loading::homogeneous: {
      const auto cells = static_cast<std::size_t>(std::llround(bulk.length / dx));
      if (cells < 1) throw std::invalid_argument("Bulk: bulk.length must hold at least one cell");
      dx_ = dx;
      x_.resize(cells + 1);
      for (std::size_t i = 0; i <= cells; ++i) x_[i] = static_cast<double>(i) * dx;
      k_ = bulk.mu / dx;
      w_in_ = dx;
      w_end_ = 0.5 * dx;
      if (drive.loading == Loading::edge) {
        spring_K_ = drive.K;
        v_d_ = drive.v_d;
      } else {
        sigma_d_ = drive.sigma_d;
        rear_traction_ = drive.rear_traction;
      }
      break;
    }
    case Loading::spring_block:
      dx_ = 1.0;
      x_ = {0.0};
      spring_K_ = drive.K;
      v_d_ = drive.v_d;
      break;
    case Loading::imposed_rate:
      throw std::invalid_argument("Bulk: an imposed slip rate scene has no bulk");
  }
  stable_dt_ = stable_time_step(bulk, drive, law, GridParams{dx});
}

Eigen::SparseMatrix<double> Bulk::stiffness_matrix() const {
  const auto n = static_cast<Eigen::Index>(nodes());
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < n; ++i) {
    t.emplace_back(i, i, elastic_diagonal(static_cast<std::size_t>(i)) + (i == 0 ? spring_K_ : 0.0));
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -k_);
      t.emplace_back(i + 1, i, -k_);
    }
  }
  Eigen::SparseMatrix<double> s(n, n);
  s.setFromTriplets(t.begin(), t.end());
  return s;
}

}  // namespace slipfront::core
