// Bit-for-bit equality of whole results (restart and identity tests): one implementation for every body's
// checkpoint tests (tests/test_checkpoint.cpp, test_strip_runs.cpp, test_strip_accuracy.cpp, test_strip_adaptive.cpp).
#pragma once

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

#include "compare/alongside.hpp"
#include "compare/result.hpp"
#include "compare/run_control.hpp"
#include "scenes.hpp"

namespace slipfront::testing {

/// Every field of two model results, exactly (NaN equal to NaN; the wall time aside): series, snapshots, the body's
/// bulk snapshots, cycles, the slip-event sequence, contact statistics, events, reasons, labels and scalars.
inline void require_identical(const compare::ModelResult& a, const compare::ModelResult& b) {
  INFO("model " << a.model);
  CHECK(a.status == b.status);
  CHECK(a.model == b.model);
  CHECK(same(a.series, b.series));
  CHECK(same(a.snapshot_t, b.snapshot_t));
  CHECK(same(a.snapshots, b.snapshots));
  CHECK(same(a.bulk_t, b.bulk_t));
  CHECK(same(a.bulk, b.bulk));
  CHECK(same(a.cycles, b.cycles));
  CHECK(same(a.sequence, b.sequence));  // output.sequence: computed from the series at the end
  CHECK(same(a.contacts, b.contacts));
  CHECK(a.contacts_2d.size() == b.contacts_2d.size());
  for (const auto& [k, t] : a.contacts_2d) CHECK(same(t.data, b.contacts_2d.at(k).data));
  for (const auto& [name, field] : compare::event_fields) {
    CHECK(same(a.events.*field, b.events.*field));
    CHECK(same(a.events_alt.*field, b.events_alt.*field));
  }
  CHECK(a.events.reasons == b.events.reasons);
  CHECK(a.labels == b.labels);
  REQUIRE(a.scalars.size() == b.scalars.size());
  for (const auto& [k, v] : a.scalars) CHECK(same(v, b.scalars.at(k)));
}

/// Every model of two scene results and their comparison, exactly.
inline void require_identical(const compare::SceneResult& x, const compare::SceneResult& y) {
  REQUIRE(x.models.size() == y.models.size());
  for (std::size_t m = 0; m < x.models.size(); ++m) require_identical(x.models[m], y.models[m]);
  CHECK(same(x.comparison.fields, y.comparison.fields));
  CHECK(same(x.comparison.contacts, y.comparison.contacts));
  REQUIRE(x.comparison.metrics.size() == y.comparison.metrics.size());
  for (const auto& [k, v] : x.comparison.metrics) CHECK(same(v, y.comparison.metrics.at(k)));
}

/// A scene run with checkpoints every `every` and restarted from its first checkpoint and, when `last`, its last one,
/// against the run without checkpoints (`whole`, run_scene_alongside of s): every field exactly. Returns the number of
/// checkpoints written.
inline std::size_t require_restarts_identical(const compare::Scene& s, const compare::SceneResult& whole, double every,
                                              bool last) {
  std::vector<std::pair<double, std::string>> saved;
  compare::RunControl ctl;
  ctl.checkpoint_every = every;
  ctl.checkpoint = [&](const std::string& state, double t) { saved.emplace_back(t, state); };
  require_identical(whole, compare::run_scene_alongside(s, ctl));
  REQUIRE(!saved.empty());
  std::vector<std::size_t> from = {0};
  if (last && saved.size() > 1) from.push_back(saved.size() - 1);
  for (const std::size_t k : from) {
    INFO("restarted from the checkpoint at t = " << saved[k].first);
    compare::RunControl rc;
    rc.restart = saved[k].second;
    require_identical(whole, compare::run_scene_alongside(s, rc));
  }
  return saved.size();
}

}  // namespace slipfront::testing
