// `slipfront fronts` on an in-plane scene (bulk.body = "inplane", docs/fronts.md §11.6; issue 39 item 1): the in-plane
// solver's branch to its end, c_min against the 1D c_min of mu = E'H, every speed with its estimate, profiles with
// u_x, u_y and the interface normal stress, and a scene sigma_d whose front would be supershear reported as such (not a
// failure). Runs the real binary on configs/steady_front_inplane.toml (the paper's column on H = 4). Before issue 39
// the verb refused an in-plane scene.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using slipfront::testing::TempDir;

namespace {
const std::string inplane_scene = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/steady_front_inplane.toml";
}

TEST_CASE("inplane fronts verb: the branch, c_min against the 1D c_min of mu = E'H, u_x, u_y and sigma_yy",
          "[fronts][cli][inplane]") {
  // 4 rows, 200 intervals (measured: 21 s of wall time, 8.5 s of CPU under a load of 11): the branch starts at
  // sigma_d = 0.683 (c = 89.80; at 0.8 the front would be above c_s = 100) and ends at the saddle-node with
  // c_min = 11.29470 (1D: 11.28108, ratio 1.0012); the scene's front at 0.5 runs at 60.9079 ± 0.037.
  const TempDir dir("fronts-inplane");
  const auto o = slipfront::testing::run(
      {SLIPFRONT_BINARY, "fronts", inplane_scene, "--out", (dir.path / "s").string(), "--rows", "4", "--intervals", "200"},
      dir.path);
  INFO(o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "s" / "fronts.h5");
  CHECK(f.strings.at("/meta@status") == "complete");
  CHECK(f.strings.at("/branch@end") == "saddle_node");
  CHECK(f.numbers.at("/branch@shear_speed") == Approx(100.0).epsilon(1e-12));
  CHECK(f.numbers.at("/branch@pressure_speed") == Approx(200.0).epsilon(1e-12));
  CHECK(f.numbers.at("/branch@rayleigh_speed") == Approx(93.2526).epsilon(1e-5));
  CHECK(f.numbers.at("/branch@plate_speed") == Approx(173.205).epsilon(1e-5));
  CHECK(f.numbers.at("/branch@mu_strip") == Approx(25.0).epsilon(1e-12));  // mu (1 - nu)/(2H)
  CHECK(f.numbers.at("/branch@c_min") == Approx(11.29470).epsilon(1e-5));
  CHECK(f.numbers.at("/branch@c_min_1d") == Approx(11.28108382).epsilon(1e-8));
  CHECK(f.numbers.at("/branch@c_min_over_1d") > 1.0);
  CHECK(f.numbers.at("/branch@c_min_over_1d") < 1.002);
  CHECK(f.numbers.at("/branch@c_min_error") > 0.0);
  CHECK(f.numbers.at("/branch@rtol_met") == 1.0);
  const auto& sd = f.datasets.at("/branch/sigma_d");
  const auto& c = f.datasets.at("/branch/c");
  CHECK(sd.front() == Approx(0.6833257569).epsilon(1e-9));  // 0.8 retried: sigma_c + (0.8 - sigma_c) 0.8
  for (double ci : c) CHECK(ci < 100.0);
  CHECK(f.numbers.at("/profiles/0@sigma_d") == 0.5);
  CHECK(f.numbers.at("/profiles/0@c") == Approx(60.9079).epsilon(1e-5));
  int profiles = 0;
  for (int k = 0; f.datasets.count("/profiles/" + std::to_string(k) + "/xi"); ++k, ++profiles) {
    const std::string p = "/profiles/" + std::to_string(k);
    INFO(p);
    const auto& xi = f.datasets.at(p + "/xi");
    const auto& y = f.datasets.at(p + "/y");
    const auto& uy = f.datasets.at(p + "/uy_xy");
    const auto& lift = f.datasets.at(p + "/lift_xy");
    const auto& syy = f.datasets.at(p + "/sigma_yy");
    REQUIRE(y.size() == 5);
    REQUIRE(uy.size() == xi.size() * y.size());
    REQUIRE(syy.size() == xi.size());
    for (std::size_t i = 0; i < xi.size(); ++i) CHECK(uy[i * y.size()] == 0.0);  // u_y = 0 on the interface
    CHECK(std::abs(syy.front()) < 1e-6);  // far behind: sigma_yy = -p = 0
    const double s = f.numbers.at(p + "@sigma_d");
    CHECK(lift[y.size() - 1] == Approx(s * 4.0 / 25.0).epsilon(1e-6));  // far behind, top row: sigma_d H/mu'
    CHECK(std::isfinite(f.numbers.at(p + "@c_error")));
  }
  CHECK(profiles == 7);  // the scene's front, five along the branch (below its first front), the limiting front
  CHECK(o.out.find("in-plane: nu = 0.333333, c_R = 93.2526, c_s = 100") != std::string::npos);
  CHECK(o.out.find("c_min / c_min(1D, mu = E'H) = 1.0012") != std::string::npos);
}

TEST_CASE("inplane fronts verb: a supershear scene sigma_d is reported, not failed, and --scaling collapses on mu = E'H",
          "[fronts][cli][inplane]") {
  // sigma_d = 0.9: the 1D front of mu = E'H runs at 121 > c_s = 100; the in-plane solver does not solve supershear
  // fronts (docs/fronts.md §11.2). 2 rows, 100 intervals: the branch and the verdict as usual, the scene's front named.
  // --scaling (mu with rho, alpha, eta, kappa at 0.5 … 4 times): measured prefactor 0.5757 over 16 of 16 points, largest
  // deviation 5.45 %, exponents 0.496, 0.553, -0.497, -0.470 (the 1D prefactor 0.576, docs/fronts.md §6).
  const TempDir dir("fronts-inplane-super");
  const auto o = slipfront::testing::run({SLIPFRONT_BINARY, "fronts", inplane_scene, "--out", (dir.path / "s").string(),
                                          "--rows", "2", "--intervals", "100", "--set", "drive.sigma_d=0.9", "--scaling"},
                                         dir.path);
  INFO(o.err);
  REQUIRE(o.code == 0);
  const auto f = slipfront::testing::read_h5(dir.path / "s" / "fronts.h5");
  CHECK(f.strings.at("/meta@status") == "complete");
  CHECK(std::isnan(f.numbers.at("/branch@c_at_scene_sigma_d")));
  CHECK(f.strings.at("/branch@scene_front").find("supershear in-plane fronts are not solved") != std::string::npos);
  CHECK(f.strings.count("/branch@profiles_failed") == 0);
  CHECK(o.out.find("no steady front (not solved: the 1D front of mu = E'H at sigma_d = 0.9 runs at") != std::string::npos);
  CHECK(o.out.find("sqrt(mu alpha/(eta kappa)), mu = E'H, fitted to 16 of 16 points") != std::string::npos);
  const auto& prefactor = f.datasets.at("/scaling/fits/prefactor");
  CHECK(prefactor.back() == Approx(0.5757).epsilon(2e-3));
  const auto& exponent = f.datasets.at("/scaling/fits/exponent");
  for (std::size_t k = 0; k < 4; ++k) CHECK(std::abs(std::abs(exponent[k]) - 0.5) < 0.06);
}
