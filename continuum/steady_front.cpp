#include "continuum/steady_front.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "continuum/front_solver.hpp"
#include "continuum/sigma_continuation.hpp"

namespace slipfront::continuum {

const char* to_string(FrontStatus s) {
  switch (s) {
    case FrontStatus::converged: return "converged";
    case FrontStatus::no_front_state: return "no_front_state";
    case FrontStatus::newton_failed: return "newton_failed";
    case FrontStatus::sonic: return "sonic";
    case FrontStatus::resticks: return "resticks";
    case FrontStatus::reverse_slip: return "reverse_slip";
    case FrontStatus::not_a_saddle: return "not_a_saddle";
    case FrontStatus::stopped: return "stopped";
  }
  return "?";
}

const char* to_string(BranchEnd e) {
  switch (e) {
    case BranchEnd::saddle_node: return "saddle_node";
    case BranchEnd::resticking: return "resticking";
    case BranchEnd::sonic: return "sonic";
    case BranchEnd::reverse_slip: return "reverse_slip";
    case BranchEnd::newton_failure: return "newton_failure";
    case BranchEnd::sigma_stop: return "sigma_stop";
    case BranchEnd::max_points: return "max_points";
    case BranchEnd::no_branch: return "no_branch";
    case BranchEnd::stopped: return "stopped";
  }
  return "?";
}

bool followed_to_end(BranchEnd e) {
  switch (e) {
    case BranchEnd::saddle_node:
    case BranchEnd::resticking:
    case BranchEnd::sonic:
    case BranchEnd::reverse_slip:
    case BranchEnd::sigma_stop: return true;
    case BranchEnd::newton_failure:
    case BranchEnd::max_points:
    case BranchEnd::no_branch:
    case BranchEnd::stopped: return false;
  }
  return false;
}

namespace detail {

using front_solver::Arclength;
using front_solver::branch_point;
using front_solver::end_of;
using front_solver::make_mesh;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

struct Model {
  double rho, mu, alpha, kappa, eta;
  /// The limiting problem at σ_d = σ_c^d: the sliding state behind is v_m and its decaying mode is
  /// the null mode (λ_s = 0 exactly), instead of rounding near a double root.
  bool saddle_node = false;
  Model(const core::InterfaceParams& law, double rho_, double mu_)
      : rho(rho_), mu(mu_), alpha(law.alpha), kappa(law.kappa), eta(law.eta) {}
  double sound_speed() const { return std::sqrt(mu / rho); }
  core::InterfaceParams law() const { return {alpha, kappa, eta}; }
};

// docs/model.md §1 in the co-moving frame behind the tip (Θ = 1), docs/fronts.md eq. (1), y = (v, A, σ̄):
//   v' = c (σ_d − σ̄ − η v)/D,  A' = −(1 − A − κ A |v|)/c,  σ̄' = −(α A v − σ̄ |v|)/c,  D = μ − ρ c².
// f, its Jacobian in y and its derivatives in c and σ_d.
struct Rhs {
  Vec3 f, fc, fs;
  Mat3 J;
};
Rhs rhs(const Model& m, const Vec3& y, double c, double sigma_d) {
  const double v = y[0], A = y[1], s = y[2];
  const double speed = std::abs(v), sign = v >= 0.0 ? 1.0 : -1.0;
  const double D = m.mu - m.rho * c * c;
  const double drive = sigma_d - s - m.eta * v;
  const double relax_A = 1.0 - A - m.kappa * A * speed;
  const double source_s = m.alpha * A * v - s * speed;
  Rhs r;
  r.f << c * drive / D, -relax_A / c, -source_s / c;
  r.J << -c * m.eta / D, 0.0, -c / D,                          //
      m.kappa * A * sign / c, (1.0 + m.kappa * speed) / c, 0.0,  //
      -(m.alpha * A - s * sign) / c, -m.alpha * v / c, speed / c;
  r.fc << drive * (m.mu + m.rho * c * c) / (D * D), relax_A / (c * c), source_s / (c * c);
  r.fs << c / D, 0.0, 0.0;
  return r;
}

// Ahead of the tip (Θ = 0, A ≡ 1): (μ − ρc²) v'' + η c v' − α v = 0, v = v_tip e^{λ₋ ξ} with λ₋ the
// negative root, σ̄ − σ_d = k v with k = α/(c |λ₋|); the tip condition σ̄ + η v = 1 gives
// v_tip = (1 − σ_d)/(η + k). docs/fronts.md eqs. (2)–(3).
struct StuckRegion {
  double lambda, k, v_tip, sigma_bar_tip;
};
StuckRegion stuck_region(const Model& m, double c, double sigma_d) {
  const double D = m.mu - m.rho * c * c;
  const double lambda = -(m.eta * c + std::sqrt(m.eta * m.eta * c * c + 4.0 * m.alpha * D)) / (2.0 * D);
  const double k = m.alpha / (c * -lambda);
  const double v_tip = (1.0 - sigma_d) / (m.eta + k);
  return {lambda, k, v_tip, 1.0 - m.eta * v_tip};
}
Vec3 tip_state(const Model& m, double c, double sigma_d) {
  const auto st = stuck_region(m, c, sigma_d);
  return {st.v_tip, 1.0, st.sigma_bar_tip};
}

// Steady sliding behind on the strengthening branch (docs/model.md §1): σ_ss(v_b) = σ_d, v_b > v_m.
Vec3 behind_state(const Model& m, double sigma_d) {
  const double v = m.saddle_node ? steady_minimum_velocity(m.law()) : strengthening_branch_velocity(m.law(), sigma_d);
  const double A = 1.0 / (1.0 + m.kappa * v);
  return {v, A, m.alpha * A};
}

// The decaying eigenvalue λ_s of the sliding state (forward ξ) and its left eigenvector w (w_σ̄ = 1).
// With g = cη/D, a = (1+κv)/c, b = v/c, K = καAv/(cD) the characteristic polynomial is
// q(λ) = (λ + g)(λ − a)(λ − b) − K; q(−g) = −K < 0 and q(0) = gab − K > 0 on the strengthening branch,
// so λ_s is the unique root in (−g, 0) (docs/fronts.md §1, §2). Found by TOMS 748 (Boost.Math).
struct StableMode {
  double lambda;
  Vec3 w;
  bool ok;
};
StableMode stable_mode(const Model& m, const Vec3& yb, double c) {
  const double v = yb[0], A = yb[1];
  const double D = m.mu - m.rho * c * c;
  const double g = c * m.eta / D, a = (1.0 + m.kappa * v) / c, b = v / c;
  const double K = m.kappa * m.alpha * A * v / (c * D);
  auto q = [&](double l) { return (l + g) * (l - a) * (l - b) - K; };
  if (m.saddle_node) return {0.0, Vec3(b * D / c, (m.alpha * v / c) / a, 1.0), K > 0.0};
  const double q0 = q(0.0);
  if (!(q0 > 0.0) || !(K > 0.0)) return {nan_value, Vec3::Constant(nan_value), false};
  std::uintmax_t iters = 200;
  const auto bracket = boost::math::tools::toms748_solve(
      q, -g, 0.0, -K, q0, boost::math::tools::eps_tolerance<double>(52), iters);
  const double l = 0.5 * (bracket.first + bracket.second);
  Vec3 w((b - l) * D / c, (m.alpha * v / c) / (a - l), 1.0);
  return {l, w, true};
}

Mat3 behind_jacobian(const Model& m, const Vec3& yb, double c, double sigma_d) {
  return rhs(m, yb, c, sigma_d).J;
}

// The chain's node block for the collocation (docs/fronts.md §3): y = (v, A, σ̄) at every node, one projection
// row behind and the tip state. Its c and σ_d columns are stored whole (exact zeros too), as they always were.
struct ChainBlock {
  using Vec = Vec3;
  using Mat = Mat3;
  using Rhs = detail::Rhs;
  static constexpr bool keep_zero_columns = true;
  Model m;

