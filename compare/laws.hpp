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

/// The discrete.* keys mean_field reads (its row of compare::model_kinds, discrete_keys; label_mean_field stores them):
/// a study shares one mean_field among runs that differ in the others only (compare::reference_ignores).
inline constexpr const auto& mean_field_keys = find_model_kind("mean_field")->discrete_keys;

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

/// The models of the table as types, one per row of compare::model_kinds (compare/models.hpp): its row (`kind`), how
/// its law is built (`with_law(s, f)` calls f(make_law), make_law(n_sites) building the law on scene s) and the
/// settings its law read as attributes of its group (`label`). A new model is its law's own files, one such type, and
/// its row and its entry in ShippedModels (docs/architecture.md "Where a new law goes").
struct ContinuumModel {
  static constexpr const ModelKind& kind = model_kinds[0];
  template <class F>
  static decltype(auto) with_law(const Scene& s, F&& f) {
    return f([&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); });
  }
  static void label(const Scene&, ModelResult&) {}
};
struct MeanFieldModel {
  static constexpr const ModelKind& kind = model_kinds[1];
  template <class F>
  static decltype(auto) with_law(const Scene& s, F&& f) {
    return f([&](std::size_t n) { return mean_field_law(s, n); });
  }
  static void label(const Scene& s, ModelResult& r) { label_mean_field(s, r); }
};
struct DiscreteModel {
  static constexpr const ModelKind& kind = model_kinds[2];
  template <class F>
  static decltype(auto) with_law(const Scene& s, F&& f) {
    return with_discrete_law(s, f);  // docs/model.md §2: by discrete.representation
  }
  static void label(const Scene& s, ModelResult& r) { label_discrete(s, r); }
};

/// A set of models (types as above), in the order of their rows: what the run layer switches on. The shipped set is
/// ShippedModels; a test adds its own law with a set of its own (tests/test_law_seam.cpp).
template <class... M>
struct ModelSet {
  /// f.template operator()<M>() for each model, in order.
  template <class F>
  static constexpr void each(F&& f) {
    (f.template operator()<M>(), ...);
  }
  /// The row of model `name`, or nullptr.
  static const ModelKind* find(std::string_view name) {
    const ModelKind* out = nullptr;
    ((out = !out && M::kind.name == name ? &M::kind : out), ...);
    return out;
  }
  /// The names, "a, b or c" (for messages).
  static std::string names() {
    const std::array<std::string_view, sizeof...(M)> n{M::kind.name...};
    std::string out;
    for (std::size_t k = 0; k < n.size(); ++k) out += (k == 0 ? "" : k + 1 == n.size() ? " or " : ", ") + std::string(n[k]);
    return out;
  }
  /// The one switch from a model's name to its law: M::with_law(s, f) of the model called `name`; every model's f
  /// must return one type.
  template <class F>
  static decltype(auto) with_law(const Scene& s, std::string_view name, F&& f) {
    return with_law_of<F, M...>(s, name, f);
  }
  /// The settings the law of `name` read, as attributes of its group.
  static void label(const Scene& s, std::string_view name, ModelResult& r) {
    ((M::kind.name == name ? M::label(s, r) : void()), ...);
  }

 private:
  template <class F, class First, class... Rest>
  static decltype(auto) with_law_of(const Scene& s, std::string_view name, F& f) {
    if constexpr (sizeof...(Rest) == 0) {
      if (name != First::kind.name)
        throw std::invalid_argument("unknown model '" + std::string(name) + "' (" + names() + ")");
      return First::with_law(s, f);
    } else {
      if (name == First::kind.name) return First::with_law(s, f);
      return with_law_of<F, Rest...>(s, name, f);
    }
  }
};

/// The models slipfront ships: the rows of compare::model_kinds, in order.
using ShippedModels = ModelSet<ContinuumModel, MeanFieldModel, DiscreteModel>;
static_assert([] {
  std::size_t k = 0;
  bool same = true;
  ShippedModels::each([&]<class M>() { same = same && k < model_kinds.size() && &M::kind == &model_kinds[k++]; });
  return same && k == model_kinds.size();
}(), "ShippedModels lists the rows of compare::model_kinds, each once, in order");

/// The one switch from a model's name (compare/models.hpp: model_kinds) to its law: calls f(make_law) with
/// make_law(n_sites) building the law of `model` on scene s, and returns what f returns (every model's f must return
/// one type). compare::run_scene, the lockstep (compare/lockstep.hpp) and the Python module's runs call it;
/// label_model stores the settings it read.
template <class F>
decltype(auto) with_model_law(const Scene& s, std::string_view model, F&& f) {
  return ShippedModels::with_law(s, model, f);
}

/// The settings the law of `model` read, as attributes of its group.
inline void label_model(const Scene& s, std::string_view model, ModelResult& r) { ShippedModels::label(s, model, r); }

}  // namespace slipfront::compare
