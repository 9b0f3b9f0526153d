#pragma once
// The slipfront command line (docs/model.md §5; documented in docs/cli.md): verbs `run` and `check`.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace slipfront::app {

/// Exit codes of the program.
namespace exit_code {
inline constexpr int ok = 0;            ///< every model complete (run), config valid (check)
inline constexpr int failed = 1;        ///< a model failed, the run threw, or the results could not be written
inline constexpr int usage = 2;         ///< bad command line, bad configuration, unusable output directory
inline constexpr int interrupted = 130; ///< SIGINT/SIGTERM: the partial results were written
}  // namespace exit_code

struct RunOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;  ///< --set section.key=value
  std::filesystem::path out;           ///< empty: out/<scene name>
  bool force = false;
  bool quiet = false;
  std::string progress = "line";       ///< --progress: "line" (on a terminal) or "json" (apps/json_progress.hpp)
  double checkpoint_every = 0.0;       ///< > 0: write DIR/checkpoint.bin every this much simulated time
  std::filesystem::path restart;       ///< non-empty: continue from this checkpoint
  std::string command_line;            ///< recorded in /meta
};

/// `slipfront run`: returns the exit code. Messages go to `out` (summary) and `err` (errors, notes).
int run_command(const RunOptions& opts, std::ostream& out, std::ostream& err);

/// `slipfront check`: validates and prints the resolved TOML to `out`; returns the exit code.
int check_command(const std::filesystem::path& config, const std::vector<std::string>& overrides, std::ostream& out,
                  std::ostream& err);

struct FrontsOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;
  std::filesystem::path out;  ///< empty: out/<scene name>
  bool scaling = false;
  bool force = false;
  std::string command_line;
  int rows = 0;          ///< the strip (bulk.height > 0): row intervals across the height; 0: chosen by rtol
  int intervals = 0;     ///< the strip: ξ intervals; 0: chosen by rtol
  double rtol = 1e-3;    ///< the target relative error of every reported speed (docs/fronts.md §10.20)
  double budget = 0.0;   ///< the strip's mesh choice: CPU seconds it may cost; 0: compare::default_fronts_budget_seconds
};
/// `slipfront fronts`: the steady fronts of a homogeneous scene to DIR/fronts.h5 (docs/model.md §6).
int fronts_command(const FrontsOptions& opts, std::ostream& out, std::ostream& err);

/// The whole program: parses argv and dispatches to a verb.
int main_cli(int argc, char** argv);

/// "slipfront 0.1.0 (git <commit>)".
std::string version_string();

}  // namespace slipfront::app
