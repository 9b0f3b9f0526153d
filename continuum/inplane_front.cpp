#include "continuum/inplane_front.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <utility>

#include "continuum/far_field.hpp"
#include "continuum/rows_block.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/front_solver.hpp"

namespace slipfront::continuum {

double rayleigh_ratio(double nu) {
  const double r2 = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));  // c_s²/c_p²
  auto f = [&](double x) {
    const double x2 = x * x;
    return (2.0 - x2) * (2.0 - x2) - 4.0 * std::sqrt(1.0 - x2) * std::sqrt(1.0 - x2 * r2);
  };
  std::uintmax_t iters = 200;
  const auto br = boost::math::tools::toms748_solve(f, 0.5, 1.0 - 1e-12, boost::math::tools::eps_tolerance<double>(50), iters);
  return 0.5 * (br.first + br.second);
}

InPlaneMaterial inplane_material(const core::BulkParams& bulk) {
  InPlaneMaterial m;
  m.nu = bulk.poisson;
  m.mu = bulk.mu * (1.0 - m.nu) / (2.0 * bulk.height);
  m.rho = bulk.rho / bulk.height;
  m.lambda = 2.0 * m.mu * m.nu / (1.0 - 2.0 * m.nu);
  m.shear_speed = std::sqrt(m.mu / m.rho);
  m.pressure_speed = std::sqrt((m.lambda + 2.0 * m.mu) / m.rho);
  m.rayleigh_speed = rayleigh_ratio(m.nu) * m.shear_speed;
  m.plate_speed = std::sqrt(bulk.mu / bulk.rho);
  return m;
}

namespace inplane_detail {

using front_solver::Arclength;
using front_solver::make_mesh;
using far_field::interp_rows;
using far_field::Subspace;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

// The strip across its height: rows y_0 = 0 (interface) < … < y_M = H (the antiplane front's, docs/fronts.md §10.2),
// spacings k_j, dual widths w_j. The state at a ξ node (docs/fronts.md §11.1):
//   (u_0, d_1 … d_M, w_1 … w_M, p_0 … p_M, q_1 … q_M, A, σ̄),
// u_0 the slip, d_j = u_x,j − u_0 the lift, w_j = u_y,j (w_0 = 0: the interface), p_j = ∂ξ u_x,j, q_j = ∂ξ u_y,j.
struct Model {
  double mu, lam, rho, H, alpha, kappa, eta, pload;
  std::vector<double> y, k, w;
  int M;
  double gamma = 0.0;
  bool saddle_node = false;
  core::InterfaceParams law() const { return {alpha, kappa, eta}; }
  int ns() const { return 4 * M + 4; }
  int nb() const { return 4 * M + 2; }  // the bulk part
  int iu(int j) const { return j; }
  int iw(int j) const { return M + j; }  // j ≥ 1
  int ip(int j) const { return 2 * M + 1 + j; }
  int iq(int j) const { return 3 * M + 1 + j; }  // j ≥ 1
  int iA() const { return 4 * M + 2; }
  int iS() const { return 4 * M + 3; }
  double sound_speed() const { return std::sqrt(mu / rho); }  // c_s: the shear-row coefficient μ' − ρ'c² vanishes
  far_field::InterfaceIndex interface() const { return {iA(), iS(), iu(0), ip(0)}; }
  int far_count() const { return 2 * M + 1; }  // the far-field conditions on each side (docs/fronts.md §11.2)
};

Model make_model(const core::InterfaceParams& law, const core::BulkParams& bulk, const StripFrontOptions& o,
                 const std::vector<double>* rows = nullptr) {
  const InPlaneMaterial mat = inplane_material(bulk);
  Model m{mat.mu, mat.lambda, mat.rho, bulk.height, law.alpha, law.kappa, law.eta, bulk.normal_load, {}, {}, {}, 1};
  m.M = std::max(1, rows ? static_cast<int>(rows->size()) - 1 : o.rows);
  if (rows) {
    m.y = *rows;
  } else {
    m.gamma = far_field::row_grading_of(m.H, m.M, o.row_spacing, o.row_grading);
    m.y = far_field::make_rows(m.H, m.M, m.gamma);
  }
  far_field::row_widths(m.y, m.k, m.w);
  return m;
}

enum class Side { behind, ahead };

using Rhs = far_field::Rhs;

// The rows' traveling-wave system (docs/fronts.md §11.1, eq. P2): P1 Galerkin across the height, the ξξ terms lumped.
// For row j, with S_j(x) = ∫φ_j' ∂y x dy, C_j(x) = ∫φ_j' x dy, D_j(x) = ∫φ_j ∂y x dy (exact for P1 fields):
//   x: (λ' + 2μ' − ρ'c²) w_j p_j' = μ' S_j(u) + μ' C_j(q) − λ' D_j(q) + [τ on row 0] − [σ_d on row M]
//   y: (μ' − ρ'c²) w_j q_j'        = (λ' + 2μ') S_j(w) + λ' C_j(p) − μ' D_j(p) + [p on row M]      (j ≥ 1)
// with u_j' = p_j, w_j' = q_j, τ = σ̄ + η v behind (α u_0 + η v ahead), v = −c p_0, and the law (docs/fronts.md
// eq. 1b, 1c) behind the tip. f, ∂f/∂y, ∂f/∂c, ∂f/∂σ_d.
class RowsRhs {
 public:
  RowsRhs(const Model& m, const Vec& y, bool jac) : m_(m), y_(y), jac_(jac) {
    R_ = Vec::Zero(m.ns());
    if (jac) Jr_ = Mat::Zero(m.ns(), m.ns());
  }
  // coef · x[col] into row `out` (col < 0: a held zero, u_y and its derivative on the interface, the lift of row 0).
  void lin(int out, int col, double coef) {
    if (col < 0) return;
    R_[out] += coef * y_[col];
    if (jac_) Jr_(out, col) += coef;
  }
  template <class Col>
  void stiffness(int out, double coef, int j, Col col) {  // coef · S_j
    if (j > 0) lin(out, col(j), coef / m_.k[j - 1]), lin(out, col(j - 1), -coef / m_.k[j - 1]);
    if (j < m_.M) lin(out, col(j), coef / m_.k[j]), lin(out, col(j + 1), -coef / m_.k[j]);
  }
  template <class Col>
  void cross(int out, double coef, int j, Col col) {  // coef · C_j
    if (j > 0) lin(out, col(j - 1), 0.5 * coef), lin(out, col(j), 0.5 * coef);
    if (j < m_.M) lin(out, col(j), -0.5 * coef), lin(out, col(j + 1), -0.5 * coef);
  }
  template <class Col>
  void gradient(int out, double coef, int j, Col col) {  // coef · D_j
    if (j > 0) lin(out, col(j), 0.5 * coef), lin(out, col(j - 1), -0.5 * coef);
    if (j < m_.M) lin(out, col(j + 1), 0.5 * coef), lin(out, col(j), -0.5 * coef);
  }
  Vec R_;
  Mat Jr_;

