#include "continuum/friction_law.hpp"

#include <cmath>
#include <limits>

namespace slipfront::continuum {

// σ_ss(v) = σ_d on the strengthening branch: core/steady_sliding.hpp.
double strengthening_branch_velocity(const core::InterfaceParams& p, double sigma_d) {
  return core::overloaded_steady_velocity(p, sigma_d);
}

}  // namespace slipfront::continuum
