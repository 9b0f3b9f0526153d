#include "apps/checkpoint.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "apps/read_file.hpp"
#include "apps/h5out.hpp"

namespace slipfront::app {
namespace {

void write_all(int fd, const char* p, std::size_t n, const std::filesystem::path& where) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      throw CheckpointError("cannot write " + where.string() + ": " + std::strerror(errno));
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

// The whole file, refused before anything is read unless it is a regular file of at most max_bytes
// (apps/read_file.hpp).
std::string read_whole(const std::filesystem::path& path, std::uint64_t max_bytes) {
  try {
    return read_regular_file(path, max_bytes);
  } catch (const UnreadableFile& e) {
    switch (e.why) {
      case UnreadableFile::Why::not_regular:
        throw CheckpointError(path.string() + ": not a usable checkpoint: it is " + e.kind +
                              ", not a regular file (a checkpoint is the file DIR/checkpoint.bin written by "
                              "--checkpoint-every)");
      case UnreadableFile::Why::too_large:
        throw CheckpointError(path.string() + ": not a usable checkpoint: it has " + (e.at_least ? "at least " : "") +
                              std::to_string(e.size) + " bytes, more than the " + std::to_string(e.limit) +
                              " a checkpoint of this run may have (it is read whole into memory: limits.max_memory_gib)");
      case UnreadableFile::Why::system: break;
    }
    throw CheckpointError(path.string() + ": " + e.what());
  }
}

}  // namespace

void write_checkpoint(const std::filesystem::path& path, std::string_view resolved_toml, double time,
                      std::string_view state) {
  const std::string bytes = checkpoint_bytes(resolved_toml, time, state);
  const std::filesystem::path tmp = temporary_path(path);
  ::unlink(tmp.c_str());  // a leftover of this very process id
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("cannot create " + tmp.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, bytes.data(), bytes.size(), tmp);
    if (::fsync(fd) != 0) throw CheckpointError("cannot flush " + tmp.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0 || std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw CheckpointError("cannot write " + path.string() + ": " + why);
  }
}

Checkpoint read_checkpoint(const std::filesystem::path& path, std::uint64_t max_bytes) {
  return parse_checkpoint(read_whole(path, max_bytes), path.string());
}

}  // namespace slipfront::app