 private:
  const Model& m_;
  const Vec& y_;
  bool jac_;
};

Rhs rhs(const Model& m, const Vec& y, double c, double sd, Side side, bool with_jacobian = true) {
  const int M = m.M, n = m.ns();
  Rhs r;
  r.f = Vec::Zero(n);
  r.fc = Vec::Zero(n);
  r.fs = Vec::Zero(n);
  RowsRhs b(m, y, with_jacobian);
  Vec Rc = Vec::Zero(n), Rs = Vec::Zero(n);
  const double p0 = y[m.ip(0)];
  auto cd = [&](int j) { return j == 0 ? -1 : m.iu(j); };
  auto cw = [&](int j) { return j == 0 ? -1 : m.iw(j); };
  auto cp = [&](int j) { return m.ip(j); };
  auto cq = [&](int j) { return j == 0 ? -1 : m.iq(j); };
  for (int j = 0; j <= M; ++j) {
    const int ox = m.ip(j);
    b.stiffness(ox, m.mu, j, cd);
    b.cross(ox, m.mu, j, cq);
    b.gradient(ox, -m.lam, j, cq);
    if (j == 0) {  // + τ
      b.lin(ox, side == Side::behind ? m.iS() : m.iu(0), side == Side::behind ? 1.0 : m.alpha);
      b.lin(ox, m.ip(0), -m.eta * c);
      Rc[ox] += -m.eta * p0;
    }
    if (j == M) {  // − σ_d
      b.R_[ox] -= sd;
      Rs[ox] = -1.0;
    }
    if (j == 0) continue;
    const int oy = m.iq(j);
    b.stiffness(oy, m.lam + 2.0 * m.mu, j, cw);
    b.cross(oy, m.lam, j, cp);
    b.gradient(oy, -m.mu, j, cp);
    if (j == M) b.R_[oy] += m.pload;
  }
  const double rc2 = m.rho * c * c, ax = m.lam + 2.0 * m.mu - rc2, ay = m.mu - rc2;
  for (int j = 0; j <= M; ++j) {
    const double W = m.w[static_cast<std::size_t>(j)];
    for (const auto& [o, a] : {std::pair{m.ip(j), ax}, std::pair{j > 0 ? m.iq(j) : -1, ay}}) {
      if (o < 0) continue;
      const double g = 1.0 / (a * W);
      r.f[o] = b.R_[o] * g;
      r.fc[o] = Rc[o] * g + b.R_[o] * 2.0 * m.rho * c * g / a;  // ∂(1/a)/∂c = 2ρ'c/a²
      r.fs[o] = Rs[o] * g;
      if (with_jacobian) b.Jr_.row(o) *= g;
    }
  }
  if (with_jacobian) r.J = std::move(b.Jr_);
  for (int j = 0; j <= M; ++j) {  // u_0' = p_0, d_j' = p_j − p_0, w_j' = q_j
    r.f[m.iu(j)] = j == 0 ? p0 : y[m.ip(j)] - p0;
    if (with_jacobian) {
      r.J(m.iu(j), m.ip(j)) = 1.0;
      if (j > 0) r.J(m.iu(j), m.ip(0)) = -1.0;
    }
    if (j == 0) continue;
    r.f[m.iw(j)] = y[m.iq(j)];
    if (with_jacobian) r.J(m.iw(j), m.iq(j)) = 1.0;
  }
  if (side == Side::behind) far_field::interface_law_rows(m.law(), y, c, m.interface(), with_jacobian, r);  // eq. 1b, 1c
  return r;
}

Rhs behind_rhs(const Model& m, const Vec& y, double c, double sd, bool with_jacobian) {
  return rhs(m, y, c, sd, Side::behind, with_jacobian);
}

// The sliding state behind (docs/fronts.md §11.1): u_x = −(v_b/c) ξ + σ_d y/μ' + const, σ_yy = −p through the
// height, so u_y = y (−p − λ' p_b)/(λ' + 2μ') with p_b = −v_b/c; u_0 = 0 (the translation is projected out).
Vec behind_state(const Model& m, double c, double sd) {
  const double vb = m.saddle_node ? steady_minimum_velocity(m.law()) : strengthening_branch_velocity(m.law(), sd);
  const double Ab = 1.0 / (1.0 + m.kappa * vb), pb = -vb / c;
  const double wy = (-m.pload - m.lam * pb) / (m.lam + 2.0 * m.mu);
  Vec y = Vec::Zero(m.ns());
  for (int j = 0; j <= m.M; ++j) {
    const double yy = m.y[static_cast<std::size_t>(j)];
    if (j > 0) {
      y[m.iu(j)] = sd * yy / m.mu;
      y[m.iw(j)] = wy * yy;
    }
    y[m.ip(j)] = pb;
  }
  y[m.iA()] = Ab;
  y[m.iS()] = m.alpha * Ab;
  return y;
}

// The stuck state ahead (docs/model.md §10.3): u_x = σ_d/α + σ_d y/μ', u_y = −p y/(λ' + 2μ'), A = 1, σ̄ = σ_d.
Vec stuck_state(const Model& m, double sd) {
  Vec y = Vec::Zero(m.ns());
  y[m.iu(0)] = sd / m.alpha;
  for (int j = 1; j <= m.M; ++j) {
    const double yy = m.y[static_cast<std::size_t>(j)];
    y[m.iu(j)] = sd * yy / m.mu;
    y[m.iw(j)] = -m.pload * yy / (m.lam + 2.0 * m.mu);
  }
  y[m.iA()] = 1.0;
  y[m.iS()] = sd;
  return y;
}

// The far fields (docs/fronts.md §11.2): behind, without u_0 (the translation), the 2M + 1 modes that decay in
// forward ξ; ahead, of the linear stuck system (the bulk part, u_0 included: the Robin spring α leaves no null
// mode), the 2M + 1 modes that grow.
Mat translation_free(const Model& m) { return far_field::translation_free(m.ns()); }
Subspace behind_subspace(const Model& m, double c, double sd) {
  const Mat J = rhs(m, behind_state(m, c, sd), c, sd, Side::behind).J;
  const Mat T = translation_free(m);
  Mat S = T.transpose();
  S.row(m.iu(0)).setZero();
  return far_field::left_subspace(T * J * S, 2 * m.M + 1, true, m.saddle_node);
}
Subspace ahead_subspace(const Model& m, double c, double sd) {
  const Mat J = rhs(m, stuck_state(m, sd), c, sd, Side::ahead).J.topLeftCorner(m.nb(), m.nb());
  return far_field::left_subspace(J, 2 * m.M + 1, false, false);
}

// The in-plane node block (docs/fronts.md §11.2): 2M + 1 far-field rows on each side (far_field::RowsBlock, shared
// with the antiplane strip).
using InPlaneBlock = far_field::RowsBlock<Model>;

using Collocation = front_solver::Collocation<InPlaneBlock>;

StripFront empty_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sd) {
  StripFront f;
  f.law = law;
  f.bulk = bulk;
  const InPlaneMaterial mat = inplane_material(bulk);
  f.mu_strip = mat.mu;
  f.rho_strip = mat.rho;
  f.sigma_d = sd;
  return f;
}

