// The strip's body snapshots (issue 19 item 4, docs/output.md /<model>/bulk/): output.bulk_dt and
// output.bulk_stride, run through the program and read back from results.h5 — shapes, times, the kept
// rows and columns, the homogeneous stuck state's exact stresses (docs/model.md §9.4), none without
// bulk_dt or on a chain; the records in a checkpoint (a restart is bit-identical); the estimate counts them.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/estimate.hpp"
#include "core/strip.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;

namespace {

using testing::TempDir;

// The minimal configuration (L = 20, dx = 2: nx = 11; t_end = 2) on a strip of height 4, dy = 1 (5 rows).
std::string strip_config(const std::string& output) {
  return testing::minimal_config() + "[output]\nsnapshot_dt = 0\n" + output;
}
const std::vector<std::string> strip_sets = {"bulk.height=4", "grid.dy=1"};
// Homogeneous loading without a nucleation patch: the stuck state u = σ_d/α + σ_d y/μ' everywhere.
const std::vector<std::string> stuck_sets = {"drive.loading=homogeneous", "drive.sigma_d=0.5",
                                             "drive.nucleation_length=0"};

struct Ran {
  testing::ShellResult run;
  fs::path file;
};

// `slipfront run cfg.toml --out out --set ...` in dir.
Ran run_program(const fs::path& dir, const std::string& config, const std::vector<std::string>& sets) {
  testing::write_text(dir / "cfg.toml", config);
  std::string args = "run cfg.toml --out out";  // (not --quiet: the notes are checked)
  for (const auto& s : sets) args += " --set " + testing::shell_quote(s);
  Ran r{testing::run_in_shell(dir, SLIPFRONT_BINARY, args), dir / "out" / "results.h5"};
  INFO(r.run.err);
  REQUIRE(r.run.code == 0);
  REQUIRE(fs::exists(r.file));
  return r;
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("strip output: kept_indices keeps every k-th node and the last", "[strip][output]") {
  using V = std::vector<std::size_t>;
  CHECK(compare::kept_indices(11, 4) == V{0, 4, 8, 10});
  CHECK(compare::kept_indices(5, 4) == V{0, 4});
  CHECK(compare::kept_indices(5, 3) == V{0, 3, 4});
  CHECK(compare::kept_indices(5, 1) == V{0, 1, 2, 3, 4});
  CHECK(compare::kept_indices(5, 100) == V{0, 4});
  CHECK(compare::kept_indices(1, 4) == V{0});
  CHECK(compare::kept_indices(2, 1) == V{0, 1});
}

TEST_CASE("strip output: core::Strip::shear_stresses is exact for a quadratic field", "[strip][output]") {
  // u = a + b x + c y + d x² + e y² + f x y: second-order differences (central and one-sided) are exact.
  core::BulkParams bulk;
  bulk.rho = 0.01;
  bulk.mu = 300.0;
  bulk.length = 20.0;
  bulk.height = 3.0;
  core::DriveParams drive;
  drive.loading = core::Loading::homogeneous;
  drive.sigma_d = 0.5;
  const core::Strip s(bulk, drive, testing::paper_interface(), 2.0, 0.5);
  const double a = 0.3, b = -0.02, c = 0.07, d = 1e-3, e = -4e-3, f = 2e-3, mup = bulk.mu / bulk.height;
  std::vector<double> u(s.dofs());
  for (std::size_t j = 0; j < s.rows(); ++j)
    for (std::size_t i = 0; i < s.sites(); ++i) {
      const double x = s.x()[i], y = s.row_height(j);
      u[j * s.sites() + i] = a + b * x + c * y + d * x * x + e * y * y + f * x * y;
    }
  for (std::size_t j = 0; j < s.rows(); ++j)
    for (std::size_t i = 0; i < s.sites(); ++i) {
      const double x = s.x()[i], y = s.row_height(j);
      double txz = 0, tyz = 0;
      s.shear_stresses(u, i, j, txz, tyz);
      INFO("i " << i << " j " << j);
      CHECK(txz == Approx(mup * (b + 2 * d * x + f * y)).margin(1e-11));
      CHECK(tyz == Approx(mup * (c + 2 * e * y + f * x)).margin(1e-11));
    }
}

TEST_CASE("strip output: /<model>/bulk/ of a homogeneous strip in its stuck state", "[strip][output][cli]") {
  const TempDir dir("strip-output");
  const Ran r = run_program(dir.path, strip_config("bulk_dt = 0.5\nbulk_stride = 3\n"), with(strip_sets, stuck_sets));
  const auto h = testing::read_h5(r.file);
  // nb = 5 (t = 0, 0.5, ..., 2); columns 0, 3, 6, 9 and the last (10); rows 0, 3 and the top (4)
  const std::size_t nb = 5, nyk = 3, nxk = 5;
  CHECK(testing::dataset_shape(r.file, "/continuum/bulk/t") == std::vector<hsize_t>{nb});
  CHECK(testing::dataset_shape(r.file, "/continuum/bulk/x") == std::vector<hsize_t>{nxk});
  CHECK(testing::dataset_shape(r.file, "/continuum/bulk/y") == std::vector<hsize_t>{nyk});
  for (const char* f : {"u", "tau_xz", "tau_yz"})
    CHECK(testing::dataset_shape(r.file, std::string("/continuum/bulk/") + f) == std::vector<hsize_t>{nb, nyk, nxk});
  CHECK(h.datasets.at("/continuum/bulk/x") == std::vector<double>{0, 6, 12, 18, 20});
  CHECK(h.datasets.at("/continuum/bulk/y") == std::vector<double>{0, 3, 4});  // the interface and the top kept
  const auto& t = h.datasets.at("/continuum/bulk/t");
  const double dt = h.numbers.at("/continuum@dt");
  for (std::size_t k = 0; k < nb; ++k) {  // the first step end at or after each multiple
    CHECK(t[k] >= 0.5 * static_cast<double>(k) - 1e-9 * 0.5);
    CHECK(t[k] < 0.5 * static_cast<double>(k) + dt);
  }
  CHECK(t[0] == 0.0);
  for (const char* f : {"group", "t", "x", "y", "u", "tau_xz", "tau_yz"}) {
    const std::string key = std::string("/continuum/bulk") + (std::string(f) == "group" ? "" : std::string("/") + f) +
                            "@description";
    INFO(key);
    CHECK_FALSE(h.strings.at(key).empty());
  }
  // t = 0: u = σ_d/α + σ_d y/μ', so τ_yz = σ_d and τ_xz = 0 at every node, to round-off
  const double sigma_d = 0.5, alpha = 1.05, mup = 300.0 / 4.0;
  const auto& u = h.datasets.at("/continuum/bulk/u");
  const auto& txz = h.datasets.at("/continuum/bulk/tau_xz");
  const auto& tyz = h.datasets.at("/continuum/bulk/tau_yz");
  const std::vector<double> ys = {0, 3, 4};
  for (std::size_t j = 0; j < nyk; ++j)
    for (std::size_t i = 0; i < nxk; ++i) {
      const std::size_t k = j * nxk + i;
      INFO("row " << j << " column " << i);
      CHECK(u[k] == Approx(sigma_d / alpha + sigma_d * ys[j] / mup).epsilon(1e-14));
      CHECK(std::abs(tyz[k] - sigma_d) < 1e-12);
      CHECK(std::abs(txz[k]) < 1e-12);
    }
  // and it stays stuck: the same at every snapshot
  for (std::size_t k = nxk * nyk; k < u.size(); ++k) {
    CHECK(std::abs(tyz[k] - sigma_d) < 1e-9);
    CHECK(std::abs(txz[k]) < 1e-9);
  }
  // the interface snapshots are not asked for (snapshot_dt = 0): only the bulk group
  CHECK(h.datasets.count("/continuum/snapshots/t") == 0);
}

TEST_CASE("strip output: the default stride keeps the interface and top rows, and bulk_dt = 0 writes no group",
          "[strip][output][cli]") {
  {
    const TempDir dir("strip-output-stride");
    const Ran r = run_program(dir.path, strip_config("bulk_dt = 1\n"), strip_sets);  // edge loading, stride 4
    const auto h = testing::read_h5(r.file);
    CHECK(h.datasets.at("/continuum/bulk/x") == std::vector<double>{0, 8, 16, 20});
    CHECK(h.datasets.at("/continuum/bulk/y") == std::vector<double>{0, 4});
    CHECK(h.datasets.at("/continuum/bulk/t").size() == 3);  // t = 0, 1, 2
    CHECK(testing::dataset_shape(r.file, "/continuum/bulk/tau_yz") == std::vector<hsize_t>{3, 2, 4});
    // the interface row of u is the slip of the interface snapshots' nodes
    const auto& u = h.datasets.at("/continuum/bulk/u");
    CHECK(std::isfinite(u.back()));
  }
  {
    const TempDir dir("strip-output-stride1");
    const Ran r = run_program(dir.path, strip_config("bulk_dt = 1\nbulk_stride = 1\n"), strip_sets);
    const auto h = testing::read_h5(r.file);
    CHECK(h.datasets.at("/continuum/bulk/x").size() == 11);
    CHECK(h.datasets.at("/continuum/bulk/y") == std::vector<double>{0, 1, 2, 3, 4});
  }
  {
    const TempDir dir("strip-output-none");
    const Ran r = run_program(dir.path, strip_config(""), strip_sets);  // bulk_dt: default 0
    const auto h = testing::read_h5(r.file);
    for (const auto& [k, v] : h.datasets) CHECK(k.find("/bulk/") == std::string::npos);
    CHECK(h.strings.count("/continuum/bulk@description") == 0);
    // the resolved configuration says bulk_dt = 0 and not the stride (it is not used)
    const std::string toml = h.strings.at("/config@toml");
    CHECK(toml.find("bulk_dt = 0.0") != std::string::npos);
    CHECK(toml.find("bulk_stride") == std::string::npos);
  }
}

TEST_CASE("strip output: a chain's output.bulk_dt is ignored with a note", "[strip][output][cli]") {
  const TempDir dir("strip-output-chain");
  const Ran r = run_program(dir.path, strip_config("bulk_dt = 0.5\nbulk_stride = 2\n"), {});
  CHECK(testing::contains(r.run.err, "output.bulk_dt is ignored: it is used only with bulk.height (the strip)"));
  CHECK(testing::contains(r.run.err, "output.bulk_stride is ignored"));
  const auto h = testing::read_h5(r.file);
  for (const auto& [k, v] : h.datasets) CHECK(k.find("/bulk/") == std::string::npos);
  CHECK(h.strings.at("/config@toml").find("bulk_") == std::string::npos);
  // the same in code: the recorder keeps no bulk snapshot for a chain
  compare::Scene s = app::parse_scene(testing::minimal_config(), "chain.toml", {});
  s.bulk_output.dt = 0.5;
  const auto results = compare::run_scene(s, {});
  REQUIRE(results.size() == 1);
  CHECK(results[0].bulk_t.empty());
  CHECK(results[0].bulk.empty());
}

TEST_CASE("strip output: bad keys are refused, tiny cadences by the memory estimate", "[strip][output][config]") {
  const std::string text = strip_config("");
  auto refused = [&](const std::vector<std::string>& sets) -> std::string {
    try {
      (void)app::parse_scene(text, "t.toml", with(strip_sets, sets));
    } catch (const app::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  CHECK(testing::contains(refused({"output.bulk_dt=-1"}), "output.bulk_dt"));
  CHECK(testing::contains(refused({"output.bulk_dt=1", "output.bulk_stride=0"}), "output.bulk_stride"));
  CHECK(testing::contains(refused({"output.bulk_dt=1", "output.bulk_stride=1.5"}), "output.bulk_stride"));
  const std::string big = refused({"output.bulk_dt=1e-300", "time.t_end=2000", "limits.max_memory_gib=0.1"});
  CHECK(testing::contains(big, "limits.max_memory_gib"));
  CHECK(testing::contains(big, "bulk snapshots (output.bulk_dt)"));
  // the estimate lists them, in proportion to the kept nodes
  const auto s = app::parse_scene(text, "t.toml", with(strip_sets, {"output.bulk_dt=0.5"}));
  const auto e = compare::estimate(s);
  double bytes = -1;
  for (const auto& [what, b] : e.memory_items)
    if (what.find("bulk snapshots (output.bulk_dt)") != std::string::npos) bytes = b;
  CHECK(bytes > 5 * 4 * 2 * 3 * 8.0);  // ≥ 5 snapshots of 4 × 2 nodes, three fields
  CHECK(bytes < 1e4);
}

TEST_CASE("strip output: the bulk snapshots are in the checkpoint: a restart is bit-identical", "[strip][output][checkpoint]") {
  compare::Scene s = app::parse_scene(strip_config("bulk_dt = 0.25\nbulk_stride = 2\n"), "t.toml", strip_sets);
  const auto whole = compare::run_scene_alongside(s, {});
  REQUIRE(whole.models.size() == 1);
  REQUIRE(whole.models[0].bulk_t.size() == 9);
  std::vector<std::pair<double, std::string>> saved;
  compare::RunControl ctl;
  ctl.checkpoint_every = 0.7;
  ctl.checkpoint = [&](const std::string& state, double t) { saved.emplace_back(t, state); };
  (void)compare::run_scene_alongside(s, ctl);
  REQUIRE(saved.size() >= 2);
  compare::RunControl again;
  again.restart = saved[1].second;  // t ≈ 1.4: some bulk snapshots already taken, some to come
  const auto resumed = compare::run_scene_alongside(s, again);
  const auto &a = whole.models[0], &b = resumed.models[0];
  CHECK(testing::same_bits(a.bulk_t, b.bulk_t));
  CHECK(testing::same_bits(a.bulk_x, b.bulk_x));
  CHECK(testing::same_bits(a.bulk_y, b.bulk_y));
  REQUIRE(a.bulk.size() == 3);
  for (const auto& [name, v] : a.bulk) {
    INFO(name);
    CHECK(testing::same_bits(v, b.bulk.at(name)));
  }
  CHECK(testing::same_bits(a.series.at("drive_force"), b.series.at("drive_force")));
}
