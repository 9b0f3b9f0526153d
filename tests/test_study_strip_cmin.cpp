// The study kind strip_cmin_height (issue 20, docs/studies.md): c_min(H) of the strip at the base scene's material,
// no scene runs. `slipfront study` on a small range (H = 1 .. 10, one per decade, 6 rows, 150 intervals: ~1 s) writes
// a complete study.h5 whose table is the library's (studies::strip_cmin_height) bit for bit, and the same CSV; the
// smallest H is the 1D c_min of the same column stiffness within the path's own test bound
// (tests/test_strip_front.cpp: 0 < c_min/c_min,1D - 1 < 1e-3). Hostile study files are refused before any work
// with the file, the key and the reason, and nothing is created.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "studies/strip_cmin_height.hpp"
#include "continuum/steady_front.hpp"
#include "continuum/inplane_front.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using namespace slipfront::testing;

namespace {

const std::string bin = SLIPFRONT_BINARY;

// The strip of configs/steady_front_strip.toml (H = 16, mu = 4800: mu' = 300; the paper's law) at rho = 16e-9
// (rho' = 1e-9, the quasi-static material of docs/fronts.md §10.12), written here so that the test does not follow
// edits of configs/. The limits keys lift the checks of a time-dependent run that loading the scene makes.
void write_strip_scene(const fs::path& dir) {
  write_text(dir / "strip.toml", R"(scene = "strip"
models = ["continuum"]
[interface]
alpha = 1.05
kappa = 8.0
eta = 0.1
[bulk]
rho = 16e-9
mu = 4800.0
length = 1000.0
height = 16.0
[drive]
loading = "homogeneous"
sigma_d = 0.5
nucleation_length = 150.0
[grid]
dx = 0.5
dy = 0.5
[time]
t_end = 15.0
cfl = 0.5
[limits]
max_hours = 1000
min_nodes_per_elastic_length = 0
)");
}

const char* const small_paths = "[paths]\nhmin = 1.0\nhmax = 10.0\nper_decade = 1.0\nrows = 6\nintervals = 150\nbranches = false\n";

// The library's options of small_paths at the scene's law, rho' = 1e-9 and the strip material mu'.
studies::StripCminHeightOptions small_options(double mu_strip) {
  studies::StripCminHeightOptions o;
  o.law = {1.05, 8.0, 0.1};
  o.mu_strip = mu_strip;
  o.rho_strip = 1e-9;
  o.hmin = 1.0;
  o.hmax = 10.0;
  o.per_decade = 1.0;
  o.rows = 6;
  o.intervals = 150;
  o.branches = false;
  return o;
}

fs::path write_study(const fs::path& dir, const std::string& name, const std::string& body) {
  const fs::path f = dir / (name + ".toml");
  write_text(f, "study = \"" + name + "\"\nkind = \"strip_cmin_height\"\nscene = \"strip.toml\"\n" + body);
  return f;
}

}  // namespace