// A guess on the mesh of `col` from an in-plane front g (any H, rows, mesh), stretched by s in ξ and y (s = 1: a plain
// transfer; the front's lengths scale with c, docs/fronts.md §10.11): linear in ξ and y, the sliding state continued
// behind g's −L; above g's top the lift beyond the uniform shear σ_d y/μ' and u_y's last slope are continued.
Vec transfer(const Collocation& col, const StripFront& g, double sd, double s) {
  const Model& m = col.block().model();
  const int ns = m.ns();
  const std::size_t ro = g.y.size();
  const double old_strain = g.sigma_d / g.mu_strip, new_strain = sd / m.mu;
  Vec x = Vec::Zero(col.size());
  std::vector<double> rcol(ro), pcol(ro), wcol(ro), qcol(ro);
  for (int i = 0; i < col.nodes(); ++i) {
    const far_field::MeshBracket k = far_field::bracket(g, col.xi()[static_cast<std::size_t>(i)] / s);
    for (std::size_t j = 0; j < ro; ++j) {
      rcol[j] = k.lerp(g.lift, ro, j) - old_strain * g.y[j];
      pcol[j] = k.lerp(g.strain, ro, j);
      wcol[j] = k.lerp(g.uy, ro, j);
      qcol[j] = k.lerp(g.uy_strain, ro, j);
    }
    const double top_slope = (wcol[ro - 1] - wcol[ro - 2]) / (g.y[ro - 1] - g.y[ro - 2]);
    const double u0 = k.lerp(g.slip) + k.shift;
    for (int j = 0; j <= m.M; ++j) {
      const double yy = m.y[static_cast<std::size_t>(j)], yo = yy / s;
      x[ns * i + m.iu(j)] = j == 0 ? u0 : new_strain * yy + interp_rows(g.y, rcol.data(), yo, 0.0);
      x[ns * i + m.ip(j)] = interp_rows(g.y, pcol.data(), yo, 0.0) / s;
      if (j == 0) continue;
      x[ns * i + m.iw(j)] = s * interp_rows(g.y, wcol.data(), yo, top_slope);
      x[ns * i + m.iq(j)] = interp_rows(g.y, qcol.data(), yo, 0.0);
    }
    x[ns * i + m.iA()] = k.lerp(g.area);
    x[ns * i + m.iS()] = k.lerp(g.sigma_bar);
  }
  x[col.c_index()] = g.c * s;
  if (col.size() > col.c_index() + 1) x[col.c_index() + 1] = sd;
  return x;
}

