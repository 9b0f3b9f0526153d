// libFuzzer target for the configuration reader (issue 10): TOML text in, a validated scene or a
// ConfigError out, nothing else. An input may carry --set overrides after a line "%%", one per line.
// For every accepted scene the resolved TOML must reload to the same scene and the cost estimate must
// be finite; any other exception, crash, sanitizer report, leak or timeout is a finding.
// Built only with -DSLIPFRONT_FUZZ=ON and clang (scripts/fuzz.sh); docs/robustness.md §6.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "compare/estimate.hpp"

namespace {
std::size_t inputs = 0, accepted = 0, refused = 0;
void report() {
  std::fprintf(stderr, "fuzz_config: %zu inputs: %zu accepted, %zu refused with a ConfigError\n", inputs, accepted,
               refused);
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::atexit(report);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slipfront;
  ++inputs;
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (const auto sep = text.find("\n%%\n"); sep != std::string::npos) {
    std::string rest = text.substr(sep + 4);
    text.resize(sep);
    for (std::size_t start = 0; start <= rest.size();) {
      const auto nl = rest.find('\n', start);
      const std::string line = rest.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
      if (!line.empty()) overrides.push_back(line);
      if (nl == std::string::npos) break;
      start = nl + 1;
    }
  }
  try {
    const compare::Scene s = app::parse_scene(text, "fuzz.toml", overrides);
    ++accepted;
    const std::string resolved = app::to_toml(s);
    const compare::Scene again = app::parse_scene(resolved, "resolved", {});
    if (!app::same_scene(s, again)) {
      std::fprintf(stderr, "resolved TOML does not reload to the same scene:\n%s\n", resolved.c_str());
      std::abort();
    }
    const compare::Estimate e = compare::estimate(s);
    if (!(e.memory_bytes > 0 && std::isfinite(e.memory_bytes) && std::isfinite(e.seconds) && e.steps >= 1)) {
      std::fprintf(stderr, "estimate not finite: memory %g, seconds %g, steps %g\n", e.memory_bytes, e.seconds, e.steps);
      std::abort();
    }
  } catch (const app::ConfigError&) {
    ++refused;
  }
  return 0;
}
