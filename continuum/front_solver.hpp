#pragma once
// What the steady-front solvers share (docs/fronts.md §3, §4, §10.3, §10.8): the ξ mesh, the damped Newton
// iteration with Eigen's SparseLU, and the bookkeeping of a continuation in σ_d. The chain
// (continuum/steady_front.cpp) and the strip (continuum/strip_front.cpp) differ in the unknowns of one ξ node
// and their boundary rows, not in these. Internal to continuum/; plain functions, no I/O.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "continuum/steady_front.hpp"

namespace slipfront::continuum::front_solver {

/// Nodes ξ_0 = −L < … < ξ_N = 0 with ξ_N − ξ_{N−1} = h_tip, growing geometrically behind: measured from the
/// tip, ξ_j = −L (e^{β j/N} − 1)/(e^β − 1); β from the first spacing (TOMS 748), or `grading` if > 0
/// (docs/fronts.md §3).
std::vector<double> make_mesh(double L, int N, double h_tip, double grading = 0.0);

/// The pseudo-arclength condition t_σ (σ_d − σ_0) + t_c (c − c_0)/c_scale = step (docs/fronts.md §4).
struct Arclength {
  double sigma0, c0, t_sigma, t_c, step, c_scale;
};

// ---------------------------------------------------------------------------------------------------
// Damped Newton (backtracking on ‖F‖₂) with Eigen's SparseLU (COLAMD ordering, pattern analysed once).

/// F(x) and, when the matrix is given, its Jacobian; false: x is not admissible (F not finite, c out of range).
using Assemble = std::function<bool(const Eigen::VectorXd& x, Eigen::VectorXd& F, Eigen::SparseMatrix<double>* jac)>;

/// How the iteration stops. The chain's rule (floor_tolerance = 0): converged when a full step, accepted by
/// the line search, is below `tolerance`. The strip's rule (floor_tolerance > 0, docs/fronts.md §10.11): a step
/// below `tolerance`, or below floor_tolerance and no longer shrinking (the round-off floor of an
/// ill-conditioned Jacobian), is taken without the line search and ends the iteration.
struct NewtonRule {
  double tolerance = 1e-11;
  int max_iterations = 40;
  double floor_tolerance = 0.0;
  std::string inadmissible_guess;      ///< the failure when the initial x is not admissible
  const std::function<bool()>* stop = nullptr;  ///< polled before every iteration (true: `stopped`)
};

struct NewtonResult {
  bool converged = false;
  bool stopped = false;
  int iterations = 0;
  double residual = std::numeric_limits<double>::quiet_NaN();  ///< max-norm of F at the returned x
  std::string failure;
};

NewtonResult newton(const Assemble& assemble, Eigen::VectorXd& x, const NewtonRule& rule);

// ---------------------------------------------------------------------------------------------------
// The continuation in σ_d (docs/fronts.md §4 steps 3–7, §10.8).

/// A front's point of its branch (SteadyFront and StripFront carry the same diagnostics).
template <class Front>
BranchPoint branch_point(const Front& f) {
  return {f.sigma_d, f.c, f.v_tip, f.v_behind, f.area_behind, f.overstress_margin, f.min_slip_rate,
          f.stable_eigenvalue, f.domain_length, f.residual_norm, f.speed_error, f.newton_iterations};
}

/// The end of a branch whose last solve ended with status `s`.
BranchEnd end_of(FrontStatus s);

/// The unit secant in (σ_d, c/c_s) of the last two fronts, the predictor direction.
struct Secant {
  double t_sigma, t_c;
};
/// The secant from (σ_prev, c_prev) to (σ_cur, c_cur); a sign change of its σ_d component against
/// `t_sigma_before` (updated) is a fold at σ_cur, appended to `folds` (§4 step 6).
Secant secant(double sigma_prev, double c_prev, double sigma_cur, double c_cur, double cs, double& t_sigma_before,
              std::vector<double>& folds);

/// The step before a predictor: capped at max_step and, approaching σ_c^d, so that the predictor keeps a quarter
/// of the remaining gap σ_cur − σ_c^d (§4 step 7).
double capped_step(double step, double max_step, const Secant& t, double sigma_cur, double sigma_c);

/// Step control (§4 step 4): grow by 1.5 when the corrector took fewer than `target` iterations, shrink by 0.6
/// when it took more.
double controlled_step(double step, int newton_iterations, int target);

/// The smallest c of a branch's points (not empty): its index, and whether it is the last point.
struct SlowestPoint {
  std::size_t index;
  bool at_end;
};
SlowestPoint slowest_point(const std::vector<BranchPoint>& points);

/// min over the interior minima and the far end (index 0) of |σ̄ + η v|/A − 1 behind the tip: Θ = 1 needs it > 0
/// (docs/fronts.md §4).
double overstress_margin(const std::vector<double>& sigma_bar, const std::vector<double>& slip_rate,
                         const std::vector<double>& area, double eta);

}  // namespace slipfront::continuum::front_solver