// A guess from the 1D front (docs/fronts.md §11.3): its interface fields and, across the height, the thin strip:
// u_x = u_0 + (τ/μ') y + q y²/2, q = (σ_d − τ)/(μ'H), uniform ∂ξu_x = −v/c, and σ_yy ≈ −p, so
// u_y = y (−p − λ' ∂ξu_x)/(λ' + 2μ'), with ∂ξu_y from differences of ∂ξu_x along the nodes.
Vec from_one_dimensional(const Collocation& col, const SteadyFront& f1) {
  const Model& m = col.block().model();
  const int ns = m.ns(), n = col.nodes();
  const auto s = sample_steady_front(f1, col.xi(), 0.0);
  const double e = m.lam + 2.0 * m.mu;
  Vec x = Vec::Zero(col.size());
  std::vector<double> p(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) p[static_cast<std::size_t>(i)] = -s.slip_rate[static_cast<std::size_t>(i)] / f1.c;
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    const auto lo = static_cast<std::size_t>(std::max(0, i - 1)), hi = static_cast<std::size_t>(std::min(n - 1, i + 1));
    const double dp = (p[hi] - p[lo]) / (col.xi()[hi] - col.xi()[lo]);
    const double tau = s.sigma_bar[a] + m.eta * s.slip_rate[a];
    const double q = (f1.sigma_d - tau) / (m.mu * m.H);
    for (int j = 0; j <= m.M; ++j) {
      const double yy = m.y[static_cast<std::size_t>(j)];
      x[ns * i + m.iu(j)] = j == 0 ? s.slip[a] : tau * yy / m.mu + 0.5 * q * yy * yy;
      x[ns * i + m.ip(j)] = p[a];
      if (j == 0) continue;
      x[ns * i + m.iw(j)] = yy * (-m.pload - m.lam * p[a]) / e;
      x[ns * i + m.iq(j)] = -yy * m.lam * dp / e;
    }
    x[ns * i + m.iA()] = s.area[a];
    x[ns * i + m.iS()] = s.sigma_bar[a];
  }
  x[col.c_index()] = f1.c;
  return x;
}

