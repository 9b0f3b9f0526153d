#include "continuum/friction_law.hpp"

#include <cmath>
#include <limits>

namespace slipfront::continuum {

// σ_ss(v) = α/(1+κv) + ηv = σ_d  ⇔  ηκ v² + (η − σ_d κ) v + (α − σ_d) = 0; the larger root is
// on the strengthening branch (v > v_m).
double strengthening_branch_velocity(const core::InterfaceParams& p, double sigma_d) {
  const double a = p.eta * p.kappa, b = p.eta - sigma_d * p.kappa, c = p.alpha - sigma_d;
  if (a == 0.0) return b != 0.0 && -c / b > 0.0 ? -c / b : std::numeric_limits<double>::quiet_NaN();
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (-b + std::sqrt(disc)) / (2.0 * a);
}

}  // namespace slipfront::continuum