  int width() const { return 3; }
  int behind_count() const { return 1; }
  bool admissible(double c) const { return c > 0.0 && c < m.sound_speed(); }
  Rhs rhs(const Vec3& y, double c, double sd, bool /*with_jacobian*/) const { return detail::rhs(m, y, c, sd); }

  // Row 0: the projection of y_0 − y_b on the decaying mode's left eigenvector vanishes. Its c and σ_d columns
  // are central differences of the closed forms (relative error ~1e-10).
  bool behind_rows(const Vec3& y0, double c, double sd, front_solver::Rows& rows, front_solver::ScalarColumns col) const {
    auto projection = [&](double cc, double ss) {
      const Vec3 yb = behind_state(m, ss);
      const auto mode = stable_mode(m, yb, cc);
      return mode.ok ? mode.w.dot(y0 - yb) : nan_value;
    };
    const Vec3 yb = behind_state(m, sd);
    const auto mode = stable_mode(m, yb, c);
    if (!mode.ok) return false;
    rows.F[0] = mode.w.dot(y0 - yb);
    if (!rows.jacobian()) return true;
    for (int k = 0; k < 3; ++k) rows.entry(0, k, mode.w[k]);
    const double hc = 1e-6 * c;
    rows.entry(0, col.c, (projection(c + hc, sd) - projection(c - hc, sd)) / (2.0 * hc));
    if (col.free_sigma()) {
      // Near σ_c^d, v_b(σ_d) has a square-root singularity: keep σ_d − h above it.
      const double hs = std::min(1e-7, 0.25 * (sd - steady_minimum_stress(m.law())));
      rows.entry(0, col.sigma, (projection(c, sd + hs) - projection(c, sd - hs)) / (2.0 * hs));
    }
    return true;
  }

