#pragma once
// Steady fronts in the antiplane strip of height H (docs/model.md §9, issue 20 item 1): the traveling-wave
// problem of docs/fronts.md §1 with the strip under the interface instead of the 1D chain. Derivation,
// method, far-field conditions, order and results: docs/fronts.md §10.
//
// In ξ = x − c t (tip at ξ = 0) the bulk obeys β² ∂ξξ u + ∂yy u = 0, β² = 1 − c²/c_s², with
//   μ' ∂y u(ξ, 0) = τ = σ̄ + η v,  v = −c ∂ξ u(ξ, 0)   (interface, y = 0)
//   μ' ∂y u(ξ, H) = σ_d                                 (top)
// and the interface law of docs/fronts.md eq. (1b, 1c) behind the tip. The strip is discretised across
// its height by vertex-centred finite volumes (the rows of core::Strip, docs/model.md §9.6) on rows graded
// toward the interface, which leaves a first-order system of ODEs in ξ. It is collocated on [−L, 0]
// (Lobatto IIIA, as the 1D solver) with c an unknown, in one Newton iteration with Eigen's SparseLU.
// Ahead of the tip the problem is linear (A ≡ 1, σ̄ = α u(ξ, 0)) and is solved exactly in its modes: the
// tip state lies in the decaying subspace (the 2D form of the 1D closed form ahead). Behind, a projection
// condition at ξ = −L removes the modes that grow toward −∞ (the 2D form of the 1D projection condition).
//
// The scene convention of docs/model.md §9.1: `bulk.mu`, `bulk.rho` are thickness-integrated, the strip's
// material is μ' = μ/H, ρ' = ρ/H; H → 0 at fixed μ is the 1D model. Plain structs; nothing here does I/O.
#include <complex>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "continuum/steady_front.hpp"
#include "core/params.hpp"

namespace slipfront::continuum {

/// Discretisation and Newton settings of one strip-front solve.
struct StripFrontOptions {
  int intervals = 600;            ///< ξ intervals on [−L, 0]
  int rows = 16;                  ///< row intervals across the height (M; M + 1 rows, row 0 the interface)
  double tip_spacing = 0.05;      ///< ξ interval at the tip (geometric growth behind, as in 1D)
  double grading = 0.0;           ///< β of the ξ mesh map if > 0 (overrides tip_spacing), docs/fronts.md §3
  double row_spacing = 0.25;      ///< first row spacing at the interface; rows uniform when H/M ≤ this
  double row_grading = 0.0;       ///< γ of the row map y_j = H (e^{γj/M} − 1)/(e^γ − 1) if > 0 (overrides row_spacing)
  double domain_length = 0.0;     ///< L; 0 = automatic: tip_length + decay_lengths / (slowest mode behind)
  double tip_length = 40.0;       ///< automatic L: in units of c/(1 + κ v_b)
  double decay_lengths = 20.0;    ///< automatic L: e-folds of the slowest mode of the sliding state behind
  double tolerance = 1e-11;       ///< Newton: stop when the scaled update is below this
  int max_newton = 40;
  /// Cold start (no guess): the 1D front at the same σ_d is solved and the strip is grown from
  /// H_0 = min(H, thin_height) by factors of `height_factor` at fixed μ (docs/fronts.md §10.4).
  double thin_height = 0.5;
  double height_factor = 2.0;
  bool estimate_error = false;    ///< also solve on every other ξ node: speed_error = |c_2h − c_h|/15
  /// Polled before every Newton iteration (and every step of the cold start): true ends the solve with
  /// status `stopped` within one iteration (strip_max_iteration_seconds bounds its length where fronts refuses). Empty: never.
  std::function<bool()> stop;
};

/// The row grading γ of `o` at height H (make_rows: y_j = H (e^{γj/M} − 1)/(e^γ − 1)): o.row_grading if set,
/// else the γ that gives the first spacing o.row_spacing; 0 for uniform rows (H/M ≤ row_spacing).
double strip_row_grading(double H, const StripFrontOptions& o);
/// `o` with `rows` row intervals on the same grading (γ fixed: every spacing scales as 1/rows), the
/// refinement of docs/fronts.md §10.20 (rows × 2 halves every spacing; rows / 2 keeps every other row).
StripFrontOptions with_rows(double H, const StripFrontOptions& o, int rows);

/// What one Newton iteration of a strip solve costs (docs/fronts.md §10.20): the Jacobian's dense blocks
/// (2 per ξ interval, (2M + 4)² each) and SparseLU's factorisation, calibrated on the reference machine: CPU
/// seconds of one thread (a quiet machine's wall time; the shared machine under load takes several times more).
struct StripSolveCost {
  double iteration_seconds = 0.0;  ///< one Newton iteration (assembly, four far-field eigenproblems, SparseLU), CPU s
  double memory_bytes = 0.0;       ///< the Jacobian, its triplets and the LU factors
};
/// `components`: unknowns per row and ξ node pair (1: the antiplane strip's u; 2: the in-plane strip's u_x, u_y, whose
/// block is (4M + 4)², docs/fronts.md §11.5).
StripSolveCost strip_solve_cost(int rows, int intervals, int components = 1);
/// A stop request is seen between Newton iterations: a mesh whose iteration is estimated above this (CPU s;
/// ~5 s of wall time on the shared machine under load) is refused up front (`slipfront fronts --rows/--intervals`),
/// so that a stop is always prompt. At 300 intervals: up to 69 rows, as with the wall-time calibration before.
inline constexpr double strip_max_iteration_seconds = 1.0;

/// One steady front in the strip at one σ_d. Fields on the nodes ξ_0 = −L < … < ξ_N = 0 (tip) and the
/// rows 0 = y_0 < … < y_M = H; bulk fields node-major, index i·(M + 1) + j.
struct StripFront {
  FrontStatus status = FrontStatus::newton_failed;
  std::string reason;

