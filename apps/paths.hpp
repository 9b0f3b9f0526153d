#pragma once
// Where the program finds its files at run time: the scripts of `slipfront report` and the MPI
// engine module, relative to the executable first, so that an installed slipfront
// (<prefix>/bin/slipfront) works wherever it is copied, with no path baked in but the source
// directory as the last resort. And the one lock every verb that writes into an output directory
// takes on it (OutputLock: run, study, fronts).
#include <filesystem>
#include <string>
#include <vector>

namespace slipfront::app {

/// The running executable (/proc/self/exe, symbolic links resolved); empty if unknown.
std::filesystem::path executable_path();

/// Where a data file (report.py, plot.py, ...) is looked for, in order:
///  1. $SLIPFRONT_DATA_DIR/<name>, when the variable is set (an explicit choice wins),
///  2. <exe dir>/<bin-to-data>/<name>: <prefix>/share/slipfront/<name> for <prefix>/bin/slipfront,
///  3. <source dir>/scripts/<name> (the build tree).
std::vector<std::filesystem::path> data_file_candidates(const std::string& name);

/// The first candidate that exists; empty if none (the caller lists the candidates).
std::filesystem::path find_data_file(const std::string& name);

/// Where the MPI engine module (libslipfront_mpi.so) is looked for, in order: $SLIPFRONT_MPI_ENGINE
/// (a path to the module), <exe dir>/libslipfront_mpi.so (build tree),
/// <exe dir>/<bin-to-lib>/libslipfront_mpi.so (installed: <prefix>/lib/slipfront/).
std::vector<std::filesystem::path> mpi_engine_candidates();

/// One writer at a time in an output directory (issue 18; `study` and `fronts` since issue 36): an advisory
/// lock (flock) on DIR/.slipfront.lock, taken before anything in DIR is looked at and held until the results
/// are renamed into place. The file holds the holder's pid (named when a second writer is refused); its holder
/// removes it on release. A process killed with SIGKILL leaves the file but not the lock (the kernel drops
/// it): the next one takes it. Taking the lock checks that the file locked is still the one at the path (its
/// holder may have removed it in between), so that two processes never hold two different files. `run`,
/// `study` and `fronts` take the same lock: any two of them into one directory exclude each other.
class OutputLock {
 public:
  OutputLock() = default;
  ~OutputLock() { release(); }
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  /// Takes the lock of `dir` (an existing directory): "" when held, else why not (naming the directory and
  /// the holder's pid).
  std::string acquire(const std::filesystem::path& dir);
  /// Removes the file and drops the lock (removed first, while still held: see acquire).
  void release();

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

/// Creates `dir` (and its parents) and takes its lock: "" when held, else why not.
std::string create_and_lock(const std::filesystem::path& dir, OutputLock& lock);

}  // namespace slipfront::app