  // Rows `row` … row + 2: y_N = (v_tip(c, σ_d), 1, σ̄_tip(c, σ_d)); the c column by central differences.
  bool tip_rows(const Vec3& yN, int row, int base, double c, double sd, front_solver::Rows& rows,
                front_solver::ScalarColumns col) const {
    rows.F.segment<3>(row) = yN - tip_state(m, c, sd);
    if (!rows.jacobian()) return true;
    for (int k = 0; k < 3; ++k) rows.entry(row + k, base + k, 1.0);
    const double hc = 1e-6 * c;
    const Vec3 dc = -(tip_state(m, c + hc, sd) - tip_state(m, c - hc, sd)) / (2.0 * hc);
    rows.entry(row, col.c, dc[0]);
    rows.entry(row + 2, col.c, dc[2]);
    if (col.free_sigma()) {
      // ∂v_tip/∂σ_d = −1/(η + k), ∂σ̄_tip/∂σ_d = η/(η + k) (k does not depend on σ_d).
      const auto st = stuck_region(m, c, sd);
      rows.entry(row, col.sigma, 1.0 / (m.eta + st.k));
      rows.entry(row + 2, col.sigma, -m.eta / (m.eta + st.k));
    }
    return true;
  }
};

// The discrete boundary-value problem of the chain (docs/fronts.md §3): the shared collocation on its block.
using Collocation = front_solver::Collocation<ChainBlock>;

// Damped Newton with the chain's rule (docs/fronts.md §3): converged when a full step accepted by the line
// search is below the tolerance.
front_solver::NewtonResult newton(const Collocation& col, Eigen::VectorXd& x, double tol, int max_iter) {
  front_solver::NewtonRule rule;
  rule.tolerance = tol;
  rule.max_iterations = max_iter;
  rule.inadmissible_guess = "the initial guess is not admissible (c outside (0, c_s), or no decaying mode behind)";
  return front_solver::newton([&](const Eigen::VectorXd& z, Eigen::VectorXd& F, Eigen::SparseMatrix<double>* jac) {
    return col.assemble(z, F, jac);
  }, x, rule);
}

// Backward shooting from the tip (cold start only): classical RK4 from ξ = 0 to ξ = −L at speed c;
// returns the profile on the mesh and the projection w·(y − y_b) where the trajectory ends (at −L or
// where it leaves the physical region). Written by hand: 20 lines, used only to start Newton.
struct Shot {
  double mismatch;
  std::vector<Vec3> profile;
};
Shot shoot(const Model& m, const std::vector<double>& xi, double c, double sigma_d) {
  const Vec3 yb = behind_state(m, sigma_d);
  const auto mode = stable_mode(m, yb, c);
  Shot out{nan_value, std::vector<Vec3>(xi.size(), yb)};
  if (!mode.ok) return out;
  Vec3 y = tip_state(m, c, sigma_d);
  const std::size_t N = xi.size() - 1;
  out.profile[N] = y;
  auto f = [&](const Vec3& z) { return rhs(m, z, c, sigma_d).f; };
  for (std::size_t i = N; i-- > 0;) {
    const double H = xi[i] - xi[i + 1];  // < 0
    const int sub = std::max(1, static_cast<int>(std::ceil(std::abs(H) / 0.05)));
    const double h = H / sub;
    for (int s = 0; s < sub; ++s) {
      const Vec3 k1 = f(y), k2 = f(y + 0.5 * h * k1), k3 = f(y + 0.5 * h * k2), k4 = f(y + h * k3);
      y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    const bool lost = !y.allFinite() || y[0] <= 0.0 || y[0] > 10.0 * yb[0] + 10.0 || y[1] <= 0.0 || y[1] > 1.5;
    if (lost) {
      out.mismatch = y.allFinite() ? mode.w.dot(y - yb) : nan_value;
      return out;  // the rest of the profile stays at the sliding state
    }
    out.profile[i] = y;
  }
  out.mismatch = mode.w.dot(y - yb);
  return out;
}

// Domain length: the nonlinear region near the tip plus `decay_lengths` e-folds of the slowest growing
// mode of the sliding state (the error of the linear projection condition is ~ e^{−2 decay_lengths}).
double domain_length(const Model& m, const SteadyFrontOptions& o, double c, double sigma_d) {
  if (o.domain_length > 0.0) return o.domain_length;
  const Vec3 yb = behind_state(m, sigma_d);
  const Mat3 J = behind_jacobian(m, yb, c, sigma_d);
  const Eigen::EigenSolver<Mat3> es(J, false);
  double slowest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)  // the growing modes (not the null mode at σ_c^d)
    if (es.eigenvalues()[k].real() > 1e-9 * J.norm()) slowest = std::min(slowest, es.eigenvalues()[k].real());
  if (!std::isfinite(slowest)) slowest = 1.0 / c;
  return o.tip_length * c / (1.0 + m.kappa * yb[0]) + o.decay_lengths / slowest;
}

// The converged iterate x into f: speed, tip and far-behind states, the profiles (v, A, σ̄) on the
// mesh. Returns the sliding state behind, y_b.
Vec3 store_solution(const Model& m, const Collocation& col, const Eigen::VectorXd& x, SteadyFront& f) {
  const auto& xi = col.xi();
  const int n = col.nodes();
  const double c = col.c_of(x), sd = col.sigma_of(x);
  f.sigma_d = sd;
  f.c = c;
  const auto st = stuck_region(m, c, sd);
  f.v_tip = st.v_tip;
  f.sigma_bar_tip = st.sigma_bar_tip;
  f.stuck_decay = st.lambda;
  const Vec3 yb = behind_state(m, sd);
  f.v_behind = yb[0];
  f.area_behind = yb[1];
  f.sigma_bar_behind = yb[2];
  f.far_field_strain = -yb[0] / c;
  f.xi = xi;
  f.domain_length = -xi.front();
  f.area.resize(xi.size());
  f.sigma_bar.resize(xi.size());
  f.slip_rate.resize(xi.size());
  f.slip.resize(xi.size());
  for (int i = 0; i < n; ++i) {
    const Vec3 y = col.y(x, i);
    f.slip_rate[static_cast<std::size_t>(i)] = y[0];
    f.area[static_cast<std::size_t>(i)] = y[1];
    f.sigma_bar[static_cast<std::size_t>(i)] = y[2];
  }
  return yb;
}

// u: σ̄ = α u at the tip (stuck convention); U' = −v/c integrated exactly on the cubic Hermite
// interpolant of v (the collocation polynomial): ∫ v = h (v_i + v_{i+1})/2 + h² (v'_i − v'_{i+1})/12.
void integrate_slip(const Model& m, const Collocation& col, const Eigen::VectorXd& x, SteadyFront& f) {
  const auto& xi = col.xi();
  const double c = col.c_of(x), sd = col.sigma_of(x);
  f.slip.back() = f.sigma_bar_tip / m.alpha;
  for (int i = col.nodes() - 1; i-- > 0;) {
    const auto a = static_cast<std::size_t>(i), b = a + 1;
    const double h = xi[b] - xi[a];
    const double da = rhs(m, col.y(x, i), c, sd).f[0], db = rhs(m, col.y(x, i + 1), c, sd).f[0];
    const double integral = h * 0.5 * (f.slip_rate[a] + f.slip_rate[b]) + h * h * (da - db) / 12.0;
    f.slip[a] = f.slip[b] + integral / c;
  }
}

// The modes of the sliding state behind (forward ξ): its eigenvalues and decaying eigenvalue into f,
// and, when it is a saddle (one decaying mode, the null mode at σ_c^d counted as one, and two growing),
// the tail y(−L) − y_b = Σ d_k r_k over the eigenvectors (d_stable = 0 by the projection condition).
struct ModeCount {
  int decaying = 0, growing = 0;
};
ModeCount behind_modes(const Model& m, const Collocation& col, const Eigen::VectorXd& x, const Vec3& yb, SteadyFront& f) {
  const double c = col.c_of(x), sd = col.sigma_of(x);
  const Mat3 Jb = behind_jacobian(m, yb, c, sd);
  const Eigen::EigenSolver<Mat3> es(Jb, true);
  int negative = 0, positive = 0, stable_index = -1;
  const double centre = m.saddle_node ? 1e-9 * Jb.norm() : 0.0;  // the null mode at σ_c^d
  for (int k = 0; k < 3; ++k) {
    f.behind_eigenvalues[static_cast<std::size_t>(k)] = es.eigenvalues()[k];
    if (es.eigenvalues()[k].real() < 0.0 || (m.saddle_node && std::abs(es.eigenvalues()[k]) <= centre)) {
      ++negative;
      stable_index = k;
    } else if (es.eigenvalues()[k].real() > 0.0) {
      ++positive;
    }
  }
  f.stable_eigenvalue = stable_mode(m, yb, c).lambda;
  if (negative == 1 && positive == 2) {
    const Eigen::Matrix3cd R = es.eigenvectors();
    const Eigen::Vector3cd d = R.partialPivLu().solve((col.y(x, 0) - yb).cast<std::complex<double>>());
    int j = 0;
    for (int k = 0; k < 3; ++k) {
      if (k == stable_index) continue;
      f.tail_rate[static_cast<std::size_t>(j)] = es.eigenvalues()[k];
      for (int r = 0; r < 3; ++r) f.tail_mode[static_cast<std::size_t>(j)][static_cast<std::size_t>(r)] = d[k] * R(r, k);
      ++j;
    }
  }
  return {negative, positive};
}

// The status of a converged iterate: a front only if the sliding state behind is a saddle, v > 0 and
// |σ|/A > 1 behind the tip (docs/fronts.md §4), with the first violated condition as the reason.
void classify(const ModeCount& modes, SteadyFront& f) {
  f.status = FrontStatus::converged;
  f.reason.clear();
  if (modes.decaying != 1 || modes.growing != 2) {
    f.status = FrontStatus::not_a_saddle;
    f.reason = "the sliding state behind has " + std::to_string(modes.decaying) + " decaying and " +
               std::to_string(modes.growing) + " growing modes (need 1 and 2)";
  } else if (f.min_slip_rate <= 0.0) {
    f.status = FrontStatus::reverse_slip;
    f.reason = "v <= 0 behind the tip (min v = " + core::format_number(f.min_slip_rate) + ")";
  } else if (f.overstress_margin <= 0.0) {
    f.status = FrontStatus::resticks;
    f.reason = "|sigma|/A - 1 <= 0 behind the tip (min " + core::format_number(f.overstress_margin) +
               "): Theta = 1 violated";
  }
}

// Post-processing of a converged iterate: fields, u, diagnostics, admissibility, tail modes.
void finish(const Model& m, const Collocation& col, const Eigen::VectorXd& x, SteadyFront& f) {
  const Vec3 yb = store_solution(m, col, x, f);  // c, tip and far-behind states, profiles
  integrate_slip(m, col, x, f);                  // u
  // Θ = 1 behind the tip needs |σ|/A > 1 there: |σ|/A − 1 vanishes at the tip and grows behind it
  f.overstress_margin = front_solver::overstress_margin(f.sigma_bar, f.slip_rate, f.area, m.eta);
  f.min_slip_rate = *std::min_element(f.slip_rate.begin(), f.slip_rate.end());
  const ModeCount modes = behind_modes(m, col, x, yb, f);  // eigenvalues behind, tail beyond −L
  classify(modes, f);                                      // converged, or why not a front
}

SteadyFront empty_front(const Model& m, double sigma_d) {
  SteadyFront f;
  f.law = m.law();
  f.rho = m.rho;
  f.mu = m.mu;
  f.sigma_d = sigma_d;
  return f;
}

// Pack a guess (previous front, or a shot) on the mesh of `col`.
Eigen::VectorXd pack(const Collocation& col, const std::vector<Vec3>& profile, double c, double sigma_d, bool free_sigma) {
  Eigen::VectorXd x(col.size());
  for (int i = 0; i < col.nodes(); ++i) x.segment<3>(3 * i) = profile[static_cast<std::size_t>(i)];
  x[col.c_index()] = c;
  if (free_sigma) x[col.c_index() + 1] = sigma_d;
  return x;
}

std::vector<Vec3> resample(const SteadyFront& g, const std::vector<double>& xi) {
  const auto s = sample_steady_front(g, xi, 0.0);
  std::vector<Vec3> p(xi.size());
  for (std::size_t i = 0; i < xi.size(); ++i) p[i] = Vec3(s.slip_rate[i], s.area[i], s.sigma_bar[i]);
  return p;
}

// The speed scale of the fronts, sqrt(μα/(ηκ)) (docs/fronts.md §6: c_min ≈ 0.58 of it in the paper's regime).
double speed_scale(const Model& m) { return std::sqrt(m.mu * m.alpha / (m.eta * m.kappa)); }

// The slowest speed the cold start tries: 1e-3 of the speed scale (or of c_s, if smaller). On every branch
// computed c_min/scale ≥ 0.19 (docs/fronts.md §9), so this is far below any front.
double slowest_cold_speed(const Model& m) {
  const double scale = speed_scale(m), cs = m.sound_speed();
  return 1e-3 * (scale < cs ? scale : cs);
}

// The two parts of the cold-start scan: upward over c = 0.02k c_s, k = 1 … 49 (where fronts are when inertia
// matters; unchanged, so every front found before is found bit for bit as before), and, for a front slower
// than 0.02 c_s (c_s large against the speed scale), downward from 0.02 c_s by a factor 0.8 a step to
// slowest_cold_speed.
enum class ColdScan { grid, below };

// Cold-start speed (docs/fronts.md §3): the first sign change of the shooting mismatch in that part of the
// scan, then TOMS 748.
std::optional<double> bracket_speed(const Model& m, const SteadyFrontOptions& o, double sigma_d, ColdScan part) {
  const double cs = m.sound_speed();
  auto mismatch = [&](double c) {
    const double L = std::min(domain_length(m, o, c, sigma_d), 400.0);
    return shoot(m, make_mesh(L, 400, 0.05), c, sigma_d).mismatch;
  };
  auto changes_sign = [](double a, double b) { return std::isfinite(a) && std::isfinite(b) && a * b < 0.0; };
  auto refine = [&](double lo, double hi, double f_lo, double f_hi) {
    std::uintmax_t iters = 60;
    const auto br = boost::math::tools::toms748_solve(mismatch, lo, hi, f_lo, f_hi,
                                                      boost::math::tools::eps_tolerance<double>(30), iters);
    return 0.5 * (br.first + br.second);
  };
  const double first_c = 0.02 * cs, first = mismatch(first_c);
  if (part == ColdScan::grid) {
    double prev_c = first_c, prev = first;
    for (int k = 2; k <= 49; ++k) {  // upward over 0.02k c_s
      const double cc = 0.02 * k * cs, mm = mismatch(cc);
      if (changes_sign(prev, mm)) return refine(prev_c, cc, prev, mm);
      prev_c = cc;
      prev = mm;
    }
    return std::nullopt;
  }
  double upper_c = first_c, upper = first;
  for (double cc = 0.8 * first_c; cc >= slowest_cold_speed(m); cc *= 0.8) {  // downward below 0.02 c_s
    const double mm = mismatch(cc);
    if (changes_sign(mm, upper)) return refine(cc, upper_c, mm, upper);
    upper_c = cc;
    upper = mm;
  }
  return std::nullopt;
}

// One Newton solve on a fresh mesh; σ_d fixed or (with arc) free.
SteadyFront solve_on_mesh(const Model& m, const SteadyFrontOptions& o, double sigma_d, double c_guess,
                          const std::vector<Vec3>* profile, const SteadyFront* guess,
                          std::optional<Arclength> arc) {
  SteadyFront f = empty_front(m, sigma_d);
  const double L = domain_length(m, o, c_guess, sigma_d);
  Collocation col(ChainBlock{m}, make_mesh(L, o.intervals, o.tip_spacing, o.grading), sigma_d, arc);
  std::vector<Vec3> p;
  if (guess) p = resample(*guess, col.xi());
  else if (profile) p = *profile;
  else p = shoot(m, col.xi(), c_guess, sigma_d).profile;
  if (p.size() != col.xi().size()) p = shoot(m, col.xi(), c_guess, sigma_d).profile;
  Eigen::VectorXd x = pack(col, p, c_guess, sigma_d, arc.has_value());
  const auto nr = newton(col, x, o.tolerance, o.max_newton);
  f.newton_iterations = nr.iterations;
  f.domain_length = L;
  if (!nr.converged) {
    f.status = col.c_of(x) >= 0.999 * m.sound_speed() ? FrontStatus::sonic : FrontStatus::newton_failed;
    f.reason = nr.failure;
    f.c = col.c_of(x);
    f.sigma_d = col.sigma_of(x);
    return f;
  }
  finish(m, col, x, f);
  f.residual_norm = nr.residual;
  f.saddle_node_limit = m.saddle_node;
  // Error estimate of c (docs/fronts.md §3): the same problem on every other node, (c_2h − c_h)/15.
  if (o.estimate_error && o.intervals % 2 == 0 && o.intervals >= 8)
    f.speed_error = front_solver::coarse_speed_error(col, x, ChainBlock{m}, f.sigma_d, [&](const Collocation& coarse, Eigen::VectorXd& xc) {
      return newton(coarse, xc, o.tolerance, o.max_newton);
    });
  return f;
}

// A cold start: Newton from the speed bracketed on the grid 0.02k c_s, as ever; when that gives no front
// (no sign change there, or a spurious one: a front far below 0.02 c_s), from the speed bracketed below it.
// A failure reports the first attempt's status and reason.
SteadyFront solve_cold(const Model& m, const SteadyFrontOptions& o, double sigma_d, const SteadyFront* guess) {
  std::optional<SteadyFront> first;
  for (const ColdScan part : {ColdScan::grid, ColdScan::below}) {
    const auto c0 = bracket_speed(m, o, sigma_d, part);
    if (!c0) continue;
    SteadyFront f = solve_on_mesh(m, o, sigma_d, *c0, nullptr, guess, std::nullopt);
    if (f.status == FrontStatus::converged) return f;
    if (!first) first = std::move(f);
  }
  if (first) return std::move(*first);
  SteadyFront f = empty_front(m, sigma_d);
  f.status = FrontStatus::newton_failed;
  f.reason = "no sign change of the shooting mismatch for c in [" + core::format_number(slowest_cold_speed(m)) + ", " +
             core::format_number(0.98 * m.sound_speed()) + "] (c_s = " + core::format_number(m.sound_speed()) +
             "): no starting speed";
  return f;
}

}  // namespace detail

SteadyFront solve_steady_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                               const SteadyFrontOptions& o, const SteadyFront* guess) {
  const detail::Model m(law, bulk.rho, bulk.mu);
  const double sigma_c = steady_minimum_stress(law);
  if (!(sigma_d > sigma_c) || !(sigma_d < 1.0)) {
    SteadyFront f = detail::empty_front(m, sigma_d);
    f.status = FrontStatus::no_front_state;
    f.reason = "sigma_d = " + core::format_number(sigma_d) + " outside (sigma_c^d, 1) = (" + core::format_number(sigma_c) +
               ", 1): no sliding state on the strengthening branch behind, or no stuck state ahead";
    return f;
  }
  const double c0 = guess ? guess->c : o.c_guess;
  if (!(c0 > 0.0)) return detail::solve_cold(m, o, sigma_d, guess);
  return detail::solve_on_mesh(m, o, sigma_d, c0, nullptr, guess, std::nullopt);
}

