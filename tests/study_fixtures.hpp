#pragma once
// Small studies for the tests of `slipfront study` (resume, MPI, install): scene and study files
// written into a scratch directory, so the tests do not depend on configs/ (which others edit).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/h5in.hpp"
#include "scenes.hpp"

namespace slipfront::testing {

/// Edge loading (paper parameters, L = 150, dx = 0.5, t_end = 80), both models alongside with
/// N = 300 or 1000 contacts per site, 3 seeds: 6 runs of ~0.25 s each on this machine, with
/// snapshots, events and /compare. Kind front_speeds (fits over N, seed spreads).
inline std::filesystem::path write_front_study(const std::filesystem::path& dir, double t_end = 80.0) {
  std::ofstream(dir / "edge.toml") << R"(scene = "edge"
models = ["continuum", "discrete"]
)" << paper_interface_toml() << R"(mu = 300
length = 150
[drive]
loading = "edge"
K = 2.5
v_d = 0.3
[grid]
dx = 0.5
[time]
t_end = )" << t_end << R"(
[output]
snapshot_dt = 2
[discrete]
contacts_per_site = 1000
)";
  const auto study = dir / "fronts.toml";
  std::ofstream(study) << R"(study = "fronts"
kind = "front_speeds"
scene = "edge.toml"
seeds = 3
[vary]
"discrete.contacts_per_site" = [300, 1000]
)";
  return study;
}

/// Imposed-rate sweep (5 rates, 500 steps each), both models, N = 100 .. 10000, 2 seeds: 6 runs of
/// a few milliseconds. Kind friction_law.
inline std::filesystem::path write_sweep_study(const std::filesystem::path& dir) {
  std::ofstream(dir / "sweep.toml") << sweep_config(500);
  const auto study = dir / "sweeps.toml";
  std::ofstream(study) << R"(study = "sweeps"
kind = "friction_law"
scene = "sweep.toml"
seeds = 2
[vary]
"discrete.contacts_per_site" = [100, 1000, 10000]
)";
  return study;
}

/// The run files under DIR/runs, in run order.
inline std::vector<std::filesystem::path> run_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir / "runs"))
    files.push_back(e.path() / "results.h5");
  std::sort(files.begin(), files.end());
  return files;
}

/// /meta status of a run file; "" if it is missing or unreadable.
inline std::string run_status(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return "";
  try {
    return compare::to_string(app::read_results_header(file).status);
  } catch (const app::InputError&) {
    return "";
  }
}

}  // namespace slipfront::testing
