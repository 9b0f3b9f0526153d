#pragma once
// Steady fronts (traveling waves) of the continuum model under homogeneous loading, docs/model.md §1, and their
// continuation in the applied stress σ_d down to the end of the branch (issue 11). Derivation, method,
// order and results: docs/fronts.md.
//
// A front runs toward +x at speed c into the stuck interface (A = 1, σ̄ = σ_d, v = 0 far ahead) and
// leaves steady sliding on the strengthening branch far behind (σ_ss(v_b) = σ_d, v_b > v_m). In the
// co-moving coordinate ξ = x − c t (tip at ξ = 0, v = −c U'), docs/fronts.md §1:
//   v' = c (σ_d − σ̄ − η v)/(μ − ρ c²),  A' = −(1 − A − Θ κ A |v|)/c,  σ̄' = −(α A v − Θ σ̄ |v|)/c.
// Ahead of the tip (Θ = 0) the solution is closed-form (A ≡ 1, v = v_tip e^{λ₋ξ}); behind it (Θ = 1)
// the solver collocates the system on [−L, 0] (Lobatto IIIA, 4th order; Newton with Eigen's SparseLU),
// with c an unknown and a projection condition at ξ = −L onto the unstable subspace of the sliding state.
//
// Plain structs in and out; nothing here does I/O.
#include <array>
#include <complex>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "continuum/friction_law.hpp"
#include "core/params.hpp"

namespace slipfront::continuum {

/// Discretisation and Newton settings of one steady-front solve.
struct SteadyFrontOptions {
  int intervals = 600;          ///< mesh intervals on [−L, 0]
  double tip_spacing = 0.05;    ///< length of the interval at the tip (the mesh grows geometrically behind)
  double grading = 0.0;         ///< β of the mesh map ξ_j = −L (e^{β j/N} − 1)/(e^β − 1) if > 0 (overrides tip_spacing)
  double domain_length = 0.0;   ///< L; 0 = automatic: tip_length + decay_lengths / (slowest decay rate behind)
  double tip_length = 40.0;     ///< automatic L: extent of the nonlinear region, in units of c/(1 + κ v_b)
  double decay_lengths = 20.0;  ///< automatic L: e-folds of the slowest mode of the sliding state (error ~ e^{−2·20})
  double tolerance = 1e-11;     ///< Newton: stop when the scaled update is below this
  int max_newton = 40;          ///< Newton iterations before giving up
  bool estimate_error = true;   ///< also solve on every other node: speed_error = |c_2h − c_h|/15
  /// Speed guess for a cold start (no previous front): 0 = bracket it by shooting (docs/fronts.md §3):
  /// on c = 0.02k c_s, then geometrically below 0.02 c_s down to 1e-3 min(sqrt(μα/(ηκ)), c_s).
  double c_guess = 0.0;
};

/// Outcome of a solve. Anything but `converged` leaves the numbers of the last iterate, for diagnosis.
enum class FrontStatus {
  converged,       ///< the discrete equations hold and the front is admissible
  no_front_state,  ///< σ_d outside (σ_c^d, 1): no sliding state behind or no stuck state ahead
  newton_failed,   ///< Newton did not converge (no solution near the guess, or at a fold)
  sonic,           ///< an iterate reached c ≥ c_s (the stuck region's decay rate degenerates)
  resticks,        ///< |σ|/A − 1 ≤ 0 somewhere behind the tip: Θ = 1 is violated (re-sticking)
  reverse_slip,    ///< v ≤ 0 somewhere behind the tip
  not_a_saddle,    ///< the sliding state behind has not one decaying and two growing modes
  stopped,         ///< a stop was requested during the solve (the strip's StripFrontOptions::stop)
};
const char* to_string(FrontStatus s);

/// One steady front at one σ_d. Profiles are on the nodes ξ_0 = −L < … < ξ_N = 0 (tip).
struct SteadyFront {
  FrontStatus status = FrontStatus::newton_failed;
  std::string reason;  ///< one line: why the status (empty when converged)

  // Problem (kept so that sample_steady_front needs nothing else).
  core::InterfaceParams law;
  double rho = 0.0, mu = 0.0;
  double sigma_d = 0.0;

