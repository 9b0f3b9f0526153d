// `slipfront fronts` trusts nothing it did not compute (issue 18, docs/fronts.md §8a): no front or a solver
// failure ends `failed` (exit 1, /meta status and the reason in the file, c_min NaN, no branch point); the
// cold start finds the branch for any c_s (rho = 1e-6); the front at the scene's sigma_d is reported; a stop
// request (SIGINT) writes an `interrupted` file and exits 130. Runs the real binary.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using slipfront::testing::TempDir;

namespace {

const std::string paper_scene = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/homogeneous_front.toml";

struct Fronts {
  int code = -1;
  std::string out, err;
  slipfront::testing::H5Content file;
};

// `slipfront fronts` on the paper's homogeneous scene with `sets` (--set each), into a fresh directory.
Fronts run_fronts(const TempDir& dir, const std::string& tag, const std::vector<std::string>& sets) {
  std::vector<std::string> args = {SLIPFRONT_BINARY, "fronts", paper_scene, "--out", (dir.path / tag).string()};
  for (const auto& s : sets) args.insert(args.end(), {"--set", s});
  const auto o = slipfront::testing::run(args, dir.path);
  Fronts f{o.code, o.out, o.err, {}};
  const fs::path file = dir.path / tag / "fronts.h5";
  if (fs::exists(file)) f.file = slipfront::testing::read_h5(file);
  return f;
}

double number(const Fronts& f, const std::string& key) {
  const auto it = f.file.numbers.find(key);
  return it == f.file.numbers.end() ? -1.0 : it->second;  // -1: absent (not NaN, which is a value)
}
std::string text(const Fronts& f, const std::string& key) {
  const auto it = f.file.strings.find(key);
  return it == f.file.strings.end() ? "(absent)" : it->second;
}

}  // namespace

TEST_CASE("fronts verb: no front, or no branch, ends failed with the reason, exit 1 and NaN, never an empty complete",
          "[fronts][cli]") {
  // Each reproducer of issue 18 wrote `complete`, exit 0, an empty /branch and c_min = 0. Now: exit 1, /meta
  // status failed with the reason (the same on stderr), c_min, sigma_d_at_c_min and c_min_over_scale NaN,
  // /branch/c empty, and the reason in the equations' terms:
  //  - eta = 0, kappa = 0: the steady law has no minimum at a finite v > 0 (no sigma_c^d to end at);
  //  - alpha = 1e6: sigma_c^d = 223.6 >= 1, no sigma_d has a front;
  //  - eta = 1e-6, rho = 1000: the speed scale sqrt(mu alpha/(eta kappa)) is 36 times c_s: supersonic fronts.
  struct Case {
    std::string set, reason;
  };
  const std::vector<Case> cases = {
      {"interface.eta=0", "has no minimum at a finite v > 0"},
      {"interface.eta=1e-6", "the fronts would be faster than sound"},
      {"interface.kappa=0", "has no minimum at a finite v > 0"},
      {"interface.alpha=1e6", "sigma_c^d = 223.5942977 >= 1"},
      {"bulk.rho=1000", "the fronts would be faster than sound"},
  };
  const TempDir dir("fronts-failed");
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const auto& c = cases[k];
    INFO(c.set);
    // alpha = 1e6 makes the elastic length sqrt(mu/alpha) shorter than the scene's grid: lift that check (the
    // grid is not used by `fronts`).
    const Fronts f = run_fronts(dir, "case" + std::to_string(k), {c.set, "limits.min_nodes_per_elastic_length=0"});
    INFO(f.err);
    CHECK(f.code == 1);
    CHECK(text(f, "/meta@status") == "failed");
    CHECK(text(f, "/meta@message").find("no steady front found") != std::string::npos);
    CHECK(text(f, "/meta@message").find(c.reason) != std::string::npos);
    CHECK(text(f, "/branch@reason").find(c.reason) != std::string::npos);
    CHECK(f.err.find("fronts failed: ") != std::string::npos);
    CHECK(f.err.find(c.reason) != std::string::npos);
    CHECK(std::isnan(number(f, "/branch@c_min")));
    CHECK(std::isnan(number(f, "/branch@sigma_d_at_c_min")));
    CHECK(std::isnan(number(f, "/branch@c_min_over_scale")));
    CHECK(std::isnan(number(f, "/branch@c_min_at_end")));
    CHECK(f.file.datasets.count("/branch/c") == 0);  // no continuation point: no column at all
    CHECK(f.out.find("c_min = nan") != std::string::npos);
  }
}