// σ_yy(ξ, 0): the interface row's y-equation, which u_y = 0 replaces, read as the reaction (docs/fronts.md §11.1):
// σ_yy(0) = μ' D_0(p) − λ' C_0(p) − (λ' + 2μ') S_0(w) = μ'(p_1 − p_0)/2 + λ'(p_0 + p_1)/2 + (λ' + 2μ') w_1/k_0.
double normal_stress(const Model& m, const Vec& y) {
  const double p0 = y[m.ip(0)], p1 = y[m.ip(1)];
  return 0.5 * m.mu * (p1 - p0) + 0.5 * m.lam * (p0 + p1) + (m.lam + 2.0 * m.mu) * y[m.iw(1)] / m.k[0];
}

// The converged iterate into f: fields, diagnostics, the modes ahead, status.
void finish(const Collocation& col, const Vec& x, StripFront& f) {
  const Model& m = col.block().model();
  const int n = col.nodes();
  const double c = col.c_of(x), sd = col.sigma_of(x);
  f.sigma_d = sd;
  f.c = c;
  f.xi = col.xi();
  f.y = m.y;
  f.domain_length = -f.xi.front();
  f.row_grading = m.gamma;
  const std::size_t ro = m.y.size(), nn = static_cast<std::size_t>(n);
  for (auto* v : {&f.u, &f.strain, &f.lift, &f.uy, &f.uy_strain}) v->assign(nn * ro, 0.0);
  for (auto* v : {&f.slip_rate, &f.area, &f.sigma_bar, &f.slip, &f.traction, &f.normal_stress}) v->assign(nn, 0.0);
  for (int i = 0; i < n; ++i) {
    const auto a = static_cast<std::size_t>(i);
    const Vec yi = col.y(x, i);
    for (std::size_t j = 0; j < ro; ++j) {
      const int jj = static_cast<int>(j);
      f.lift[a * ro + j] = j == 0 ? 0.0 : yi[m.iu(jj)];
      f.u[a * ro + j] = yi[m.iu(0)] + f.lift[a * ro + j];
      f.strain[a * ro + j] = yi[m.ip(jj)];
      f.uy[a * ro + j] = j == 0 ? 0.0 : yi[m.iw(jj)];
      f.uy_strain[a * ro + j] = j == 0 ? 0.0 : yi[m.iq(jj)];
    }
    f.slip[a] = yi[m.iu(0)];
    f.slip_rate[a] = -c * yi[m.ip(0)];
    f.area[a] = yi[m.iA()];
    f.sigma_bar[a] = yi[m.iS()];
    f.traction[a] = f.sigma_bar[a] + m.eta * f.slip_rate[a];
    f.normal_stress[a] = normal_stress(m, yi);
  }
  // modes ahead: the decaying ones carry the bulk state at the tip minus the stuck state (the solver's layout)
  const Vec ys = stuck_state(m, sd);
  const Mat Ja = rhs(m, ys, c, sd, Side::ahead).J.topLeftCorner(m.nb(), m.nb());
  far_field::finish_diagnostics(m, c, sd, Ja, col.y(x, n - 1).head(m.nb()) - ys.head(m.nb()), f, [](auto&) {});
}

