#pragma once
// The plan of a study (issue 4): a base scene, overrides common to all runs, and groups of varied keys
// (cartesian product inside a group, union over groups) × seeds, expanded into independent scene runs. The run
// layer's side of a study: what compare::estimate_study prices and the study engine (apps/study.cpp) runs. The
// kinds of study and their analyses are studies/ (studies/study.hpp). Nothing here reads or writes files.
#include <any>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/params.hpp"

namespace slipfront::compare {

struct StudyGroup {
  std::string name;                                               ///< e.g. "mu" in a Fig. 2 sweep
  std::vector<std::pair<std::string, std::vector<std::string>>> vary;  ///< key -> values (TOML text)
};

/// What a study may cost in its own process, study file section [limits] (docs/studies.md): checked
/// against compare::estimate_study before any run is expanded or any directory created. (Each run's
/// own cost is checked against its scene's [limits].)
struct StudyLimits {
  double max_runs = 1e5;         ///< runs of the study: points x seeds over every group
  double max_memory_gib = 16.0;  ///< the plan and the results kept for the analysis
};

struct StudySpec {
  std::string name, kind, description;
  std::string scene_file;            ///< base scene (path as given, resolved by the caller)
  std::vector<std::string> common;   ///< overrides for every run ("section.key=value")
  std::vector<StudyGroup> groups;
  int seeds = 1;                     ///< runs per point with discrete.seed = 1..seeds
  /// N-convergence fits: besides the fit over every N, a second fit (suffix _from) over N >= fit_from,
  /// the mean-field regime (below it small N re-sticks: a bias, not the N^(-1/2) random error).
  double fit_from = 0.0;
  StudyLimits limits;
  /// The kind's own section of the study file, of the type its kind defines (studies/): [paths] of
  /// strip_cmin_height (StripCminHeightOptions), [resolution] of resolution (ResolutionOptions); empty: the kind's
  /// defaults (kind_options in studies/study.hpp). Read by apps/study.cpp; opaque here, so a kind with a section of its own
  /// changes nothing in compare/.
  std::any kind_options;
  /// The deterministic references (the continuum, mean_field) of runs that differ only in keys they do not read
  /// (compare::reference_ignores: the seed, N, ...) are run once and shared (compare::shareable_references;
  /// docs/studies.md "The shared references"); false: every run its own. Study key share_references (or its
  /// earlier name share_continuum).
  bool share_references = true;
  std::vector<std::string> notes;    ///< what loading the file changed (repeated vary values collapsed)
};

/// One run of a study: its overrides and the values of the varied keys.
struct StudyRun {
  std::string id;                           ///< "0007"
  std::string group;
  std::vector<std::string> overrides;       ///< common + varied + seed
  std::map<std::string, std::string> point; ///< varied key -> value text
  int seed = 1;
};

std::vector<StudyRun> expand(const StudySpec& spec);

/// The domains of the study file's numeric keys (seeds, fit_from, limits.*), as core::KeyDomain rows.
std::span<const core::KeyDomain> study_key_domains();

/// Runs of the study: points (the cartesian product of each group's lists, summed over the groups)
/// times seeds, counted without expanding them (a double: never overflows).
double count_runs(const StudySpec& spec);

/// One run per group, at the group's first point and seed 1: what the study's estimate measures
/// (compare::estimate_study) before every run is expanded.
std::vector<StudyRun> sample_runs(const StudySpec& spec);

}  // namespace slipfront::compare