TEST_CASE("fronts verb: the cold start finds the branch for any c_s (rho = 1e-6), rho = 1e-5 unchanged", "[fronts][cli]") {
  // rho = 1e-6 (c_s = 17320) found no front: the cold start scanned only c >= 0.02 c_s = 346, above every
  // speed of the branch (108 at sigma_d = 0.8). It now continues below 0.02 c_s; the branch ends at the
  // saddle-node with c_min = 11.30508552 (between rho = 1e-5's 11.30506385 and the rho -> 0 limit, 11.3050879
  // at rho = 1e-8: inertia slows the front by rho c^2/mu ~ 1e-6), from sigma_d = 0.8. rho = 1e-5, found
  // before, keeps its c_min = 11.305063851170592 (to 1e-12; in fact bit for bit).
  const TempDir dir("fronts-rho");
  const Fronts tiny = run_fronts(dir, "rho1e-6", {"bulk.rho=1e-6"});
  INFO(tiny.err);
  CHECK(tiny.code == 0);
  CHECK(text(tiny, "/meta@status") == "complete");
  CHECK(text(tiny, "/branch@end") == "saddle_node");
  CHECK(number(tiny, "/branch@c_min") == Approx(11.30508552).epsilon(1e-9));
  REQUIRE(tiny.file.datasets.count("/branch/sigma_d") == 1);
  CHECK(tiny.file.datasets.at("/branch/sigma_d").front() == 0.8);
  CHECK(tiny.file.datasets.at("/branch/sigma_d").size() >= 10);

  const Fronts small = run_fronts(dir, "rho1e-5", {"bulk.rho=1e-5"});
  CHECK(small.code == 0);
  CHECK(number(small, "/branch@c_min") == Approx(11.305063851170592).epsilon(1e-12));
}

TEST_CASE("fronts verb: the front at the scene's sigma_d is solved and reported, or its absence", "[fronts][cli]") {
  // The branch is a property of the interface and bulk (continued from sigma_d = 0.8 whatever the scene's);
  // the scene's sigma_d is used for its own front: at 0.5 it is profile 0, c = 61.474837 (docs/fronts.md §5,
  // 1e-7); at 0.2 (below sigma_c^d = 0.2166) there is none, and the file and the summary say why. Either way
  // the branch is the same, so the status is complete.
  const TempDir dir("fronts-scene");
  const Fronts at = run_fronts(dir, "half", {});
  CHECK(at.code == 0);
  CHECK(number(at, "/branch@scene_sigma_d") == 0.5);
  CHECK(number(at, "/branch@c_at_scene_sigma_d") == Approx(61.474837).epsilon(1e-7));
  CHECK(number(at, "/profiles/0@c") == number(at, "/branch@c_at_scene_sigma_d"));
  CHECK(number(at, "/profiles/0@sigma_d") == 0.5);
  CHECK(text(at, "/branch@scene_front") == "converged");
  CHECK(at.out.find("at the scene's sigma_d = 0.5: c = 61.4748 ± ") != std::string::npos);  // with its estimate
  CHECK(number(at, "/branch@c_at_scene_sigma_d_error") > 0.0);
  CHECK(number(at, "/branch@c_at_scene_sigma_d_error") < 1e-6);  // the 1D mesh: ~1e-9 (docs/fronts.md §3)
  CHECK(number(at, "/branch@rtol_met") == 1.0);

  const Fronts below = run_fronts(dir, "below", {"drive.sigma_d=0.2"});
  CHECK(below.code == 0);
  CHECK(text(below, "/meta@status") == "complete");
  CHECK(std::isnan(number(below, "/branch@c_at_scene_sigma_d")));
  CHECK(text(below, "/branch@scene_front").find("no_front_state: sigma_d = 0.2 outside (sigma_c^d, 1)") != std::string::npos);
  CHECK(below.out.find("at the scene's sigma_d = 0.2: no steady front (no_front_state") != std::string::npos);
  CHECK(number(below, "/profiles/0@sigma_d") != 0.2);  // profile 0 is then the first along the branch
  CHECK(number(below, "/branch@c_min") == number(at, "/branch@c_min"));
}

