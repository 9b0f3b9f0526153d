#pragma once
// The resolution check of a scene (issue 36; docs/studies.md "`resolution`"): the scene run at
// its own resolution and at levels refined (and optionally coarsened) by a ratio r — the grid (dx, and dy on the
// strip), the fixed step or the integrator's tolerances together —, each event's discretisation error at the
// scene's own level estimated by Richardson extrapolation from the finest three levels with its observed order,
// and judged against a relative tolerance. A stochastic model (the discrete model with noise) is judged on its
// noise-off skeleton (the same law and integrator, every draw replaced by its expectation: deterministic, so its
// differences between levels are discretisation only); its sampling part is measured apart, by seeds at the
// scene's own level. A study kind (studies::study_kinds(): `resolution`) whose runs are planned from the base
// scene; `slipfront check-resolution CONFIG` writes that study for one scene. Nothing here reads or writes files.
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "core/params.hpp"

namespace slipfront::compare {
struct Scene;
struct StudySpec;
struct StudyGroup;
struct StudyRun;
struct ModelResult;
}  // namespace slipfront::compare

namespace slipfront::studies {
using namespace compare;  // the run layer's vocabulary: Scene, StudySpec, ModelResult, ...

struct StudyReport;

/// [resolution] of a study of kind resolution (and the options of `slipfront check-resolution`).
struct ResolutionOptions {
  int levels = 2;                ///< refined levels beyond the scene's own: h/r, h/r², ...
  int coarser = 0;               ///< coarser levels: h r, ... (a cheaper order for a costly scene)
  double ratio = 2.0;            ///< refinement ratio r between neighbouring levels
  double tolerance = 0.01;       ///< relative error every event must meet at the scene's own level
  /// Tolerances (time.rtol, time.atol, time.leap_epsilon, time.implicit_tolerance) are divided by r^q per level,
  /// q = tolerance_order: a global error proportional to the tolerance then shrinks as h^q.
  double tolerance_order = 2.0;
  int seeds = 4;                 ///< a stochastic model: runs (seeds) at the scene's own level for its sampling part
};

/// The domains of the [resolution] keys ("resolution.levels", ...), as core::KeyDomain rows.
std::span<const core::KeyDomain> resolution_key_domains();
/// The rules between the keys (throws core::ParamError naming the key): at least three levels in all.
void check_resolution_options(const ResolutionOptions& o);

/// Richardson's estimate of the error of one level's value from values at levels h_j = r^-j (coarsest first).
struct RichardsonEstimate {
  double order = std::numeric_limits<double>::quiet_NaN();         ///< observed order p from the finest three levels
  double extrapolated = std::numeric_limits<double>::quiet_NaN();  ///< f_inf = f_fine - d/(r^p - 1) ("richardson")
  double error = std::numeric_limits<double>::quiet_NaN();         ///< |f_base - f_inf|, or the scatter bound
  double rel_error = std::numeric_limits<double>::quiet_NaN();     ///< error / |f_inf| (scatter: / |f_base|)
  /// "richardson": the finest three levels converge monotonically at an order in [order_band_low, order_band_high];
  /// "scatter": they do not (differences at the event's own resolution, or an order outside the band), and the
  /// error is bounded by the largest distance of the base value to another level's; "exact": every level gives
  /// the same value (to 1e-12 relative); "missing": a level did not measure the event.
  const char* method = "missing";
};
inline constexpr double order_band_low = 0.5, order_band_high = 5.0;
/// The estimate for the value at index `base` of `f` (at least three levels, coarsest first, ratio r > 1).
RichardsonEstimate richardson(std::span<const double> f, std::size_t base, double ratio);

/// The levels of a resolution study, planned from its base scene (after `set` and --set): one group per level,
/// named "level<k>" (k = -coarser .. levels; h = r^-k of the scene's), and for a stochastic model "level0" holds
/// the seeds and "level<k>_noise_off" its skeleton at every level. Finest first (the pool starts the longest runs).
std::vector<StudyGroup> resolution_groups(const StudySpec& spec, const Scene& base);
/// The checks of the base scene before any work (throws core::ParamError naming the key): a scene with events.
void check_resolution_scene(const StudySpec& spec, const Scene& base);
/// The analysis of kind resolution (signature of studies::StudyAnalysis).
void analyse_resolution(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                        const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& results);

}  // namespace slipfront::studies
