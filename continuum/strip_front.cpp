#include "continuum/strip_front.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>

#include "continuum/friction_law.hpp"
#include "continuum/far_field.hpp"
#include "continuum/rows_block.hpp"
#include "continuum/front_solver.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/sigma_continuation.hpp"
#include "core/strip.hpp"

namespace slipfront::continuum {

namespace strip_detail {

using front_solver::Arclength;
using front_solver::branch_point;
using front_solver::end_of;
using front_solver::make_mesh;
using far_field::interp_rows;
using far_field::left_subspace;
using far_field::make_rows;
using far_field::row_grading_of;
using far_field::Subspace;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using CMat = Eigen::MatrixXcd;

// The strip across its height (docs/model.md §9.6 rows): nodes y_0 = 0 (interface) < … < y_M = H, spacings
// k_j = y_{j+1} − y_j, dual widths w_j (half cells on both faces). The state at a ξ node is
// (u_0 … u_M, p_0 … p_M, A, σ̄) with p_j = ∂ξ u_j.
struct Model {
  double mu_s, rho_s, H, alpha, kappa, eta, cs2;
  std::vector<double> y, k, w;
  int M;
  double gamma = 0.0;  // the rows' grading (0: uniform)
  bool saddle_node = false;
  core::InterfaceParams law() const { return {alpha, kappa, eta}; }
  int ns() const { return 2 * (M + 1) + 2; }
  int nb() const { return 2 * (M + 1); }  // the bulk part (u, p)
  int iu(int j) const { return j; }
  int ip(int j) const { return M + 1 + j; }
  int iA() const { return 2 * (M + 1); }
  int iS() const { return 2 * (M + 1) + 1; }
  double sound_speed() const { return std::sqrt(cs2); }
  far_field::InterfaceIndex interface() const { return {iA(), iS(), iu(0), ip(0)}; }
  int far_count() const { return M + 1; }  // the far-field conditions on each side (docs/fronts.md §10.3)
};

Model make_model(const core::InterfaceParams& law, const core::BulkParams& bulk, const StripFrontOptions& o) {
  Model m;
  m.H = bulk.height;
  m.mu_s = core::Strip::modulus(bulk);
  m.rho_s = bulk.rho / bulk.height;
  m.cs2 = bulk.mu / bulk.rho;
  m.alpha = law.alpha;
  m.kappa = law.kappa;
  m.eta = law.eta;
  m.M = std::max(1, o.rows);
  m.gamma = row_grading_of(m.H, m.M, o.row_spacing, o.row_grading);
  m.y = make_rows(m.H, m.M, m.gamma);
  far_field::row_widths(m.y, m.k, m.w);
  return m;
}

enum class Side { behind, ahead };

// The semi-discrete traveling-wave system (docs/fronts.md §10.2, eq. S2): for every row j
//   u_j' = p_j,   β² w_j p_j' = −(top_j − bottom_j),
// top_j = (u_{j+1} − u_j)/k_j (σ_d/μ' on the top row), bottom_j = (u_j − u_{j−1})/k_{j−1} (τ/μ' on the
// interface row), τ = σ̄ + η v behind and α u_0 + η v ahead (σ̄ = α u_0 in the stuck region), v = −c p_0;
// behind the tip A' = −(1 − A − κA|v|)/c, σ̄' = −(αAv − σ̄|v|)/c (docs/fronts.md eq. 1b, 1c); ahead A, σ̄
// are not dynamic (their components are 0). The unknowns of the rows j ≥ 1 are d_j = u_j − u_0 (the
// strain across the height is small against u itself, so the fluxes are computed without cancellation):
// d_j' = p_j − p_0. f, its Jacobian J, ∂f/∂c and ∂f/∂σ_d.
using Rhs = far_field::Rhs;
Rhs rhs(const Model& m, const Vec& y, double c, double sd, Side side, bool with_jacobian = true) {
  const int M = m.M, n = m.ns();
  Rhs r;
  r.f = Vec::Zero(n);
  r.fc = Vec::Zero(n);
  r.fs = Vec::Zero(n);
  if (with_jacobian) r.J = Mat::Zero(n, n);
  const double b2 = 1.0 - c * c / m.cs2, db2 = -2.0 * c / m.cs2;
  const double p0 = y[m.ip(0)], v = -c * p0;
  const double tau = (side == Side::behind ? y[m.iS()] : m.alpha * y[m.iu(0)]) + m.eta * v;
  auto d = [&](int j) { return j == 0 ? 0.0 : y[m.iu(j)]; };
  auto add = [&](int row, int j, double value) {  // ∂(row)/∂d_j (nothing for d_0 = 0)
    if (j > 0) r.J(row, m.iu(j)) += value;
  };
  for (int j = 0; j <= M; ++j) {
    const auto a = static_cast<std::size_t>(j);
    r.f[m.iu(j)] = j == 0 ? y[m.ip(0)] : y[m.ip(j)] - y[m.ip(0)];
    if (with_jacobian) {
      r.J(m.iu(j), m.ip(j)) = 1.0;
      if (j > 0) r.J(m.iu(j), m.ip(0)) = -1.0;
    }
    const double top = j < M ? (d(j + 1) - d(j)) / m.k[a] : sd / m.mu_s;
    const double bottom = j > 0 ? (d(j) - d(j - 1)) / m.k[a - 1] : tau / m.mu_s;
    const double X = top - bottom, scale = 1.0 / (b2 * m.w[a]);
    r.f[m.ip(j)] = -X * scale;
    r.fc[m.ip(j)] = X * db2 / (b2 * b2 * m.w[a]);
    if (j == M) r.fs[m.ip(j)] = -scale / m.mu_s;
    if (j == 0) r.fc[m.ip(j)] += -(m.eta * p0 / m.mu_s) * scale;  // ∂bottom/∂c = ∂τ/∂c / μ' = −η p_0/μ'
    if (!with_jacobian) continue;
    if (j < M) {
      add(m.ip(j), j + 1, -scale / m.k[a]);
      add(m.ip(j), j, scale / m.k[a]);
    }
    if (j > 0) {
      add(m.ip(j), j, scale / m.k[a - 1]);
      add(m.ip(j), j - 1, -scale / m.k[a - 1]);
    } else {
      // bottom = τ/μ': ∂τ/∂p_0 = −η c; ∂τ/∂σ̄ = 1 behind, ∂τ/∂u_0 = α ahead.
      const double g = scale / m.mu_s;
      r.J(m.ip(0), m.ip(0)) += g * (-m.eta * c);
      if (side == Side::behind) r.J(m.ip(0), m.iS()) += g;
      else r.J(m.ip(0), m.iu(0)) += g * m.alpha;
    }
  }
  if (side == Side::behind) far_field::interface_law_rows(m.law(), y, c, m.interface(), with_jacobian, r);
  return r;
}

Rhs behind_rhs(const Model& m, const Vec& y, double c, double sd, bool with_jacobian) {
  return rhs(m, y, c, sd, Side::behind, with_jacobian);
}

// The sliding state behind (σ_ss(v_b) = σ_d on the strengthening branch; v_m at the saddle-node), with
// ∂y u = σ_d/μ' through the height (the interface carries τ = σ_d); u_0 = 0 (u is defined up to a constant
// there: the projection does not see it).
Vec behind_state(const Model& m, double c, double sd) {
  const double vb = m.saddle_node ? steady_minimum_velocity(m.law()) : strengthening_branch_velocity(m.law(), sd);
  const double Ab = 1.0 / (1.0 + m.kappa * vb);
  Vec y(m.ns());
  for (int j = 0; j <= m.M; ++j) {
    y[m.iu(j)] = sd * m.y[static_cast<std::size_t>(j)] / m.mu_s;  // u_0 = 0, d_j
    y[m.ip(j)] = -vb / c;
  }
  y[m.iA()] = Ab;
  y[m.iS()] = m.alpha * Ab;
  return y;
}
// The stuck state ahead (docs/model.md §9.4): u = σ_d/α + σ_d y/μ', p = 0, A = 1, σ̄ = σ_d.
Vec stuck_state(const Model& m, double sd) {
  Vec y = Vec::Zero(m.ns());
  y[m.iu(0)] = sd / m.alpha;
  for (int j = 1; j <= m.M; ++j) y[m.iu(j)] = sd * m.y[static_cast<std::size_t>(j)] / m.mu_s;
  y[m.iA()] = 1.0;
  y[m.iS()] = sd;
  return y;
}

// The far-field conditions (docs/fronts.md §10.3; far_field::Subspace). Behind, in the coordinates z = (u_1 − u_0, …,
// u_M − u_0, p, A, σ̄) that remove the translation u → u + const (the one null mode of the sliding state), the M + 1
// modes that decay in forward ξ (λ_s and M bulk modes, growing toward −∞) must be absent at ξ = −L. Ahead, the M + 1
// modes of the linear stuck system (u, p) that grow with ξ must be absent at the tip.
// T: y → z (drops u_0, the translation u → u + const); behind only.
Mat translation_free(const Model& m) { return far_field::translation_free(m.ns()); }

Subspace behind_subspace(const Model& m, double c, double sd) {
  const Vec yb = behind_state(m, c, sd);
  const Mat J = rhs(m, yb, c, sd, Side::behind).J;
  const Mat T = translation_free(m);
  Mat S = T.transpose();  // a right inverse of T with δu_0 = 0: T S = I
  S.row(m.iu(0)).setZero();
  const Mat Jz = T * J * S;
  return left_subspace(Jz, m.M + 1, true, m.saddle_node);
}

Subspace ahead_subspace(const Model& m, double c, double sd) {
  const Vec ys = stuck_state(m, sd);
  const Mat J = rhs(m, ys, c, sd, Side::ahead).J.topLeftCorner(m.nb(), m.nb());
  return left_subspace(J, m.M + 1, false, false);
}

// The strip's node block for the collocation (docs/fronts.md §10.3): y = (u_0, d_1 … d_M, p_0 … p_M, A, σ̄) at every
// node, M + 1 far-field rows on each side (far_field::RowsBlock, shared with the in-plane strip).
using StripBlock = far_field::RowsBlock<Model>;

// The discrete boundary-value problem of the strip: the shared collocation on its block.
using Collocation = front_solver::Collocation<StripBlock>;

StripFront empty_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sd) {
  StripFront f;
  f.law = law;
  f.bulk = bulk;
  f.mu_strip = core::Strip::modulus(bulk);
  f.rho_strip = bulk.rho / bulk.height;
  f.sigma_d = sd;
  return f;
}

// A guess on the mesh of `col` from a strip front stretched by `s` in ξ and y (the front's lengths scale
// with c: s = c_new/c_old, docs/fronts.md §10.11). u, v, A, σ̄ are carried as functions of (ξ/s, y/s), so
// p = ∂ξu scales as 1/s; across the height the part of the lift beyond the uniform strain σ_d y/μ' is
// carried (constant above the old top, where ∂y of it vanishes). s = 1 is the plain transfer below.
Vec transfer_stretched(const Collocation& col, const StripFront& g, double sd, double s) {
  const Model& m = col.block().model();
  const int ns = m.ns(), M = m.M;
  const std::size_t ro = g.y.size();
  const double old_strain = g.sigma_d / g.mu_strip, new_strain = sd / m.mu_s;
  Vec x = Vec::Zero(col.size());
  std::vector<double> rcol(ro), pcol(ro);
  for (int i = 0; i < col.nodes(); ++i) {
    const far_field::MeshBracket k = far_field::bracket(g, col.xi()[static_cast<std::size_t>(i)] / s);
    for (std::size_t j = 0; j < ro; ++j) {
      rcol[j] = k.lerp(g.lift, ro, j) - old_strain * g.y[j];
      pcol[j] = k.lerp(g.strain, ro, j);
    }
    const double u0 = k.lerp(g.slip) + k.shift;
    for (int j = 0; j <= M; ++j) {
      const double yy = m.y[static_cast<std::size_t>(j)], yo = yy / s;
      x[ns * i + m.iu(j)] = j == 0 ? u0 : new_strain * yy + interp_rows(g.y, rcol.data(), yo, 0.0);
      x[ns * i + m.ip(j)] = interp_rows(g.y, pcol.data(), yo, 0.0) / s;
    }
    x[ns * i + m.iA()] = k.lerp(g.area);
    x[ns * i + m.iS()] = k.lerp(g.sigma_bar);
  }
  x[col.c_index()] = g.c * s;
  if (col.size() > col.c_index() + 1) x[col.c_index() + 1] = sd;
  return x;
}

// A guess on the mesh of `col` from a strip front (any H, rows, mesh): bilinear in (ξ, y), the sliding
// state continued beyond its −L, the top slope σ_d/μ' above its H.
Vec transfer(const Collocation& col, const StripFront& g, double sd) {
  const Model& m = col.block().model();
  const int ns = m.ns(), M = m.M, Mo = g.rows();
  Vec x = Vec::Zero(col.size());
  const std::size_t ro = static_cast<std::size_t>(Mo) + 1;
  std::vector<double> ucol(ro), pcol(ro);
  for (int i = 0; i < col.nodes(); ++i) {
    const far_field::MeshBracket k = far_field::bracket(g, col.xi()[static_cast<std::size_t>(i)]);
    for (std::size_t j = 0; j < ro; ++j) {
      ucol[j] = k.lerp(g.lift, ro, j);
      pcol[j] = k.lerp(g.strain, ro, j);
    }
    const double u0 = k.lerp(g.slip) + k.shift;
    for (int j = 0; j <= M; ++j) {
      const double yy = m.y[static_cast<std::size_t>(j)];
      x[ns * i + m.iu(j)] = j == 0 ? u0 : interp_rows(g.y, ucol.data(), yy, sd / m.mu_s);
      x[ns * i + m.ip(j)] = interp_rows(g.y, pcol.data(), yy, 0.0);
    }
    x[ns * i + m.iA()] = k.lerp(g.area);
    x[ns * i + m.iS()] = k.lerp(g.sigma_bar);
  }
  x[col.c_index()] = g.c;
  if (col.size() > col.c_index() + 1) x[col.c_index() + 1] = sd;
  return x;
}

// A guess from the 1D front (docs/fronts.md §10.4): its interface fields, and across the height the thin-strip
// profile of docs/model.md §9.2, u = u_0 + (τ/μ') y + q y²/2, q = (σ_d − τ)/(μ' H), p_j = −v/c.
Vec from_one_dimensional(const Collocation& col, const SteadyFront& f1) {
  const Model& m = col.block().model();
  const int ns = m.ns();
  const auto s = sample_steady_front(f1, col.xi(), 0.0);
  Vec x = Vec::Zero(col.size());
  for (int i = 0; i < col.nodes(); ++i) {
    const auto a = static_cast<std::size_t>(i);
    const double tau = s.sigma_bar[a] + m.eta * s.slip_rate[a];
    const double q = (f1.sigma_d - tau) / (m.mu_s * m.H);
    for (int j = 0; j <= m.M; ++j) {
      const double yy = m.y[static_cast<std::size_t>(j)];
      x[ns * i + m.iu(j)] = j == 0 ? s.slip[a] : tau * yy / m.mu_s + 0.5 * q * yy * yy;
      x[ns * i + m.ip(j)] = -s.slip_rate[a] / f1.c;
    }
    x[ns * i + m.iA()] = s.area[a];
    x[ns * i + m.iS()] = s.sigma_bar[a];
  }
  x[col.c_index()] = f1.c;
  return x;
}

// The converged iterate into f: fields, far fields, the modes ahead, diagnostics, status.
void finish(const Collocation& col, const Vec& x, StripFront& f) {
  const Model& m = col.block().model();
  const int ns = m.ns(), n = col.nodes();
  const double c = col.c_of(x), sd = col.sigma_of(x);
  f.sigma_d = sd;
  f.c = c;
  f.xi = col.xi();
  f.y = m.y;
  f.domain_length = -f.xi.front();
  f.row_grading = m.gamma;
  const std::size_t ro = m.y.size();
  f.u.resize(static_cast<std::size_t>(n) * ro);
  f.strain.resize(f.u.size());
  f.lift.resize(f.u.size());
  f.slip_rate.resize(static_cast<std::size_t>(n));
  f.area.resize(f.slip_rate.size());
  f.sigma_bar.resize(f.slip_rate.size());
  f.slip.resize(f.slip_rate.size());
  f.traction.resize(f.slip_rate.size());
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    for (std::size_t j = 0; j < ro; ++j) {
      f.lift[a * ro + j] = j == 0 ? 0.0 : x[ns * i + static_cast<int>(j)];
      f.u[a * ro + j] = x[ns * i] + f.lift[a * ro + j];
      f.strain[a * ro + j] = x[ns * i + m.M + 1 + static_cast<int>(j)];
    }
    f.slip[a] = x[ns * i + m.iu(0)];
    f.slip_rate[a] = -c * x[ns * i + m.ip(0)];
    f.area[a] = x[ns * i + m.iA()];
    f.sigma_bar[a] = x[ns * i + m.iS()];
    f.traction[a] = f.sigma_bar[a] + m.eta * f.slip_rate[a];
  }
  // modes ahead: the decaying ones carry (u, p)(0) − stuck; the solver's d_j are stored as u_j = u_0 + d_j
  const Vec ys = stuck_state(m, sd);
  const Mat Ja = rhs(m, ys, c, sd, Side::ahead).J.topLeftCorner(m.nb(), m.nb());
  far_field::finish_diagnostics(m, c, sd, Ja, x.segment(ns * (n - 1), m.nb()) - ys.head(m.nb()), f, [&](auto& mode) {
    for (int j = 1; j <= m.M; ++j) mode[static_cast<std::size_t>(j)] += mode[0];
  });
}

