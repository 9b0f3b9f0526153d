#include "core/bulk.hpp"

#include <cmath>
#include <stdexcept>

namespace slipfront::core {

Bulk::Bulk(const BulkParams& bulk, const DriveParams& drive, const InterfaceParams& law, double dx)
    : rho_(bulk.rho) {
  double omega2 = law.alpha / bulk.rho;
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
      omega2 += 4.0 * bulk.mu / (bulk.rho * dx * dx);
      if (drive.loading == Loading::edge) {
        spring_K_ = drive.K;
        v_d_ = drive.v_d;
        omega2 += spring_K_ / (bulk.rho * w_end_);
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
      omega2 += spring_K_ / bulk.rho;
      break;
    case Loading::imposed_rate:
      throw std::invalid_argument("Bulk: an imposed slip rate scene has no bulk");
  }
  stable_dt_ = 2.0 / std::sqrt(omega2);
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
