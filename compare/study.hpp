#pragma once
// Convergence studies (issue 4): a study is a base scene, overrides common to all runs, and groups
// of varied keys (cartesian product inside a group, union over groups) × seeds. Each run is an
// independent scene run; the analysis of a study kind turns the runs' results into tables and
// fitted rates, each with its definition. Nothing here reads or writes files.
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"

namespace slipfront::compare {

struct StudyGroup {
  std::string name;                                               ///< e.g. "mu" in a Fig. 2 sweep
  std::vector<std::pair<std::string, std::vector<std::string>>> vary;  ///< key -> values (TOML text)
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

/// What a study produced: tables of columns, scalars (fitted rates), a definition for every
/// table column and scalar, and notes (findings, points that could not be measured).
struct StudyReport {
  std::map<std::string, Columns> tables;
  std::map<std::string, double> scalars;
  std::map<std::string, std::string> definitions;  ///< "table/column" or scalar name -> definition
  std::vector<std::string> notes;
};

/// The analysis of one study kind: adds its tables, scalars, definitions and notes to `rep`
/// (scenes[i], results[i] belong to runs[i]).
using StudyAnalysis = void (*)(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                               const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& results);

/// One study kind: the name a study file gives as `kind`, what it analyses, and its analysis
/// (nullptr: none, the kind "runs").
struct StudyKind {
  std::string_view name;
  std::string_view description;
  StudyAnalysis analyse = nullptr;
};

/// The known study kinds, in the order they are listed; analyse_study dispatches on the same table.
std::span<const StudyKind> study_kinds();

/// The kind called `name` (nullptr if there is none).
const StudyKind* find_study_kind(std::string_view name);

/// Analyse the results of every run (scenes[i], results[i] belong to runs[i]; one result per model).
StudyReport analyse_study(const StudySpec& spec, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& results);

/// Result of the model named `model` in one run's results (nullptr if absent).
const ModelResult* find_model(const std::vector<ModelResult>& r, const std::string& model);

}  // namespace slipfront::compare