SteadyFront solve_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                    const SteadyFrontOptions& o, const SteadyFront* guess) {
  detail::Model m(law, bulk.rho, bulk.mu);
  m.saddle_node = true;
  const double sigma_c = steady_sliding(law, steady_minimum_velocity(law)).sigma;  // = σ_c^d
  const double c0 = guess ? guess->c : o.c_guess;
  if (!(c0 > 0.0)) {
    SteadyFront f = detail::empty_front(m, sigma_c);
    f.status = FrontStatus::newton_failed;
    f.reason = "the front at sigma_c^d needs a guess (a front of the branch close to sigma_c^d)";
    return f;
  }
  return detail::solve_on_mesh(m, o, sigma_c, c0, nullptr, guess, std::nullopt);
}

namespace detail {

// The continuation of the branch in σ_d (docs/fronts.md §4): the shared stages (front_solver::SigmaContinuation)
// with the chain's fronts, its first front, its limiting front and Brent's method at an interior minimum of c.
class BranchContinuation
    : public front_solver::SigmaContinuation<BranchContinuation, SteadyFront, FrontBranch, ContinuationOptions> {
 public:
  BranchContinuation(const core::InterfaceParams& law, const core::BulkParams& bulk, const ContinuationOptions& o)
      : SigmaContinuation(o, std::sqrt(bulk.mu / bulk.rho), steady_minimum_stress(law)), law_(law), bulk_(bulk),
        m_(law, bulk.rho, bulk.mu) {}

  bool start() { return admissible_parameters() && first_front() && second_front(); }
  void solve_limiting_front();
  void locate_minimal_speed();

 private:
  friend SigmaContinuation;
  bool admissible_parameters();
  bool stop_requested();
  bool first_front();
  bool reached_own_end();
  SteadyFront solve_at(double sigma_d, const SteadyFront* guess) const {
    return solve_steady_front(law_, bulk_, sigma_d, o_.front, guess);
  }
  SteadyFront correct(double sigma_p, double c_p, const Arclength& arc) const {
    return solve_on_mesh(m_, o_.front, sigma_p, c_p, nullptr, &cur_, arc);
  }
  void keep(const SteadyFront&) const {}

  const core::InterfaceParams& law_;
  const core::BulkParams& bulk_;
  const Model m_;
};

// Before anything is solved: a branch needs the steady law's minimum (v_m, σ_c^d) at a finite v > 0,
// where it ends (§4), and σ_c^d < 1: steady sliding behind needs σ_d > σ_c^d, the stuck state ahead σ_d < 1.
bool BranchContinuation::admissible_parameters() {
  const double v_m = steady_minimum_velocity(law_);
  const std::string law = "alpha = " + core::format_number(law_.alpha) + ", kappa = " + core::format_number(law_.kappa) +
                          ", eta = " + core::format_number(law_.eta);
  if (!std::isfinite(v_m) || !(v_m > 0.0) || !std::isfinite(sigma_c_)) {
    stop(BranchEnd::no_branch, "the steady friction law sigma_ss(v) = alpha/(1 + kappa v) + eta v has no minimum at a "
                               "finite v > 0 (" + law + ": v_m = " + core::format_number(v_m) + ", sigma_c^d = " +
                               core::format_number(sigma_c_) + "): there is no saddle-node sigma_c^d for a branch "
                               "of fronts to end at (docs/fronts.md §4); nothing solved");
    return false;
  }
  if (!(sigma_c_ < 1.0)) {
    stop(BranchEnd::no_branch, "sigma_c^d = " + core::format_number(sigma_c_) + " >= 1 (" + law +
                               "): steady sliding behind a front needs sigma_d > sigma_c^d and the stuck state "
                               "ahead sigma_d < 1, so no sigma_d has a front; nothing solved");
    return false;
  }
  return true;
}

// A stop request (options.stop) ends the branch where it is, with the fronts found so far.
bool BranchContinuation::stop_requested() {
  if (!o_.stop || !o_.stop()) return false;
  stop(BranchEnd::stopped, "stopped on request after " + std::to_string(br_.points.size()) + " fronts" +
                               (br_.points.empty() ? std::string()
                                                   : ", at sigma_d = " + core::format_number(br_.points.back().sigma_d)) +
                               ": the branch is partial, c_min not computed");
  return true;
}

// Why a cold start found nothing, in the physics' terms when the numbers say so: c_s far below the speed
// scale (c_min/scale was 0.19–0.68 on every branch computed, docs/fronts.md §9).
std::string supersonic_hint(const Model& m) {
  const double scale = speed_scale(m), cs = m.sound_speed();
  if (!(cs < 0.19 * scale)) return "";
  return "; c_s = " + core::format_number(cs) + " is " + core::format_number(cs / scale) +
         " times the speed scale sqrt(mu alpha/(eta kappa)) = " + core::format_number(scale) +
         ", and c_min was 0.19-0.68 times it on every branch computed (docs/fronts.md §9): the fronts would be "
         "faster than sound";
}

// §4 step 1: the first front, cold at σ_start. With no front there (its speed would reach c_s: the
// branch's upper end lies below), try σ_c^d + (σ_start − σ_c^d)·0.8^k, k = 1 … 20, and say so.
bool BranchContinuation::first_front() {
  if (stop_requested()) return false;
  prev_ = solve_steady_front(law_, bulk_, o_.sigma_start, o_.front);
  br_.sigma_first = o_.sigma_start;
  for (int k = 1; k <= 20 && prev_.status != FrontStatus::converged; ++k) {
    if (stop_requested()) return false;
    br_.sigma_first = sigma_c_ + (o_.sigma_start - sigma_c_) * std::pow(0.8, k);
    prev_ = solve_steady_front(law_, bulk_, br_.sigma_first, o_.front);
  }
  if (prev_.status != FrontStatus::converged) {
    stop(end_of(prev_.status), "no front at sigma_start = " + core::format_number(o_.sigma_start) +
                                   " nor below it (down to sigma_d = " + core::format_number(br_.sigma_first) +
                                   "): " + prev_.reason + supersonic_hint(m_));
    br_.sigma_first = detail::nan_value;
    br_.last = prev_;
    return false;
  }
  br_.points.push_back(branch_point(prev_));
  return true;
}

// The chain's own end besides σ_c^d: σ_stop.
bool BranchContinuation::reached_own_end() {
  if (cur_.sigma_d <= o_.sigma_stop) {
    stop(BranchEnd::sigma_stop, "reached sigma_stop = " + core::format_number(o_.sigma_stop));
    return true;
  }
  return false;
}

// The end at σ_c^d: the limiting front (v_b = v_m, null mode behind), solved directly.
void BranchContinuation::solve_limiting_front() {
  const SteadyFront end = solve_saddle_node_front(law_, bulk_, o_.front, &cur_);
  if (end.status == FrontStatus::converged) {
    br_.points.push_back(branch_point(end));
    br_.last = end;
    br_.reason = "sigma_d -> sigma_c^d = " + core::format_number(sigma_c_) +
                 ": v_b -> v_m, the decaying eigenvalue of the sliding state behind -> 0 (saddle-node with the "
                 "weakening branch); below sigma_c^d there is no steady sliding state behind a front. Limiting "
                 "front at sigma_c^d solved directly: c = " + core::format_number(end.c);
  } else {
    br_.reason = "sigma_d -> sigma_c^d (saddle-node of the sliding state behind); the limiting front did not "
                 "converge: " + end.reason;
  }
}

// Minimal speed: the smallest c on the branch; an interior minimum is located by Brent's method on
// fixed-σ_d solves between its neighbours (so it does not depend on the continuation step).
void BranchContinuation::locate_minimal_speed() {
  std::size_t k = 0;
  if (!slowest_point_to_c_min(k)) return;  // not computed: NaN
  if (br_.c_min_at_end || k == 0 || !o_.refine_minimum) return;
  SteadyFront seed = solve_steady_front(law_, bulk_, br_.points[k].sigma_d, o_.front, &br_.last);
  if (seed.status != FrontStatus::converged) seed = cur_;
  auto speed = [&](double sd) {
    const SteadyFront f = solve_steady_front(law_, bulk_, sd, o_.front, &seed);
    return f.status == FrontStatus::converged ? f.c : std::numeric_limits<double>::infinity();
  };
  const double lo = std::min(br_.points[k - 1].sigma_d, br_.points[k + 1].sigma_d);
  const double hi = std::max(br_.points[k - 1].sigma_d, br_.points[k + 1].sigma_d);
  std::uintmax_t iters = 100;
  const auto best = boost::math::tools::brent_find_minima(speed, lo, hi, 26, iters);
  if (best.second < br_.c_min) {
    br_.c_min = best.second;
    br_.sigma_d_at_c_min = best.first;
  }
}

}  // namespace detail