// One Newton solve on a fresh mesh from an initial iterate built by `start`.
template <class Start>
StripFront solve_on_mesh(const core::InterfaceParams& law, const core::BulkParams& bulk, const Model& m,
                         const StripFrontOptions& o, double sd, double c_guess, std::optional<Arclength> arc,
                         Start&& start) {
  return far_field::solve_rows_on_mesh(empty_front(law, bulk, sd), m, o, sd, c_guess, arc, std::forward<Start>(start),
                                       FrontStatus::not_a_saddle);
}

}  // namespace strip_detail

StripFront solve_strip_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                             const StripFrontOptions& o, const StripFront* guess) {
  using namespace strip_detail;
  if (bulk.body() == core::BodyKind::inplane) return solve_inplane_front(law, bulk, sigma_d, o, guess);  // §11
  StripFront f = empty_front(law, bulk, sigma_d);
  if (!(bulk.height > 0.0)) {
    f.reason = "bulk.height must be > 0 for the strip (H = " + core::format_number(bulk.height) + ")";
    return f;
  }
  if (!far_field::admissible_sigma(law, sigma_d, f)) return f;
  if (guess && guess->status == FrontStatus::converged) {
    const Model m = make_model(law, bulk, o);
    return solve_on_mesh(law, bulk, m, o, sigma_d, guess->c, std::nullopt,
                         [&](const Collocation& col) { return transfer(col, *guess, sigma_d); });
  }
  // Cold start: the 1D front, then the strip grown from H_0 = min(H, thin_height) at fixed μ, ρ.
  return far_field::cold_start(
      law, bulk, o, sigma_d, std::move(f),
      [&](const core::BulkParams& b, const SteadyFront& f1) {
        return solve_on_mesh(law, b, make_model(law, b, o), o, sigma_d, f1.c, std::nullopt,
                             [&](const Collocation& col) { return from_one_dimensional(col, f1); });
      },
      [&](const core::BulkParams& b, const StripFront& last) {
        return solve_on_mesh(law, b, make_model(law, b, o), o, sigma_d, last.c, std::nullopt,
                             [&](const Collocation& col) { return transfer(col, last, sigma_d); });
      });
}

