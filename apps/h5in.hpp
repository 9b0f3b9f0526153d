#pragma once
// Reads a results.h5 written by apps/h5out back into memory: what a resumed study needs to skip the
// runs already complete (/meta status, config_hash, /config toml) and to analyse them
// (compare::ModelResult: series, events, friction law, cycles, scalars, labels, status, message).
// The inverse of write_results for everything it writes (tested round trip); the layout is
// docs/output.md.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "compare/result.hpp"

namespace slipfront::app {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a results file says about itself (/meta and /config).
struct ResultsHeader {
  compare::RunStatus status = compare::RunStatus::failed;  ///< /meta status
  std::string message;        ///< /meta message
  std::string config_hash;    ///< /meta config_hash ("" when absent: written before it existed)
  std::string resolved_toml;  ///< /config toml
  std::string git_commit;     ///< /meta git_commit
  std::string scene;          ///< /meta scene
  std::vector<std::string> models;  ///< /meta models, in run order
};

struct ResultsFile {
  ResultsHeader header;
  std::vector<compare::ModelResult> models;  ///< in the order of header.models
  compare::Comparison comparison;            ///< /compare (empty when absent)
};

struct ReadOptions {
  /// Read /<model>/snapshots and /<model>/contacts (the large fields). A study's analysis does not
  /// use them.
  bool fields = true;
  /// Verify the file's checksum first (verify_checksum) and refuse it (InputError) unless it is intact.
  bool verified = false;
};

/// What the checksum of a results file says (apps/h5out.hpp: checksum_block; docs/output.md).
enum class Checksum {
  intact,  ///< the user block is exactly the checksum of every byte after it
  absent,  ///< an HDF5 file without checksum block: written by a slipfront before issue 18 (or not by slipfront)
  failed,  ///< not what was written: flipped bytes (in the block too), truncated, appended, or neither block nor HDF5
};
struct ChecksumCheck {
  Checksum state = Checksum::absent;
  std::string detail;  ///< absent, failed: what was found ("stored xxh3-64 ..., the content hashes to ...")
};

/// Verifies the checksum of a results file, reading every byte (a memory map; XXH3 costs ~0.1 ms per
/// MB). Throws InputError when the file cannot be read or is not a regular file.
ChecksumCheck verify_checksum(const std::filesystem::path& path);

/// /meta and /config only (cheap). Throws InputError if the file cannot be opened or is not a
/// slipfront results file.
ResultsHeader read_results_header(const std::filesystem::path& path);

/// The whole file. Throws InputError naming the file and the object that could not be read (with
/// options.verified, also when its checksum is absent or fails).
ResultsFile read_results(const std::filesystem::path& path, const ReadOptions& options = {});

/// The study a study.h5 belongs to (/study attribute `name`). Throws InputError.
std::string read_study_name(const std::filesystem::path& path);

/// What a study.h5 says of the study that wrote it: /study attributes `name`, `kind` and `toml` (the study
/// file's text). Throws InputError.
struct StudyHeader {
  std::string name, kind, toml;
};
StudyHeader read_study_header(const std::filesystem::path& path);

}  // namespace slipfront::app
