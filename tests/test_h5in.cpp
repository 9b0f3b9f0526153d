// apps/h5in: a results.h5 read back is what write_results wrote, field by field and bit for bit
// (NaN included) — the results a resumed or MPI study analyses come from these files. Also the
// config hash stored in /meta (CRC-64/XZ of the resolved configuration).
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "compare/alongside.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;

namespace {

using testing::TempDir;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

void check_columns(const compare::Columns& a, const compare::Columns& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.size() == b.size());
  for (const auto& [name, v] : a) {
    INFO(name);
    REQUIRE(b.count(name) == 1);
    CHECK(same_bits(v, b.at(name)));
  }
}

void check_events(const compare::Events& a, const compare::Events& b) {
  for (auto m : {&compare::Events::t_star, &compare::Events::t_hat, &compare::Events::c_slow,
                 &compare::Events::c_transient, &compare::Events::c_transient_peak, &compare::Events::x_arrest,
                 &compare::Events::t_arrest, &compare::Events::c_front, &compare::Events::v_behind,
                 &compare::Events::c_front_middle, &compare::Events::c_front_drift, &compare::Events::x_settled,
                 &compare::Events::front_settled})
    CHECK(same_bits(a.*m, b.*m));
}

// Every field of ModelResult.
void check_model(const compare::ModelResult& w, const compare::ModelResult& r, bool fields) {
  INFO("model " << w.model);
  CHECK(r.model == w.model);
  CHECK(r.status == w.status);
  CHECK(r.message == w.message);
  CHECK(same_bits(r.wall_seconds, w.wall_seconds));
  CHECK(same_bits(r.x, w.x));
  check_columns(w.series, r.series, "series");
  check_events(w.events, r.events);
  check_events(w.events_alt, r.events_alt);
  check_columns(w.cycles, r.cycles, "cycles");
  check_columns(w.friction_law, r.friction_law, "friction_law");
  REQUIRE(r.scalars.size() == w.scalars.size());
  for (const auto& [k, v] : w.scalars) {
    INFO(k);
    REQUIRE(r.scalars.count(k) == 1);
    CHECK(same_bits(r.scalars.at(k), v));
  }
  CHECK(r.labels == w.labels);
  if (!fields) {
    CHECK(r.snapshots.empty());
    CHECK(r.snapshot_t.empty());
    CHECK(r.contacts.empty());
    CHECK(r.contacts_2d.empty());
    return;
  }
  CHECK(same_bits(r.snapshot_t, w.snapshot_t));
  check_columns(w.snapshots, r.snapshots, "snapshots");
  check_columns(w.contacts, r.contacts, "contacts");
  REQUIRE(r.contacts_2d.size() == w.contacts_2d.size());
  for (const auto& [k, t] : w.contacts_2d) {
    INFO(k);
    REQUIRE(r.contacts_2d.count(k) == 1);
    CHECK(r.contacts_2d.at(k).cols == t.cols);
    CHECK(same_bits(r.contacts_2d.at(k).data, t.data));
  }
}

// Runs `toml` with `overrides`, writes results.h5 in `dir`, reads it back both ways and compares.
void round_trip(const fs::path& dir, const std::string& toml, const std::vector<std::string>& overrides,
                const std::string& tag) {
  INFO(tag);
  const compare::Scene scene = app::parse_scene(toml, tag + ".toml", overrides);
  compare::SceneResult sr = compare::run_scene_alongside(scene, {});
  REQUIRE(!sr.models.empty());
  const fs::path file = dir / (tag + ".h5");
  app::RunMeta meta;
  meta.command_line = "test";
  const std::string resolved = app::to_toml(scene);
  app::write_results(file, scene, resolved, sr.models, meta, &sr.comparison);

  const app::ResultsHeader h = app::read_results_header(file);
  CHECK(h.status == slipfront::compare::RunStatus::complete);
  CHECK(h.resolved_toml == resolved);
  CHECK(h.config_hash == app::config_hash(resolved));
  CHECK(h.scene == scene.name);

  const app::ResultsFile f = app::read_results(file);
  REQUIRE(f.models.size() == sr.models.size());
  for (std::size_t k = 0; k < sr.models.size(); ++k) check_model(sr.models[k], f.models[k], true);
  CHECK(f.comparison.metrics.size() == sr.comparison.metrics.size());
  for (const auto& [k, v] : sr.comparison.metrics) {
    INFO(k);
    REQUIRE(f.comparison.metrics.count(k) == 1);
    CHECK(same_bits(f.comparison.metrics.at(k), v));
  }
  check_columns(sr.comparison.fields, f.comparison.fields, "compare/fields");
  check_columns(sr.comparison.friction_law, f.comparison.friction_law, "compare/friction_law");

  const app::ResultsFile lean = app::read_results(file, {.fields = false});
  REQUIRE(lean.models.size() == sr.models.size());
  for (std::size_t k = 0; k < sr.models.size(); ++k) check_model(sr.models[k], lean.models[k], false);
}

}  // namespace

