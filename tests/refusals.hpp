#pragma once
// Scene files for the refusal tests of the interface keys (test_aging, test_normal_load): a scene from its parts, and
// the check that loading it is refused naming the key and the reason (docs/cli.md "Errors").
#include <catch2/catch.hpp>

#include <string>

#include "apps/config.hpp"

namespace slipfront::testing {

/// A scene file from its parts: top-level keys, extra [interface] keys, [drive], extra sections and extra [time]
/// keys (the paper's interface, ρ = 0.01, μ = 300, L = 10, dx = 0.5, t_end = 10).
inline std::string interface_scene(const std::string& top, const std::string& interface, const std::string& drive,
                                   const std::string& extra, const std::string& time) {
  return "scene = \"a\"\n" + top + "[interface]\nalpha = 1.05\nkappa = 8.0\neta = 0.1\n" + interface +
         "[bulk]\nrho = 0.01\nmu = 300\nlength = 10\n[grid]\ndx = 0.5\n" + drive + extra + "[time]\nt_end = 10.0\n" + time;
}

/// Loading `text` must throw app::ConfigError naming `key`, its message containing `words`.
inline void check_refused(const std::string& text, const char* key, const char* words) {
  try {
    (void)app::parse_scene(text, "a.toml", {});
    FAIL("accepted: " << text);
  } catch (const app::ConfigError& e) {
    INFO(e.what());
    CHECK(e.key == key);
    CHECK(std::string(e.what()).find(words) != std::string::npos);
  }
}

}  // namespace slipfront::testing