TEST_CASE("fronts verb: SIGINT writes a readable file with status interrupted and exits 130", "[fronts][cli]") {
  // With --scaling the verb runs about 5 s; SIGINT after 1.5 s stops it at the next solve (StopSignals, as
  // `run`): exit 130 within 5 s of the signal, /meta status interrupted with what was stopped, the partial
  // results readable. (On a quiet machine the branch is done by then and the scaling study is partial.)
  const TempDir dir("fronts-sigint");
  const fs::path out = dir.path / "out";
  const auto child = slipfront::testing::spawn({SLIPFRONT_BINARY, "fronts", paper_scene, "--scaling", "--out", out.string()},
                                               dir.path, dir.path / "stdout.txt", dir.path / "stderr.txt");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto sent = std::chrono::steady_clock::now();
  REQUIRE(::kill(child.pid, SIGINT) == 0);
  const int code = slipfront::testing::wait_for(child, 60);
  const double stop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  const std::string err = slipfront::testing::slurp(child.err_path);
  INFO(err);
  CHECK(code == 130);
  CHECK(stop_seconds < 5.0);
  REQUIRE(fs::exists(out / "fronts.h5"));
  const auto file = slipfront::testing::read_h5(out / "fronts.h5");
  CHECK(file.strings.at("/meta@status") == "interrupted");
  CHECK(file.strings.at("/meta@message").find("stopped on request") != std::string::npos);
  CHECK(err.find("partial results written to") != std::string::npos);
  CHECK(slipfront::testing::slurp(child.out_path).find("steady fronts interrupted") != std::string::npos);
}

TEST_CASE("fronts verb: a strip scene (bulk.height) gives the strip's branch, c_min against the 1D line and u(xi, y)",
          "[fronts][cli][strip]") {
  // configs/steady_front_strip.toml (H = 16, mu' = 300, rho' = 0.01) on a small mesh (4 rows, 200 intervals):
  // the branch ends at the saddle-node with c_min = 43.7668 (16 rows, 400 intervals: 43.7681, docs/fronts.md
  // §10.7), 3e-4 above the 1D c_min of mu = mu' H (43.7537); the front at the scene's sigma_d = 0.5 is
  // profile 0 (c = 144.536); every profile carries the rows y and u(xi, y) on xi × y, whose lift at the far
  // end behind is the uniform strain sigma_d y/mu' (0.5 * 16/300 at the top).
  const TempDir dir("fronts-strip");
  const std::string scene = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/steady_front_strip.toml";
  const auto o = slipfront::testing::run(
      {SLIPFRONT_BINARY, "fronts", scene, "--out", (dir.path / "s").string(), "--rows", "4", "--intervals", "200"}, dir.path);
  INFO(o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "s" / "fronts.h5");
  CHECK(f.strings.at("/meta@status") == "complete");
  CHECK(f.strings.at("/branch@end") == "saddle_node");
  CHECK(f.numbers.at("/branch@height") == 16.0);
  CHECK(f.numbers.at("/branch@mu_strip") == Approx(300.0).epsilon(1e-12));
  CHECK(f.numbers.at("/branch@c_min") == Approx(43.7668).epsilon(1e-4));
  CHECK(f.numbers.at("/branch@c_min_1d") == Approx(43.7537).epsilon(1e-4));
  CHECK(f.numbers.at("/branch@c_min_over_1d") > 1.0);
  CHECK(f.numbers.at("/branch@c_min_over_1d") < 1.001);
  CHECK(f.numbers.at("/branch@c_min_at_end") == 1.0);
  CHECK(f.numbers.at("/branch@ell_kappa") == Approx(300.0 * 8.0 / (0.1 * 1.05)).epsilon(1e-12));
  REQUIRE(f.datasets.count("/branch/c") == 1);
  CHECK(f.datasets.at("/branch/c").size() > 20);
  CHECK(f.datasets.at("/branch/sigma_d").front() == 0.8);
  CHECK(f.numbers.at("/profiles/0@sigma_d") == 0.5);
  CHECK(f.numbers.at("/profiles/0@c") == Approx(144.536).epsilon(1e-5));
  for (int k = 0; f.datasets.count("/profiles/" + std::to_string(k) + "/xi"); ++k) {
    const std::string p = "/profiles/" + std::to_string(k);
    INFO(p);
    const auto& xi = f.datasets.at(p + "/xi");
    const auto& y = f.datasets.at(p + "/y");
    const auto& u = f.datasets.at(p + "/u_xy");
    const auto& lift = f.datasets.at(p + "/lift_xy");
    REQUIRE(y.size() == 5);
    CHECK(y.front() == 0.0);
    CHECK(y.back() == Approx(16.0).epsilon(1e-14));
    REQUIRE(u.size() == xi.size() * y.size());
    REQUIRE(lift.size() == u.size());
    CHECK(u[0] == f.datasets.at(p + "/u")[0]);  // row 0 is the interface
    const double sd = f.numbers.at(p + "@sigma_d");
    CHECK(lift[y.size() - 1] == Approx(sd * 16.0 / 300.0).epsilon(1e-6));  // far behind, top row
    CHECK(f.datasets.count(p + "/tau") == 1);
  }
  CHECK(o.out.find("c_min / c_min(1D, mu = mu' H) = 1.0003") != std::string::npos);
}
