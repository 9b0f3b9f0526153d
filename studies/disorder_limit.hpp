#pragma once
// Study kind "disorder_limit" (issue 21, docs/studies.md): the two limits of the ensemble with threshold
// disorder w, on fig1's events or on the steady friction law (whichever the base scene measures):
//   (a) the noisy discrete ensemble -> mean_field as N -> inf at the same w (docs/model.md §2.2), and
//   (b) mean_field -> the continuum as w -> 0, with the w at which they differ by more than 1 %.
// Pure analysis of study results (no I/O).
#include <string>
#include <vector>

#include "studies/study.hpp"

namespace slipfront::studies {

/// The level of the w axis of the validity map (docs/model.md §8): where mean_field departs from the
/// continuum by more than this.
inline constexpr double disorder_limit_level = 0.01;

/// The w at which a relative difference rel(w) first crosses `level` going up from the smallest w,
/// interpolated linearly in log w between the two bracketing widths (`w` increasing). `status`: 0 crossed,
/// -1 already above the level at the smallest w (the crossing lies below it), +1 within it at every w.
struct LevelCrossing {
  double w = 0.0;  ///< NaN unless status == 0
  int status = 0;
};
LevelCrossing crossing_in_log_w(const std::vector<double>& w, const std::vector<double>& rel, double level);

/// Tables `disorder_limit_N` (per threshold law, renewal, w and N: RMS over seeds of the discrete model's
/// relative difference to mean_field, per observable) and `disorder_limit_w` (per threshold law, renewal and w:
/// |mean_field - continuum| / continuum per observable); scalars `disorder_N_<obs>_<law>_<renewal>_w<w>_exponent`
/// (N-rate of the RMS over seeds, with put_fits' interval and _from variant) and `..._sd_exponent` (of the spread over
/// seeds: the random part), `disorder_w_<obs>_<law>_<renewal>_exponent` (w-rate over the widths w <= alpha - 1 with a
/// difference above round-off) and `disorder_w1pct_<obs>_<law>_<renewal>` (+ `_status`, see
/// LevelCrossing). Observables: fig1's t_star, t_hat, c_slow (A_tip_alt front), c_transient, x_arrest for a
/// bulk scene; the steady law's `sigma` (RMS over v of the relative difference) and `sigma_min` for a sweep.
void analyse_disorder_limit(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                            const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res);

}  // namespace slipfront::studies
