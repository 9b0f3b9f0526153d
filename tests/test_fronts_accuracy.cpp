// Steady fronts carry their error (issue 36 item 1 and probes 2, 3, 6a, 6b; docs/fronts.md §10.20): the strip
// solver's estimate of a speed's error (the front re-solved on every other row) bounds the distance to a 4×
// finer solve and is not grossly larger; `fronts` stores an estimate beside every speed and says when the
// tolerance is not met (--intervals 8, which was 0.46 % off and `complete` with speed_error NaN); a mesh whose
// Newton iteration cannot be stopped promptly is refused before any work, one that can is stopped inside the
// solve; --scaling keeps alpha in its domain and says how many points it fitted; strip_cmin_height names
// every NaN. Cheap cases only (seconds); the H = 17, 50, 200 check is test_slow_fronts_accuracy.cpp.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "compare/fronts.hpp"
#include "continuum/strip_front.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using slipfront::testing::TempDir;
namespace continuum = slipfront::continuum;
namespace compare = slipfront::compare;

namespace {
const std::string strip_scene = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/steady_front_strip.toml";

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("fronts accuracy: the strip's speed estimate bounds the distance to a 4x finer solve", "[fronts][strip]") {
  // homogeneous_front's column (mu = 300, rho = 0.01) at H = 17, sigma_d = 0.5, 8 rows graded from 0.25: the
  // estimate |c_8 - c_4|/(2^1.5 - 1) + xi part against the same front on 32 rows of the same grading (whose own
  // error is ~1/16 of the 8-row one at the observed order ~2). Measured: c_8 = 58.93, c_32 = 58.87,
  // estimate 1.4x the distance. Fails if the estimate is below the distance (too optimistic) or above 4x it.
  const slipfront::core::InterfaceParams law{1.05, 8.0, 0.1};
  const slipfront::core::BulkParams bulk{0.01, 300.0, 1500.0, 17.0};
  continuum::StripFrontOptions o;
  o.rows = 8;
  o.intervals = 300;
  const auto f = continuum::solve_strip_front(law, bulk, 0.5, o);
  REQUIRE(f.status == continuum::FrontStatus::converged);
  const auto e = continuum::estimate_strip_speed_error(f, o);
  INFO("c_8 = " << f.c << ", estimate " << e.total << " (rows " << e.rows << ", xi " << e.xi << ") " << e.note);
  REQUIRE(std::isfinite(e.total));
  CHECK(e.other_rows == 4);
  const auto fine = continuum::solve_strip_front(law, bulk, 0.5, continuum::with_rows(bulk.height, o, 32), &f);
  REQUIRE(fine.status == continuum::FrontStatus::converged);
  const double distance = std::abs(f.c - fine.c);
  INFO("c_32 = " << fine.c << ", distance " << distance);
  CHECK(distance <= e.total);
  CHECK(e.total <= 4.0 * distance);
  CHECK(e.xi < 1e-6 * f.c);  // 300 intervals: the xi part is negligible
}

TEST_CASE("fronts accuracy: --intervals 8 is flagged (rtol not met), every strip speed carries an estimate",
          "[fronts][strip][cli]") {
  // Probe 6b of issue 36: strip fronts.h5 stored speed_error = NaN everywhere and --intervals 8 (0.46 % off)
  // ended complete with nothing said. Now each branch point, profile and c_min carries a finite estimate, the
  // 8-interval run says "NOT met" on stdout and in /branch@accuracy with rtol_met = 0, and its c_min estimate
  // covers the 200-interval c_min.
  const TempDir dir("fronts-accuracy-8");
  auto run = [&](const std::string& tag, const std::string& intervals) {
    const auto o = slipfront::testing::run({SLIPFRONT_BINARY, "fronts", strip_scene, "--out", (dir.path / tag).string(),
                                            "--rows", "4", "--intervals", intervals},
                                           dir.path);
    INFO(o.err);
    REQUIRE(o.code == 0);
    return std::pair{o.out, slipfront::testing::read_h5(dir.path / tag / "fronts.h5")};
  };
  const auto [out8, f8] = run("i8", "8");
  const auto [out200, f200] = run("i200", "200");
  INFO(out8);
  CHECK(f8.strings.at("/meta@status") == "complete");
  CHECK(f8.numbers.at("/branch@rtol_met") == 0.0);
  CHECK(contains(f8.strings.at("/branch@accuracy"), "NOT met"));
  CHECK(contains(out8, "rtol NOT met"));
  for (const auto* f : {&f8, &f200}) {
    const auto& err = f->datasets.at("/branch/speed_error");
    REQUIRE(err.size() == f->datasets.at("/branch/c").size());
    for (double e : err) CHECK(std::isfinite(e));
    CHECK(std::isfinite(f->numbers.at("/branch@c_min_error")));
    CHECK(std::isfinite(f->numbers.at("/branch@c_at_scene_sigma_d_error")));
    CHECK(std::isfinite(f->numbers.at("/profiles/0@c_error")));
  }
  const double c8 = f8.numbers.at("/branch@c_min"), c200 = f200.numbers.at("/branch@c_min");
  INFO("c_min 8 intervals " << c8 << " +- " << f8.numbers.at("/branch@c_min_error") << ", 200: " << c200);
  CHECK(std::abs(c8 - c200) <= f8.numbers.at("/branch@c_min_error"));
  CHECK(f8.numbers.at("/branch@c_min_error") > 1e-3 * c8);  // the 8-interval c_min is not within 1e-3
  CHECK(contains(out200, "c_min = "));
  CHECK(contains(out200, " ± "));
}

TEST_CASE("fronts accuracy: a small --budget stops the mesh choice: NOT met (budget), every number with its estimate",
          "[fronts][strip][cli]") {
  // Issue 36 item 1, the whole-branch cost budget (docs/fronts.md §10.20): at H = 17 (homogeneous_strip) the
  // default chooses 16 rows (8 rows: largest estimate 0.16 % > rtol 0.1 %). With --budget 10 (CPU seconds) the
  // 16-row branch, predicted at ~45 s, is not solved: the result stays on 8 rows and says so in /branch@accuracy,
  // @resolution and the summary, while every number it returns still carries its (finite) estimate. Fails if the
  // budget is ignored (16 rows, met) or the flag or an estimate is missing.
  const TempDir dir("fronts-accuracy-budget");
  const auto o = slipfront::testing::run(
      {SLIPFRONT_BINARY, "fronts", std::string(SLIPFRONT_SOURCE_DIR) + "/configs/homogeneous_strip.toml", "--budget", "10",
       "--out", (dir.path / "b").string()},
      dir.path);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "b" / "fronts.h5");
  CHECK(f.strings.at("/meta@status") == "complete");
  CHECK(f.numbers.at("/branch@rows") == 8.0);
  CHECK(f.numbers.at("/branch@rtol_met") == 0.0);
  CHECK(f.numbers.at("/branch@budget_seconds") == 10.0);
  CHECK(contains(f.strings.at("/branch@accuracy"), "NOT met (budget)"));
  CHECK(contains(f.strings.at("/branch@resolution"), "budget: 16 rows"));
  CHECK(contains(o.out, "rtol NOT met (budget)"));
  CHECK(f.numbers.at("/branch@largest_relative_error") > 1e-3);
  for (const char* k : {"/branch@c_min_error", "/branch@c_at_scene_sigma_d_error", "/profiles/0@c_error"}) {
    INFO(k);
    CHECK(std::isfinite(f.numbers.at(k)));
    CHECK(f.numbers.at(k) > 0.0);
  }
  for (double e : f.datasets.at("/branch/speed_error")) CHECK(std::isfinite(e));
  // the prediction of the whole is the cost model's, and the CPU spent is of the same order
  INFO("predicted " << f.numbers.at("/branch@predicted_seconds") << " s, spent " << f.numbers.at("/branch@cpu_seconds") << " s");
  CHECK(f.numbers.at("/branch@predicted_seconds") > f.numbers.at("/branch@cpu_seconds") / 3.0);
  CHECK(f.numbers.at("/branch@predicted_seconds") < f.numbers.at("/branch@cpu_seconds") * 3.0);
}

