#pragma once
// The scene of the leap integrator's tests (tests/test_leap.cpp, tests/test_slow_leap.cpp).
#include "compare/scene.hpp"
#include "tests/scenes.hpp"

namespace slipfront::testing {

/// fig1 with the discrete model alone: the count law at w = 0 with N contacts per site and the given seed, on the
/// integrator `integ`, no snapshots.
inline compare::Scene count_fig1_scene(core::Integrator integ, long n, unsigned seed) {
  compare::Scene s = fig1_scene();
  s.models = {"discrete"};
  s.discrete.representation = "count";
  s.discrete.contacts_per_site = n;
  s.discrete.threshold = "delta";
  s.discrete.width = 0.0;
  s.discrete.seed = seed;
  s.time.integrator = integ;
  s.output.snapshot_dt = 0.0;
  return s;
}

}  // namespace slipfront::testing