  core::InterfaceParams law;
  core::BulkParams bulk;          ///< as given: μ, ρ integrated over the height, `height` = H
  double mu_strip = 0.0, rho_strip = 0.0;  ///< μ' = μ/H, ρ' = ρ/H (in-plane: μ' = μ(1 − ν)/(2H), docs/model.md §10.2)
  double sigma_d = 0.0;

  double c = 0.0;
  double v_tip = 0.0, sigma_bar_tip = 0.0;  ///< at ξ = 0 (σ̄_tip + η v_tip = 1)
  double v_behind = 0.0, area_behind = 0.0, sigma_bar_behind = 0.0;  ///< the sliding state (as in 1D)

  std::vector<double> xi, y;
  std::vector<double> slip_rate, area, sigma_bar, slip, traction;  ///< interface: v, A, σ̄, u(ξ,0), τ = σ̄ + η v
  std::vector<double> u, strain;  ///< bulk u(ξ_i, y_j) and ∂ξ u (u → σ_d/α + σ_d y/μ' far ahead)
  std::vector<double> lift;       ///< u(ξ_i, y_j) − u(ξ_i, 0): the solver's unknowns for j ≥ 1 (not rounded by u's size)
  /// The in-plane strip only (bulk.body() == inplane, continuum/inplane_front.hpp; empty for the antiplane strip):
  /// u, strain, lift above are u_x's; uy = u_y(ξ_i, y_j) (0 on the interface), uy_strain = ∂ξ u_y, both node-major,
  /// and normal_stress = σ_yy(ξ_i, 0), the interface's normal traction (the reaction that holds u_y = 0).
  std::vector<double> uy, uy_strain, normal_stress;

  double residual_norm = 0.0;     ///< max-norm of the discrete equations at the returned solution
  double speed_error = std::numeric_limits<double>::quiet_NaN();  ///< the ξ part (options.estimate_error)
  double row_grading = 0.0;       ///< γ of the rows (0: uniform)
  int newton_iterations = 0;
  double domain_length = 0.0;
  double overstress_margin = 0.0; ///< min of |σ|/A − 1 behind the tip (interior minima and far end)
  double min_slip_rate = 0.0;
  double stable_eigenvalue = 0.0; ///< the decaying mode of the sliding state nearest 0 (λ_s; → 0 at σ_c^d)
  double slowest_growing = 0.0;   ///< slowest mode approaching the sliding state (sets L)
  double slowest_ahead = 0.0;     ///< slowest decay rate ahead of the tip (> 0)
  bool saddle_node_limit = false;
  /// Ahead of the tip: (u_0 … u_M, ∂ξu_0 … ∂ξu_M)(ξ) − stuck state = Σ_k Re(ahead_mode[k] e^{ahead_rate[k] ξ}),
  /// Re rate < 0 (the M + 1 decaying modes of the linear stuck system).
  std::vector<std::complex<double>> ahead_rate;
  std::vector<std::vector<std::complex<double>>> ahead_mode;

