#include "apps/paths.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
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

namespace {
// "pid N" from the lock file of another process (it writes its pid right after taking the lock).
std::string holder_of(int fd) {
  char buf[24] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string pid(buf, n > 0 ? static_cast<std::size_t>(n) : 0);
  pid = pid.substr(0, pid.find('\n'));
  if (pid.empty() || pid.size() > 10 || pid.find_first_not_of("0123456789") != std::string::npos) return "pid unknown";
  return "pid " + pid;
}
}  // namespace

std::string OutputLock::acquire(const fs::path& dir) {
  path_ = dir / ".slipfront.lock";
  const std::string cannot = "cannot lock the output directory '" + dir.string() + "' (" + path_.string() + "): ";
  for (int attempt = 0; attempt < 16; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return cannot + std::strerror(errno);
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int e = errno;
      const std::string holder = holder_of(fd);
      ::close(fd);
      if (e == EWOULDBLOCK)
        return "the output directory '" + dir.string() + "' is in use by another slipfront run (" + holder +
               ", holding " + path_.string() + "); wait for it to end, or choose another --out";
      return cannot + std::strerror(e);
    }
    struct stat held {}, now {};
    if (::fstat(fd, &held) == 0 && ::lstat(path_.c_str(), &now) == 0 && held.st_dev == now.st_dev &&
        held.st_ino == now.st_ino) {
      const std::string pid = std::to_string(::getpid()) + "\n";
      if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
        const std::string why = std::strerror(errno);
        ::close(fd);
        return cannot + why;
      }
      fd_ = fd;
      return "";
    }
    ::close(fd);  // removed or replaced by its previous holder: lock the file now at the path
  }
  return "cannot lock the output directory '" + dir.string() + "': " + path_.string() + " keeps being replaced";
}

void OutputLock::release() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

std::string create_and_lock(const fs::path& dir, OutputLock& lock) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "cannot create the output directory '" + dir.string() + "': " + ec.message();
  if (!fs::is_directory(dir, ec)) return "the output path '" + dir.string() + "' is not a directory";
  return lock.acquire(dir);
}

}  // namespace slipfront::app
