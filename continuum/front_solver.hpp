#pragma once
// What the steady-front solvers share (docs/fronts.md §3, §4, §10.3, §10.8): the ξ mesh, the collocation over a
// front model's node block (Collocation<Block>) and its error estimate, the damped Newton iteration with Eigen's
// SparseLU, and the bookkeeping of a continuation in σ_d (its stages: continuum/sigma_continuation.hpp). The chain
// (continuum/steady_front.cpp) and the strip (continuum/strip_front.cpp) differ in the unknowns of one ξ node
// and their boundary rows, not in these. Internal to continuum/; no I/O.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
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
// The discrete boundary-value problem on the ξ mesh (docs/fronts.md §3, §10.3): unknowns [y_0 … y_N, c (, σ_d)]
// with y_i the block of one node, rows
//   behind:  the far-field rows at ξ_0 = −L                     (the front model's)
//   N · ns:  Lobatto IIIA (Hermite–Simpson) on every interval   (here, from the model's right-hand side)
//   tip:     the rows at ξ_N = 0                                (the front model's)
//   (1:      pseudo-arclength)
// The behind and tip rows together number ns + 1 (the unknowns c and one boundary value problem of order ns).

/// Where one assembly writes: the residual F and, when the Jacobian is asked for, its triplets.
struct Rows {
  Eigen::VectorXd& F;
  std::vector<Eigen::Triplet<double>>* triplets;  ///< null: the residual only
  bool keep_zero_columns;  ///< column(): store exact zeros too (the chain's c and σ_d columns always did)
  bool jacobian() const { return triplets != nullptr; }
  void entry(int row, int col, double value) { triplets->emplace_back(row, col, value); }
  /// The nonzeros of a dense block at (row, col).
  template <class M>
  void block(int row, int col, const M& B) {
    for (int r = 0; r < B.rows(); ++r)
      for (int k = 0; k < B.cols(); ++k)
        if (B(r, k) != 0.0) triplets->emplace_back(row + r, col + k, B(r, k));
  }
  /// A column segment at (row, col): the nonzeros, or every entry with keep_zero_columns.
  template <class V>
  void column(int row, int col, const V& v) {
    for (int r = 0; r < v.size(); ++r)
      if (keep_zero_columns || v[r] != 0.0) triplets->emplace_back(row + r, col, v[r]);
  }
};

/// The columns of the scalar unknowns: c, and σ_d (< 0 when σ_d is fixed).
struct ScalarColumns {
  int c, sigma;
  bool free_sigma() const { return sigma >= 0; }
};

/// The collocation of one front model. `Block` is the model's node block (docs/fronts.md §10.2 for the strip's):
///   types Vec, Mat (the node state and its Jacobian), Rhs {f, fc, fs, J} (f, ∂f/∂y, ∂f/∂c, ∂f/∂σ_d);
///   static constexpr bool keep_zero_columns (how it stores its c and σ_d columns);
///   int width() (ns), int behind_count() (rows at ξ_0), bool admissible(c) (c in (0, c_s), far fields found);
///   Rhs rhs(y, c, σ_d, with_jacobian): the first-order system y' = f behind the tip;
///   bool behind_rows(y_0, c, σ_d, Rows&, ScalarColumns): rows 0 … behind_count − 1;
///   bool tip_rows(y_N, row, column of y_N, c, σ_d, Rows&, ScalarColumns): the next ns + 1 − behind_count rows.
template <class Block>
class Collocation {
 public:
  using Vec = typename Block::Vec;
  using Mat = typename Block::Mat;
  using Rhs = typename Block::Rhs;

  Collocation(Block block, std::vector<double> xi, double sigma_d, std::optional<Arclength> arc)
      : block_(std::move(block)), xi_(std::move(xi)), sigma_fixed_(sigma_d), arc_(arc) {}

  const Block& block() const { return block_; }
  int nodes() const { return static_cast<int>(xi_.size()); }
  int size() const { return block_.width() * nodes() + 1 + (arc_ ? 1 : 0); }
  int c_index() const { return block_.width() * nodes(); }
  double c_of(const Eigen::VectorXd& x) const { return x[c_index()]; }
  double sigma_of(const Eigen::VectorXd& x) const { return arc_ ? x[c_index() + 1] : sigma_fixed_; }
  Vec y(const Eigen::VectorXd& x, int i) const { return x.segment(block_.width() * i, block_.width()); }
  const std::vector<double>& xi() const { return xi_; }

