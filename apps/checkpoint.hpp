#pragma once
// Checkpoint files of `slipfront run --checkpoint-every T` (issue 10; docs/cli.md): the state of a scene
// run (compare::RunControl) with the configuration it belongs to, written atomically (a temporary file
// created exclusively, renamed when complete), read back by `slipfront run --restart FILE`.
//
// Format 2 (issue 18: trust nothing read back):
//   slipfront-checkpoint 2\n
//   checksum xxh3-64 <16 hex digits>\n      XXH3-64 (core::content_hash) of every byte after this line
//   commit <git commit of the build>\n
//   time <simulated time>\n
//   toml <N>\n<N bytes: the resolved configuration>\n
//   state <M>\n<M bytes: the compare::RunControl state (core::Archive), to the end of the file>
// A file is refused (CheckpointError naming it and the reason) unless it is a regular file within the
// size limit, its checksum matches, it was written by this build (the same commit) and every size in
// it fits in what follows. Format 1 (no checksum) is refused with its version and writer named.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace slipfront::app {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Checkpoint {
  std::string resolved_toml;  ///< the fully resolved configuration of the run
  double time = 0.0;          ///< simulated time of the state
  std::string state;          ///< compare::RunControl state (core::Archive bytes)
  std::string commit;         ///< the build that wrote it (read back: always this build's)
};

/// The largest checkpoint read_checkpoint accepts unless told otherwise (a checkpoint is read whole into
/// memory; `slipfront run` passes its limits.max_memory_gib instead).
inline constexpr std::uint64_t default_max_checkpoint_bytes = std::uint64_t{16} << 30;

/// The bytes of a checkpoint (the format above) of the run state `state` at simulated time `time`.
std::string checkpoint_bytes(std::string_view resolved_toml, double time, std::string_view state);
/// Verifies and reads checkpoint bytes (format 2, checksum, this build's commit, sizes); throws CheckpointError
/// "<source>: not a usable checkpoint: <why>".
Checkpoint parse_checkpoint(std::string_view bytes, const std::string& source);

/// Writes `path` atomically (".<name>.tmp.<pid>", app::temporary_path, created exclusively, synced,
/// then renamed): the resolved configuration and the state at simulated time `time`. Throws
/// CheckpointError.
void write_checkpoint(const std::filesystem::path& path, std::string_view resolved_toml, double time,
                      std::string_view state);
/// Reads and verifies a checkpoint (see the format above): a regular file of at most `max_bytes`,
/// format 2, checksum, commit, sizes. Throws CheckpointError naming the file and what is wrong with it.
Checkpoint read_checkpoint(const std::filesystem::path& path, std::uint64_t max_bytes = default_max_checkpoint_bytes);

}  // namespace slipfront::app
