#pragma once
// Reading a file the program was given (issue 18: trust nothing read back): configurations and
// checkpoints are read by this one function, which refuses anything but a regular file of bounded size
// before reading a byte of it.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace slipfront::app {

/// Why read_regular_file refused a file. what() is the reason without the file's name, e.g. "is a FIFO
/// (named pipe), not a regular file", "is 100 bytes, more than the limit of 99 bytes", "cannot open the
/// file: No such file or directory"; the fields let a caller phrase it in its own terms.
struct UnreadableFile : std::runtime_error {
  enum class Why { not_regular, too_large, system } why;
  std::string kind;          ///< not_regular: what it is ("a directory", "a character device", ...)
  std::uintmax_t size = 0;   ///< too_large: its size (at_least: it grew past the limit while read)
  std::uintmax_t limit = 0;  ///< too_large: the limit
  bool at_least = false;
  UnreadableFile(Why w, std::string reason) : std::runtime_error(std::move(reason)), why(w) {}
};

/// The whole of `path`, if it is a regular file of at most `max_bytes`: its type is checked before it is
/// opened (so a FIFO is never waited on) and again on the opened descriptor (the path may have changed in
/// between; it is opened O_NONBLOCK), and at most max_bytes + 1 bytes are read whatever its size says (a
/// file may grow; /proc files say 0). Throws UnreadableFile.
std::string read_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

}  // namespace slipfront::app
