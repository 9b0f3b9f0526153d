#pragma once
// The one module that owns the HDF5 layout of results.h5 (docs/model.md §5; documented in docs/output.md).
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "compare/fronts.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "studies/study.hpp"

namespace slipfront::app {

/// Version of the file layout written to /meta (attribute `layout_version`); bump on incompatible changes.
inline constexpr int layout_version = 1;

/// What the caller knows about the run as a whole.
struct RunMeta {
  std::string command_line;       ///< how the program was invoked
  std::string message;            ///< overall message (empty: the models' messages are joined)
  double wall_seconds = 0.0;      ///< wall time of the whole run
  compare::RunStatus status = compare::RunStatus::complete;  ///< floor of /meta status (failed when the run threw)
};

struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Worst of `floor` and every model's status: failed > interrupted > complete.
compare::RunStatus overall_status(const std::vector<compare::ModelResult>& results,
                                  compare::RunStatus floor = compare::RunStatus::complete);

/// Every results file written by write_results begins with an HDF5 user block of this size (HDF5 and
/// h5py skip it) holding the checksum of every byte after it: checksum_block (docs/output.md, "Checksum").
inline constexpr std::size_t checksum_block_bytes = 512;
/// How the block begins: a file without it has no checksum (written before issue 18).
inline constexpr std::string_view checksum_magic = "slipfront results checksum\n";

/// The user block of a file whose bytes after the block are `payload`: checksum_magic, "xxh3-64 <16 hex
/// digits>\n" (core::content_hash_hex of the payload), "bytes <payload size>\n", then zeros up to
/// checksum_block_bytes. A file is intact when its block is exactly checksum_block(rest of the file).
std::string checksum_block(std::string_view payload);

/// Writes the results to `path` atomically: the file is built in memory, written to ".<name>.tmp.<pid>"
/// in the same directory (created exclusively, never through a symbolic link; stale temporaries of
/// dead processes removed first), flushed and renamed onto `path` (replacing it) once complete.
/// Throws OutputError with the reason (a full disk: "No space left on device"); the temporary file
/// is removed then. The file begins with its checksum (checksum_block).
/// `comparison` (may be null or empty): the /compare group of alongside runs.
void write_results(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                   const std::vector<compare::ModelResult>& results, const RunMeta& meta,
                   const compare::Comparison* comparison = nullptr);

/// How the runs of a study were obtained (attributes and a dataset of /study/runs).
struct StudyExecution {
  std::string engine = "threads";  ///< threads | mpi
  int workers = 1;                 ///< threads, or MPI ranks x threads per rank
  long long computed = 0;          ///< runs run by this invocation (complete, interrupted or failed)
  std::vector<int> skipped;        ///< per run: 1 if its results file was complete already (not rerun)
  std::vector<std::string> untrusted;  ///< run files made again because their checksum failed ("runs/<id>/results.h5: why")
};

/// Writes a study's analysis to `path` (study.h5) atomically, like write_results.
void write_study(const std::filesystem::path& path, const compare::StudySpec& spec, const std::string& spec_toml,
                 const std::vector<compare::StudyRun>& runs, const studies::StudyReport& report, const RunMeta& meta,
                 const StudyExecution& execution = {});

/// Writes `text` to `path` atomically, as write_results writes its file (a temporary created exclusively, flushed,
/// renamed onto `path`), without a checksum block: a text file for other programs (the CSV of a strip_cmin_height
/// study, docs/studies.md).
void write_text_file(const std::filesystem::path& path, const std::string& text);

/// The hash stored in /meta `config_hash` of every results file: CRC-64/XZ (Boost.CRC) of the fully
/// resolved configuration (`to_toml(scene)`, the text stored in /config `toml`), as
/// "crc64-xz:<16 hex digits>". A resumed study compares it, and the text itself, with the run's.
std::string config_hash(const std::string& resolved_toml);

/// Writes the steady fronts of a scene (`slipfront fronts`) to `path` (fronts.h5) atomically:
/// /meta, /config, /branch, /profiles/<k>, /scaling (docs/output.md).
void write_fronts(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                  const compare::FrontsResult& fronts, const RunMeta& meta);

struct StabilityResult;  // apps/stability.hpp
/// Writes the growth rates of `slipfront stability` (apps/stability.hpp) to `path` (stability.h5) atomically: /meta,
/// /config, /stability with one group per channel (docs/output.md).
void write_stability(const std::filesystem::path& path, const compare::Scene& scene, const std::string& resolved_toml,
                     const StabilityResult& result, const RunMeta& meta);

/// The temporary name write_results uses for `path` in this process.
std::filesystem::path temporary_path(const std::filesystem::path& path);

/// Removes the files `dir/<prefix><pid>` of processes that no longer exist (kill(pid, 0) fails with
/// ESRCH) and that belong to this user (regular files and symbolic links only): the temporary files
/// of runs that were killed. Returns how many were removed.
std::size_t remove_stale_temporaries(const std::filesystem::path& dir, const std::string& prefix);

/// Versions of the libraries this program was built with ("hdf5 1.10.8", ...), for /meta and --version.
struct LibraryVersions {
  std::string compiler, hdf5, boost, tomlplusplus, cli11, eigen;
};
LibraryVersions library_versions();

}  // namespace slipfront::app