  // Speed, tip and far-behind states.
  double c = 0.0;               ///< front speed
  double v_tip = 0.0;           ///< slip rate at the tip, closed form of the stuck region (docs/fronts.md eq. 3)
  double sigma_bar_tip = 0.0;   ///< σ̄ at the tip (= 1 − η v_tip)
  double stuck_decay = 0.0;     ///< λ₋ < 0: v = v_tip e^{λ₋ ξ} ahead of the tip
  double v_behind = 0.0;        ///< v_b: σ_ss(v_b) = σ_d, v_b > v_m
  double area_behind = 0.0;     ///< A_ss(v_b) = 1/(1 + κ v_b)
  double sigma_bar_behind = 0.0;///< α A_ss(v_b)
  double far_field_strain = 0.0;///< u_x far behind = −v_b/c (rear traction μ u_x of a finite run)

  // Profiles on the mesh (ξ ascending), and u with the convention σ̄ = α u in the stuck region
  // (u → σ_d/α far ahead, the stuck state of docs/model.md §1).
  std::vector<double> xi, area, sigma_bar, slip_rate, slip;

  // Diagnostics.
  double residual_norm = 0.0;   ///< max-norm of the discrete equations at the returned solution
  double speed_error = std::numeric_limits<double>::quiet_NaN();  ///< estimated |c_h − c| (4th-order Richardson)
  int newton_iterations = 0;
  double domain_length = 0.0;   ///< L
  double overstress_margin = 0.0; ///< min of |σ|/A − 1 behind the tip (interior minima and far end); ≤ 0: re-sticks
  double min_slip_rate = 0.0;   ///< min v over the profile
  std::array<std::complex<double>, 3> behind_eigenvalues{};  ///< Jacobian of the sliding state (forward ξ)
  double stable_eigenvalue = 0.0;  ///< the one with Re < 0 (→ 0 as σ_d → σ_c^d)
  bool saddle_node_limit = false;  ///< the limiting front at σ_d = σ_c^d (v_b = v_m, null mode behind)
  /// Far-behind asymptotics used beyond −L: y(ξ) = y_b + Σ_k Re(tail_mode[k] e^{tail_rate[k] (ξ + L)}),
  /// y = (v, A, σ̄); the two growing modes of the sliding state fitted to y(−L).
  std::array<std::complex<double>, 2> tail_rate{};
  std::array<std::array<std::complex<double>, 3>, 2> tail_mode{};
};

/// Solve for the steady front at applied stress σ_d. `guess` (optional, e.g. the neighbouring front of
/// a continuation) gives the starting speed and profile; without it the speed is bracketed by shooting.
SteadyFront solve_steady_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                               const SteadyFrontOptions& options = {}, const SteadyFront* guess = nullptr);

/// The limiting front at the end of the branch, σ_d = σ_c^d: sliding at v_m behind, the decaying mode
/// replaced by the null mode of the saddle-node (docs/fronts.md §4). Needs a guess (a front near σ_c^d).
SteadyFront solve_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                    const SteadyFrontOptions& options, const SteadyFront* guess);

/// Fields of a solved front sampled on nodes x (any order) with the tip at x_tip, for starting a
/// time-dependent run: closed form ahead of the tip, the collocation polynomial on [−L, 0], the
/// linearised approach to steady sliding beyond −L.
struct FrontSample {
  std::vector<double> area, sigma_bar, slip_rate, slip;
};
FrontSample sample_steady_front(const SteadyFront& front, std::span<const double> x, double x_tip);

// ---------------------------------------------------------------------------------------------------
// Continuation in σ_d (docs/fronts.md §4).

struct ContinuationOptions {
  double sigma_start = 0.8;     ///< first front (solved cold)
  double sigma_stop = 0.0;      ///< lowest σ_d asked for (the branch may end above; σ_c^d bounds it anyway)
  double initial_step = 0.01;   ///< pseudo-arclength step in (σ_d, c/c_s)
  double max_step = 0.05;
  double min_step = 1e-7;
  int target_newton = 5;        ///< step grows when a correction takes fewer iterations, shrinks when more
  double end_gap = 1e-7;        ///< stop when σ_d − σ_c^d < end_gap · σ_c^d (the sliding state's saddle-node)
  int max_points = 4000;
  bool refine_minimum = true;   ///< locate an interior minimum of c(σ_d) by Brent's method on fixed-σ_d solves
  SteadyFrontOptions front;     ///< settings of every solve
  /// Polled before every solve of the continuation (a cold start takes up to a second): true ends the
  /// branch where it is, with end `stopped` (a program's Ctrl-C). Empty: never.
  std::function<bool()> stop;
};

