#pragma once
// Where the program finds its files at run time: the scripts of `slipfront report` and the MPI
// engine module, relative to the executable first, so that an installed slipfront
// (<prefix>/bin/slipfront) works wherever it is copied, with no path baked in but the source
// directory as the last resort.
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

}  // namespace slipfront::app