  int rows() const { return static_cast<int>(y.size()) - 1; }
  double u_at(std::size_t i, std::size_t j) const { return u[i * y.size() + j]; }
};

/// Solve for the strip front at σ_d. `guess`: a strip front (any H, σ_d, mesh; e.g. the neighbour of a
/// continuation); without it, a cold start from the 1D front (options.thin_height).
StripFront solve_strip_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                             const StripFrontOptions& options = {}, const StripFront* guess = nullptr);

/// The error of a solved front's speed (docs/fronts.md §10.20), from the same front re-solved on every other
/// row (M/2, the same grading, guess: the front itself; M = 1: on 2M rows instead), then that on twice the
/// intervals: rows = |c_M − c_{M/2}|/(2^p − 1), p = strip_row_order (M = 1: |c_1 − c_2| 2^p/(2^p − 1)),
/// xi = |c_N − c_2N| 8/7 (order 3 assumed, 4 proven); total = rows + xi. NaN with `note` when a re-solve fails.
struct StripSpeedError {
  double rows = std::numeric_limits<double>::quiet_NaN(), xi = std::numeric_limits<double>::quiet_NaN();
  double total = std::numeric_limits<double>::quiet_NaN();
  double c_other = std::numeric_limits<double>::quiet_NaN();  ///< c on the other rows
  int other_rows = 0;
  std::string note;               ///< why there is no estimate ("" when there is)
};
/// The order assumed across the rows: observed 1.8–2.5 (docs/fronts.md §10.5, §10.13, §10.20); the lower
/// value makes the estimate larger than the error it estimates.
inline constexpr double strip_row_order = 1.5;
StripSpeedError estimate_strip_speed_error(const StripFront& front, const StripFrontOptions& options);

/// The limiting front at σ_d = σ_c^d (v_b = v_m, the null mode of the saddle-node behind). Needs a guess;
/// with c_guess > 0 the guess is stretched in ξ and y by c_guess/guess.c (a neighbouring problem whose front
/// is longer or shorter, docs/fronts.md §10.11) and Newton starts at c_guess.
StripFront solve_strip_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                         const StripFrontOptions& options, const StripFront& guess, double c_guess = 0.0);

/// The front at σ_d (σ_c^d with saddle_node: the limiting front) from `from` stretched in ξ and y by c_guess/from.c,
/// Newton starting at c_guess (docs/fronts.md §10.11: a neighbouring problem whose front is longer or shorter;
/// the path in H). No checks of σ_d or H: the caller's problem is a neighbour of `from`'s.
StripFront solve_strip_front_stretched(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                                       const StripFrontOptions& options, const StripFront& from, double c_guess,
                                       bool saddle_node);

/// The interface fields of a solved front at positions ξ (any order, tip at 0): the collocation
/// polynomial on [−L, 0], the modes ahead of the tip; beyond −L the sliding state.
struct StripInterfaceSample {
  std::vector<double> slip_rate, area, sigma_bar, slip;
};
StripInterfaceSample sample_strip_interface(const StripFront& front, std::span<const double> xi);
/// The whole front at positions ξ on its own rows (docs/fronts.md §10.15): the interface fields as above and,
/// on every row j, u(ξ, y_j) and the velocity ∂t u = −c ∂ξ u(ξ, y_j), index k·(M + 1) + j (k the position).
/// Ahead of the tip the modes; behind −L every row translates at v_b with the lift it has at −L.
struct StripFrontSample {
  StripInterfaceSample interface;
  std::vector<double> u, velocity;
};
StripFrontSample sample_strip_front(const StripFront& front, std::span<const double> xi);

// ---------------------------------------------------------------------------------------------------
// Continuation in σ_d (docs/fronts.md §10.8): the pattern of continue_steady_fronts (docs/fronts.md §4).