StripFront solve_strip_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                         const StripFrontOptions& o, const StripFront& guess, double c_guess) {
  using namespace strip_detail;
  if (bulk.body() == core::BodyKind::inplane) return solve_inplane_saddle_node_front(law, bulk, o, guess, c_guess);
  const double sigma_c = steady_sliding(law, steady_minimum_velocity(law)).sigma;
  if (c_guess > 0.0) return solve_strip_front_stretched(law, bulk, sigma_c, o, guess, c_guess, true);
  Model m = make_model(law, bulk, o);
  m.saddle_node = true;
  return solve_on_mesh(law, bulk, m, o, sigma_c, guess.c, std::nullopt,
                       [&](const Collocation& col) { return transfer(col, guess, sigma_c); });
}

StripFront solve_strip_front_stretched(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                                       const StripFrontOptions& o, const StripFront& from, double c_guess, bool saddle_node) {
  using namespace strip_detail;
  if (bulk.body() == core::BodyKind::inplane)
    return solve_inplane_front_stretched(law, bulk, sigma_d, o, from, c_guess, saddle_node);
  Model m = make_model(law, bulk, o);
  m.saddle_node = saddle_node;
  const double s = c_guess / from.c;
  return solve_on_mesh(law, bulk, m, o, sigma_d, c_guess, std::nullopt,
                       [&](const Collocation& col) { return transfer_stretched(col, from, sigma_d, s); });
}

