// apps/config: the TOML schema of docs/model.md §5 (docs/cli.md). Every refusal must name the file, the key
// and a reason; the resolved TOML written to /config must reload to the identical scene.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using slipfront::app::ConfigError;
using slipfront::app::load_scene;
using slipfront::app::parse_scene;
using slipfront::app::same_scene;
using slipfront::app::to_toml;
using slipfront::compare::Scene;
using slipfront::core::Loading;
using slipfront::testing::TempDir;

namespace {

fs::path write_config(const std::string& name, const std::string& text) {
  static const TempDir dir("config");  // one per test process, removed at exit
  const fs::path file = dir.path / name;
  std::ofstream(file) << text;
  return file;
}

// Edge loading, every required key and nothing else.
const std::string minimal = slipfront::testing::minimal_config();

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}

// Loading `text` (with `overrides`) must throw a ConfigError whose message names the file and
// contains every one of `fragments` (the key and the reason).
void require_refused(const std::string& name, const std::string& text, const std::vector<std::string>& overrides,
                     const std::vector<std::string>& fragments) {
  const fs::path file = write_config(name, text);
  try {
    load_scene(file, overrides);
    FAIL("accepted " << name);
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    INFO(msg);
    CHECK(msg.rfind(file.string() + ":", 0) == 0);  // starts with "<file>:"
    CHECK_FALSE(e.reason.empty());
    for (const auto& f : fragments) CHECK(msg.find(f) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("config: a minimal valid scene loads with the struct defaults filled in", "[config]") {
  const Scene s = load_scene(write_config("minimal.toml", minimal), {});
  CHECK(s.name == "tiny");
  CHECK(s.models == std::vector<std::string>{"continuum"});
  CHECK(s.interface.alpha == 1.05);
  CHECK(s.interface.kappa == 8.0);  // an integer where a number is expected
  CHECK(s.bulk.length == 20.0);
  CHECK(s.drive.loading == Loading::edge);
  CHECK(s.grid.dx == 2.0);
  CHECK(s.time.t_end == 2.0);
  CHECK(s.time.dt == 0.0);
  CHECK(s.time.cfl == 0.5);
  CHECK(s.measure.A_tip == 0.5);
  CHECK(s.output.snapshot_dt == 1.0);
}

TEST_CASE("config: unknown keys and sections are refused with the list of known keys", "[config]") {
  require_refused("unknown_key.toml", replace(minimal, "eta = 0.1", "eta = 0.1\nalpah = 2"), {},
                  {"interface.alpah", "unknown key", "alpha, kappa, eta", "did you mean 'alpha'"});
  require_refused("unknown_section.toml", minimal + "[solver]\norder = 2\n", {}, {"solver", "unknown key or section"});
  require_refused("unknown_top.toml", "colour = 3\n" + minimal, {}, {"colour", "unknown"});
  require_refused("section_not_table.toml", "grid = 3\n" + replace(minimal, "[grid]\ndx = 2\n", ""), {},
                  {"grid", "expected a section"});
}

TEST_CASE("config: missing required keys are refused", "[config]") {
  require_refused("no_alpha.toml", replace(minimal, "alpha = 1.05\n", ""), {},
                  {"interface.alpha", "required key is missing"});
  require_refused("no_loading.toml", replace(minimal, "loading = \"edge\"\n", ""), {},
                  {"drive.loading", "required key is missing"});
  require_refused("no_mu.toml", replace(minimal, "mu = 300\n", ""), {}, {"bulk.mu", "required key is missing"});
  require_refused("no_scene.toml", replace(minimal, "scene = \"tiny\"\n", ""), {}, {"scene", "required key is missing"});
  // What is required depends on the loading.
  require_refused("no_sigma_d.toml", minimal, {"drive.loading=homogeneous"},
                  {"drive.sigma_d", "required key is missing"});
  require_refused("no_v.toml", minimal, {"drive.loading=imposed_rate"}, {"drive.v", "required key is missing"});
  require_refused("no_switch_times.toml", minimal, {"drive.loading=imposed_rate", "drive.v=[0.1, 1.0]"},
                  {"drive.switch_times", "required key is missing"});
}

TEST_CASE("config: wrong types are refused", "[config]") {
  require_refused("alpha_string.toml", replace(minimal, "alpha = 1.05", "alpha = \"big\""), {},
                  {"interface.alpha", "expected a number", "string"});
  require_refused("loading_number.toml", replace(minimal, "loading = \"edge\"", "loading = 1"), {},
                  {"drive.loading", "expected a string"});
  require_refused("loading_unknown.toml", replace(minimal, "loading = \"edge\"", "loading = \"edgy\""), {},
                  {"drive.loading", "unknown loading"});
  require_refused("energy_int.toml", minimal + "[output]\nenergy = 1\n", {}, {"output.energy", "true or false"});
  require_refused("batches_float.toml", minimal + "[measure]\nbatches = 2.5\n", {},
                  {"measure.batches", "expected an integer"});
  require_refused("models_numbers.toml", "models = [1]\n" + minimal, {}, {"models", "array of strings"});
}

TEST_CASE("config: output.deflate is an integer gzip level in 0..9, 0 by default", "[config]") {
  CHECK(load_scene(write_config("deflate_default.toml", minimal), {}).output.deflate == 0);
  CHECK(load_scene(write_config("deflate_9.toml", minimal + "[output]\ndeflate = 9\n"), {}).output.deflate == 9);
  CHECK(load_scene(write_config("deflate_set.toml", minimal), {"output.deflate=1"}).output.deflate == 1);
  require_refused("deflate_high.toml", minimal + "[output]\ndeflate = 10\n", {}, {"output.deflate", "[0, 9]", "10"});
  require_refused("deflate_negative.toml", minimal, {"output.deflate=-1"}, {"output.deflate", "[0, 9]"});
  require_refused("deflate_float.toml", minimal + "[output]\ndeflate = 1.5\n", {}, {"output.deflate", "integer"});
  require_refused("deflate_string.toml", minimal + "[output]\ndeflate = \"gzip\"\n", {}, {"output.deflate"});
}

TEST_CASE("config: out-of-range values are refused with the key and the reason", "[config]") {
  require_refused("alpha_low.toml", replace(minimal, "alpha = 1.05", "alpha = 0.9"), {},
                  {"interface.alpha", "must be >= 1"});
  require_refused("rho_zero.toml", replace(minimal, "rho = 0.01", "rho = 0"), {}, {"bulk.rho", "must be > 0"});
  require_refused("rho_negative.toml", replace(minimal, "rho = 0.01", "rho = -1"), {}, {"bulk.rho", "must be > 0"});
  require_refused("mu_zero.toml", replace(minimal, "mu = 300", "mu = 0"), {}, {"bulk.mu", "must be > 0"});
  require_refused("mu_negative.toml", replace(minimal, "mu = 300", "mu = -300"), {}, {"bulk.mu", "must be > 0"});
  require_refused("dx_zero.toml", replace(minimal, "dx = 2", "dx = 0"), {}, {"grid.dx", "must be > 0"});
  require_refused("dx_negative.toml", replace(minimal, "dx = 2", "dx = -0.5"), {}, {"grid.dx", "must be > 0"});
  require_refused("l_below_dx.toml", replace(minimal, "length = 20", "length = 1"), {},
                  {"bulk.length", "must be >= grid.dx"});
  require_refused("kappa_negative.toml", replace(minimal, "kappa = 8", "kappa = -8"), {}, {"interface.kappa", ">= 0"});
  require_refused("points_one.toml", minimal, {"drive.loading=imposed_rate", "drive.points=1"},
                  {"drive.points", "at least 2 points"});
  require_refused("contacts_zero.toml", "models = [\"continuum\", \"discrete\"]\n" + minimal,
                  {"discrete.contacts_per_site=0"}, {"discrete.contacts_per_site", ">= 1"});
  require_refused("models_twice.toml", "models = [\"continuum\", \"continuum\"]\n" + minimal, {},
                  {"models", "twice"});
  require_refused("unknown_model.toml", "models = [\"lattice\"]\n" + minimal, {}, {"models", "unknown model"});
}

TEST_CASE("config: --set values are parsed as TOML or else taken as bare strings", "[config]") {
  const fs::path file = write_config("overrides.toml", "models = [\"continuum\", \"discrete\"]\n" + minimal);
  const Scene s = load_scene(file, {"bulk.mu=200", "discrete.threshold=uniform", "discrete.renewal=\"quenched\"",
                                    "discrete.width = 0.25", "discrete.noise=false", "time.dt=1e-3", "scene=renamed"});
  CHECK(s.bulk.mu == 200.0);
  CHECK(s.discrete.threshold == "uniform");
  CHECK(s.discrete.renewal == "quenched");
  CHECK(s.discrete.width == 0.25);
  CHECK_FALSE(s.discrete.noise);
  CHECK(s.time.dt == 1e-3);
  CHECK(s.name == "renamed");

  const Scene r = load_scene(file, {"drive.loading=imposed_rate", "drive.v=[0.1,1.0]", "drive.switch_times=[0, 1.5]"});
  CHECK(r.drive.v == std::vector<double>{0.1, 1.0});
  CHECK(r.drive.v_times == std::vector<double>{0.0, 1.5});
  const Scene one = load_scene(file, {"drive.loading=imposed_rate", "drive.v=3"});
  CHECK(one.drive.v == std::vector<double>{3.0});
  CHECK(one.drive.v_times == std::vector<double>{0.0});  // default for a single v

  // Overrides win over the file, and a value given by --set is named as such in errors.
  require_refused("override_bad_value.toml", minimal, {"interface.alpha=0.5"},
                  {"--set interface.alpha", "must be >= 1"});
  require_refused("override_bad_type.toml", minimal, {"interface.alpha=abc"},
                  {"--set interface.alpha", "expected a number", "abc"});
}

TEST_CASE("config: a --set naming an unknown key is refused", "[config]") {
  require_refused("set_unknown_key.toml", minimal, {"bulk.muu=3"},
                  {"--set bulk.muu", "unknown key", "rho, mu, length"});
  require_refused("set_unknown_section.toml", minimal, {"blk.mu=3"}, {"--set blk.mu", "unknown section"});
  require_refused("set_no_equals.toml", minimal, {"bulk.mu"}, {"--set bulk.mu", "section.key=value"});
}

TEST_CASE("config: a TOML syntax error names file and line and column", "[config]") {
  const std::string text = "scene = \"x\"\n[interface\nalpha = 1\n";
  const fs::path file = write_config("syntax.toml", text);
  try {
    load_scene(file, {});
    FAIL("accepted a syntax error");
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    INFO(msg);
    CHECK(msg.rfind(file.string() + ":2:", 0) == 0);  // "<file>:<line>:<col>: <reason>", error on line 2
    CHECK(e.key.empty());
    CHECK_FALSE(e.reason.empty());
  }
  CHECK_THROWS_WITH(load_scene(fs::temp_directory_path() / "slipfront-no-such-dir" / "absent.toml", {}),
                    Catch::Contains("absent.toml: cannot open the file"));
}

TEST_CASE("config: keys the scene does not use are accepted and noted and reset", "[config]") {
  const std::string text = replace(minimal, "loading = \"edge\"", "loading = \"spring_block\"") +
                           "[discrete]\nthreshold = \"uniform\"\n";
  std::vector<std::string> notes;
  const Scene s = load_scene(write_config("ignored.toml", text), {}, &notes);
  const Scene defaults;
  CHECK(s.bulk.mu == defaults.bulk.mu);  // 1D-only keys of a 0D scene
  CHECK(s.grid.dx == defaults.grid.dx);
  CHECK(s.discrete.threshold == defaults.discrete.threshold);  // discrete not in models
  CHECK(s.drive.K == 2.5);
  auto noted = [&](const std::string& key) {
    for (const auto& n : notes)
      if (n.rfind(key + " ", 0) == 0) return true;
    return false;
  };
  CHECK(noted("bulk.mu"));
  CHECK(noted("bulk.length"));
  CHECK(noted("grid.dx"));
  CHECK(noted("discrete.threshold"));
  CHECK_FALSE(noted("drive.K"));
}

TEST_CASE("config: to_toml round trip is exact", "[config]") {
  const fs::path file = write_config("roundtrip.toml", "description = \"a \\\"quoted\\\" line\\nand a tab\\t\"\n" +
                                                           minimal);
  const std::vector<std::vector<std::string>> variants = {
      {},
      {"interface.eta=0.30000000000000004", "bulk.rho=0.010000000000000002", "measure.v_event=0.1234567890123456789",
       "time.dt=0.001", "output.energy=true"},
      {"drive.loading=homogeneous", "drive.sigma_d=0.45", "drive.nucleation_length=6"},
      {"drive.loading=spring_block", "drive.K=0.7"},
      {"drive.loading=imposed_rate", "drive.v=[0.1, 1.0, 0.1]", "drive.switch_times=[0, 0.5, 1.25]", "time.steps=100"},
      {"drive.loading=imposed_rate", "drive.points=7", "drive.v_min=0.01", "drive.v_max=10", "time.slip_end=0"},
      {"models=[\"continuum\", \"discrete\"]", "discrete.contacts_per_site=50", "discrete.threshold=weibull",
       "discrete.width=0.2", "discrete.renewal=quenched", "discrete.representation=agent", "discrete.noise=false",
       "discrete.seed=9007199254740993", "discrete.bins=8", "discrete.contact_statistics=true"},
  };
  for (const auto& overrides : variants) {
    const Scene s1 = load_scene(file, overrides);
    const std::string text = to_toml(s1);
    INFO(text);
    const Scene s2 = parse_scene(text, "resolved", {});
    CHECK(same_scene(s1, s2));
    CHECK(to_toml(s2) == text);
  }
  // The round trip is bit-exact for doubles that need all 17 digits.
  const Scene s = load_scene(file, {"interface.eta=0.30000000000000004"});
  CHECK(parse_scene(to_toml(s), "resolved", {}).interface.eta == 0.30000000000000004);
  CHECK(parse_scene(to_toml(s), "resolved", {}).description == "a \"quoted\" line\nand a tab\t");
  // same_scene really compares: a changed value is seen.
  Scene changed = s;
  changed.measure.batches += 1;
  CHECK_FALSE(same_scene(s, changed));
}

TEST_CASE("config: switch times at or after t_end are refused", "[config]") {
  // A switch at or after t_end would be silently dropped: refuse it with the key named.
  const fs::path file = write_config(
      "switch.toml", "scene = \"s\"\n[interface]\nalpha = 1.05\nkappa = 8\neta = 0.1\n[bulk]\nrho = 0.01\n"
                     "[drive]\nloading = \"imposed_rate\"\nv = [0.1, 1.0]\nswitch_times = [0, 3]\n[time]\nt_end = 2\n");
  try {
    (void)load_scene(file, {});
    FAIL("expected a ConfigError");
  } catch (const ConfigError& e) {
    CHECK(e.key == "drive.switch_times");
    CHECK(std::string(e.what()).find("switch.toml") != std::string::npos);
  }
}