struct StripContinuationOptions {
  double sigma_start = 0.8;
  double initial_step = 0.01;     ///< pseudo-arclength step in (σ_d, c/c_s)
  double max_step = 0.05;
  double min_step = 1e-6;
  int target_newton = 5;
  double end_gap = 1e-7;          ///< stop when σ_d − σ_c^d < end_gap · σ_c^d
  int max_points = 400;
  StripFrontOptions front;
  std::function<bool()> stop;     ///< polled before every solve; true ends the branch (`stopped`)
  /// A converged strip front of the same problem (any σ_d, H, rows; e.g. from continue_strip_height) used as
  /// the guess of the first front at sigma_start instead of the cold start from the 1D front. Not owned.
  const StripFront* start = nullptr;
  /// Called with every front the branch keeps (its points, in order, the limiting front last): for profiles.
  std::function<void(const StripFront&)> on_front;
};

struct StripBranch {
  std::vector<BranchPoint> points;
  BranchEnd end = BranchEnd::max_points;
  std::string reason;
  std::vector<double> folds;
  double c_min = std::numeric_limits<double>::quiet_NaN();
  double sigma_d_at_c_min = std::numeric_limits<double>::quiet_NaN();
  bool c_min_at_end = false;
  StripFront first;               ///< the first front (at sigma_start or below it)
  StripFront last;
};

StripBranch continue_strip_fronts(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                  const StripContinuationOptions& options = {});

// ---------------------------------------------------------------------------------------------------
// Continuation in the height at a fixed strip material (docs/fronts.md §10.11; continuum/height_continuation.cpp):
// μ' = μ/H, ρ' = ρ/H held, H grown from the first of `heights` to the last, either at a fixed σ_d or for the
// limiting front at σ_c^d (c_min(H) wherever the branch ends at the saddle-node with c monotone, as on every
// branch computed).

/// The meshes that follow a front's own length (docs/fronts.md §10.11): the ξ spacing at the tip ℓ_tip/30 and the
/// first row spacing ℓ_tip/10, ℓ_tip the tip zone (strip_tip_zone).
inline constexpr double strip_tip_resolution = 30.0, strip_row_resolution = 10.0;

/// `base` on the meshes of a front with tip zone `tip_zone`: tip_spacing = tip_zone/tip_resolution, row_spacing =
/// tip_zone/row_resolution (a resolution ≤ 0 keeps base's spacing). The path in H, the branches started from it
/// and the scaling study on thick strips use it.
inline StripFrontOptions following_tip(StripFrontOptions base, double tip_zone, double tip_resolution = strip_tip_resolution,
                                       double row_resolution = strip_row_resolution) {
  if (tip_resolution > 0.0) base.tip_spacing = tip_zone / tip_resolution;
  if (row_resolution > 0.0) base.row_spacing = tip_zone / row_resolution;
  return base;
}

struct StripHeightOptions {
  std::vector<double> heights;    ///< increasing; the path stops at each (its front is returned)
  bool limiting = true;           ///< the limiting front at σ_c^d; false: the front at sigma_d
  double sigma_d = 0.8;
  double max_factor = 2.0;        ///< largest step H_{n+1}/H_n
  double min_factor = 1.002;      ///< the path fails when a step below this does not converge
  int target_newton = 4;          ///< the step grows after at most this many Newton iterations,
  double target_miss = 2e-3;      ///< or when the predicted c was within this (relative); shrinks beyond 5 times it
  /// The meshes follow the front's own length, the tip zone ℓ_tip = c/(1 + κ v_b) (c the predicted speed):
  /// the ξ spacing at the tip is ℓ_tip/tip_resolution and the first row spacing ℓ_tip/row_resolution
  /// (0: keep front.tip_spacing, front.row_spacing). L is automatic (docs/fronts.md §10.3) unless set.
  double tip_resolution = strip_tip_resolution;
  double row_resolution = strip_row_resolution;
  StripFrontOptions front;        ///< rows, intervals, Newton settings of every solve (max_newton: 12 is plenty)
  /// The first front (at heights.front()); without it the first front is solved cold: the 1D front's
  /// branch is not needed, the strip's branch is (limiting) or solve_strip_front (fixed σ_d).
  const StripFront* start = nullptr;
  std::function<bool()> stop;     ///< polled before every solve
};

