#pragma once
// The node block of a front in a body of finite height (docs/fronts.md §10.3, §11.2), written once for the antiplane
// strip (continuum/strip_front.cpp) and the in-plane strip (continuum/inplane_front.cpp): the far-field rows behind
// and ahead as projections on the excluded modes' left eigenspaces (reference bases fixed for one Newton solve), the
// tip's law conditions, the solve's Newton rule and the automatic domain length. Internal to continuum/; no I/O.
//
// `Model` (the body's rows) supplies, found by argument-dependent lookup in its namespace:
//   m.ns(), m.nb() (the node state and its bulk part), m.far_count() (the conditions on each side), m.sound_speed(),
//   m.law(), m.interface(), m.saddle_node, m.kappa;
//   behind_subspace(m, c, σ_d), ahead_subspace(m, c, σ_d), behind_state(m, c, σ_d), stuck_state(m, σ_d),
//   translation_free(m), behind_rhs(m, y, c, σ_d, with_jacobian) (a far_field::Rhs),
//   finish(collocation, x, front) (the converged iterate into the front: fields, diagnostics, status).
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "continuum/far_field.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/front_solver.hpp"
#include "continuum/strip_front.hpp"

namespace slipfront::continuum::far_field {

/// The right-hand side of a row model's first-order system with its derivatives: f, ∂f/∂c, ∂f/∂σ_d, ∂f/∂y.
struct Rhs {
  Eigen::VectorXd f, fc, fs;
  Eigen::MatrixXd J;
};

// y = (the body's unknowns, A, σ̄) at every node, rows
//   far_count  behind: Q_ref,bᵀ P_b(c, σ_d) T (y_0 − y_b) = 0     (no mode growing toward −∞ at ξ = −L)
//   N · ns     Lobatto IIIA on every interval (docs/fronts.md eq. 5; front_solver::Collocation)
//   far_count  tip: Q_ref,aᵀ P_a(c) (bulk_N − stuck) = 0           (only decaying modes ahead)
//   3          tip: A_N = 1, σ̄_N = α u_{0,N}, σ̄_N + η v_N = 1   (Θ switches at the tip)
// P = Q Qᵀ is the orthogonal projector on the excluded left eigenspace; the reference bases Q_ref (fixed for one
// Newton solve, from the far fields at (c0, s0)) make the rows smooth in c and σ_d, which enter through finite
// differences.
template <class Model>
class RowsBlock {
 public:
  using Vec = Eigen::VectorXd;
  using Mat = Eigen::MatrixXd;
  using Rhs = far_field::Rhs;
  static constexpr bool keep_zero_columns = false;

  RowsBlock(const Model& m, double c0, double s0) : m_(m), T_(translation_free(m)) {
    const Subspace b = behind_subspace(m_, c0, s0), a = ahead_subspace(m_, c0, s0);
    ok_ = b.ok && a.ok;
    why_ = !b.ok ? "behind: " + b.why : (!a.ok ? "ahead: " + a.why : std::string());
    if (ok_) {
      Qb_ = b.Q;
      Qa_ = a.Q;
    }
  }
  bool ok() const { return ok_; }
  const std::string& why() const { return why_; }
  const Model& model() const { return m_; }
  int width() const { return m_.ns(); }
  int behind_count() const { return m_.far_count(); }
  bool admissible(double c) const { return ok_ && c > 0.0 && c < m_.sound_speed(); }
  Rhs rhs(const Vec& y, double c, double sd, bool with_jacobian) const { return behind_rhs(m_, y, c, sd, with_jacobian); }

  // The far-field rows as functions of (node state, c, σ_d).
  Vec behind_projection(const Vec& y0, double c, double sd, Mat* dy) const {
    const Subspace b = behind_subspace(m_, c, sd);
    if (!b.ok) return Vec::Constant(behind_count(), std::numeric_limits<double>::quiet_NaN());
    const Mat G = Qb_.transpose() * b.Q * b.Q.transpose() * T_;
    if (dy) *dy = G;
    return G * (y0 - behind_state(m_, c, sd));
  }
  Vec ahead_projection(const Vec& yN, double c, double sd, Mat* dy) const {
    const Subspace a = ahead_subspace(m_, c, sd);
    if (!a.ok) return Vec::Constant(behind_count(), std::numeric_limits<double>::quiet_NaN());
    const Mat G = Qa_.transpose() * a.Q * a.Q.transpose();
    if (dy) *dy = G;
    return G * (yN - stuck_state(m_, sd)).head(m_.nb());
  }

