#pragma once
// The comparison layer (docs/model.md §2 hierarchy, issue 4): the continuum and the discrete model run
// alongside on one scene — same grid, time step and loading, advanced in lockstep in one process —
// with the field distances computed online at a cadence (so neither full history has to be kept),
// and the event times, speeds, friction histories and friction laws compared at the end. Every
// metric carries its definition.
#include <map>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "compare/run_control.hpp"
#include "compare/scene.hpp"

namespace slipfront::compare {

/// Run every model of the scene; with two or more of continuum, mean_field and discrete on a bulk scene on a
/// fixed-step integrator, in lockstep. Each model's result is bit-identical to the one run_scene gives for it
/// alone. The comparison (fields, events) is of the discrete model with its reference (mean_field when listed,
/// else the continuum; compare_results), when the discrete model and a reference run.
SceneResult run_scene_alongside(const Scene& s, const RunControl& ctl);

/// Whether the continuum of `s` can be computed once for several runs (a study's shared continuum, docs/studies.md):
/// the scene lists the continuum and another model, predicts no contact statistics (the prediction reads
/// discrete.contacts_per_site), and does not compare the continuum's fields online (in lockstep the discrete model's
/// fields are compared with its reference: the continuum's only when mean_field does not run and
/// output.compare_dt > 0). Then the continuum run reads no discrete.* key and no other model's state: its result is
/// the same for every discrete.* setting and seed, and each other model's is the one it gives alone.
bool continuum_shareable(const Scene& s);
/// run_scene_alongside of a continuum_shareable scene with its continuum given (`continuum`: run_scene of the scene
/// with models = {"continuum"}): the other models as run_scene_alongside runs them, the continuum's result put in
/// its place, the discrete model compared with its reference. Bit-identical to run_scene_alongside.
SceneResult run_scene_with_continuum(const Scene& s, const ModelResult& continuum, const RunControl& ctl);

/// The end-of-run comparison of the discrete model's results with its reference's (events, series, friction
/// law): the reference is mean_field when the scene lists it (docs/model.md §2.2: the ensemble's own N → ∞
/// limit at its w), else the continuum; fields are compared online by run_scene_alongside and merged in. The
/// contact statistics are compared with `predictor`'s prediction (docs/model.md §7.2; the run_scene_alongside
/// passes the reference: mean_field's prediction at the scene's w, else the continuum's; nullptr: none).
Comparison compare_results(const Scene& s, const ModelResult& reference, const ModelResult& discrete,
                           const ModelResult* predictor);
/// The same with the reference as the predictor (the continuum).
inline Comparison compare_results(const Scene& s, const ModelResult& continuum, const ModelResult& discrete) {
  return compare_results(s, continuum, discrete, &continuum);
}

}  // namespace slipfront::compare