  /// Residual F(x); with jac, also its Jacobian. False: x is not admissible (or F is not finite).
  bool assemble(const Eigen::VectorXd& x, Eigen::VectorXd& F, Eigen::SparseMatrix<double>* jac) const {
    const int N = nodes() - 1, n = size(), ns = block_.width();
    const double c = c_of(x), sd = sigma_of(x);
    if (!block_.admissible(c)) return false;
    F.setZero(n);
    std::vector<Eigen::Triplet<double>> t;
    if (jac) t.reserve(static_cast<std::size_t>(N) * 2 * static_cast<std::size_t>(ns * ns) + 64);
    Rows rows{F, jac ? &t : nullptr, Block::keep_zero_columns};
    const ScalarColumns cols{c_index(), arc_ ? c_index() + 1 : -1};
    if (!block_.behind_rows(y(x, 0), c, sd, rows, cols)) return false;       // ξ_0 = −L
    interval_rows(x, c, sd, rows, cols);                                        // Lobatto IIIA
    if (!block_.tip_rows(y(x, N), block_.behind_count() + ns * N, ns * N, c, sd, rows, cols)) return false;  // ξ_N = 0
    arclength_row(c, sd, rows, cols);
    if (jac) {
      jac->resize(n, n);
      jac->setFromTriplets(t.begin(), t.end());
    }
    return F.allFinite();
  }

 private:
  // Rows behind_count + ns i … : y_{i+1} − y_i − h/6 (f_i + 4 f_m + f_{i+1}), y_m = (y_i + y_{i+1})/2 + h/8 (f_i − f_{i+1})
  // (docs/fronts.md eq. 5), with their blocks in y_i, y_{i+1} and columns in c and σ_d.
  void interval_rows(const Eigen::VectorXd& x, double c, double sd, Rows& rows, const ScalarColumns& cols) const {
    const int N = nodes() - 1, ns = block_.width();
    const Mat I = Mat::Identity(ns, ns);
    Rhs right = block_.rhs(y(x, 0), c, sd, rows.jacobian());
    for (int i = 0; i < N; ++i) {
      const Rhs left = std::move(right);
      right = block_.rhs(y(x, i + 1), c, sd, rows.jacobian());
      const double h = xi_[static_cast<std::size_t>(i) + 1] - xi_[static_cast<std::size_t>(i)];
      const Vec ym = 0.5 * (y(x, i) + y(x, i + 1)) + h / 8.0 * (left.f - right.f);
      const Rhs mid = block_.rhs(ym, c, sd, rows.jacobian());
      const int row = block_.behind_count() + ns * i;
      rows.F.segment(row, ns) = y(x, i + 1) - y(x, i) - h / 6.0 * (left.f + 4.0 * mid.f + right.f);
      if (!rows.jacobian()) continue;
      const Mat Bi = -I - h / 6.0 * (left.J + 4.0 * mid.J * (0.5 * I + h / 8.0 * left.J));
      const Mat Bn = I - h / 6.0 * (right.J + 4.0 * mid.J * (0.5 * I - h / 8.0 * right.J));
      rows.block(row, ns * i, Bi);
      rows.block(row, ns * (i + 1), Bn);
      const Vec dc = -h / 6.0 * (left.fc + 4.0 * (mid.fc + mid.J * (h / 8.0 * (left.fc - right.fc))) + right.fc);
      rows.column(row, cols.c, dc);
      if (!cols.free_sigma()) continue;
      const Vec ds = -h / 6.0 * (left.fs + 4.0 * (mid.fs + mid.J * (h / 8.0 * (left.fs - right.fs))) + right.fs);
      rows.column(row, cols.sigma, ds);
    }
  }

  // The last row with σ_d free: t_σ (σ_d − σ_0) + t_c (c − c_0)/c_scale = step.
  void arclength_row(double c, double sd, Rows& rows, const ScalarColumns& cols) const {
    if (!arc_) return;
    const auto& a = *arc_;
    const int last = size() - 1;
    rows.F[last] = a.t_sigma * (sd - a.sigma0) + a.t_c * (c - a.c0) / a.c_scale - a.step;
    if (!rows.jacobian()) return;
    rows.entry(last, cols.sigma, a.t_sigma);
    rows.entry(last, cols.c, a.t_c / a.c_scale);
  }

  Block block_;
  std::vector<double> xi_;
  double sigma_fixed_;
  std::optional<Arclength> arc_;
};

/// The error estimate of c (docs/fronts.md §3): the same problem on every other node of `col` (the same mesh map,
/// twice the spacing; `coarse_block` the model's block for it) from the converged x, solved by `solve(coarse, xc)`
/// (a NewtonResult); the scheme is 4th order, so c_h − c ≈ (c_2h − c_h)/15. ∞ when the coarse solve fails.
template <class Block, class Solve>
double coarse_speed_error(const Collocation<Block>& col, const Eigen::VectorXd& x, Block coarse_block, double sigma_d,
                          Solve&& solve) {
  const int ns = col.block().width();
  const double c = col.c_of(x);
  std::vector<double> coarse_xi;
  Eigen::VectorXd xc(ns * (col.nodes() / 2 + 1) + 1);
  int k = 0;
  for (int i = 0; i < col.nodes(); i += 2, ++k) {
    coarse_xi.push_back(col.xi()[static_cast<std::size_t>(i)]);
    xc.segment(ns * k, ns) = col.y(x, i);
  }
  xc[xc.size() - 1] = c;
  const Collocation<Block> coarse(std::move(coarse_block), std::move(coarse_xi), sigma_d, std::nullopt);
  const auto nc = solve(coarse, xc);
  return nc.converged ? std::abs(coarse.c_of(xc) - c) / 15.0 : std::numeric_limits<double>::infinity();
}

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
