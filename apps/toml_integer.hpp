#pragma once
// The one conversion of a TOML integer into a C++ integer (issue 18): every integer read from a scene
// or a study file goes through checked_integer, which checks the value against the range of the C++
// type before it is narrowed, so that 4294967297 is refused as out of range instead of becoming 1.
// Errors are ConfigErrors naming the file and the key (apps/config.hpp).
#include <toml++/toml.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>

namespace slipfront::app {

/// Whether a float with an integral value (`points = 4e1`) is taken where an integer is expected: the
/// scene schema accepts it (docs/cli.md), study files do not (docs/studies.md: `seeds = 1e9` is refused
/// as "expected an integer").
enum class IntegralFloats { accepted, refused };

/// The integer a TOML value holds (ConfigError(file, key, "expected an integer, got ...") otherwise).
std::int64_t toml_integer(const toml::node& n, const std::string& file, const std::string& key, IntegralFloats floats);

/// ConfigError(file, key, "the integer <v> is out of range of <what> (<lo> .. <hi>)").
[[noreturn]] void refuse_integer_range(const std::string& file, const std::string& key, std::int64_t v,
                                       const std::string& lo, const std::string& hi);

/// The TOML value `n` as a T, checked to fit T before it is narrowed.
template <class T>
T checked_integer(const toml::node& n, const std::string& file, const std::string& key,
                  IntegralFloats floats = IntegralFloats::refused) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>);
  const std::int64_t v = toml_integer(n, file, key, floats);
  using L = std::numeric_limits<T>;
  const bool below = std::is_unsigned_v<T> ? v < 0 : v < static_cast<std::int64_t>(L::min());
  const bool above = std::is_unsigned_v<T> ? static_cast<std::uint64_t>(std::max<std::int64_t>(v, 0)) > L::max()
                                           : v > static_cast<std::int64_t>(L::max());
  if (below || above) refuse_integer_range(file, key, v, std::to_string(L::min()), std::to_string(L::max()));
  return static_cast<T>(v);
}

}  // namespace slipfront::app
