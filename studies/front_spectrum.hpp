#pragma once
// The spectrum of fronts against the body's wave speeds (issue 39 item 4, docs/fronts.md §12): for every run of a
// front_spectrum study, homogeneous (σ_d) or edge-loaded (drive.K, drive.v_d), its peak tip speed and its settled
// speed in units of the shear wave speed c_s, beside c_R and c_p of the in-plane strip. Pure analysis (no I/O).
#include <string>

#include "compare/peak_speed.hpp"
#include "studies/study.hpp"

namespace slipfront::studies {

/// The wave speeds of a scene's body: c_s = sqrt(μ/ρ) on the chain and the antiplane strip (μ' = μ/H, ρ' = ρ/H),
/// sqrt(μ'/ρ') with μ' = μ(1 − ν)/(2H) on the in-plane strip; c_p and c_R (the Rayleigh wave, c_R/c_s =
/// rayleigh_ratio(ν)) on the in-plane strip only, NaN on the others (they have no P wave: an antiplane front is
/// bounded by c_s).
struct WaveSpeeds {
  double c_s = 0.0, c_p = 0.0, c_R = 0.0;
};
WaveSpeeds wave_speeds(const core::BulkParams& bulk);

/// The peak tip speed of a homogeneously loaded run, from its series (t, tip_x): compare::peak_tip_speed over
/// windows of `span` time units, on the samples from the first defined tip to the last at or before x_end (the far
/// end's zone, measure.settle_end_zone, left out as for c_front: the tip speeds up as it reaches the free end) or
/// before the tip is lost (the front healed).
PeakSpeed front_peak_speed(const ModelResult& r, double x_end, double span);

/// Adds the table `front_spectrum_speeds` (one row per run, in run order: its loading, σ_d, K, v_d, the stored
/// elastic energy per unit length of the homogeneous stuck state, the peak and the settled speed and their ratios to
/// c_s, the body's c_s, c_p, c_R), the scalars spectrum_c_s, spectrum_c_p, spectrum_c_R (NaN unless every run shares
/// them), spectrum_max_peak_over_cs, spectrum_max_settled_over_cs, spectrum_supershear_runs and the settled speeds
/// nearest c_s from below and above (spectrum_fastest_subshear, spectrum_slowest_supershear), with their definitions.
void add_spectrum_speeds(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                         const std::vector<std::vector<ModelResult>>& res);

}  // namespace slipfront::studies
