#include "compare/imposed_rate.hpp"

namespace slipfront::compare {

std::vector<double> sweep_rates(const core::DriveParams& d) {
  std::vector<double> v(static_cast<std::size_t>(d.sweep_points));
  const double a = std::log(d.v_min), b = std::log(d.v_max);
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = std::exp(a + (b - a) * static_cast<double>(k) / static_cast<double>(v.size() - 1));
  return v;
}

}  // namespace slipfront::compare
