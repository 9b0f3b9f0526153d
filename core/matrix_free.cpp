#include "core/matrix_free.hpp"

namespace slipfront::core {

std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace slipfront::core
