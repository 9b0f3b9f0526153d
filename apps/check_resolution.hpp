#pragma once
// `slipfront check-resolution CONFIG`: the resolution check of one scene (issue 36; docs/cli.md). It writes the study
// of kind resolution for the scene (studies/resolution.hpp; the study file's text is kept in DIR/study.h5) and runs it
// on the study engine (apps/study.hpp): its runs, resume, progress, stop and DIR/study.h5 are a study's.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "studies/resolution.hpp"

namespace CLI {
class App;
}

namespace slipfront::app {

struct ResolutionCheckOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;  ///< --set, applied to every level's runs
  std::filesystem::path out;           ///< empty: out/resolution/<scene name>
  unsigned threads = 0;                ///< as `study -j`
  bool force = false;
  bool quiet = false;
  studies::ResolutionOptions check;    ///< --levels, --coarser, --ratio, --tolerance, --tolerance-order, --seeds
  std::string command_line;
};

/// The study file of kind resolution for the scene (its path absolute) and these options, as TOML text.
std::string resolution_study_text(const std::string& scene_name, const std::filesystem::path& config,
                                  const studies::ResolutionOptions& o);

/// `slipfront check-resolution`: returns the exit code (a study's: 0, 1, 2, 130).
int check_resolution_command(const ResolutionCheckOptions& opts, std::ostream& out, std::ostream& err);

/// The verb and its options on `app`.
CLI::App* add_check_resolution_verb(CLI::App& app, ResolutionCheckOptions& opts);

}  // namespace slipfront::app