TEST_CASE("study strip_cmin_height: slipfront study writes a complete study.h5 whose c_min(H) is the library's bit for "
          "bit, the same CSV, and the 1D c_min at the smallest H",
          "[study][strip][cmin]") {
  const TempDir dir("study-cmin");
  write_strip_scene(dir.path);
  const fs::path study = write_study(dir.path, "cmin", small_paths);
  const Output o = run({bin, "study", study.string(), "--out", (dir.path / "out").string()}, dir.path, {}, {}, 60.0);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  CHECK(contains(o.err, "[study cmin] limiting path: 2 fronts"));  // progress lines on stderr
  REQUIRE(fs::exists(dir.path / "out" / "study.h5"));
  CHECK(!fs::exists(dir.path / "out" / "runs"));  // no scene runs

  // The library called directly with the scene's material and the study's [paths].
  const studies::StripCminHeightOptions lib = small_options(300.0);
  const auto direct = studies::strip_cmin_height(lib);
  REQUIRE(direct.path.complete);
  REQUIRE(direct.rows.size() == 2);

  const H5Content h = read_h5(dir.path / "out" / "study.h5");
  CHECK(h.strings.at("/meta@status") == "complete");
  CHECK(h.strings.at("/study@kind") == "strip_cmin_height");
  CHECK(h.strings.at("/study@name") == "cmin");
  CHECK(h.strings.at("/study/runs@runs").empty());
  const std::string table = "/study/tables/strip_cmin_height/";
  std::vector<double> c_min, H, c_1d;
  for (const auto& r : direct.rows) {
    c_min.push_back(r.c_min);
    H.push_back(r.H);
    c_1d.push_back(r.c_min_1d);
  }
  CHECK(same_bits(h.datasets.at(table + "c_min"), c_min));
  CHECK(same_bits(h.datasets.at(table + "H"), H));
  CHECK(same_bits(h.datasets.at(table + "c_min_1d"), c_1d));
  CHECK(h.numbers.at("/study/scalars@mu_strip") == 300.0);
  CHECK(h.numbers.at("/study/scalars@rho_strip") == 1e-9);
  CHECK(h.numbers.at("/study/scalars@heights_reached") == 2.0);
  // The CSV beside it: the library's text, byte for byte (no branches: no timing column differs).
  CHECK(slurp(dir.path / "out" / "strip_cmin_height.csv") == studies::strip_cmin_csv(direct.rows));

  // The smallest H against the 1D c_min of mu = mu' H, rho = rho' H, solved here on its own.
  const auto b1 = continuum::continue_steady_fronts(lib.law, {1e-9 * 1.0, 300.0 * 1.0, 1000.0, 0.0});
  INFO("c_min(H = 1) = " << c_min[0] << ", 1D " << b1.c_min);
  CHECK(c_min[0] / b1.c_min - 1.0 > 0.0);
  CHECK(c_min[0] / b1.c_min - 1.0 < 1e-3);

  // A second invocation without --force replaces the study's own study.h5; another study's is refused.
  const fs::path other = write_study(dir.path, "other", small_paths);
  const Output o2 = run({bin, "study", other.string(), "--out", (dir.path / "out").string()}, dir.path, {}, {}, 60.0);
  CHECK(o2.code == 2);
  CHECK(contains(o2.err, "belongs to the study 'cmin'"));
}

TEST_CASE("study strip_cmin_height: a study.h5 of the same study name made from another study file is refused "
          "without --force (issue 36)",
          "[study][strip][cmin][hostile]") {
  // Was: silently replaced (a kind without scene runs has no run files whose configurations would tell the two
  // apart). Now refused naming the first line that differs; the same study again, or --force, replaces it.
  const TempDir dir("study-cmin-other-text");
  write_strip_scene(dir.path);
  const fs::path out = dir.path / "out";
  const fs::path study = write_study(dir.path, "cmin", small_paths);
  REQUIRE(run({bin, "study", study.string(), "--out", out.string(), "-q"}, dir.path, {}, {}, 60.0).code == 0);
  const std::string first = slurp(out / "study.h5");
  std::string changed = small_paths;
  changed.replace(changed.find("intervals = 150"), 15, "intervals = 160");
  write_study(dir.path, "cmin", changed);  // the same name, another [paths]
  const Output refused = run({bin, "study", study.string(), "--out", out.string(), "-q"}, dir.path, {}, {}, 60.0);
  INFO(refused.err);
  CHECK(refused.code == 2);
  CHECK(contains(refused.err, "belongs to the study 'cmin' made from another study file (line "));
  CHECK(contains(refused.err, "`intervals = 150` in the file, `intervals = 160` now"));
  CHECK(contains(refused.err, "--force"));
  CHECK(slurp(out / "study.h5") == first);  // untouched
  const Output forced = run({bin, "study", study.string(), "--out", out.string(), "-q", "--force"}, dir.path, {}, {}, 60.0);
  INFO(forced.err);
  CHECK(forced.code == 0);
  CHECK(contains(read_h5(out / "study.h5").strings.at("/study@toml"), "intervals = 160"));
  // the same study again (the same text): recomputed, not refused
  CHECK(run({bin, "study", study.string(), "--out", out.string(), "-q"}, dir.path, {}, {}, 60.0).code == 0);
}