double strip_row_grading(double H, const StripFrontOptions& o) {
  return strip_detail::row_grading_of(H, std::max(1, o.rows), o.row_spacing, o.row_grading);
}

StripFrontOptions with_rows(double H, const StripFrontOptions& o, int rows) {
  StripFrontOptions r = o;
  r.row_grading = strip_row_grading(H, o);
  if (!(r.row_grading > 0.0)) r.row_spacing = std::numeric_limits<double>::infinity();  // uniform stays uniform
  r.rows = rows;
  return r;
}

// Calibrated (docs/fronts.md §10.20) in CPU seconds of one thread on the reference machine: per ξ interval three
// right-hand sides with their (2M + 4)² Jacobians, two dense block products and SparseLU's factorisation, all ∝
// (2M + 4)²; measured 1.1–1.6e−7 s per interval and ns² (8 rows × 300 and 3000 intervals: 0.022, 0.21 s; 32 × 300:
// 0.21 s; 64 × 300: 0.85 s; 17 and 34 uniform rows × 600: 0.10, 0.39 s) and ≤ 80 bytes (8 × 3000: 70; 64 × 300: 23).
// Before issue 36's budget the constant was 8e−7, the wall time of the shared machine under a load of 9–12.
StripSolveCost strip_solve_cost(int rows, int intervals, int components) {
  const double ns = 2.0 * std::max(1, components) * (std::max(1, rows) + 1) + 2.0, n = std::max(1, intervals);
  StripSolveCost c;
  c.iteration_seconds = 1.6e-7 * n * ns * ns;
  c.memory_bytes = 80.0 * n * ns * ns + 64.0e6;
  return c;
}