/// Why the branch ends (docs/fronts.md §4).
enum class BranchEnd {
  saddle_node,        ///< σ_d → σ_c^d: v_b → v_m, the decaying eigenvalue of the sliding state → 0
  resticking,         ///< |σ|/A − 1 → 0 somewhere behind the tip
  sonic,              ///< c → c_s
  reverse_slip,       ///< min v → 0 behind the tip
  newton_failure,     ///< corrections fail at the minimum step (reported, not explained)
  sigma_stop,         ///< reached options.sigma_stop
  max_points,
  no_branch,          ///< the parameters admit no branch (σ_c^d not finite, or ≥ 1): nothing solved
  stopped,            ///< options.stop asked to stop (the branch is partial)
};
const char* to_string(BranchEnd e);
/// Whether a branch that ended with `e` was followed to one of its ends (saddle_node, resticking, sonic,
/// reverse_slip) or to options.sigma_stop: only then is its c_min the minimal speed (NaN otherwise).
bool followed_to_end(BranchEnd e);

struct BranchPoint {
  double sigma_d, c, v_tip, v_behind, area_behind, overstress_margin, min_slip_rate, stable_eigenvalue;
  double domain_length, residual_norm, speed_error;
  int newton_iterations;
};

struct FrontBranch {
  double sigma_first = std::numeric_limits<double>::quiet_NaN();  ///< σ_d of the first front (σ_start, or below it if there was no front there; NaN: none)
  std::vector<BranchPoint> points;  ///< in continuation order (σ_d decreasing unless there is a fold)
  BranchEnd end = BranchEnd::max_points;
  std::string reason;               ///< the end in the equations' terms
  std::vector<double> folds;        ///< σ_d where dσ_d/ds changed sign (turning points), if any
  /// Minimal front speed on the branch; NaN (with σ_d at it) unless the branch was followed to an end
  /// (followed_to_end): no front found, a solver failure or a stop leave it not computed.
  double c_min = std::numeric_limits<double>::quiet_NaN();
  double sigma_d_at_c_min = std::numeric_limits<double>::quiet_NaN();
  bool c_min_at_end = false;        ///< c_min is the end point (c monotone along the branch)
  SteadyFront last;                 ///< the last converged front (for a time-dependent start, or diagnosis)
};

FrontBranch continue_steady_fronts(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                   const ContinuationOptions& options = {});

// ---------------------------------------------------------------------------------------------------
// Minimal-speed scaling (issue 11 part 3; docs/fronts.md §6).

struct ScalingPoint {
  std::string parameter;   ///< "mu", "alpha", "eta" or "kappa": the one varied
  double value;
  double c_min, sigma_d_at_c_min;  ///< NaN where the branch was not followed to an end (no front found, ...)
  double scale;            ///< sqrt(μ α/(η κ))
  BranchEnd end;
  std::string reason;      ///< the branch's reason (why there is no c_min, when there is none)
  double c_min_error = std::numeric_limits<double>::quiet_NaN();  ///< the c_min point's speed_error (NaN: none)
};
/// A fit needs at least this many points with a c_min: through one point the line c = a·scale passes
/// exactly (deviation 0), which tests nothing. The pooled fit also needs this many in every parameter
/// that was varied (asked for two values or more), so that each exponent of μα/(ηκ) is tested.
inline constexpr int min_scaling_fit_points = 2;
struct ScalingFit {
  std::string parameter;   ///< "all" for the pooled fit
  double prefactor;        ///< least squares through the origin: c_min ≈ prefactor · scale (NaN: refused)
  double spread;           ///< max |c_min/scale − prefactor| / prefactor over the fitted points (NaN: refused)
  double rms_relative;     ///< RMS of (c_min − prefactor·scale)/(prefactor·scale) over them (NaN: refused)
  int points;              ///< points fitted: those with a c_min
  int tried;               ///< points of the study in this fit (fitted or not)
  std::string refused;     ///< why no fit was made (fewer than min_scaling_fit_points); empty when made
};
struct ScalingStudy {
  std::vector<ScalingPoint> points;
  std::vector<ScalingFit> fits;  ///< one per parameter, then "all"
  bool stopped = false;          ///< continuation.stop asked to stop: the study is partial
};
/// Vary each of μ, α, η, κ over `values[p]` (others at `law`/`bulk`) and find c_min by continuation;
/// every point is kept, those without a c_min with their branch's end and reason.
struct ScalingOptions {
  std::vector<double> mu{150.0, 300.0, 600.0, 1200.0};
  std::vector<double> alpha{1.05, 1.5, 2.0, 3.0};
  std::vector<double> eta{0.05, 0.1, 0.2, 0.4};
  std::vector<double> kappa{4.0, 8.0, 16.0, 32.0};
  ContinuationOptions continuation;
};
ScalingStudy minimal_speed_scaling(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                   const ScalingOptions& options = {});

}  // namespace slipfront::continuum
