#include "apps/checkpoint.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "apps/build_info.hpp"
#include "core/checksum.hpp"

// The bytes of a checkpoint (the format of apps/checkpoint.hpp), apart from the file that holds them: the
// program writes and reads them as DIR/checkpoint.bin (apps/checkpoint.cpp), the Python module as bytes
// (python/module.cpp, docs/python.md).
namespace slipfront::app {
namespace {

// 3: a model's results carry its slip-event sequence (output.sequence, compare::ModelResult::sequence).
constexpr int format_version = 3;
constexpr std::string_view magic_prefix = "slipfront-checkpoint ";
constexpr std::string_view checksum_prefix = "checksum xxh3-64 ";

// What is wrong with a checkpoint's content (read_checkpoint adds the file name).
struct Bad {
  std::string why;
};

// A cursor over the bytes of a checkpoint: lines and sized blocks, every size checked against what is
// left before it is used.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : rest_(bytes) {}
  std::size_t left() const { return rest_.size(); }

  /// The next line without its '\n' (at most `max_length` characters).
  std::string_view line(const char* what, std::size_t max_length) {
    const std::size_t end = rest_.substr(0, max_length + 1).find('\n');
    if (end == std::string_view::npos) throw Bad{std::string("no ") + what + " line"};
    const std::string_view l = rest_.substr(0, end);
    rest_.remove_prefix(end + 1);
    return l;
  }
  /// The value of the line "<name> <value>".
  std::string_view field(const char* name, std::size_t max_length = 256) {
    const std::string_view l = line(name, max_length);
    const std::size_t n = std::strlen(name);
    if (l.size() <= n + 1 || l.substr(0, n) != name || l[n] != ' ') throw Bad{std::string("no ") + name + " line"};
    return l.substr(n + 1);
  }
  /// The size in the line "<name> <decimal digits>".
  std::uint64_t size(const char* name) {
    const std::string_view v = field(name, 64);
    std::uint64_t n = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (ec != std::errc() || end != v.data() + v.size() || v.size() > 20)
      throw Bad{std::string(name) + " size '" + printable(v) + "' is not a byte count"};
    return n;
  }
  /// The next n bytes (n checked against what is left, before anything is taken).
  std::string_view block(std::uint64_t n, const char* name) {
    if (n > rest_.size())
      throw Bad{std::string(name) + " size " + std::to_string(n) + " exceeds the " + std::to_string(rest_.size()) +
                " bytes left"};
    const std::string_view b = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return b;
  }

  /// Text from the file shown in a message: printable ASCII, at most 64 characters.
  static std::string printable(std::string_view s) {
    std::string out;
    for (const char c : s.substr(0, 64)) out += c >= 0x20 && c < 0x7f ? c : '?';
    return s.size() > 64 ? out + "..." : out;
  }

 private:
  std::string_view rest_;
};

// The magic line: format 3, or a refusal naming what the file is (format 1 with its writer).
void check_format(Cursor& in) {
  const std::string_view magic = in.line("slipfront-checkpoint", 64);
  if (magic.substr(0, magic_prefix.size()) != magic_prefix) throw Bad{"not a slipfront checkpoint (wrong first line)"};
  const std::string_view version = magic.substr(magic_prefix.size());
  if (version == std::to_string(format_version)) return;
  if (version == "1") {
    std::string writer = "an unknown commit";
    try {
      writer = "slipfront " + Cursor::printable(in.field("commit"));
    } catch (const Bad&) {
    }
    throw Bad{"checkpoint format 1 (written by " + writer +
              ") has no checksum, so it cannot be verified; rerun the run from the start, or continue it with the "
              "slipfront that wrote it (this one writes and reads format " + std::to_string(format_version) + ")"};
  }
  if (version == "2")
    throw Bad{"checkpoint format 2 (before the slip-event sequence was part of a model's results) is not one this "
              "slipfront reads (format " + std::to_string(format_version) + "); rerun the run from the start, or continue "
              "it with the slipfront that wrote it"};
  throw Bad{"checkpoint format '" + Cursor::printable(version) + "' is not one this slipfront reads (format " +
            std::to_string(format_version) + ")"};
}

Checkpoint parse(std::string_view bytes) {
  Cursor in(bytes);
  check_format(in);
  // the checksum, verified before anything after it is used
  const std::string_view stored = in.line("checksum", 64);
  if (stored.size() != checksum_prefix.size() + 16 || stored.substr(0, checksum_prefix.size()) != checksum_prefix)
    throw Bad{"no checksum line"};
  const std::string_view body = bytes.substr(bytes.size() - in.left());
  const std::string computed = core::content_hash_hex(body);
  if (stored.substr(checksum_prefix.size()) != computed)
    throw Bad{"checksum mismatch: the file is corrupted (stored xxh3-64 " +
              Cursor::printable(stored.substr(checksum_prefix.size())) + ", computed " + computed + " over its " +
              std::to_string(body.size()) + " bytes)"};
  Checkpoint c;
  c.commit = std::string(in.field("commit"));
  if (c.commit != build_info::git_commit)
    throw Bad{"written by slipfront " + Cursor::printable(c.commit) + ", this is slipfront " + build_info::git_commit +
              ": a checkpoint is read back only by the build that wrote it (rerun from the start, or continue with "
              "that build)"};
  const std::string_view time = in.field("time", 64);
  const auto [end, ec] = std::from_chars(time.data(), time.data() + time.size(), c.time);
  if (ec != std::errc() || end != time.data() + time.size() || !std::isfinite(c.time))
    throw Bad{"time '" + Cursor::printable(time) + "' is not a finite number"};
  c.resolved_toml = std::string(in.block(in.size("toml"), "toml"));
  if (in.block(1, "toml") != "\n") throw Bad{"no line end after the configuration"};
  const std::uint64_t n = in.size("state");
  c.state = std::string(in.block(n, "state"));
  if (in.left() != 0) throw Bad{std::to_string(in.left()) + " bytes after the state"};
  return c;
}

}  // namespace

std::string checkpoint_bytes(std::string_view resolved_toml, double time, std::string_view state) {
  char time_text[40];
  std::snprintf(time_text, sizeof time_text, "%.17g", time);
  std::string body = "commit ";  // everything the checksum covers
  body.reserve(resolved_toml.size() + state.size() + 256);
  body += build_info::git_commit;
  body += "\ntime ";
  body += time_text;
  body += "\ntoml " + std::to_string(resolved_toml.size()) + "\n";
  body += resolved_toml;
  body += "\nstate " + std::to_string(state.size()) + "\n";
  body += state;
  return std::string(magic_prefix) + std::to_string(format_version) + "\n" + std::string(checksum_prefix) +
         core::content_hash_hex(body) + "\n" + body;
}

Checkpoint parse_checkpoint(std::string_view bytes, const std::string& source) {
  try {
    return parse(bytes);
  } catch (const Bad& b) {
    throw CheckpointError(source + ": not a usable checkpoint: " + b.why);
  }
}

}  // namespace slipfront::app