// Continuation of the steady-front branch in σ_d (docs/fronts.md §4).
FrontBranch continue_steady_fronts(const core::InterfaceParams& law, const core::BulkParams& bulk, const ContinuationOptions& o) {
  detail::BranchContinuation run(law, bulk, o);
  if (!run.start()) return run.take_branch();  // first front cold, second by a natural step in σ_d
  run.follow();                                // pseudo-arclength down to an end of the branch
  if (run.ended_at_saddle_node()) run.solve_limiting_front();  // the front at σ_c^d itself
  run.locate_minimal_speed();                  // c_min (Brent's method at an interior minimum)
  return run.take_branch();
}

namespace detail {

// One fit of c_min = a · scale by least squares through the origin over the points of `parameter` ("all":
// every point) that have a c_min; refused (NaN) below min_scaling_fit_points, and for "all" unless every
// parameter varied (asked for two values or more, `asked`) has that many.
ScalingFit fit_scaling(const std::vector<ScalingPoint>& points, const std::string& parameter,
                       const std::vector<std::pair<std::string, std::size_t>>& asked) {
  const bool all = parameter == "all";
  auto in_fit = [&](const ScalingPoint& q) { return all || q.parameter == parameter; };
  auto has_c_min = [](const ScalingPoint& q) { return std::isfinite(q.c_min) && q.c_min > 0.0; };
  ScalingFit f{parameter, nan_value, nan_value, nan_value, 0, 0, ""};
  double cs = 0.0, ss = 0.0;
  std::string without;  // the points with no c_min, by name and value
  for (const auto& q : points) {
    if (!in_fit(q)) continue;
    ++f.tried;
    if (!has_c_min(q)) {
      without += (without.empty() ? "" : ", ") + q.parameter + " = " + core::format_number(q.value) + " (" +
                 to_string(q.end) + ")";
      continue;
    }
    cs += q.c_min * q.scale;
    ss += q.scale * q.scale;
    ++f.points;
  }
  const std::string counted = std::to_string(f.points) + " of " + std::to_string(f.tried) + " points have a c_min" +
                              (without.empty() ? std::string() : " (none for " + without + ")");
  const std::string need = "a fit needs at least " + std::to_string(min_scaling_fit_points) +
                           " (the line through the origin passes exactly through one point: a deviation of 0 tests "
                           "nothing)";
  if (f.points < min_scaling_fit_points) {
    f.refused = "only " + counted + "; " + need;
    return f;
  }
  if (all) {
    for (const auto& [name, values] : asked) {
      if (values < 2) continue;
      int n = 0;
      for (const auto& q : points) n += q.parameter == name && has_c_min(q) ? 1 : 0;
      if (n < min_scaling_fit_points) {
        f.refused = counted + ", but only " + std::to_string(n) + " with " + name + " varied; " + need +
                    " in every parameter varied, so that each exponent of mu alpha/(eta kappa) is tested";
        return f;
      }
    }
  }
  f.prefactor = cs / ss;
  f.spread = 0.0;
  double sum2 = 0.0;
  for (const auto& q : points)
    if (in_fit(q) && has_c_min(q)) {
      const double r = (q.c_min - f.prefactor * q.scale) / (f.prefactor * q.scale);
      f.spread = std::max(f.spread, std::abs(r));
      sum2 += r * r;
    }
  f.rms_relative = std::sqrt(sum2 / f.points);
  return f;
}

}  // namespace detail

