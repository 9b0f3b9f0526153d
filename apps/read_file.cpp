#include "apps/read_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace slipfront::app {
namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

UnreadableFile not_regular(mode_t mode) {
  UnreadableFile e(UnreadableFile::Why::not_regular, "is " + kind_of(mode) + ", not a regular file");
  e.kind = kind_of(mode);
  return e;
}

UnreadableFile too_large(std::uintmax_t size, std::uintmax_t limit, bool at_least) {
  UnreadableFile e(UnreadableFile::Why::too_large, "is " + std::string(at_least ? "at least " : "") +
                                                       std::to_string(size) + " bytes, more than the limit of " +
                                                       std::to_string(limit) + " bytes");
  e.size = size;
  e.limit = limit;
  e.at_least = at_least;
  return e;
}

UnreadableFile system_error(const char* what) {
  return UnreadableFile(UnreadableFile::Why::system, std::string(what) + ": " + std::strerror(errno));
}

// Closes a file descriptor on scope exit.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::string read_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw system_error("cannot open the file");
  if (!S_ISREG(st.st_mode)) throw not_regular(st.st_mode);
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large(static_cast<std::uintmax_t>(st.st_size), max_bytes, false);
  const Fd in{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)};
  if (in.fd < 0) throw system_error("cannot open the file");
  if (::fstat(in.fd, &st) != 0) throw system_error("cannot read the file");
  if (!S_ISREG(st.st_mode)) throw not_regular(st.st_mode);
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) throw too_large(static_cast<std::uintmax_t>(st.st_size), max_bytes, false);
  // At most max_bytes + 1 bytes, whatever the size said.
  std::string text(static_cast<std::size_t>(st.st_size) + 1, '\0');
  std::size_t got = 0;
  for (;;) {
    if (got == text.size()) {
      if (text.size() > max_bytes) break;
      text.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(max_bytes + 1, 2 * text.size() + 4096)));
    }
    const ssize_t n = ::read(in.fd, text.data() + got, text.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw system_error("cannot read the file");
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got > max_bytes) throw too_large(got, max_bytes, true);
  text.resize(got);
  return text;
}

}  // namespace slipfront::app
