#pragma once
// Fig. 2 (right) against the minimal steady front speed (issue 20 item 4, docs/fronts.md §10.16): for every run
// of a "fig2" study, c_min of the run's own scene — the end of the 1D branch on the chain, the limiting front
// of the strip at the run's height (continuum::continue_strip_height_at_column) on the strip — and the
// transient speed against it, per height. Pure analysis of study results (no I/O).
#include <string>
#include <vector>

#include "studies/study.hpp"

namespace slipfront::studies {

/// c_min of each scene (NaN where the branch or the path did not end at a limiting front; `why[i]` then says
/// why). Scenes with the same law, μ, ρ share one path in H; the paths run concurrently (one thread each).
/// With `error`, each c_min's estimated error (docs/fronts.md §10.20; NaN: none): the chain's branch point's
/// own, the strip's front re-solved on every other row and on twice the intervals (estimate_strip_speed_error).
std::vector<double> minimal_front_speeds(const std::vector<Scene>& scenes, std::vector<std::string>& why,
                                         std::vector<double>* error = nullptr);

/// Adds to a fig2 analysis: columns H, c_min, c_min_error, ratio_<model> = c_transient/c_min to `all` (runs in order, its columns c_continuum and c_discrete filled), the
/// table `fig2_heights` (one row per height: H, the range of H/l and H/l_kappa over its runs, runs, slope of c_transient vs
/// c_min through the origin, mean and relative spread of the ratio, the same against sqrt(μα/(ηκ)), per model) and its definitions.
void fig2_against_cmin(StudyReport& rep, Columns& all, const std::vector<Scene>& scenes);

}  // namespace slipfront::studies
