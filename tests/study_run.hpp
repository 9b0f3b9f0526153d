#pragma once
// The slow tiers' way to run a study of configs/studies/ as `slipfront study` runs it: every point on a pool of
// all cores, then the analysis; each scalar is printed (WARN) so that a run's log holds the measured numbers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include "apps/config.hpp"
#include "apps/study.hpp"
#include "compare/alongside.hpp"
#include "compare/pool.hpp"
#include "studies/study.hpp"

namespace slipfront::testing {

/// The study configs/studies/<name>.toml (name may hold a folder: "checks/x"), run and analysed.
inline studies::StudyReport run_study(const std::string& name) {
  const auto spec = app::load_study(std::string(SLIPFRONT_SOURCE_DIR) + "/configs/studies/" + name + ".toml");
  const auto runs = compare::expand(spec);
  std::vector<compare::Scene> scenes;
  for (const auto& r : runs) scenes.push_back(app::load_scene(spec.scene_file, r.overrides));
  std::vector<std::vector<compare::ModelResult>> results(runs.size());
  compare::run_pool(runs.size(), std::max(1u, std::thread::hardware_concurrency()), [&](std::size_t i) {
    auto sr = compare::run_scene_alongside(scenes[i], {});
    for (auto& m : sr.models) m.snapshots.clear();
    results[i] = std::move(sr.models);
  });
  auto rep = studies::analyse_study(spec, runs, scenes, results);
  for (const auto& [k, v] : rep.scalars) WARN(name << ": " << k << " = " << v);
  return rep;
}

/// A scalar of a study's report (throws if it has none: a test of a missing result fails).
inline double scalar(const studies::StudyReport& r, const std::string& k) { return r.scalars.at(k); }

}  // namespace slipfront::testing
