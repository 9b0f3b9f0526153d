#pragma once
// The validity map of the mean-field limit (issue 13, docs/validity.md): where the discrete ensemble's
// observables stay within 1% / 5% of the continuum law, as a function of N, α − 1 and the threshold
// width w; the crossover N* with an interval, its scaling with α − 1 (the collapse), and for fig1 the
// fraction of continuum-like runs. Pure analysis of study results (no I/O).
#include <span>
#include <vector>

#include "studies/study.hpp"

namespace slipfront::studies {

/// The first N (log-log interpolation between the grid points) at which `error` falls below `level`
/// and stays below it for every larger N; NaN when it is below at the smallest N already (bounded
/// above by N[0]: see below_at_start) or never falls below. N ascending.
struct Crossover {
  double n_star = 0.0;
  bool below_at_start = false;  ///< valid at every N of the grid: N* < N[0]
  bool never_below = false;     ///< not valid at any N of the grid: N* > N.back()
};
Crossover crossover_n(std::span<const double> n, std::span<const double> error, double level);

/// Fig1 runs split into the continuum-like mode and the others by the ratio r = c_transient(discrete) /
/// c_transient(continuum) and the relative shift d = t^(discrete)/t^(continuum) − 1: continuum-like iff
/// r < c_threshold (1.2: in the empty gap between the continuum-like mode, r ≤ 1.16, and the others, r ≥ 1.24
/// among the 1344 runs of the validity_fig1 study with |d| < 0.1; the re-stuck mode sits at r ≈ 1.6 at small
/// α − 1 and at 1.25–1.45 at α − 1 = 0.2)
/// and |d| < t_threshold (0.1: the noise-driven early instability of very small N, t^ 25–30% early with
/// r ≈ 1, is not continuum-like); docs/validity.md. A run with no transient is not continuum-like.
/// Returns the fraction and its 95% Wilson interval.
struct ModeSplit {
  int runs = 0, continuum_like = 0;
  double fraction = 0.0, low = 0.0, high = 0.0;
};
ModeSplit classify_modes(std::span<const double> c_ratio, std::span<const double> t_hat_shift, double c_threshold = 1.2,
                         double t_threshold = 0.1);
/// Whether one run is continuum-like (the rule of classify_modes).
bool continuum_like(double c_ratio, double t_hat_shift, double c_threshold = 1.2, double t_threshold = 0.1);

/// Study kind "validity_friction": the steady friction law at imposed v, varying N, interface.alpha and
/// discrete.width, seeds; kind "validity_fig1": fig1 runs varying N and interface.alpha, seeds.
void analyse_validity_friction(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                               const std::vector<std::vector<ModelResult>>& res);
void analyse_validity_fig1(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                           const std::vector<std::vector<ModelResult>>& res);

}  // namespace slipfront::studies