TEST_CASE("h5in: the config hash is CRC-64/XZ of the resolved configuration", "[h5in]") {
  CHECK(app::config_hash("123456789") == "crc64-xz:995dc9bbdf1939fa");  // the standard check value
  CHECK(app::config_hash("") == "crc64-xz:0000000000000000");
  const std::string a = testing::minimal_config();
  std::string b = a;
  b[b.find("mu = 300")] = 'M';
  CHECK(app::config_hash(a) != app::config_hash(b));
}

TEST_CASE("h5in: results read back equal what write_results wrote, for every kind of scene", "[h5in]") {
  const TempDir dir("h5in");
  const std::string tiny = testing::minimal_config() + "[output]\nsnapshot_dt = 0.5\n";
  // 1D edge loading, both models alongside: series, snapshots, events, /compare fields
  round_trip(dir.path, tiny, {"models=[\"continuum\",\"discrete\"]", "discrete.contacts_per_site=100"}, "edge");
  // the discrete model first, agent representation with contact statistics (contacts, 2D tables)
  round_trip(dir.path, tiny,
             {"models=[\"discrete\",\"continuum\"]", "discrete.representation=agent", "discrete.contacts_per_site=20",
              "discrete.contact_statistics=true"},
             "agent");
  // 0D friction-law sweep: friction_law columns and scalars (v_m fits), /compare/friction_law
  const std::string sweep = testing::sweep_config(300) + "[discrete]\ncontacts_per_site = 100\n";
  round_trip(dir.path, sweep, {}, "sweep");
  // 0D spring block: stick-slip cycles
  const std::string block = R"(scene = "block"
)" + testing::paper_interface_toml() + R"([drive]
loading = "spring_block"
K = 2.5
v_d = 0.3
[time]
t_end = 40
)";
  round_trip(dir.path, block, {}, "block");
}

TEST_CASE("h5in: statuses, messages, NaN events and labels survive and a bad file is an InputError", "[h5in]") {
  const TempDir dir("h5in-synthetic");
  const compare::Scene scene = app::parse_scene(testing::minimal_config(), "tiny.toml", {});
  compare::ModelResult a;
  a.model = "discrete";
  a.status = slipfront::compare::RunStatus::interrupted;
  a.message = "stopped at t = 1.5";
  a.x = {0.0, 1.0};
  a.series = {{"t", {0.0, 0.5}}, {"max_v", {std::numeric_limits<double>::quiet_NaN(), -0.0}}, {"empty", {}}};
  a.events.t_star = 1.25;
  a.events_alt.c_front = -3.5;
  a.scalars = {{"dt", 1e-3}, {"steps", 12345.0}, {"inf", std::numeric_limits<double>::infinity()}};
  a.labels = {{"representation", "count"}, {"threshold", "delta"}};
  a.wall_seconds = 0.25;
  compare::ModelResult b;
  b.model = "continuum";
  b.status = slipfront::compare::RunStatus::failed;
  b.message = "non-finite state at step 7, site 3";
  b.x = {0.0};
  b.friction_law = {{"v", {0.1, 1.0}}, {"sigma", {0.5, 0.25}}};
  b.cycles = {{"t_start", {1.0}}, {"F_peak", {2.0}}};
  const fs::path file = dir.path / "results.h5";
  app::RunMeta meta;
  meta.message = "run-level message";
  app::write_results(file, scene, app::to_toml(scene), {a, b}, meta);
  const app::ResultsFile f = app::read_results(file);
  CHECK(f.header.status == slipfront::compare::RunStatus::failed);
  CHECK(f.header.message == "run-level message");
  REQUIRE(f.models.size() == 2);
  check_model(a, f.models[0], true);  // order as written, not alphabetical
  check_model(b, f.models[1], true);
  CHECK(f.comparison.empty());

  // no model at all (the run threw before any result)
  app::write_results(dir.path / "empty.h5", scene, app::to_toml(scene), {}, meta);
  CHECK(app::read_results(dir.path / "empty.h5").models.empty());

  std::ofstream(dir.path / "junk.h5") << "not an HDF5 file";
  CHECK_THROWS_AS(app::read_results_header(dir.path / "junk.h5"), app::InputError);
  CHECK_THROWS_AS(app::read_results(dir.path / "missing.h5"), app::InputError);
  try {
    app::read_results(dir.path / "junk.h5");
  } catch (const app::InputError& e) {
    CHECK(std::string(e.what()).find("junk.h5") != std::string::npos);  // names the file
  }
}
