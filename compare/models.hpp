#pragma once
// The models a scene can list (`models`, docs/model.md §2, §2.2), one row each, as the study kinds are one table:
// what every switch on a model's name reads — the scene's check of `models` (compare/scene.cpp), the reference a
// discrete model is compared with (discrete_reference), and the one dispatch from a name to its law type
// (compare::with_model_law, compare/laws.hpp), which compare::run_scene and the Python module's runs both call.
// No law header here: the scene reads the table without building a law.
#include <array>
#include <string>
#include <string_view>

namespace slipfront::compare {

struct ModelKind {
  std::string_view name;        ///< as listed in `models`
  std::string_view section;     ///< the configuration section its law reads
  std::string_view law;         ///< how its law is built (compare::with_model_law)
  /// The models it is compared with, in order of preference (the first the scene lists; empty: none). Whole literals:
  /// data() is a C string.
  std::array<std::string_view, 2> references;
  std::string_view cost;        ///< what a step costs per site
  /// The discrete.* keys its law reads: none (empty), these (up to four), or all ("discrete.*"). A study shares one
  /// run of a deterministic model among runs that differ in keys it does not read (compare::reference_ignores).
  std::array<std::string_view, 4> discrete_keys;
  /// Its runs draw random numbers (a seed): never shared among the runs of a study (compare::shareable_references).
  bool seeded = false;
};

inline constexpr std::array<ModelKind, 3> model_kinds{{
    {"continuum", "interface", "continuum::FrictionLaw(interface, sites): the rate law of docs/model.md §1", {},
     "one exact update (a few exponentials)", {}, false},
    {"mean_field", "discrete (threshold, width, renewal, bins only)",
     "discrete::MeanFieldLaw: the ensemble's N -> infinity population balance, docs/model.md §2.2", {},
     "one exact update per threshold class",
     {"discrete.threshold", "discrete.width", "discrete.renewal", "discrete.bins"}, false},
    {"discrete", "discrete",
     "by discrete.representation: discrete::CountLaw (count), AgentLaw (agent), NaiveAgentLaw (naive), docs/model.md §2",
     {"mean_field", "continuum"}, "count: binomial draws per threshold bin; agent, naive: per contact event",
     {"discrete.*"}, true},
}};

/// Whether a model of the table is a reference of another (compared with it: `references`).
constexpr bool is_reference_model(std::string_view name) {
  for (const auto& k : model_kinds)
    for (const auto& r : k.references)
      if (!r.empty() && r == name) return true;
  return false;
}

/// The row of model `name`, or nullptr.
constexpr const ModelKind* find_model_kind(std::string_view name) {
  for (const auto& k : model_kinds)
    if (k.name == name) return &k;
  return nullptr;
}

/// The names of the table, "a, b or c" (for messages).
inline std::string model_names() {
  std::string out;
  for (std::size_t k = 0; k < model_kinds.size(); ++k)
    out += (k == 0 ? "" : k + 1 == model_kinds.size() ? " or " : ", ") + std::string(model_kinds[k].name);
  return out;
}

}  // namespace slipfront::compare
