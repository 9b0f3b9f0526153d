#pragma once
// Checkpoint files of `slipfront run --checkpoint-every T` (issue 10; docs/cli.md): the state of a scene
// run (compare::RunControl) with the configuration it belongs to, written atomically (a temporary file
// created exclusively, renamed when complete), read back by `slipfront run --restart FILE`.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace slipfront::app {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Checkpoint {
  std::string resolved_toml;  ///< the fully resolved configuration of the run
  double time = 0.0;          ///< simulated time of the state
  std::string state;          ///< compare::RunControl state (core::Archive bytes)
};

/// Writes `path` atomically (".<name>.tmp.<pid>" created exclusively, then renamed). Throws CheckpointError.
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c);
/// Reads a checkpoint; throws CheckpointError naming the file and what is wrong with it.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace slipfront::app