TEST_CASE("fronts accuracy: --rows without --intervals still chooses the intervals by rtol", "[fronts][strip]") {
  // Issue 36 item 1: with the rows given and the intervals not, the choice tried to double the given rows, met the
  // limit (the given count) and returned before the intervals were looked at, so the xi part of the estimate never
  // refined them. steady_front_strip's material (H = 16, mu' = 300) on 4 rows (given) from 16 intervals: the xi part
  // there is well above 0.1 rtol c, so the intervals must be doubled; the rows stay 4, and the c_min returned is
  // within rtol of the same 4 rows on 4x the intervals chosen (its xi limit). Fails if the intervals stay 16.
  compare::Scene s = slipfront::testing::homogeneous_scene(0.5, 150.0, 15.0);
  s.bulk.mu = 4800.0;
  s.bulk.rho = 0.16;
  s.bulk.height = 16.0;
  compare::StripFrontsSettings st;
  st.rows = 4;
  st.first_intervals = 16;
  const compare::FrontsResult r = compare::compute_fronts(s, false, {}, st);
  INFO(r.labels.at("resolution") << "; " << r.labels.at("accuracy"));
  REQUIRE(r.status == compare::RunStatus::complete);
  CHECK(r.scalars.at("rows") == 4.0);
  CHECK(r.scalars.at("intervals") > 16.0);
  CHECK(contains(r.labels.at("resolution"), "rows 4 (given)"));
  compare::StripFrontsSettings fine;
  fine.rows = 4;
  fine.intervals = 4 * static_cast<int>(r.scalars.at("intervals"));
  const compare::FrontsResult ref = compare::compute_fronts(s, false, {}, fine);
  REQUIRE(ref.status == compare::RunStatus::complete);
  const double c = r.scalars.at("c_min"), c_ref = ref.scalars.at("c_min");
  INFO("c_min " << c << " on " << r.scalars.at("intervals") << " intervals, " << c_ref << " on " << fine.intervals);
  CHECK(std::abs(c - c_ref) < 1e-3 * c_ref);
}