StripSpeedError estimate_strip_speed_error(const StripFront& f, const StripFrontOptions& options) {
  StripSpeedError e;
  if (f.status != FrontStatus::converged) {
    e.note = "no converged front to estimate";
    return e;
  }
  const int M = f.rows(), other = M >= 2 ? M / 2 : 2 * M;
  StripFrontOptions o = options;
  o.row_grading = f.row_grading;
  if (!(o.row_grading > 0.0)) o.row_spacing = std::numeric_limits<double>::infinity();
  o.rows = other;
  o.max_newton = std::max(o.max_newton, 40);  // from other rows: more than a continuation step (the path's 12)
  const StripFront g = f.saddle_node_limit ? solve_strip_saddle_node_front(f.law, f.bulk, o, f)
                                           : solve_strip_front(f.law, f.bulk, f.sigma_d, o, &f);
  e.other_rows = other;
  if (g.status != FrontStatus::converged) {
    e.note = "the re-solve on " + std::to_string(other) + " rows did not converge (" + to_string(g.status) + ": " + g.reason + ")";
    return e;
  }
  const double two_p = std::pow(2.0, strip_row_order), d = std::abs(g.c - f.c);
  e.c_other = g.c;
  e.rows = M >= 2 ? d / (two_p - 1.0) : d * two_p / (two_p - 1.0);
  // The ξ part: the same rows on twice the intervals (refining, not coarsening: on few intervals the every-other-
  // node difference can vanish by accident), |c_N − c_2N| 2^q/(2^q − 1) with q = 3 assumed (the scheme's is 4).
  o.intervals = 2 * std::max(1, options.intervals);
  const StripFront h = f.saddle_node_limit ? solve_strip_saddle_node_front(f.law, f.bulk, o, g)
                                           : solve_strip_front(f.law, f.bulk, f.sigma_d, o, &g);
  if (h.status != FrontStatus::converged) {
    e.note = "the re-solve on " + std::to_string(o.intervals) + " intervals did not converge (" + to_string(h.status) +
             ": " + h.reason + ")";
    return e;
  }
  e.xi = std::abs(h.c - g.c) * 8.0 / 7.0;
  e.total = e.rows + e.xi;
  return e;
}