struct StripHeightStep {          ///< one accepted step of the path
  double height = 0.0, c = 0.0;
  double c_predicted = 0.0;       ///< the secant predictor in (ln H, ln c)
  int newton_iterations = 0, rejected = 0;  ///< rejected: failed tries (step halved in ln H) before this one
};

struct StripHeightPath {
  std::vector<StripFront> fronts; ///< at heights[0], heights[1], … as far as the path got
  std::vector<StripHeightStep> steps;
  bool complete = false;
  std::string reason;             ///< why it stopped early ("" when complete)
};

/// Material (μ', ρ') and the law fixed, bulk.mu = μ'H, bulk.rho = ρ'H, bulk.length = `length` (unused by the
/// solver). Each step solves from the last front stretched in ξ and y by the ratio of the predicted to the
/// last speed (the front's lengths scale with c), with the secant prediction of c.
StripHeightPath continue_strip_height(const core::InterfaceParams& law, double mu_strip, double rho_strip,
                                      const StripHeightOptions& options, double length = 1000.0);

/// The same path at a fixed column, the scene convention of docs/model.md §9.1: bulk.mu = μ and bulk.rho = ρ
/// (integrated over the height) held, μ' = μ/H and ρ' = ρ/H falling as H grows; H → 0 is the 1D model of μ, ρ.
/// The c_min(H) of a time-dependent strip scene (its `bulk` at every `height`), docs/fronts.md §10.16.
StripHeightPath continue_strip_height_at_column(const core::InterfaceParams& law, const core::BulkParams& column,
                                                const StripHeightOptions& options);

/// The tip zone c/(1 + κ v_b) of a front at speed c with sliding at v_b behind (the front's length scale).
double strip_tip_zone(const core::InterfaceParams& law, double c, double v_behind);

// ---------------------------------------------------------------------------------------------------
// The first front of a thick strip's branch (docs/fronts.md §10.19). The cold start (§10.4: the 1D front, the
// strip grown at fixed μ by doublings on fixed meshes) fails on thick strips (H = 1e5 at μ' = 300: no Newton
// convergence at H = 65 536 after 274 s; μ' = 3, H = 1000: at H = 128), while the path in H at the strip's own
// material with meshes that follow the front (continue_strip_height, §10.11) reaches H = 1e6. The rule:
//   - H ≤ strip_path_start_ratio · ℓ (ℓ = μ' = μ/H, the paper's elastic length of the strip, §10.12): the cold
//     start, as before (results there unchanged, bit for bit); only if it finds no first front, the path;
//   - H > strip_path_start_ratio · ℓ: the path (and the cold start only if the path does not arrive).
// The ratio 10 is past the crossover (§10.12: the exponent of c_min(H) leaves ½ by H ≈ 3ℓ), above every
// height the cold start was used for in docs/fronts.md (§10.14, §10.18: H ≤ 3.3ℓ) and below the first failure
// seen (H/ℓ = 43 at μ' = 3, 4 rows).
inline constexpr double strip_path_start_ratio = 10.0;

/// H > strip_path_start_ratio · ℓ, ℓ = μ' = bulk.mu/bulk.height: the branch is started from the path in H.
bool strip_start_needs_height_path(const core::BulkParams& bulk);

struct StripPathStart {
  StripFront front;               ///< the front at sigma_start at the bulk's H (converged when the path arrived)
  /// The options for the branch from it: `options.front` with the meshes of the path's last solve (ξ spacing
  /// at the tip ℓ_tip/30, first row ℓ_tip/10, ℓ_tip = strip_tip_zone of this front) and max_newton 12.
  StripFrontOptions options;
  int steps = 0;                  ///< accepted steps of the path
  double first_height = 0.0;      ///< where the path started (ℓ/300: H/ℓ = 1/300, the 1D regime)
  std::string reason;             ///< how the front was obtained, or why the path stopped
};

/// The front at o.sigma_start of the strip `bulk` (its μ' = μ/H, ρ' = ρ/H, H) from the path in H at that
/// material (continue_strip_height at σ_d = o.sigma_start, from H = ℓ/300 cold, o.front's rows, intervals,
/// tolerance; o.stop polled), as the first front of continue_strip_fronts (StripContinuationOptions::start).
StripPathStart strip_start_from_height_path(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                            const StripContinuationOptions& o);

}  // namespace slipfront::continuum
