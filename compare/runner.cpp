#include "compare/runner.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "compare/laws.hpp"
#include "core/interrupt.hpp"

namespace slipfront::compare {

ContactPredictionSetup contact_prediction_for(const Scene& s, std::string_view model) {
  const bool agent_statistics = s.lists("discrete") && s.discrete.contact_statistics && s.discrete.representation != "count";
  ContactPredictionSetup setup;
  // the continuum's prediction (w = 0) and, when it runs, the mean-field law's at the scene's w (docs/model.md §2.2)
  if ((model == "continuum" || model == "mean_field") && agent_statistics &&
      s.time.integrator != core::Integrator::adaptive_rosenbrock)
    setup.mode = ContactPredictionSetup::Mode::on;
  return setup;
}

std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl) {
  // Models one after the other. A checkpoint holds the models finished so far and the one running.
  std::vector<ModelResult> out;
  std::optional<core::Archive> resume;
  if (!ctl.restart.empty()) {
    resume = core::Archive::reader(ctl.restart);
    resume->tag("sequential");
    (*resume)(out);
  }
  const CheckpointHeader header = [&](core::Archive& ar) {
    ar.tag("sequential");
    auto done = out;
    ar(done);
  };
  for (std::size_t k = out.size(); k < s.models.size(); ++k) {
    const std::string& m = s.models[k];
    core::Archive* from = resume && !resume->at_end() ? &*resume : nullptr;
    try {
      // compare/models.hpp: the model's law from the table's one switch
      out.push_back(with_model_law(s, m, [&](auto make) {
        using Law = decltype(make(std::size_t{1}));
        return run_model<Law>(s, make, m, ctl, header, from);
      }));
      label_model(s, m, out.back());
    } catch (const core::ArchiveError&) {
      throw;  // a checkpoint that does not fit this scene: the caller reports it
    } catch (const core::Interrupted& e) {  // a stop request during the set-up of its law
      ModelResult stopped;
      stopped.model = m;
      stopped.status = RunStatus::interrupted;
      stopped.message = e.what();
      out.push_back(std::move(stopped));
    } catch (const std::exception& e) {  // keep what the earlier models produced
      ModelResult failed;
      failed.model = m;
      failed.status = RunStatus::failed;
      failed.message = e.what();
      out.push_back(std::move(failed));
    }
    if (out.back().status != RunStatus::complete) break;
  }
  return out;
}

}  // namespace slipfront::compare