StripFrontSample sample_strip_front(const StripFront& f, std::span<const double> xs) {
  using namespace strip_detail;
  if (f.bulk.body() == core::BodyKind::inplane) return sample_inplane_front(f, xs).x;  // u_x's rows (docs/fronts.md §11.10)
  StripFrontOptions o;
  o.rows = f.rows();
  Model m = make_model(f.law, f.bulk, o);
  m.y = f.y;  // the front's own rows
  far_field::row_widths(m.y, m.k, m.w);
  const std::size_t ro = f.y.size();
  auto node = [&](std::size_t i) {
    Vec y(m.ns());
    for (std::size_t j = 0; j < ro; ++j) {
      y[static_cast<int>(j)] = j == 0 ? f.u[i * ro] : f.lift[i * ro + j];
      y[m.M + 1 + static_cast<int>(j)] = f.strain[i * ro + j];
    }
    y[m.iA()] = f.area[i];
    y[m.iS()] = f.sigma_bar[i];
    return y;
  };
  const Vec ys = stuck_state(m, f.sigma_d);
  StripFrontSample out;
  auto& in = out.interface;
  out.u.reserve(xs.size() * ro);
  out.velocity.reserve(xs.size() * ro);
  for (double xi : xs) {
    double A, s;
    if (xi > 0.0) {  // the modes of the stuck system: (u_j, p_j) − stuck
      for (std::size_t j = 0; j < ro; ++j) {
        double du = 0.0, dp = 0.0;
        for (std::size_t k = 0; k < f.ahead_rate.size(); ++k) {
          const auto e = std::exp(f.ahead_rate[k] * xi);
          du += (f.ahead_mode[k][j] * e).real();
          dp += (f.ahead_mode[k][ro + j] * e).real();
        }
        out.u.push_back(ys[m.iu(0)] + (j == 0 ? 0.0 : ys[m.iu(static_cast<int>(j))]) + du);
        out.velocity.push_back(-f.c * dp);
      }
      A = 1.0;
      s = f.law.alpha * out.u[out.u.size() - ro];
    } else if (xi >= f.xi.front()) {  // the collocation solution: cubic Hermite on the interval
      const auto it = std::upper_bound(f.xi.begin(), f.xi.end(), xi);
      const std::size_t b = std::min<std::size_t>(static_cast<std::size_t>(it - f.xi.begin()), f.xi.size() - 1), a = b - 1;
      const double h = f.xi[b] - f.xi[a], t = (xi - f.xi[a]) / h;
      const Vec ya = node(a), yb = node(b);
      const Vec fa = rhs(m, ya, f.c, f.sigma_d, Side::behind, false).f, fb = rhs(m, yb, f.c, f.sigma_d, Side::behind, false).f;
      const double h00 = (2 * t - 3) * t * t + 1, h10 = ((t - 2) * t + 1) * t, h01 = (3 - 2 * t) * t * t, h11 = (t - 1) * t * t;
      const Vec y = h00 * ya + h10 * h * fa + h01 * yb + h11 * h * fb;
      for (std::size_t j = 0; j < ro; ++j) {
        const int jj = static_cast<int>(j);
        out.u.push_back(y[m.iu(0)] + (j == 0 ? 0.0 : y[m.iu(jj)]));
        out.velocity.push_back(-f.c * y[m.ip(jj)]);
      }
      A = y[m.iA()];
      s = y[m.iS()];
    } else {  // beyond −L: the sliding state, every row translating at v_b with the lift it has at −L
      for (std::size_t j = 0; j < ro; ++j) {
        out.u.push_back(f.u[j] - f.v_behind / f.c * (xi - f.xi.front()));
        out.velocity.push_back(f.v_behind);
      }
      A = f.area_behind;
      s = f.sigma_bar_behind;
    }
    const std::size_t first = out.u.size() - ro;
    in.slip_rate.push_back(out.velocity[first]);
    in.area.push_back(A);
    in.sigma_bar.push_back(s);
    in.slip.push_back(out.u[first]);
  }
  return out;
}

