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
/// alone. The comparison (fields, events) is of the continuum and the discrete model, when both run.
SceneResult run_scene_alongside(const Scene& s, const RunControl& ctl);

/// The end-of-run comparison of two models' results (events, series, friction law); fields are
/// compared online by run_scene_alongside and merged in.
Comparison compare_results(const Scene& s, const ModelResult& continuum, const ModelResult& discrete);

}  // namespace slipfront::compare