  // Behind: ξ_0 = −L (rows 0 … far_count − 1); c and σ_d columns by central differences.
  bool behind_rows(const Vec& y0, double c, double sd, front_solver::Rows& rows, front_solver::ScalarColumns col) const {
    const double hs = std::min(1e-7, 0.25 * (sd - steady_minimum_stress(m_.law())));
    projection_rows(0, 0, y0, c, sd, hs, rows, col, [this](const Vec& y, double cc, double ss, Mat* G) {
      return behind_projection(y, cc, ss, G);
    });
    return true;
  }

  // The tip ξ_N = 0 (rows `row` …, y_N at column `base`): the decaying subspace ahead, and Θ's switch.
  bool tip_rows(const Vec& yN, int row, int base, double c, double sd, front_solver::Rows& rows,
                front_solver::ScalarColumns col) const {
    projection_rows(row, base, yN, c, sd, 1e-7, rows, col, [this](const Vec& y, double cc, double ss, Mat* G) {
      return ahead_projection(y, cc, ss, G);
    });
    tip_law_rows(yN, row + behind_count(), base, c, m_.law(), m_.interface(), rows, col);
    return true;
  }

 private:
  Model m_;
  Mat T_, Qb_, Qa_;
  bool ok_ = false;
  std::string why_;
};

/// Damped Newton with the strips' rule (docs/fronts.md §10.4, §10.11): a step below the tolerance, or at the round-off
/// floor (below 1e-6 and no longer shrinking), is taken and ends the iteration.
template <class Block>
front_solver::NewtonResult rows_newton(const front_solver::Collocation<Block>& col, Eigen::VectorXd& x, double tol,
                                       int max_iter, const std::function<bool()>& stop) {
  if (!col.block().ok()) {
    front_solver::NewtonResult out;
    out.failure = "no far-field subspace: " + col.block().why();
    return out;
  }
  front_solver::NewtonRule rule;
  rule.tolerance = tol;
  rule.max_iterations = max_iter;
  rule.floor_tolerance = 1e-6;
  rule.inadmissible_guess =
      "the initial guess is not admissible (c outside (0, c_s), or the far fields have no saddle structure)";
  rule.stop = &stop;
  return front_solver::newton(
      [&](const Eigen::VectorXd& z, Eigen::VectorXd& F, Eigen::SparseMatrix<double>* jac) { return col.assemble(z, F, jac); },
      x, rule);
}

/// L: the nonlinear region near the tip plus `decay_lengths` e-folds of the slowest mode approaching the sliding
/// state (the error of the linear projection is quadratic in the distance from it), docs/fronts.md §10.3.
template <class Model>
double rows_domain_length(const Model& m, const StripFrontOptions& o, double c, double sd, double* slowest_out = nullptr) {
  const Subspace b = behind_subspace(m, c, sd);
  double slowest = std::numeric_limits<double>::infinity();
  for (const auto& l : b.kept)
    if (l.real() > 0.0) slowest = std::min(slowest, l.real());
  if (!std::isfinite(slowest)) slowest = 1.0 / c;
  if (slowest_out) *slowest_out = slowest;
  if (o.domain_length > 0.0) return o.domain_length;
  const double vb = m.saddle_node ? steady_minimum_velocity(m.law()) : strengthening_branch_velocity(m.law(), sd);
  return o.tip_length * c / (1.0 + m.kappa * vb) + o.decay_lengths / slowest;
}

/// One Newton solve of a row model's front on a fresh ξ mesh (docs/fronts.md §10.4) from the iterate built by
/// start(collocation): `f` the empty front of the problem, filled by the model's finish() when Newton converges, with
/// the ξ part of the error (every other node, /15, docs/fronts.md §3) when o.estimate_error. Far fields without the
/// saddle structure at the guess: status `refused` with the modes' count in the reason.
template <class Model, class Start>
StripFront solve_rows_on_mesh(StripFront f, const Model& m, const StripFrontOptions& o, double sd, double c_guess,
                              std::optional<front_solver::Arclength> arc, Start&& start, FrontStatus refused) {
  using Block = RowsBlock<Model>;
  using Col = front_solver::Collocation<Block>;
  f.saddle_node_limit = m.saddle_node;
  const double L = rows_domain_length(m, o, c_guess, arc ? arc->sigma0 : sd);
  const double s0 = arc ? arc->sigma0 + arc->step * arc->t_sigma : sd;  // the far-field bases at the predicted σ_d
  const Col col(Block(m, c_guess, s0), front_solver::make_mesh(L, o.intervals, o.tip_spacing, o.grading), sd, arc);
  if (!col.block().ok()) {
    f.status = refused;
    f.reason = col.block().why();
    f.c = c_guess;
    return f;
  }
  Eigen::VectorXd x = start(col);
  x[col.c_index()] = c_guess;
  if (arc) x[col.c_index() + 1] = sd;
  const auto nr = rows_newton(col, x, o.tolerance, o.max_newton, o.stop);
  f.newton_iterations = nr.iterations;
  f.domain_length = L;
  if (!nr.converged) {
    f.status = nr.stopped ? FrontStatus::stopped
                          : col.c_of(x) >= 0.999 * m.sound_speed() ? FrontStatus::sonic : FrontStatus::newton_failed;
    f.reason = nr.failure;
    f.c = col.c_of(x);
    f.sigma_d = col.sigma_of(x);
    return f;
  }
  finish(col, x, f);
  f.residual_norm = nr.residual;
  if (o.estimate_error && o.intervals % 2 == 0 && o.intervals >= 8)
    f.speed_error = front_solver::coarse_speed_error(col, x, Block(m, f.c, f.sigma_d), f.sigma_d, [&](const Col& coarse, Eigen::VectorXd& xc) {
      return rows_newton(coarse, xc, o.tolerance, o.max_newton, o.stop);
    });
  return f;
}

/// σ_d in (σ_c^d, 1), where a front can exist (the sliding state behind on the strengthening branch, the stuck state
/// ahead); else false with `f` no_front_state and why.
inline bool admissible_sigma(const core::InterfaceParams& law, double sd, StripFront& f) {
  const double sigma_c = steady_minimum_stress(law);
  if (sd > sigma_c && sd < 1.0) return true;
  f.status = FrontStatus::no_front_state;
  f.reason = "sigma_d = " + core::format_number(sd) + " outside (sigma_c^d, 1) = (" + core::format_number(sigma_c) +
             ", 1): no sliding state on the strengthening branch behind, or no stuck state ahead";
  return false;
}

/// Where ξ_o falls on a front's mesh, for a guess transferred from it (docs/fronts.md §10.11): the nodes a, b and the
/// weight t of b, or behind its −L (a = b = 0, t = 0) the slip continued at the sliding state's rate (`shift`).
struct MeshBracket {
  std::size_t a = 0, b = 0;
  double t = 0.0, shift = 0.0;
  /// f linearly between the nodes (f at node k is f[k · stride + offset]).
  double lerp(const std::vector<double>& f, std::size_t stride = 1, std::size_t offset = 0) const {
    return (1.0 - t) * f[a * stride + offset] + t * f[b * stride + offset];
  }
};
inline MeshBracket bracket(const StripFront& g, double xo) {
  MeshBracket k;
  if (xo <= g.xi.front()) {
    k.shift = -g.v_behind / g.c * (xo - g.xi.front());
  } else {
    const auto it = std::upper_bound(g.xi.begin(), g.xi.end(), xo);
    k.b = std::min<std::size_t>(static_cast<std::size_t>(it - g.xi.begin()), g.xi.size() - 1);
    k.a = k.b - 1;
    k.t = (xo - g.xi[k.a]) / (g.xi[k.b] - g.xi[k.a]);
  }
  return k;
}

/// A converged front's diagnostics beside its fields (docs/fronts.md §10.3), once its interface fields (slip_rate,
/// sigma_bar, area) are stored: the tip's and the sliding state's values, the overstress margin, the modes behind (λ_s,
/// the excluded one nearest 0, and the slowest approach) and ahead (the decaying modes of `Ja`, the Jacobian ahead at
/// the stuck state, with their amplitudes in `tip` = the bulk state at the tip minus the stuck state; `to_fields`
/// maps one mode's bulk unknowns to the front's stored layout), then the status.
template <class Model, class ToFields>
void finish_diagnostics(const Model& m, double c, double sd, const Eigen::MatrixXd& Ja, const Eigen::VectorXd& tip,
                        StripFront& f, ToFields&& to_fields) {
  constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();
  f.v_tip = f.slip_rate.back();
  f.sigma_bar_tip = f.sigma_bar.back();
  const Eigen::VectorXd yb = behind_state(m, c, sd);
  f.v_behind = -c * yb[m.ip(0)];
  f.area_behind = yb[m.iA()];
  f.sigma_bar_behind = yb[m.iS()];
  f.overstress_margin = front_solver::overstress_margin(f.sigma_bar, f.slip_rate, f.area, m.eta);  // as in 1D
  f.min_slip_rate = *std::min_element(f.slip_rate.begin(), f.slip_rate.end());
  const Subspace b = behind_subspace(m, c, sd);
  f.stable_eigenvalue = b.excluded.empty() ? nan_value : b.excluded.back().real();
  f.slowest_growing = nan_value;
  for (const auto& l : b.kept)
    if (l.real() > 0.0 && !(l.real() >= f.slowest_growing)) f.slowest_growing = l.real();
  const Eigen::EigenSolver<Eigen::MatrixXd> es(Ja, true);
  const Eigen::VectorXcd d = es.eigenvectors().partialPivLu().solve(tip.cast<std::complex<double>>());
  f.ahead_rate.clear();
  f.ahead_mode.clear();
  f.slowest_ahead = std::numeric_limits<double>::infinity();
  for (int k = 0; k < Ja.rows(); ++k) {
    const auto l = es.eigenvalues()[k];
    if (l.real() >= 0.0) continue;
    f.slowest_ahead = std::min(f.slowest_ahead, -l.real());
    f.ahead_rate.push_back(l);
    std::vector<std::complex<double>> mode(static_cast<std::size_t>(Ja.rows()));
    for (int r = 0; r < Ja.rows(); ++r) mode[static_cast<std::size_t>(r)] = d[k] * es.eigenvectors()(r, k);
    to_fields(mode);
    f.ahead_mode.push_back(std::move(mode));
  }
  classify(f);
}

/// The cold start's growth in H (docs/fronts.md §10.4, §11.3): solve(b, nullptr) on H_0 = min(H, o.thin_height) (from
/// the 1D front), then H multiplied by o.height_factor at fixed μ, ρ up to bulk.height, each solve(b, &last) from the
/// last front; o.stop polled between them.
template <class Solve>
StripFront grow_from_thin(const core::BulkParams& bulk, const StripFrontOptions& o, Solve&& solve) {
  core::BulkParams b = bulk;
  b.height = std::min(bulk.height, o.thin_height);
  StripFront g = solve(b, nullptr);
  while (g.status == FrontStatus::converged && b.height < bulk.height) {
    if (o.stop && o.stop()) {
      g.status = FrontStatus::stopped;
      g.reason = "cold start: stopped on request at H = " + core::format_number(b.height);
      break;
    }
    b.height = std::min(bulk.height, b.height * o.height_factor);
    StripFront next = solve(b, &g);
    if (next.status != FrontStatus::converged)
      next.reason = "cold start: growing the strip failed at H = " + core::format_number(b.height) + ": " + next.reason;
    g = std::move(next);
  }
  return g;
}

/// The cold start (docs/fronts.md §10.4, §11.3): the 1D front of μ (the body's modulus times H) at σ_d, then the strip
/// grown from it at fixed μ, ρ (grow_from_thin): `first(b, f1)` solves the thinnest strip from the 1D front f1,
/// `next(b, last)` each thicker one from the last. `f` (the empty front) carries the 1D solve's failure.
template <class First, class Next>
StripFront cold_start(const core::InterfaceParams& law, const core::BulkParams& bulk, const StripFrontOptions& o,
                      double sigma_d, StripFront f, First&& first, Next&& next) {
  const SteadyFront f1 = solve_steady_front(law, {bulk.rho, bulk.mu, bulk.length, 0.0}, sigma_d);
  if (f1.status != FrontStatus::converged) {
    f.status = f1.status;
    f.reason = "cold start: no 1D front at this sigma_d: " + f1.reason;
    return f;
  }
  return grow_from_thin(bulk, o, [&](const core::BulkParams& b, const StripFront* last) {
    return last ? next(b, *last) : first(b, f1);
  });
}

}  // namespace slipfront::continuum::far_field