ScalingStudy minimal_speed_scaling(const core::InterfaceParams& law, const core::BulkParams& bulk, const ScalingOptions& o) {
  ScalingStudy study;
  const std::pair<const char*, const std::vector<double>*> sweeps[] = {
      {"mu", &o.mu}, {"alpha", &o.alpha}, {"eta", &o.eta}, {"kappa", &o.kappa}};
  std::vector<std::pair<std::string, std::size_t>> asked;
  for (const auto& [name, values] : sweeps) asked.emplace_back(name, values->size());
  auto one_point = [&](const std::string& p, double value) {
    core::InterfaceParams l = law;
    core::BulkParams b = bulk;
    if (p == "mu") b.mu = value;
    else if (p == "alpha") l.alpha = value;
    else if (p == "eta") l.eta = value;
    else l.kappa = value;
    ContinuationOptions co = o.continuation;
    const FrontBranch br = continue_steady_fronts(l, b, co);
    if (br.end == BranchEnd::stopped) return false;
    const double scale = std::sqrt(b.mu * l.alpha / (l.eta * l.kappa));
    double c_min_error = std::numeric_limits<double>::quiet_NaN();
    for (const auto& q : br.points)
      if (std::isfinite(br.c_min) && q.c == br.c_min) c_min_error = q.speed_error;
    study.points.push_back({p, value, br.c_min, br.sigma_d_at_c_min, scale, br.end,
                            std::isfinite(br.c_min) ? std::string() : br.reason, c_min_error});
    return true;
  };
  for (const auto& [name, values] : sweeps) {
    for (double value : *values) {
      study.stopped = (o.continuation.stop && o.continuation.stop()) || !one_point(name, value);
      if (study.stopped) break;
    }
    if (study.stopped) break;
  }
  for (const char* p : {"mu", "alpha", "eta", "kappa", "all"}) study.fits.push_back(detail::fit_scaling(study.points, p, asked));
  return study;
}