// One Newton solve on a fresh mesh from the iterate built by `start`.
template <class Start>
StripFront solve_on_mesh(const core::InterfaceParams& law, const core::BulkParams& bulk, const Model& m,
                         const StripFrontOptions& o, double sd, double c_guess, std::optional<Arclength> arc, Start&& start) {
  // far fields refused at a guess at or above c_s: the shear rows' count changed (docs/fronts.md §11.2), `sonic`
  const FrontStatus refused = c_guess >= m.sound_speed() ? FrontStatus::sonic : FrontStatus::not_a_saddle;
  return far_field::solve_rows_on_mesh(empty_front(law, bulk, sd), m, o, sd, c_guess, arc, std::forward<Start>(start), refused);
}

bool admissible_problem(const core::InterfaceParams& law, const core::BulkParams& bulk, double sd, StripFront& f) {
  if (!(bulk.height > 0.0) || bulk.body() != core::BodyKind::inplane) {
    f.reason = "the in-plane front needs bulk.body = \"inplane\" and bulk.height > 0 (H = " +
               core::format_number(bulk.height) + ")";
    return false;
  }
  return far_field::admissible_sigma(law, sd, f);
}

}  // namespace inplane_detail

StripFront solve_inplane_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                               const StripFrontOptions& o, const StripFront* guess) {
  using namespace inplane_detail;
  StripFront f = empty_front(law, bulk, sigma_d);
  if (!admissible_problem(law, bulk, sigma_d, f)) return f;
  if (guess && guess->status == FrontStatus::converged && !guess->uy.empty())
    return solve_on_mesh(law, bulk, make_model(law, bulk, o), o, sigma_d, guess->c, std::nullopt,
                         [&](const Collocation& col) { return transfer(col, *guess, sigma_d, 1.0); });
  // Cold start (docs/fronts.md §11.3): the 1D front of μ (= E'H), then the strip grown from H_0 at fixed μ, ρ.
  return far_field::cold_start(
      law, bulk, o, sigma_d, std::move(f),
      [&](const core::BulkParams& b, const SteadyFront& f1) {
        return solve_on_mesh(law, b, make_model(law, b, o), o, sigma_d, f1.c, std::nullopt,
                             [&](const Collocation& col) { return from_one_dimensional(col, f1); });
      },
      [&](const core::BulkParams& b, const StripFront& last) {
        return solve_on_mesh(law, b, make_model(law, b, o), o, sigma_d, last.c, std::nullopt,
                             [&](const Collocation& col) { return transfer(col, last, sigma_d, 1.0); });
      });
}

StripFront solve_inplane_front_stretched(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                                         const StripFrontOptions& o, const StripFront& from, double c_guess,
                                         bool saddle_node) {
  using namespace inplane_detail;
  Model m = make_model(law, bulk, o);
  m.saddle_node = saddle_node;
  const double s = c_guess / from.c;
  return solve_on_mesh(law, bulk, m, o, sigma_d, c_guess, std::nullopt,
                       [&](const Collocation& col) { return transfer(col, from, sigma_d, s); });
}

StripFront solve_inplane_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                           const StripFrontOptions& o, const StripFront& guess, double c_guess) {
  const double sigma_c = steady_sliding(law, steady_minimum_velocity(law)).sigma;
  return solve_inplane_front_stretched(law, bulk, sigma_c, o, guess, c_guess > 0.0 ? c_guess : guess.c, true);
}

StripFront correct_inplane_front(const core::InterfaceParams& law, const core::BulkParams& bulk, const StripFrontOptions& o,
                                 double sigma_p, double c_p, const front_solver::Arclength& arc, const StripFront& from) {
  using namespace inplane_detail;
  return solve_on_mesh(law, bulk, make_model(law, bulk, o), o, sigma_p, c_p, arc,
                       [&](const Collocation& col) { return transfer(col, from, sigma_p, 1.0); });
}

std::vector<double> inplane_front_node(const StripFront& f, std::size_t i) {
  using namespace inplane_detail;
  const Model m = make_model(f.law, f.bulk, {}, &f.y);
  const std::size_t ro = f.y.size();
  Vec y(m.ns());
  for (std::size_t j = 0; j < ro; ++j) {
    const int jj = static_cast<int>(j);
    y[m.iu(jj)] = j == 0 ? f.u[i * ro] : f.lift[i * ro + j];
    y[m.ip(jj)] = f.strain[i * ro + j];
    if (j == 0) continue;
    y[m.iw(jj)] = f.uy[i * ro + j];
    y[m.iq(jj)] = f.uy_strain[i * ro + j];
  }
  y[m.iA()] = f.area[i];
  y[m.iS()] = f.sigma_bar[i];
  return {y.data(), y.data() + y.size()};
}

}  // namespace slipfront::continuum

