#pragma once
// Runs the models of a scene, one after the other (docs/architecture.md §2): run_model picks the kind of
// run a loading needs (a DynamicRun on a bulk, compare/dynamic_run.hpp; an imposed slip rate,
// compare/imposed_rate.hpp) and the stepper of time.integrator (compare/dispatch.hpp), and run_loop
// (compare/run_loop.hpp) drives it. run_scene_alongside (compare/alongside.hpp) runs two models in
// lockstep instead.
#include <string>
#include <string_view>
#include <vector>

#include "compare/dispatch.hpp"
#include "compare/dynamic_run.hpp"
#include "compare/imposed_rate.hpp"
#include "compare/result.hpp"
#include "compare/run_control.hpp"
#include "compare/run_loop.hpp"
#include "compare/scene.hpp"
#include "core/bulk.hpp"

namespace slipfront::compare {

/// docs/model.md §7.2: the continuum predicts the contact statistics the agent measures, and so does the
/// mean-field law at the scene's threshold disorder (docs/model.md §2.2) — on for the models "continuum" and
/// "mean_field" of a scene that records contact statistics with a representation that has them
/// (discrete.contact_statistics, agent or naive) on a fixed-step integrator, off otherwise.
ContactPredictionSetup contact_prediction_for(const Scene& s, std::string_view model);

/// Run one model on a scene, whichever loading and integrator it has. make_law(n_sites) builds the law.
template <class Law, class MakeLaw>
ModelResult run_model(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl,
                      const CheckpointHeader& header = {}, core::Archive* resume = nullptr) {
  if (s.drive.loading == core::Loading::imposed_rate) {
    if (resume) throw core::ArchiveError("checkpoint: an imposed-rate scene has no checkpoints");
    return run_imposed_rate<Law>(s, make_law, model, ctl);
  }
  return with_integrator(s, [&](auto tag) {
    using Stepper = typename decltype(tag)::template stepper<Law>;
    return run_dynamic<Law, Stepper>(s, make_law(body_shape(s).sites), model, ctl, header, resume,
                                     contact_prediction_for(s, model));
  });
}

/// Every model the scene lists, in order, each run alone.
std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl);

}  // namespace slipfront::compare