TEST_CASE("fronts accuracy: a strip mesh whose Newton iteration cannot stop promptly is refused before any work",
          "[fronts][strip][cli]") {
  // Probe 3 of issue 36: --rows 256 (or --intervals 100000) ignored SIGINT for > 110 s and wrote no file. Now
  // refused up front (exit 2) naming the option and the estimated iteration time; no fronts.h5 is created.
  const TempDir dir("fronts-accuracy-refuse");
  for (const std::vector<std::string>& extra : {std::vector<std::string>{"--rows", "256"}, {"--intervals", "100000"}}) {
    std::vector<std::string> args{SLIPFRONT_BINARY, "fronts", strip_scene, "--out", (dir.path / "o").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto t0 = std::chrono::steady_clock::now();
    const auto o = slipfront::testing::run(args, dir.path);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(extra[0] << ": " << o.err);
    CHECK(o.code == 2);
    CHECK(contains(o.err, extra[0] + ": one Newton iteration"));
    CHECK(contains(o.err, "steady_front_strip.toml"));
    CHECK(seconds < 5.0);
    CHECK_FALSE(fs::exists(dir.path / "o" / "fronts.h5"));
  }
}

TEST_CASE("fronts accuracy: SIGINT inside a strip solve stops it within an iteration and writes an interrupted file",
          "[fronts][strip][cli]") {
  // 48 rows (one Newton iteration ~0.5 CPU s estimated, a few s of wall time under load): the cold start solves
  // strips of growing height on 48 rows; before, no solve polled the stop. SIGINT 3 s in: exit 130 within 20 s (a few iterations on a loaded machine),
  // /meta status interrupted.
  const TempDir dir("fronts-accuracy-sigint");
  const fs::path out = dir.path / "out";
  const auto child = slipfront::testing::spawn(
      {SLIPFRONT_BINARY, "fronts", strip_scene, "--rows", "48", "--out", out.string()}, dir.path, dir.path / "stdout.txt",
      dir.path / "stderr.txt");
  std::this_thread::sleep_for(std::chrono::seconds(3));
  const auto sent = std::chrono::steady_clock::now();
  REQUIRE(::kill(child.pid, SIGINT) == 0);
  const int code = slipfront::testing::wait_for(child, 120);
  const double stop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  INFO(slipfront::testing::slurp(child.err_path));
  CHECK(code == 130);
  CHECK(stop_seconds < 20.0);
  REQUIRE(fs::exists(out / "fronts.h5"));
  const auto file = slipfront::testing::read_h5(out / "fronts.h5");
  CHECK(file.strings.at("/meta@status") == "interrupted");
}

TEST_CASE("fronts accuracy: --scaling on a strip keeps alpha >= 1 and says how many points it fitted",
          "[fronts][strip][cli]") {
  // Probe 6a of issue 36: alpha was varied down to 0.525 (x 0.5), outside alpha >= 1, and the point dropped
  // without a word. Now alpha takes x 1, sqrt 2, 2, 2 sqrt 2 (the scene's alpha = 1.05), every point inside the
  // domain, and the line says "fitted to k of 16 points" with what was dropped and why.
  const TempDir dir("fronts-accuracy-scaling");
  const auto o = slipfront::testing::run(
      {SLIPFRONT_BINARY, "fronts", strip_scene, "--scaling", "--rows", "4", "--intervals", "200", "--out",
       (dir.path / "s").string()},
      dir.path);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "s" / "fronts.h5");
  const auto& index = f.datasets.at("/scaling/points/parameter_index");
  const auto& value = f.datasets.at("/scaling/points/value");
  const auto& c_min = f.datasets.at("/scaling/points/c_min");
  const auto& err = f.datasets.at("/scaling/points/c_min_error");
  REQUIRE(index.size() == 16);
  int fitted = 0;
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (index[k] == 1.0) CHECK(value[k] >= 1.0);  // alpha
    if (std::isfinite(c_min[k])) {
      ++fitted;
      CHECK(std::isfinite(err[k]));
    }
  }
  CHECK(contains(o.out, "fitted to " + std::to_string(fitted) + " of 16 points"));
}