StripInterfaceSample sample_strip_interface(const StripFront& f, std::span<const double> xs) {
  return sample_strip_front(f, xs).interface;
}

}  // namespace slipfront::continuum

namespace slipfront::continuum {

namespace strip_detail {

// The continuation of the strip's branch in σ_d (docs/fronts.md §10.8): the shared stages of
// front_solver::SigmaContinuation (docs/fronts.md §4) with strip fronts: the first front cold, the second by a natural
// step, then pseudo-arclength in (σ_d, c/c_s) with the secant as predictor, every point polished at fixed
// σ_d, the step capped to keep a quarter of the gap σ_d − σ_c^d, and the limiting front at σ_c^d.
class StripContinuation
    : public front_solver::SigmaContinuation<StripContinuation, StripFront, StripBranch, StripContinuationOptions> {
 public:
  StripContinuation(const core::InterfaceParams& law, const core::BulkParams& bulk, const StripContinuationOptions& o)
      : SigmaContinuation(o, std::sqrt(bulk.mu / bulk.rho), steady_minimum_stress(law)), law_(law), bulk_(bulk) {}

  bool start() { return admissible_parameters() && first_front() && second_front(); }
  void solve_limiting_front();
  void minimal_speed() {
    std::size_t k = 0;
    slowest_point_to_c_min(k);
  }
  StripBranch take() { return take_branch(); }

 private:
  friend SigmaContinuation;
  bool stop_requested() {
    if (!o_.stop || !o_.stop()) return false;
    stop(BranchEnd::stopped, "stopped on request after " + std::to_string(br_.points.size()) +
                                 " fronts: the branch is partial, c_min not computed");
    return true;
  }
  bool admissible_parameters();
  bool first_front();
  bool reached_own_end() const { return false; }
  StripFront solve_at(double sigma_d, const StripFront* guess) const {
    return solve_strip_front(law_, bulk_, sigma_d, o_.front, guess);
  }
  StripFront correct(double sigma_p, double c_p, const Arclength& arc) const {
    if (bulk_.body() == core::BodyKind::inplane) return correct_inplane_front(law_, bulk_, o_.front, sigma_p, c_p, arc, cur_);
    return solve_on_mesh(law_, bulk_, make_model(law_, bulk_, o_.front), o_.front, sigma_p, c_p, arc,
                         [&](const Collocation& col) { return transfer(col, cur_, sigma_p); });
  }
  void keep(const StripFront& f) const {
    if (o_.on_front) o_.on_front(f);
  }

  const core::InterfaceParams& law_;
  const core::BulkParams& bulk_;
};

bool StripContinuation::admissible_parameters() {
  const double v_m = steady_minimum_velocity(law_);
  if (!(bulk_.height > 0.0)) {
    stop(BranchEnd::no_branch, "bulk.height must be > 0 for the strip; nothing solved");
    return false;
  }
  if (!std::isfinite(v_m) || !(v_m > 0.0) || !std::isfinite(sigma_c_) || !(sigma_c_ < 1.0)) {
    stop(BranchEnd::no_branch, "the steady law has no minimum at a finite v > 0, or sigma_c^d = " +
                                   core::format_number(sigma_c_) + " >= 1: no branch (docs/fronts.md §4); nothing solved");
    return false;
  }
  return true;
}

bool StripContinuation::first_front() {
  double sd = o_.sigma_start;
  for (int k = 0; k <= 20; ++k) {
    if (stop_requested()) return false;
    if (k > 0) sd = sigma_c_ + (o_.sigma_start - sigma_c_) * std::pow(0.8, k);
    prev_ = solve_strip_front(law_, bulk_, sd, o_.front, k == 0 ? o_.start : nullptr);
    if (prev_.status == FrontStatus::converged) break;
  }
  if (prev_.status != FrontStatus::converged) {
    stop(end_of(prev_.status), "no front at sigma_start = " + core::format_number(o_.sigma_start) + " nor below: " + prev_.reason);
    br_.last = prev_;
    return false;
  }
  br_.points.push_back(branch_point(prev_));
  br_.first = prev_;
  if (o_.on_front) o_.on_front(prev_);
  return true;
}

void StripContinuation::solve_limiting_front() {
  const StripFront end = solve_strip_saddle_node_front(law_, bulk_, o_.front, cur_);
  if (end.status == FrontStatus::converged) {
    br_.points.push_back(branch_point(end));
    if (o_.on_front) o_.on_front(end);
    br_.last = end;
    br_.reason = "sigma_d -> sigma_c^d = " + core::format_number(sigma_c_) +
                 ": v_b -> v_m, the decaying mode of the sliding state behind -> 0 (saddle-node); limiting front "
                 "at sigma_c^d solved directly: c = " + core::format_number(end.c);
  } else {
    br_.reason = "sigma_d -> sigma_c^d (saddle-node of the sliding state behind); the limiting front did not converge: " +
                 end.reason;
  }
}

}  // namespace strip_detail

StripBranch continue_strip_fronts(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                  const StripContinuationOptions& o) {
  strip_detail::StripContinuation run(law, bulk, o);
  if (!run.start()) return run.take();
  run.follow();
  if (run.ended_at_saddle_node()) run.solve_limiting_front();
  run.minimal_speed();
  return run.take();
}

}  // namespace slipfront::continuum

