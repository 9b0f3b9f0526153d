#pragma once
// The one place that turns a scene's [discrete] section into an interface law type: every runner
// (run_scene, run_scene_alongside) dispatches through with_discrete_law, and builds the mean-field law
// (model mean_field, docs/model.md §2.2) with mean_field_law.
#include <array>
#include <stdexcept>
#include <string>
#include <string_view>

#include "compare/models.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "core/params.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/count_law.hpp"
#include "discrete/mean_field_law.hpp"
#include "discrete/naive_law.hpp"

namespace slipfront::compare {

/// Calls f(make_law) with make_law(n_sites) building the law of s.discrete.representation.
template <class F>
auto with_discrete_law(const Scene& s, F&& f) {
  const auto& d = s.discrete;
  if (d.representation == "count")
    return f([&](std::size_t n) { return discrete::CountLaw(s.interface, d, n); });
  if (d.representation == "agent")
    return f([&](std::size_t n) { return discrete::AgentLaw(s.interface, d, n); });
  if (d.representation == "naive")
    return f([&](std::size_t n) { return discrete::NaiveAgentLaw(s.interface, d, n); });
  throw core::ParamError("discrete.representation", "unknown representation '" + d.representation + "'");
}

/// The discrete settings as attributes of the model's group.
inline void label_discrete(const Scene& s, ModelResult& r) {
  const auto& d = s.discrete;
  r.labels["representation"] = d.representation;
  r.labels["threshold"] = d.threshold;
  r.labels["renewal"] = d.renewal;
  r.labels["noise"] = d.noise ? "true" : "false";
  r.labels["seed"] = std::to_string(d.seed);
  r.scalars["contacts_per_site"] = static_cast<double>(d.contacts_per_site);
  r.scalars["width"] = d.width;
  if (d.representation == "count") r.scalars["bins"] = d.width > 0.0 ? d.bins : 1.0;
}

/// The discrete.* keys mean_field reads (discrete::MeanFieldLaw; label_mean_field stores them): a study shares one
/// mean_field among runs that differ in the others only (compare::reference_ignores).
inline constexpr std::array<std::string_view, 4> mean_field_keys{"discrete.threshold", "discrete.width",
                                                                 "discrete.renewal", "discrete.bins"};

/// The model mean_field (docs/model.md §2.2): the population balance at the scene's threshold law, width,
/// renewal and binning (mean_field_keys).
inline discrete::MeanFieldLaw mean_field_law(const Scene& s, std::size_t sites) {
  return discrete::MeanFieldLaw(s.interface, s.discrete, sites);
}

/// The mean-field settings as attributes of its group: only the keys it reads.
inline void label_mean_field(const Scene& s, ModelResult& r) {
  const auto& d = s.discrete;
  r.labels["threshold"] = d.threshold;
  r.labels["renewal"] = d.renewal;
  r.scalars["width"] = d.width;
  r.scalars["bins"] = d.width > 0.0 ? d.bins : 1.0;
}

/// The one switch from a model's name (compare/models.hpp: model_kinds) to its law: calls f(make_law) with
/// make_law(n_sites) building the law of `model` on scene s, and returns what f returns (every model's f must return
/// one type). compare::run_scene and the Python module's runs call it; label_model stores the settings it read.
template <class F>
auto with_model_law(const Scene& s, std::string_view model, F&& f) {
  if (model == "continuum") return f([&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); });
  if (model == "mean_field") return f([&](std::size_t n) { return mean_field_law(s, n); });
  if (model == "discrete") return with_discrete_law(s, f);  // docs/model.md §2: by discrete.representation
  throw std::invalid_argument("unknown model '" + std::string(model) + "' (" + model_names() + ")");
}

/// The settings the law of `model` read, as attributes of its group.
inline void label_model(const Scene& s, std::string_view model, ModelResult& r) {
  if (model == "discrete") label_discrete(s, r);
  else if (model == "mean_field") label_mean_field(s, r);
}

}  // namespace slipfront::compare
