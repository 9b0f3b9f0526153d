#pragma once
// The kinds of study (issue 4; docs/studies.md): a study's plan (compare/study_plan.hpp) expands into independent
// scene runs; the analysis of its kind turns the runs' results into tables and fitted rates, each with its
// definition. study_kinds() is the one table of kinds: the study engine dispatches on it, `slipfront study
// --list-kinds --json` prints it, and the report's plots (scripts/report.py) are checked against it. Nothing here
// reads or writes files.
#include <any>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "compare/study_plan.hpp"

namespace slipfront::compare {
struct LineFit;
}  // namespace slipfront::compare

namespace slipfront::studies {
using namespace compare;  // the run layer's vocabulary: Scene, StudySpec, ModelResult, ...

/// The kind's own section of `spec` (StudySpec::kind_options, of type T: StripCminHeightOptions,
/// ResolutionOptions), or T's defaults when the study file has none.
template <class T>
T kind_options(const StudySpec& spec) {
  return spec.kind_options.has_value() ? std::any_cast<const T&>(spec.kind_options) : T{};
}

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
void put_fit(StudyReport& rep, const std::string& name, const LineFit& f, const std::string& what);
void put_fits(StudyReport& rep, const std::string& name, const std::vector<double>& x, const std::vector<double>& y,
              double from, const std::string& what);

/// Result of the model named `model` in one run's results (nullptr if absent).
const ModelResult* find_model(const std::vector<ModelResult>& r, const std::string& model);

}  // namespace slipfront::studies
