#include "continuum/front_solver.hpp"

#include <Eigen/SparseLU>
#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>

namespace slipfront::continuum::front_solver {

std::vector<double> make_mesh(double L, int N, double h_tip, double grading) {
  std::vector<double> xi(static_cast<std::size_t>(N) + 1);
  double beta = grading;
  if (beta <= 0.0 && L / N > h_tip) {
    auto first = [&](double bt) { return std::log(L * std::expm1(bt / N) / std::expm1(bt)) - std::log(h_tip); };
    double hi = 1.0;
    while (first(hi) > 0.0) hi *= 2.0;
    std::uintmax_t iters = 200;
    const auto br = boost::math::tools::toms748_solve(first, 1e-9, hi, boost::math::tools::eps_tolerance<double>(50), iters);
    beta = 0.5 * (br.first + br.second);
  }
  for (int j = 0; j <= N; ++j) {
    const double s = static_cast<double>(j) / N;
    const double dist = beta > 0.0 ? L * std::expm1(beta * s) / std::expm1(beta) : L * s;
    xi[static_cast<std::size_t>(N - j)] = -dist;
  }
  xi[0] = -L;
  xi[static_cast<std::size_t>(N)] = 0.0;
  return xi;
}

namespace {

// max_k |dx_k| / max(1, |x_k|): the update relative to the unknowns (absolute for small ones).
double scaled_norm(const Eigen::VectorXd& dx, const Eigen::VectorXd& x) {
  double scaled = 0.0;
  for (Eigen::Index k = 0; k < x.size(); ++k) scaled = std::max(scaled, std::abs(dx[k]) / std::max(1.0, std::abs(x[k])));
  return scaled;
}

// Backtracking along dx from x: λ = 1, ½, … (30 halvings) until ‖F(x + λ dx)‖₂ decreases enough (Armijo with
// 1e-4) or is below 1e-13. Returns λ (0: no descent) and the accepted point in xt.
double line_search(const Assemble& assemble, const Eigen::VectorXd& x, const Eigen::VectorXd& dx, double f0,
                   Eigen::VectorXd& xt) {
  Eigen::VectorXd Ft;
  double lambda = 1.0;
  for (int damp = 0; damp < 30; ++damp, lambda *= 0.5) {
    xt = x + lambda * dx;
    if (assemble(xt, Ft, nullptr) && (Ft.norm() <= (1.0 - 1e-4 * lambda) * f0 || Ft.norm() < 1e-13)) return lambda;
  }
  return 0.0;
}

}  // namespace

NewtonResult newton(const Assemble& assemble, Eigen::VectorXd& x, const NewtonRule& rule) {
  NewtonResult out;
  Eigen::VectorXd F;
  Eigen::SparseMatrix<double> J;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  if (!assemble(x, F, &J)) {
    out.failure = rule.inadmissible_guess;
    return out;
  }
  const bool take_small = rule.floor_tolerance > 0.0;  // the strip's rule
  double previous_scaled = std::numeric_limits<double>::infinity();
  // The full step, taken without the line search: converged unless x + dx is not admissible.
  auto take_full_step = [&](const Eigen::VectorXd& dx) {
    x += dx;
    if (!assemble(x, F, nullptr)) return false;
    out.converged = true;
    out.residual = F.lpNorm<Eigen::Infinity>();
    return true;
  };
  for (int it = 1; it <= rule.max_iterations; ++it) {
    out.iterations = it;
    if (rule.stop && *rule.stop && (*rule.stop)()) {
      out.failure = "stopped on request (Newton iteration " + std::to_string(it) + ")";
      out.stopped = true;
      return out;
    }
    if (it == 1) lu.analyzePattern(J);
    lu.factorize(J);
    if (lu.info() != Eigen::Success) {
      out.failure = "singular Jacobian (SparseLU: " + lu.lastErrorMessage() + ")";
      return out;
    }
    const Eigen::VectorXd dx = lu.solve(-F);
    const double scaled = scaled_norm(dx, x);
    const double f0 = F.norm();
    if (take_small) {
      // The full step is below the tolerance, or below floor_tolerance and no longer shrinking (quadratic
      // convergence lost: the round-off floor of an ill-conditioned Jacobian, thick strips, docs/fronts.md
      // §10.11): take it and stop (at the round-off floor the residual need not decrease any more).
      const bool at_floor = scaled < rule.floor_tolerance && scaled > 0.25 * previous_scaled;
      previous_scaled = scaled;
      if (scaled < rule.tolerance || at_floor) {
        if (take_full_step(dx)) return out;
        break;
      }
    }
    Eigen::VectorXd xt;
    const double lambda = line_search(assemble, x, dx, f0, xt);
    if (lambda == 0.0 && scaled < rule.floor_tolerance) {  // at the round-off floor: no descent is possible any more
      if (take_full_step(dx)) return out;
      break;
    }
    if (lambda == 0.0) {
      out.failure = "no descent along the Newton direction (no solution near the guess)";
      return out;
    }
    x = xt;
    assemble(x, F, &J);
    if (!take_small && lambda == 1.0 && scaled < rule.tolerance) {  // the chain's rule
      out.converged = true;
      out.residual = F.lpNorm<Eigen::Infinity>();
      return out;
    }
  }
  out.residual = F.lpNorm<Eigen::Infinity>();
  out.failure = "no convergence in " + std::to_string(rule.max_iterations) + " Newton iterations";
  return out;
}

BranchEnd end_of(FrontStatus s) {
  switch (s) {
    case FrontStatus::resticks: return BranchEnd::resticking;
    case FrontStatus::reverse_slip: return BranchEnd::reverse_slip;
    case FrontStatus::sonic: return BranchEnd::sonic;
    case FrontStatus::no_front_state:
    case FrontStatus::not_a_saddle: return BranchEnd::saddle_node;
    case FrontStatus::stopped: return BranchEnd::stopped;
    case FrontStatus::converged:
    case FrontStatus::newton_failed: return BranchEnd::newton_failure;
  }
  return BranchEnd::newton_failure;
}

Secant secant(double sigma_prev, double c_prev, double sigma_cur, double c_cur, double cs, double& t_sigma_before,
              std::vector<double>& folds) {
  const double d_sigma = sigma_cur - sigma_prev, d_c = (c_cur - c_prev) / cs;
  const double norm = std::hypot(d_sigma, d_c);
  const double t_sigma = d_sigma / norm, t_c = d_c / norm;
  if (t_sigma * t_sigma_before < 0.0) folds.push_back(sigma_cur);
  t_sigma_before = t_sigma;
  return {t_sigma, t_c};
}

double capped_step(double step, double max_step, const Secant& t, double sigma_cur, double sigma_c) {
  step = std::min(step, max_step);
  if (t.t_sigma < 0.0) step = std::min(step, 0.75 * (sigma_cur - sigma_c) / -t.t_sigma);
  return step;
}

double controlled_step(double step, int newton_iterations, int target) {
  if (newton_iterations < target) return step * 1.5;
  if (newton_iterations > target) return step * 0.6;
  return step;
}

SlowestPoint slowest_point(const std::vector<BranchPoint>& points) {
  std::size_t k = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].c < points[k].c) k = i;
  return {k, k + 1 == points.size()};
}

double overstress_margin(const std::vector<double>& sigma_bar, const std::vector<double>& slip_rate,
                         const std::vector<double>& area, double eta) {
  const std::size_t n = sigma_bar.size();
  std::vector<double> g(n);
  for (std::size_t i = 0; i < n; ++i) g[i] = std::abs(sigma_bar[i] + eta * slip_rate[i]) / area[i] - 1.0;
  double margin = g.front();
  for (std::size_t i = 1; i + 2 < n; ++i)
    if (g[i] <= g[i - 1] && g[i] <= g[i + 1]) margin = std::min(margin, g[i]);
  return margin;
}

}  // namespace slipfront::continuum::front_solver
