#include "apps/paths.hpp"

#include <cstdlib>
#include <system_error>

#include "apps/build_info.hpp"

namespace slipfront::app {

namespace fs = std::filesystem;

fs::path executable_path() {
  std::error_code ec;
  fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  return p;
}

std::vector<fs::path> data_file_candidates(const std::string& name) {
  std::vector<fs::path> c;
  if (const char* dir = std::getenv("SLIPFRONT_DATA_DIR"); dir && *dir) c.push_back(fs::path(dir) / name);
  if (const fs::path exe = executable_path(); !exe.empty())
    c.push_back((exe.parent_path() / build_info::data_dir_from_bin / name).lexically_normal());
  c.push_back(fs::path(build_info::source_dir) / "scripts" / name);
  return c;
}

fs::path find_data_file(const std::string& name) {
  std::error_code ec;
  for (const auto& p : data_file_candidates(name))
    if (fs::is_regular_file(p, ec)) return p;
  return {};
}

std::vector<fs::path> mpi_engine_candidates() {
  std::vector<fs::path> c;
  if (const char* p = std::getenv("SLIPFRONT_MPI_ENGINE"); p && *p) {
    c.emplace_back(p);
    return c;  // explicit: nothing else
  }
  if (const fs::path exe = executable_path(); !exe.empty()) {
    c.push_back(exe.parent_path() / build_info::mpi_engine_name);
    c.push_back((exe.parent_path() / build_info::lib_dir_from_bin / build_info::mpi_engine_name).lexically_normal());
  }
  return c;
}

}  // namespace slipfront::app