namespace slipfront::continuum {

InPlaneFrontSample sample_inplane_front(const StripFront& f, std::span<const double> xs) {
  using namespace inplane_detail;
  if (f.status != FrontStatus::converged || f.bulk.body() != core::BodyKind::inplane || f.uy.empty())
    throw std::invalid_argument("sample_inplane_front: needs a converged in-plane front");
  const Model m = make_model(f.law, f.bulk, {}, &f.y);
  const std::size_t ro = f.y.size();
  const double c = f.c;
  auto node = [&](std::size_t i) {
    const auto v = inplane_front_node(f, i);
    return Vec(Eigen::Map<const Vec>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  InPlaneFrontSample out;
  auto& sx = out.x;
  for (auto* v : {&sx.u, &sx.velocity, &out.uy, &out.uy_velocity}) v->reserve(xs.size() * ro);
  // every row of a state in the solver's layout (u_0, d_j, w_j, p_j, q_j; docs/fronts.md §11.1)
  auto put_rows = [&](const Vec& y) {
    for (std::size_t j = 0; j < ro; ++j) {
      const int jj = static_cast<int>(j);
      sx.u.push_back(y[m.iu(0)] + (j == 0 ? 0.0 : y[m.iu(jj)]));
      sx.velocity.push_back(-c * y[m.ip(jj)]);
      out.uy.push_back(j == 0 ? 0.0 : y[m.iw(jj)]);
      out.uy_velocity.push_back(j == 0 ? 0.0 : -c * y[m.iq(jj)]);
    }
  };
  const Vec ys = stuck_state(m, f.sigma_d);
  for (double xi : xs) {
    double A, s;
    if (xi > 0.0) {  // the modes of the stuck system: the bulk part − stuck
      Vec y = ys;
      for (std::size_t k = 0; k < f.ahead_rate.size(); ++k) {
        const auto e = std::exp(f.ahead_rate[k] * xi);
        for (int r = 0; r < m.nb(); ++r) y[r] += (f.ahead_mode[k][static_cast<std::size_t>(r)] * e).real();
      }
      put_rows(y);
      A = 1.0;
      s = f.law.alpha * y[m.iu(0)];
    } else if (xi >= f.xi.front()) {  // the collocation solution: cubic Hermite on the interval
      const auto it = std::upper_bound(f.xi.begin(), f.xi.end(), xi);
      const std::size_t b = std::min<std::size_t>(static_cast<std::size_t>(it - f.xi.begin()), f.xi.size() - 1), a = b - 1;
      const double h = f.xi[b] - f.xi[a], t = (xi - f.xi[a]) / h;
      const Vec ya = node(a), yb = node(b);
      const Vec fa = rhs(m, ya, c, f.sigma_d, Side::behind, false).f, fb = rhs(m, yb, c, f.sigma_d, Side::behind, false).f;
      const double h00 = (2 * t - 3) * t * t + 1, h10 = ((t - 2) * t + 1) * t, h01 = (3 - 2 * t) * t * t, h11 = (t - 1) * t * t;
      const Vec y = h00 * ya + h10 * h * fa + h01 * yb + h11 * h * fb;
      put_rows(y);
      A = y[m.iA()];
      s = y[m.iS()];
    } else {  // beyond −L: the sliding state
      for (std::size_t j = 0; j < ro; ++j) {
        sx.u.push_back(f.u[j] - f.v_behind / c * (xi - f.xi.front()));
        sx.velocity.push_back(f.v_behind);
        out.uy.push_back(f.uy[j]);
        out.uy_velocity.push_back(0.0);
      }
      A = f.area_behind;
      s = f.sigma_bar_behind;
    }
    const std::size_t first = sx.u.size() - ro;
    sx.interface.slip_rate.push_back(sx.velocity[first]);
    sx.interface.area.push_back(A);
    sx.interface.sigma_bar.push_back(s);
    sx.interface.slip.push_back(sx.u[first]);
  }
  return out;
}

}  // namespace slipfront::continuum
