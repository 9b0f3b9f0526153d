#pragma once
// The collocation defect of a solved steady front, for the front solvers' tests (test_strip_front, test_inplane_front):
// each interval's Hermite–Simpson (Lobatto IIIA) equation, docs/fronts.md eq. (5), evaluated with a right-hand side the
// test transcribes itself, so that a front that satisfies it satisfies the test's reading of its equations.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace slipfront::testing {

/// The largest defect y_{i+1} − y_i − h/6 (f_i + 4 f_m + f_{i+1}), y_m = (y_i + y_{i+1})/2 + h/8 (f_i − f_{i+1}), of each
/// of the ns components over the nodes xi, relative to the magnitude of what it balances (the largest over the
/// intervals of |Δy| + h/6 (s_i + 4 s_m + s_{i+1}), s the magnitude of f's terms); the largest over the components.
/// node(i): the state at node i; rhs(state, &s): f, with s filled (|f| where f is not a small sum of large terms).
template <class Node, class Rhs>
double scaled_collocation_defect(const std::vector<double>& xi, std::size_t ns, Node&& node, Rhs&& rhs) {
  std::vector<double> worst(ns, 0.0), scale(ns, 1e-300);
  for (std::size_t i = 0; i + 1 < xi.size(); ++i) {
    const double h = xi[i + 1] - xi[i];
    std::vector<double> sa, sb, sm;
    const std::vector<double> a = node(i), b = node(i + 1), fa = rhs(a, &sa), fb = rhs(b, &sb);
    std::vector<double> m(ns);
    for (std::size_t r = 0; r < ns; ++r) m[r] = (a[r] + b[r]) / 2 + h / 8 * (fa[r] - fb[r]);
    const std::vector<double> fm = rhs(m, &sm);
    for (std::size_t r = 0; r < ns; ++r) {
      const double defect = b[r] - a[r] - h / 6 * (fa[r] + 4 * fm[r] + fb[r]);
      worst[r] = std::max(worst[r], std::abs(defect));
      scale[r] = std::max(scale[r], std::abs(b[r] - a[r]) + h / 6 * (sa[r] + 4 * sm[r] + sb[r]));
    }
  }
  double out = 0.0;
  for (std::size_t r = 0; r < ns; ++r) out = std::max(out, worst[r] / scale[r]);
  return out;
}

}  // namespace slipfront::testing