TEST_CASE("fronts accuracy: strip_cmin_height names every NaN and gives c_min an estimate", "[fronts][strip][study]") {
  // Probe 2 of issue 36: the study ended complete with c_min_1d = ratio_to_1d = NaN where the 1D solve did not
  // converge, without a note. Now every height whose c_min_1d is NaN has a note naming it and the 1D branch's end,
  // printed in the summary; every c_min has a finite c_min_error.
  const TempDir dir("fronts-accuracy-cmin");
  slipfront::testing::write_text(dir.path / "strip.toml", slipfront::testing::slurp(strip_scene));
  slipfront::testing::write_text(dir.path / "p2.toml",
                                 "study = \"p2\"\nkind = \"strip_cmin_height\"\nscene = \"strip.toml\"\n"
                                 "set = [\"bulk.rho=16e-9\", \"limits.max_hours=1000\", "
                                 "\"limits.min_nodes_per_elastic_length=0\"]\n"
                                 "[paths]\nhmin = 1.0471\nhmax = 1.0965\nper_decade = 100\nrows = 4\nintervals = 200\n"
                                 "branches = false\n");
  const auto o = slipfront::testing::run({SLIPFRONT_BINARY, "study", "p2.toml", "--out", (dir.path / "out").string()},
                                         dir.path);
  INFO(o.out << o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "out" / "study.h5");
  const std::string t = "/study/tables/strip_cmin_height/";
  const auto& H = f.datasets.at(t + "H");
  REQUIRE(H.size() == 3);
  int nan_rows = 0;
  for (std::size_t k = 0; k < H.size(); ++k) {
    CHECK(std::isfinite(f.datasets.at(t + "c_min_error")[k]));
    if (!std::isfinite(f.datasets.at(t + "c_min_1d")[k])) {
      ++nan_rows;
      char h[32];
      std::snprintf(h, sizeof h, "%g", H[k]);
      CHECK(contains(o.out, std::string("note: c_min_1d and ratio_to_1d not computed at H = ") + h));
    } else {
      CHECK(std::isfinite(f.datasets.at(t + "c_min_1d_error")[k]));
    }
  }
  INFO(nan_rows << " heights without c_min_1d");
  CHECK(nan_rows >= 1);  // the reproducer still has a 1D failure here (1 of 3 heights measured), so the notes are tested
  CHECK(f.strings.at("/meta@status") == "complete");
}
