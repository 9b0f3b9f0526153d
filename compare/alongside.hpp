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

/// Run every model of the scene; with two or more on a bulk scene on a fixed-step integrator, in lockstep
/// (compare/lockstep.hpp: run_in_lockstep over the table's models, ShippedModels). Each model's result is bit-identical to the one run_scene gives for it
/// alone. The comparison (fields, events) is of the discrete model with its reference (mean_field when listed,
/// else the continuum; compare_results), when the discrete model and a reference run.
SceneResult run_scene_alongside(const Scene& s, const RunControl& ctl);

/// The models of `s` whose results a study can compute once for several runs (its shared references,
/// docs/studies.md): the continuum and mean_field, each when the scene lists it and another model, predicts no
/// contact statistics (the prediction reads discrete.contacts_per_site), and does not compare the model's fields
/// online (in lockstep the discrete model's fields are compared at output.compare_dt > 0 with its reference:
/// mean_field when it runs, else the continuum). Such a model reads no other model's state, so its result is the
/// one it gives alone, and it reads none of the keys reference_ignores names.
std::vector<std::string> shareable_references(const Scene& s);
/// Whether the scene key `key` (dotted, as in an override "key=value") leaves `model`'s result unchanged: the
/// continuum reads no discrete.* key; mean_field reads discrete.threshold, width, renewal and bins and no other
/// discrete.* key (docs/model.md §2.2). Every other key counts (false).
bool reference_ignores(const std::string& model, const std::string& key);
/// run_scene_alongside of `s` with the results of some of shareable_references(s) given (`given`: model → its
/// result, run_scene of the scene with that model alone): the other models as run_scene_alongside runs them, the
/// given results put in their places, the discrete model compared with its reference (mean_field when listed,
/// else the continuum). Bit-identical to run_scene_alongside. Throws std::invalid_argument for a given model that
/// is not shareable or a result of another model.
SceneResult run_scene_with_references(const Scene& s, const std::map<std::string, const ModelResult*>& given,
                                      const RunControl& ctl);

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
