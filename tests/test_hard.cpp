// The hard/* scenes (docs/model.md §4): stiff and degenerate corners. Each must run to its end with both
// models, every field finite, 0 <= A <= 1 everywhere, |sigma_bar| bounded by alpha (the largest
// value the law can reach from A <= 1: dσ̄/dt = α A v − Y|v|σ̄ relaxes σ̄ towards ±α A while
// sliding, and in stick σ̄ grows only to the yield level |σ̄ + ηv| ≤ A ≤ 1 ≤ α).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "apps/config.hpp"
#include "compare/alongside.hpp"

using namespace slipfront;

TEST_CASE("hard scenes stay stable and bounded with both models", "[hard]") {
  const std::filesystem::path dir = std::filesystem::path(SLIPFRONT_SOURCE_DIR) / "configs" / "hard";
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".toml") continue;
    ++scenes;
    const compare::Scene s = app::load_scene(entry.path(), {});
    INFO(entry.path().filename().string());
    const auto r = compare::run_scene_alongside(s, {});
    REQUIRE(r.models.size() == 2);
    for (const auto& m : r.models) {
      INFO(m.model << ": " << m.message);
      CHECK(m.status == slipfront::compare::RunStatus::complete);
      REQUIRE(!m.snapshot_t.empty());
      const double bound = s.interface.alpha * (1.0 + 1e-12);
      for (double a : m.snapshots.at("A")) {
        REQUIRE(std::isfinite(a));
        REQUIRE(a >= 0.0);
        REQUIRE(a <= 1.0);
      }
      for (double sb : m.snapshots.at("sigma_bar")) {
        REQUIRE(std::isfinite(sb));
        REQUIRE(std::abs(sb) <= bound);
      }
      for (const char* f : {"u", "v"})
        for (double x : m.snapshots.at(f)) REQUIRE(std::isfinite(x));
      for (const auto& [name, col] : m.series)
        for (double x : col)
          if (name != "tip_x" && name != "tip_x_alt") REQUIRE(std::isfinite(x));
    }
  }
  CHECK(scenes >= 6);
}
