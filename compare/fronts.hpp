#pragma once
// The steady fronts of a homogeneous scene (docs/model.md §6) as a result to store and plot: the branch
// c(σ_d) by continuation to its end, a few solved profiles along it, and optionally the minimal-speed
// scaling study (continuum/steady_front.hpp does the numerics). `slipfront fronts` writes it to
// fronts.h5 (apps/h5out, docs/output.md). Nothing here reads or writes files.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "continuum/steady_front.hpp"
#include "continuum/strip_front.hpp"

namespace slipfront::compare {

struct FrontProfile {
  double sigma_d = 0.0, c = 0.0, v_tip = 0.0, v_behind = 0.0;
  double c_error = 0.0;   ///< estimated |c − c_converged| (docs/fronts.md §10.20; NaN: no estimate)
  bool limiting = false;  ///< the limiting front at the end of the branch
  Columns fields;         ///< xi, A, sigma_bar, v, u on the solver's mesh (tip at xi = 0); the strip adds tau
  /// The strip (bulk.height > 0): the rows y_0 = 0 < … < y_M = H and the bulk fields on xi × y, node-major
  /// ([xi.size()][y.size()]): u(ξ, y) and its lift u(ξ, y) − u(ξ, 0). Empty for the 1D chain.
  std::vector<double> y, u_xy, lift_xy;
  /// The in-plane strip: u_y(ξ, y) on xi × y (node-major) and the interface normal stress σ_yy(ξ, 0) (`sigma_yy` in
  /// `fields`); empty otherwise.
  std::vector<double> uy_xy;
};

/// The default whole-branch budget of the strip's mesh choice (`fronts --budget`): 5 CPU minutes (H = 50 chooses
/// 32 rows, ~2 min; H = 200 would need 64 rows, ~11 min, and stops at 32).
inline constexpr double default_fronts_budget_seconds = 300.0;

/// The strip solver's discretisation for `slipfront fronts` on a scene with bulk.height (docs/fronts.md §10.14,
/// §10.20): chosen by the tolerance `rtol` on c unless given.
struct StripFrontsSettings {
  int rows = 0;          ///< row intervals across the height (graded toward the interface); 0: chosen by rtol
  int intervals = 0;     ///< ξ intervals on [−L, 0]; 0: chosen by rtol
  double rtol = 1e-3;    ///< the target: every reported c within rtol·c of the converged value (its estimate)
  int first_rows = 8, first_intervals = 300;   ///< where the choice starts
  int max_rows = 64, max_intervals = 2400;     ///< the largest meshes of the choice (and strip_max_iteration_seconds)
  /// The whole-branch cost budget of the choice (CPU seconds of the reference machine, continuum::strip_solve_cost):
  /// a refinement whose predicted cost (what was spent, plus the branch, its profiles and estimates on the finer
  /// meshes) is above it is not made, and the verdict says "NOT met (budget)" (docs/fronts.md §10.20).
  double budget_seconds = default_fronts_budget_seconds;
  /// Displacement components per row: 1 on the antiplane strip, 2 on the in-plane strip (u_x, u_y; its Newton
  /// iteration costs ~4× the antiplane one's on the same mesh: continuum::strip_solve_cost, docs/fronts.md §11.5).
  int components = 1;
};
/// The 1D chain's tolerance check (its mesh is fixed: 600 intervals, error ~1e−10 relative).
inline constexpr double default_fronts_rtol = 1e-3;

struct FrontsResult {
  /// complete: the branch followed to its end (and, with scaling, the pooled fit made); failed: no front,
  /// a solver failure or a refused fit, with the reason in `message`; interrupted: stopped on request.
  RunStatus status = RunStatus::complete;
  std::string message;
  Columns branch;                              ///< one entry per continuation point (see docs/output.md)
  /// c_min, sigma_d_at_c_min, sigma_c_d, scale, ...; NaN for what was not computed (c_min of a failed branch),
  /// scene_sigma_d and c_at_scene_sigma_d (the front at the scene's σ_d; NaN if none).
  std::map<std::string, double> scalars;
  std::map<std::string, std::string> labels;   ///< end, reason, scene_front (the scene's σ_d: status and reason)
  std::vector<FrontProfile> profiles;
  /// The minimal-speed scaling study (empty unless asked for): one entry per point, and per fit.
  Columns scaling_points;                      ///< value, c_min, sigma_d_at_c_min, scale, parameter_index
  std::vector<std::string> scaling_parameters; ///< names indexed by parameter_index
  Columns scaling_fits;                        ///< prefactor, spread, rms_relative, points, tried, parameter_index (-1: all)
  std::vector<std::string> scaling_refused;    ///< per fit (as scaling_fits): why it was refused ("" if made)
  double wall_seconds = 0.0;
};

/// The branch of the scene's interface and bulk parameters, continued from σ_d = 0.8 whatever the scene's
/// σ_d; the front at the scene's σ_d is solved and reported on its own (profile 0 when there is one). With
/// `scaling` the minimal-speed scaling study too. `stop` (polled between solves) ends the work early with
/// status interrupted. Throws core::ParamError when the scene is not under homogeneous loading.
/// On a scene with bulk.height > 0 the strip's branch (continuum/strip_front.hpp) with `strip` settings; its
/// profiles carry u(ξ, y); `scaling` then varies μ' (bulk.mu at fixed H), α, η, κ around the scene's values
/// (four values each, the limiting front at σ_c^d: c_min at the branch's end) against the 1D scale
/// sqrt(μα/(ηκ)) with μ = μ'H (docs/fronts.md §10.14). On the in-plane strip (bulk.body = "inplane") the same stages
/// with its solver (continuum/inplane_front.hpp, docs/fronts.md §11.6): profiles carry u_x and u_y, the 1D c_min is
/// that of μ = E'H (the scene's μ), and `strip.components` is set to 2.
FrontsResult compute_fronts(const Scene& s, bool scaling, const std::function<bool()>& stop = {},
                            const StripFrontsSettings& strip = {});

/// "" when `fronts` may solve the strip with these settings, else why not (the option to change): one Newton
/// iteration above continuum::strip_max_iteration_seconds (a stop is seen between iterations) or the
/// solver's memory above `max_memory_gib`.
std::string strip_fronts_refusal(const StripFrontsSettings& strip, double max_memory_gib);

/// c of the solved steady front at σ_d (NaN where there is none).
double solved_front_speed(const Scene& s, double sigma_d);

}  // namespace slipfront::compare