TEST_CASE("study strip_cmin_height: hostile study files are refused before any work, naming the file, the key and the "
          "reason",
          "[study][strip][cmin][hostile]") {
  const TempDir dir("study-cmin-hostile");
  write_strip_scene(dir.path);
  write_text(dir.path / "chain.toml", minimal_config());
  struct Case {
    std::string name, body, key, reason;
  };
  const std::vector<Case> cases{
      {"hmax_below_hmin", "[paths]\nhmin = 10.0\nhmax = 5.0\n", "paths.hmax", "must be > paths.hmin = 10, got 5"},
      {"rows_zero", "[paths]\nrows = 0\n", "paths.rows", "must be in [1, 256]"},
      {"intervals_huge", "[paths]\nintervals = 10000000\n", "paths.intervals", "must be in [8, 100000]"},
      {"hmin_zero", "[paths]\nhmin = 0.0\n", "paths.hmin", "must be > 0 (the first target height), got 0"},
      {"one_height", "[paths]\nhmin = 1.0\nhmax = 2.0\nper_decade = 1.0\n", "paths.per_decade", "one target height only"},
      {"rows_float", "[paths]\nrows = 12.0\n", "paths.rows", "expected an integer, got a float"},
      {"branches_number", "[paths]\nbranches = 1\n", "paths.branches", "expected true or false"},
      {"unknown_path_key", "[paths]\nhmn = 1.0\n", "paths.hmn", "unknown key (known keys of [paths]: hmin, hmax"},
      {"unknown_key", "color = \"red\"\n", "color", "unknown key (known: study, kind"},
      {"group", "[[group]]\nname = \"mu\"\nvary = { \"bulk.mu\" = [4800.0, 9600.0] }\n", "group",
       "the kind 'strip_cmin_height' makes no runs"},
      {"vary", "[vary]\n\"bulk.mu\" = [4800.0]\n", "vary", "the kind 'strip_cmin_height' makes no runs"},
      {"seeds", "seeds = 3\n", "seeds", "the kind 'strip_cmin_height' makes no runs"},
      {"chain", "", "scene", "needs a strip scene (bulk.height > 0)"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    std::string body = c.body;
    fs::path file;
    if (c.name == "chain") {
      file = dir.path / "chain_study.toml";
      write_text(file, "study = \"chain\"\nkind = \"strip_cmin_height\"\nscene = \"chain.toml\"\n");
    } else {
      file = write_study(dir.path, c.name, body);
    }
    const fs::path out = dir.path / ("out_" + c.name);
    const Output o = run({bin, "study", file.string(), "--out", out.string()}, dir.path, {}, {}, 20.0);
    INFO(o.err);
    CHECK(o.code == 2);
    CHECK(contains(o.err, file.filename().string() + ": " + c.key + ": "));
    CHECK(contains(o.err, c.reason));
    CHECK(!fs::exists(out));  // nothing created
  }
  // [paths] in a kind that runs scenes
  const fs::path fig2 = dir.path / "fig2.toml";
  write_text(fig2, "study = \"f\"\nkind = \"fig2\"\nscene = \"chain.toml\"\n[paths]\nrows = 4\n");
  const Output o = run({bin, "study", fig2.string(), "--out", (dir.path / "out_fig2").string()}, dir.path, {}, {}, 20.0);
  CHECK(o.code == 2);
  CHECK(contains(o.err, "fig2.toml: paths: only a kind without scene runs (strip_cmin_height) has [paths]"));
}

TEST_CASE("study strip_cmin_height: paths.rtol chooses each height's rows, every c_min within its estimate of a twice "
          "finer solve",
          "[study][strip][cmin]") {
  // Issue 36 item 1 (docs/fronts.md §10.20): without paths.rows the rows are chosen per height, doubled from 8 until
  // c_min's estimate is below 0.9 rtol c_min. H = 1, 10, 100 at rtol = 5e-5 (8 rows: estimates 5.6e-8, 2.4e-6, 1.1e-4
  // of c): the first two keep 8 rows, H = 100 takes 16. Each stored c_min against its front re-solved on twice the
  // rows (same grading) and twice the intervals: within its stored error. Fails if the rows are not chosen (all
  // equal), an estimate is missing or below the distance to the finer solve, or a height is judged wrongly.
  studies::StripCminHeightOptions o = studies::strip_cmin_study_defaults();
  o.law = {1.05, 8.0, 0.1};
  o.mu_strip = 300.0;
  o.rho_strip = 1e-9;
  o.hmin = 1.0;
  o.hmax = 100.0;
  o.per_decade = 1.0;
  o.branches = false;
  o.rtol = 5e-5;
  const auto r = studies::strip_cmin_height(o);
  REQUIRE(r.path.complete);
  REQUIRE(r.rows.size() == 3);
  REQUIRE(r.path.fronts.size() == 3);
  CHECK(r.rows[0].rows == 8);
  CHECK(r.rows[2].rows > r.rows[0].rows);
  CHECK(std::isfinite(r.predicted_seconds));
  for (std::size_t k = 0; k < r.rows.size(); ++k) {
    const auto& row = r.rows[k];
    const continuum::StripFront& f = r.path.fronts[k];
    continuum::StripFrontOptions fo = continuum::following_tip({}, continuum::strip_tip_zone(f.law, f.c, f.v_behind));
    fo.row_grading = f.row_grading;
    fo = continuum::with_rows(f.bulk.height, fo, 2 * f.rows());
    fo.intervals = 2 * row.intervals;
    fo.max_newton = 40;
    const auto fine = continuum::solve_strip_saddle_node_front(f.law, f.bulk, fo, f);
    INFO("H = " << row.H << ": c_min " << row.c_min << " +- " << row.c_min_error << " on " << row.rows << " rows, "
                << row.intervals << " intervals; " << fine.c << " on " << fo.rows << ", " << fo.intervals);
    REQUIRE(fine.status == continuum::FrontStatus::converged);
    CHECK(std::isfinite(row.c_min_error));
    CHECK(std::abs(row.c_min - fine.c) <= row.c_min_error);
    CHECK(row.c_min_error < o.rtol * row.c_min);
    CHECK(row.rtol_met == 1.0);
    CHECK(row.verdict.empty());
  }
}

TEST_CASE("study strip_cmin_height: a height whose rtol the budget does not allow is NOT met, in study.h5 and the "
          "summary",
          "[study][strip][cmin]") {
  // The same path with paths.budget = 1 CPU second: the 16 rows H = 100 needs are predicted above it, so H = 100 stays
  // on 8 rows, rtol_met = 0, and a note "NOT met (budget) at H = 100" is stored and printed (and counted in /meta
  // message); H = 1 and 10 are met.
  // Fails if the budget is ignored (16 rows) or the height is not flagged.
  const TempDir dir("study-cmin-budget");
  write_strip_scene(dir.path);
  const fs::path study = write_study(dir.path, "cminb",
                                     "[paths]\nhmin = 1.0\nhmax = 100.0\nper_decade = 1.0\nbranches = false\n"
                                     "rtol = 5e-5\nbudget = 1.0\n");
  const Output o = run({bin, "study", study.string(), "--out", (dir.path / "out").string()}, dir.path, {}, {}, 120.0);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  const H5Content h = read_h5(dir.path / "out" / "study.h5");
  CHECK(h.strings.at("/meta@status") == "complete");
  const std::string table = "/study/tables/strip_cmin_height/";
  const auto& rows = h.datasets.at(table + "rows");
  const auto& met = h.datasets.at(table + "rtol_met");
  REQUIRE(rows.size() == 3);
  CHECK(rows[2] == 8.0);
  CHECK(met[0] == 1.0);
  CHECK(met[1] == 1.0);
  CHECK(met[2] == 0.0);
  CHECK(h.numbers.at("/study/scalars@heights_rtol_unmet") == 1.0);
  CHECK(h.numbers.at("/study/scalars@meshes_chosen") == 1.0);
  CHECK(h.numbers.at("/study/scalars@budget_seconds") == 1.0);
  CHECK(contains(o.out, "note: NOT met (budget) at H = 100: c_min = "));
  CHECK(contains(h.strings.at("/meta@message"), "1 of 3 heights NOT met"));
}

TEST_CASE("study strip_cmin_height on the in-plane strip: the kind reads the body from the scene, and c_min at H = 1 is "
          "solve_inplane_saddle_node_front's, the analysis columns are there",
          "[study][strip][cmin][inplane]") {
  // Issue 39 item 2 (docs/fronts.md §11.8): the scene of write_strip_scene with bulk.body = "inplane" (column mu = 4800
  // on H = 16: E' = 300, mu' = E'(1 - nu)/2 = 100 at nu = 1/3; rho' = 1e-9). `slipfront study` on H = 1, 10 (6 rows,
  // 150 intervals, ~2 s) against the library with the in-plane options, bit for bit; the path's front at H = 1 against
  // the limiting front solved on its own meshes by solve_inplane_saddle_node_front from a cold in-plane front at
  // sigma_d = 0.3 (a different start: the same discrete solution, within 1e-8); and against the antiplane strip of the
  // same 1D material (mu' = 300), which differs by more than 1e-5 at H = 1 (the in-plane H^2 correction is larger).
  // Fails if the kind ignores the body (the antiplane c_min, mu_strip 300, inplane = 0), if a column of the analysis
  // is missing or NaN, or if the 1D ratio at H = 1 is not within (0, 1e-3).
  const TempDir dir("study-cmin-inplane");
  write_strip_scene(dir.path);
  std::string scene = slurp(dir.path / "strip.toml");
  scene.replace(scene.find("height = 16.0\n"), 14, "height = 16.0\nbody = \"inplane\"\npoisson = 0.3333333333333333\n");
  write_text(dir.path / "strip.toml", scene);
  const fs::path study = write_study(dir.path, "cmin_inplane", small_paths);
  const Output o = run({bin, "study", study.string(), "--out", (dir.path / "out").string()}, dir.path, {}, {}, 120.0);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  CHECK(contains(o.err, "in-plane strip, nu = 0.333333, p = 0: E' = 2 mu'/(1 - nu) = 300"));

  // mu' = mu (1 - nu)/(2H) as the scene gives it (~100)
  studies::StripCminHeightOptions lib = small_options(4800.0 * (1.0 - 1.0 / 3.0) / (2.0 * 16.0));
  lib.body = core::BodyKind::inplane;
  lib.poisson = 1.0 / 3.0;
  const auto direct = studies::strip_cmin_height(lib);
  REQUIRE(direct.path.complete);
  REQUIRE(direct.rows.size() == 2);
  const continuum::StripFront& f = direct.path.fronts[0];
  CHECK(f.bulk.body() == core::BodyKind::inplane);
  CHECK(!f.uy.empty());
  CHECK(f.saddle_node_limit);

  const H5Content h = read_h5(dir.path / "out" / "study.h5");
  CHECK(h.strings.at("/meta@status") == "complete");
  const std::string table = "/study/tables/strip_cmin_height/";
  std::vector<double> c_min;
  for (const auto& r : direct.rows) c_min.push_back(r.c_min);
  CHECK(same_bits(h.datasets.at(table + "c_min"), c_min));
  CHECK(h.numbers.at("/study/scalars@inplane") == 1.0);
  CHECK(std::abs(h.numbers.at("/study/scalars@mu_strip") - 100.0) < 1e-12);
  CHECK(std::abs(h.numbers.at("/study/scalars@mu_column") - 300.0) < 1e-12);
  CHECK(std::abs(h.numbers.at("/study/scalars@ell") - 300.0) < 1e-12);
  CHECK(std::abs(h.numbers.at("/study/scalars@c_R") / h.numbers.at("/study/scalars@c_s") - 0.93253) < 1e-5);
  // the analysis: regimes (H/l, H/l_kappa, c/s), local exponent, ratio to 1D, each with its estimate
  for (const char* col : {"H_over_l", "H_over_l_kappa", "c_min_over_s", "c_min_1d", "ratio_to_1d", "c_min_error",
                          "ratio_to_1d_error"}) {
    INFO(col);
    REQUIRE(h.datasets.count(table + col) == 1);
    CHECK(std::isfinite(h.datasets.at(table + col)[0]));
  }
  CHECK(h.datasets.count(table + "rtol_met") == 1);  // NaN here: no paths.rtol, not judged
  CHECK(std::isfinite(h.datasets.at(table + "local_exponent")[0]));
  CHECK(std::abs(h.datasets.at(table + "local_exponent")[0] - 0.5) < 0.01);  // the 1D regime: c_min ∝ sqrt(H)
  const double ratio = h.datasets.at(table + "ratio_to_1d")[0];
  CHECK(ratio - 1.0 > 0.0);
  CHECK(ratio - 1.0 < 1e-3);

  // The same limiting front solved directly on its own meshes from a cold front at sigma_d = 0.3.
  continuum::StripFrontOptions fo = continuum::following_tip({}, continuum::strip_tip_zone(f.law, f.c, f.v_behind));
  fo.rows = f.rows();
  fo.row_grading = f.row_grading;
  fo.intervals = direct.rows[0].intervals;
  const auto cold = continuum::solve_inplane_front(f.law, f.bulk, 0.3, fo);
  REQUIRE(cold.status == continuum::FrontStatus::converged);
  const auto own = continuum::solve_inplane_saddle_node_front(f.law, f.bulk, fo, cold);
  REQUIRE(own.status == continuum::FrontStatus::converged);
  INFO("path c_min(H = 1) = " << f.c << " +- " << direct.rows[0].c_min_error << ", direct " << own.c);
  CHECK(std::abs(own.c / f.c - 1.0) < 1e-8);

  // The antiplane strip of the same 1D material (mu' = E' = 300) on the same settings: another c_min.
  studies::StripCminHeightOptions anti = lib;
  anti.body = core::BodyKind::strip;
  anti.mu_strip = 300.0;
  anti.hmax = 10.0;
  const auto a = studies::strip_cmin_height(anti);
  REQUIRE(a.rows.size() == 2);
  INFO("antiplane c_min(H = 1) = " << a.rows[0].c_min);
  CHECK(std::abs(a.rows[0].c_min_1d / direct.rows[0].c_min_1d - 1.0) < 1e-12);  // the same 1D line
  CHECK(std::abs(a.rows[0].c_min / f.c - 1.0) > 1e-5);
}
