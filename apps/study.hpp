#pragma once
// `slipfront study`: convergence studies (issue 4). A study file (TOML) names a base scene, the
// overrides common to every run, the keys to vary (one [vary] table, or several [[group]]s) and the
// number of seeds. Every run is validated before any work; runs go to a pool of threads; each
// run's results are kept in DIR/runs/<id>/results.h5 and the analysis in DIR/study.h5.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "compare/study.hpp"

namespace slipfront::app {

/// Read a study file (errors: ConfigError naming file, key and reason). The scene path in the
/// returned spec is resolved relative to the study file.
compare::StudySpec load_study(const std::filesystem::path& file);

struct StudyOptions {
  std::filesystem::path study;
  std::vector<std::string> overrides;  ///< --set, applied to every run after the study's own
  std::filesystem::path out;           ///< empty: out/studies/<study name>
  unsigned threads = 0;                ///< 0: hardware concurrency
  bool force = false;
  bool quiet = false;
  std::string command_line;
};

int study_command(const StudyOptions& opts, std::ostream& out, std::ostream& err);

/// `slipfront report DIR`: runs scripts/report.py on DIR (plots + report.md).
int report_command(const std::filesystem::path& dir, const std::string& python, std::ostream& err);

}  // namespace slipfront::app
