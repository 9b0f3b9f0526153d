#pragma once
// Convergence studies (issue 4): a study is a base scene, overrides common to all runs, and groups
// of varied keys (cartesian product inside a group, union over groups) × seeds. Each run is an
// independent scene run; the analysis of a study kind turns the runs' results into tables and
// fitted rates, each with its definition. Nothing here reads or writes files.
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/resolution.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "compare/strip_cmin_height.hpp"

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
  /// [paths] of a kind without scene runs (strip_cmin_height): the path in H; its law and material are the
  /// base scene's (strip_cmin_study_options), stop and log the caller's.
  StripCminHeightOptions paths;
  /// [resolution] of the kind resolution (compare/resolution.hpp): its levels are planned from the base scene.
  ResolutionOptions resolution;
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

/// What a study produced: tables of columns, scalars (fitted rates), a definition for every
/// table column and scalar, and notes (findings, points that could not be measured).
struct StudyReport {
  std::map<std::string, Columns> tables;
  std::map<std::string, double> scalars;
  std::map<std::string, std::string> definitions;  ///< "table/column" or scalar name -> definition
  std::vector<std::string> notes;
  std::map<std::string, std::string> files;  ///< text files written beside study.h5: name -> text (strip_cmin_height.csv)
  std::vector<std::string> summary;  ///< a kind's own terminal table (resolution), printed instead of the scalars
};

/// The analysis of one study kind: adds its tables, scalars, definitions and notes to `rep`
/// (scenes[i], results[i] belong to runs[i]).
using StudyAnalysis = void (*)(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                               const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& results);

/// The models whose results an analysis measures or compares: each model marked must be listed in
/// the `models` of every run (neither: any model will do).
struct ModelsNeeded {
  bool continuum = false;
  bool discrete = false;
  bool mean_field = false;  ///< (disorder_limit: only with the continuum)
};
/// "the continuum and the discrete model", "the continuum model", ..., "any model".
std::string describe(ModelsNeeded needs);

/// What the caller gives a kind without scene runs: a stop request (polled before every solve) and progress
/// lines (without the newline).
struct StudyWork {
  std::function<bool()> stop;
  std::function<void(const std::string&)> log;
};

/// How such a kind's computation ended (complete; interrupted by a stop; failed, with the reason).
struct StudyOutcome {
  RunStatus status = RunStatus::complete;
  std::string message;
};

/// The computation of a kind without scene runs: from the study's base scene (after `set` and --set) and its
/// own keys ([paths]), adds tables, scalars, definitions, notes and files to `rep`.
using StudyComputation = StudyOutcome (*)(StudyReport& rep, const StudySpec& spec, const Scene& base,
                                          const StudyWork& work);
/// Its checks of the base scene with the study's own keys, before any work (throws core::ParamError naming the key).
using StudyCheck = void (*)(const StudySpec& spec, const Scene& base);
/// The groups of a kind that plans its runs from the base scene (resolution: the levels), instead of [vary]/[[group]].
using StudyPlan = std::vector<StudyGroup> (*)(const StudySpec& spec, const Scene& base);

/// One study kind: the name a study file gives as `kind`, what it analyses, the models its analysis
/// needs, and its analysis (nullptr: none, the kind "runs"); or, for a kind that runs no scene (no
/// [[group]], vary, seeds: refused at load), its computation instead.
struct StudyKind {
  std::string_view name;
  std::string_view description;
  ModelsNeeded needs;
  StudyAnalysis analyse = nullptr;
  StudyComputation compute = nullptr;
  StudyCheck check = nullptr;  ///< (with compute or plan)
  StudyPlan plan = nullptr;    ///< its runs' groups, from the base scene (no [[group]], vary, seeds in the file)
};

/// The models `kind` needs that `scene` does not list ("" when it lists them all), e.g. "continuum".
std::string missing_models(const StudyKind& kind, const Scene& scene);

/// The known study kinds, in the order they are listed; analyse_study dispatches on the same table.
std::span<const StudyKind> study_kinds();

/// The kind called `name` (nullptr if there is none).
const StudyKind* find_study_kind(std::string_view name);

/// Analyse the results of every run (scenes[i], results[i] belong to runs[i]; one result per model).
StudyReport analyse_study(const StudySpec& spec, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& results);

/// Analysis helpers shared by the kinds: one fitted rate as scalars `name`, `name_ci_low`, `name_ci_high`,
/// `name_points` with its definition; put_fits: the power-law fit over every point, and (name + "_from") over
/// x >= from when that leaves >= 3 points (the study key fit_from).
struct LineFit;
void put_fit(StudyReport& rep, const std::string& name, const LineFit& f, const std::string& what);
void put_fits(StudyReport& rep, const std::string& name, const std::vector<double>& x, const std::vector<double>& y,
              double from, const std::string& what);

/// Result of the model named `model` in one run's results (nullptr if absent).
const ModelResult* find_model(const std::vector<ModelResult>& r, const std::string& model);

}  // namespace slipfront::compare
