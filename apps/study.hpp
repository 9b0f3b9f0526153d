#pragma once
// `slipfront study`: convergence studies (issue 4). A study file (TOML) names a base scene, the
// overrides common to every run, the keys to vary (one [vary] table, or several [[group]]s) and the
// number of seeds. Every run is validated before any work; runs go to a pool of threads, or, when
// mpirun started the process, to every MPI rank (apps/study_mpi.hpp); each run's results are kept in
// DIR/runs/<id>/results.h5 and the analysis in DIR/study.h5. Runs whose file is complete for the same
// configuration are skipped (resume; docs/studies.md).
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "studies/study.hpp"

namespace slipfront::app {

/// Read a study file (errors: ConfigError naming file, key and reason), through read_config_file (a
/// regular file of at most 1 MiB). The scene path in the returned spec is resolved relative to the
/// study file; repeated vary values are kept once, with a note in spec.notes. `text`: the file's text.
compare::StudySpec load_study(const std::filesystem::path& file, std::string* text = nullptr);
/// The same from a study file's text (`file` names it in messages and anchors a relative `scene`).
compare::StudySpec load_study_text(const std::filesystem::path& file, const std::string& text);

struct StudyOptions {
  std::filesystem::path study;
  std::string study_text;              ///< non-empty: the study file's text (generated: check-resolution), named `study`
  std::vector<std::string> overrides;  ///< --set, applied to every run after the study's own
  std::filesystem::path out;           ///< empty: out/studies/<study name>
  unsigned threads = 0;                ///< 0: hardware concurrency (under mpirun: per rank, 0 = 1)
  bool force = false;                  ///< rerun every run, replace study.h5
  bool quiet = false;
  std::string progress = "line";       ///< --progress: "line" (on a terminal) or "json" (apps/json_progress.hpp)
  std::string command_line;
  bool list_kinds = false;             ///< --list-kinds: print the study kinds (no study file), then exit
  bool json = false;                   ///< --json (with --list-kinds): as one JSON object (study_kinds_json)
};

/// The study kinds (studies::study_kinds() of studies/study.hpp, the one table) as JSON: {"kinds": [{"name",
/// "description", "models", "runs", "analysis"}, ...]} in the table's order (docs/cli.md "slipfront study
/// --list-kinds"); what scripts/report.py's plots are checked against (tests/test_study_kinds.cpp).
std::string study_kinds_json();

int study_command(const StudyOptions& opts, std::ostream& out, std::ostream& err);

/// `slipfront report DIR`: runs report.py (apps/paths.hpp finds it) on DIR (plots + report.md), with
/// posix_spawnp and an argument vector: no shell.
int report_command(const std::filesystem::path& dir, const std::string& python, std::ostream& err);

}  // namespace slipfront::app