namespace slipfront::continuum {

bool strip_start_needs_height_path(const core::BulkParams& bulk) {
  if (!(bulk.height > 0.0) || !(bulk.mu > 0.0) || bulk.body() == core::BodyKind::inplane) return false;  // §11.7
  return bulk.height > strip_path_start_ratio * core::Strip::modulus(bulk);  // H/ℓ, ℓ = μ'
}

// docs/fronts.md §10.19: the path at the strip's material from H/ℓ = 1/300 (the 1D regime, where the cold start
// is exact to 2e-5 in c_min, §10.12) to the strip's H, at the branch's first σ_d.
StripPathStart strip_start_from_height_path(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                            const StripContinuationOptions& o) {
  StripPathStart out;
  out.options = o.front;
  if (!(bulk.height > 0.0) || !(bulk.mu > 0.0) || !(bulk.rho > 0.0)) {
    out.reason = "the path in H needs bulk.height, bulk.mu and bulk.rho > 0";
    return out;
  }
  const double H = bulk.height, mus = core::Strip::modulus(bulk), rhos = bulk.rho / H;
  out.first_height = std::min(mus / 300.0, 0.5 * H);
  StripHeightOptions ho;
  ho.heights = {out.first_height, H};
  ho.limiting = false;
  ho.sigma_d = o.sigma_start;
  ho.front = o.front;
  ho.front.max_newton = 12;
  ho.stop = o.stop;
  const StripHeightPath path = continue_strip_height(law, mus, rhos, ho, bulk.length);
  out.steps = static_cast<int>(path.steps.size());
  if (!path.complete || path.fronts.empty()) {
    out.reason = "the path in H at mu' = " + core::format_number(mus) + " from H = " + core::format_number(out.first_height) +
                 " did not reach H = " + core::format_number(H) + ": " + path.reason;
    return out;
  }
  out.front = path.fronts.back();
  // the branch's meshes: those of the path's last solve, taken from the front it found (the solver rebuilds the
  // ξ mesh from these spacings, so the branch's first solve re-solves this front on them)
  const double lt = strip_tip_zone(law, out.front.c, out.front.v_behind);
  out.options = following_tip(out.options, lt, ho.tip_resolution, ho.row_resolution);
  out.options.max_newton = 12;
  out.reason = "path in H at mu' = " + core::format_number(mus) + ", rho' = " + core::format_number(rhos) + " from H = " +
               core::format_number(out.first_height) + " (" + std::to_string(out.steps) + " steps) at sigma_d = " +
               core::format_number(o.sigma_start) + ": c = " + core::format_number(out.front.c) +
               "; meshes follow the tip zone " + core::format_number(lt) + " (docs/fronts.md §10.19)";
  return out;
}

}  // namespace slipfront::continuum
