#pragma once
// Scene configuration files (TOML) <-> compare::Scene (docs/model.md §5; the schema is in docs/cli.md).
// Every key of the schema is one row of a table in config.cpp; reading, --set overrides, defaults,
// "unknown key" messages and to_toml() all follow that table.
#include <cstddef>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "compare/scene.hpp"

namespace slipfront::app {

/// Anything wrong with a configuration: what() is "<file>: <key>: <reason>", or
/// "<file>:<line>:<col>: <reason>" for TOML syntax errors (then key is empty).
struct ConfigError : std::runtime_error {
  std::string file;
  std::string key;     ///< dotted key ("interface.alpha"), "--set <key>" for overrides, or empty
  std::string reason;
  ConfigError(std::string file, std::string key, std::string reason);
  ConfigError(std::string file, long line, long column, std::string reason);  ///< syntax error
};

/// The largest configuration file read (a scene, a study, a study's scene): 1 MiB, ten times the
/// largest file in configs/. Anything larger is not a configuration written by hand.
inline constexpr std::size_t max_config_bytes = std::size_t{1} << 20;

/// The text of a configuration file: the one reader of scene files, study files and the scene of a
/// study. Refuses anything but a regular file (a directory, a device such as /dev/zero, a FIFO, a
/// socket: named in the reason; the type is looked at before opening and a FIFO is never waited on)
/// and a file of more than `limit` bytes (its size and the limit in the reason), reading at most
/// `limit` + 1 bytes whatever the file claims. Throws ConfigError(file, "", reason).
std::string read_config_file(const std::filesystem::path& file, std::size_t limit = max_config_bytes);

/// The rule for names that name an output directory (a scene's `scene`, a study's `study`): not
/// empty, relative, no '..', no control characters. `key` is the key as shown in messages, `names`
/// the directory it names ("out/<scene>"). Throws ConfigError(file, key, reason).
void check_directory_name(const std::string& name, const std::string& file, const std::string& key,
                          const std::string& names);

/// Read, override, complete with defaults and validate a scene.
///  - `overrides`: "section.key=value" (top-level keys: "key=value"); the value is parsed as a TOML
///    value, or taken as a bare string if it does not parse. Applied before any check.
///  - Keys that the scene's loading or model list does not use are accepted but ignored: they are
///    reset to their defaults (so that to_toml() lists exactly what the run uses) and, if `notes`
///    is given, one note per ignored key is appended to it.
/// Throws ConfigError for every problem (unknown/missing key, wrong type, out of range).
compare::Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                          std::vector<std::string>* notes = nullptr);

/// The same from TOML text; `source_name` stands for the file name in messages.
compare::Scene parse_scene(const std::string& toml_text, const std::string& source_name,
                           const std::vector<std::string>& overrides, std::vector<std::string>* notes = nullptr);

/// The fully resolved configuration: every key the scene uses, with its effective value (defaults
/// included), in schema order. parse_scene(to_toml(s)) reproduces s exactly (doubles are written
/// in shortest round-trip form) for every s returned by load_scene.
std::string to_toml(const compare::Scene& scene);

/// `s` as a TOML basic string, quoted and escaped as to_toml() writes it (quote, backslash and control
/// characters): also a valid JSON string (apps/json_progress.hpp).
std::string quoted_string(const std::string& s);

/// Every key of the schema, dotted ("bulk.rho"; top-level keys bare), in schema order.
std::vector<std::string> schema_keys();

/// Whether `scene` uses `key` (keys a scene does not use are accepted, noted and reset).
bool uses_key(const compare::Scene& scene, std::string_view key);

/// Field-by-field equality of two scenes (what the round trip guarantees).
bool same_scene(const compare::Scene& a, const compare::Scene& b);

}  // namespace slipfront::app