FrontSample sample_steady_front(const SteadyFront& f, std::span<const double> x, double x_tip) {
  const detail::Model m(f.law, f.rho, f.mu);
  const auto st = detail::stuck_region(m, f.c, f.sigma_d);
  FrontSample out;
  const std::size_t n = x.size();
  out.area.resize(n);
  out.sigma_bar.resize(n);
  out.slip_rate.resize(n);
  out.slip.resize(n);
  const double L = -f.xi.front();
  for (std::size_t j = 0; j < n; ++j) {
    const double xi = x[j] - x_tip;
    double v, A, s, u;
    if (xi >= 0.0) {
      // Stuck region ahead (docs/fronts.md eq. 2): A = 1, v = v_tip e^{λ₋ξ}, σ̄ = σ_d + k v = α u.
      v = f.v_tip * std::exp(st.lambda * xi);
      A = 1.0;
      s = f.sigma_d + st.k * v;
      u = s / m.alpha;
    } else if (xi >= -L) {
      // Collocation polynomial: cubic Hermite on (y, f) at the ends of the interval.
      const auto it = std::upper_bound(f.xi.begin(), f.xi.end(), xi);
      const std::size_t b = std::min<std::size_t>(static_cast<std::size_t>(it - f.xi.begin()), f.xi.size() - 1);
      const std::size_t a = b - 1;
      const double h = f.xi[b] - f.xi[a], t = (xi - f.xi[a]) / h;
      const detail::Vec3 ya(f.slip_rate[a], f.area[a], f.sigma_bar[a]), yb(f.slip_rate[b], f.area[b], f.sigma_bar[b]);
      const detail::Vec3 fa = detail::rhs(m, ya, f.c, f.sigma_d).f, fb = detail::rhs(m, yb, f.c, f.sigma_d).f;
      const double h00 = (2 * t - 3) * t * t + 1, h10 = ((t - 2) * t + 1) * t, h01 = (3 - 2 * t) * t * t, h11 = (t - 1) * t * t;
      const detail::Vec3 y = h00 * ya + h10 * h * fa + h01 * yb + h11 * h * fb;
      v = y[0];
      A = y[1];
      s = y[2];
      // ∫_{ξ_a}^{ξ} v of the same cubic; U' = −v/c.
      const double t2 = t * t, t3 = t2 * t, t4 = t3 * t;
      const double H00 = t4 / 2 - t3 + t, H10 = t4 / 4 - 2 * t3 / 3 + t2 / 2, H01 = -t4 / 2 + t3, H11 = t4 / 4 - t3 / 3;
      const double integral = h * (ya[0] * H00 + h * fa[0] * H10 + yb[0] * H01 + h * fb[0] * H11);
      u = f.slip[a] - integral / f.c;
    } else {
      // Beyond −L: the two growing modes of the sliding state, y = y_b + Σ Re(m_k e^{λ_k (ξ + L)}).
      const double z = xi + L;  // < 0
      v = f.v_behind;
      A = f.area_behind;
      s = f.sigma_bar_behind;
      double int_v = f.v_behind * z;  // ∫_{−L}^{ξ} v
      for (std::size_t k = 0; k < 2; ++k) {
        const auto e = std::exp(f.tail_rate[k] * z);
        v += (f.tail_mode[k][0] * e).real();
        A += (f.tail_mode[k][1] * e).real();
        s += (f.tail_mode[k][2] * e).real();
        if (std::abs(f.tail_rate[k]) > 0.0) int_v += (f.tail_mode[k][0] * (e - 1.0) / f.tail_rate[k]).real();
      }
      u = f.slip.front() - int_v / f.c;
    }
    out.slip_rate[j] = v;
    out.area[j] = A;
    out.sigma_bar[j] = s;
    out.slip[j] = u;
  }
  return out;
}

}  // namespace slipfront::continuum
