#include "apps/checkpoint.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "apps/build_info.hpp"

namespace slipfront::app {
namespace {

constexpr const char* kMagic = "slipfront-checkpoint 1\n";

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

}  // namespace

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& c) {
  std::ostringstream head;
  head << kMagic << "commit " << build_info::git_commit << "\n"
       << "time " << c.time << "\n"
       << "toml " << c.resolved_toml.size() << "\n"
       << c.resolved_toml << "\nstate " << c.state.size() << "\n";
  const std::string h = head.str();
  std::string name = ".";  // (appends: GCC 12 warns falsely on "." + std::string)
  name += path.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  const std::filesystem::path tmp = path.parent_path() / name;
  ::unlink(tmp.c_str());  // a leftover of this very process id
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw CheckpointError("cannot create " + tmp.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, h.data(), h.size(), tmp);
    write_all(fd, c.state.data(), c.state.size(), tmp);
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

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path.string() + ": cannot open the checkpoint: " + std::strerror(errno));
  auto bad = [&](const std::string& why) { return CheckpointError(path.string() + ": not a readable checkpoint (" + why + ")"); };
  std::string line;
  if (!std::getline(in, line) || line + "\n" != kMagic) throw bad("wrong header");
  Checkpoint c;
  std::string word;
  if (!std::getline(in, line) || line.rfind("commit ", 0) != 0) throw bad("no commit line");
  if (!(in >> word >> c.time) || word != "time") throw bad("no time");
  std::uint64_t n = 0;
  if (!(in >> word >> n) || word != "toml" || in.get() != '\n') throw bad("no configuration");
  c.resolved_toml.resize(n);
  if (!in.read(c.resolved_toml.data(), static_cast<std::streamsize>(n))) throw bad("truncated configuration");
  if (!(in >> word >> n) || word != "state" || in.get() != '\n') throw bad("no state");
  c.state.resize(n);
  if (!in.read(c.state.data(), static_cast<std::streamsize>(n))) throw bad("truncated state");
  return c;
}

}  // namespace slipfront::app
