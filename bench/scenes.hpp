#pragma once
// Scenes of the benchmarks: the tests' scenes (tests/scenes.hpp), so that a benchmark runs exactly
// the scene the tests check.
#include <cstdlib>

#include "compare/scene.hpp"
#include "tests/scenes.hpp"

namespace slipfront::bench {

/// The smoke-test form of a benchmark ($SLIPFRONT_BENCH_QUICK set: what the default test tier runs).
inline bool quick() { return std::getenv("SLIPFRONT_BENCH_QUICK") != nullptr; }

/// Seeds per stochastic case: 2 in the quick form, else $SLIPFRONT_BENCH_SEEDS (at least `least`) or `otherwise`.
inline int seeds(int otherwise, int least) {
  if (quick()) return 2;
  const char* e = std::getenv("SLIPFRONT_BENCH_SEEDS");
  const int n = e ? std::atoi(e) : otherwise;
  return n < least ? least : n;
}

/// fig1 (docs/model.md §4, testing::fig1_scene: edge loading, paper parameters, L = 300, dx = 0.5,
/// cfl = 0.5) to t_end = $SLIPFRONT_BENCH_T_END, or `default_t_end` when it is not set. Validated.
inline compare::Scene fig1_scene(double default_t_end) {
  compare::Scene s = testing::fig1_scene();
  const char* t_end = std::getenv("SLIPFRONT_BENCH_T_END");
  s.time.t_end = t_end ? std::atof(t_end) : default_t_end;
  s.validate();
  return s;
}

}  // namespace slipfront::bench
