// Steady fronts in time (docs/model.md §6, issue 11): the time-dependent solver started from the solved
// traveling wave (drive.start = steady_front, rear traction μ v_b/c) keeps the solved speed and leaves
// steady sliding behind it, a kicked front returns to the branch, and `slipfront fronts` writes the branch.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "compare/alongside.hpp"
#include "compare/fronts.hpp"
#include "compare/runner.hpp"
#include "continuum/friction_law.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

// Homogeneous loading at σ_d started from the solved front, tip at 100 on [0, 500], run until the tip
// has run 300 length units, continuum alone.
compare::ModelResult run_from_front(double sigma_d, double dx, double kick = 0.0) {
  compare::Scene s = testing::homogeneous_scene(sigma_d, 0.0, 1.0);
  s.models = {"continuum"};
  s.bulk.length = 500.0;
  s.grid.dx = dx;
  s.drive.start = "steady_front";
  s.drive.front_x = 100.0;
  s.drive.kick_dv = kick;
  s.time.t_end = 300.0 / compare::solved_front_speed(s, sigma_d);
  s.measure.behind_tip_fraction = 0.7;
  s.output.snapshot_dt = 0.0;
  s.output.series_dt = 0.1;
  s.validate();
  auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  REQUIRE(out[0].status == slipfront::compare::RunStatus::complete);
  return out[0];
}

}  // namespace

TEST_CASE("steady front runs: started from the solved front, the front keeps its speed, grid-converged", "[fronts]") {
  // At σ_d = 0.3 (below the nucleation limit) and 0.5: c_front within 0.2% of the solved c at dx = 0.5, the gap
  // halving (first order: the scheme's Θ switching) at dx = 0.25 (ratio in [1.6, 2.5]); far behind,
  // σ_ss(v_behind) = σ_d to 1e-3 (the rear traction keeps the whole slid region in steady sliding).
  const auto p = testing::paper_interface();
  for (double sd : {0.3, 0.5}) {
    const auto coarse = run_from_front(sd, 0.5), fine = run_from_front(sd, 0.25);
    const double c = coarse.scalars.at("steady_front_c");
    const double gap_coarse = coarse.events.c_front / c - 1.0, gap_fine = fine.events.c_front / c - 1.0;
    WARN("sigma_d " << sd << ": c_solved " << c << ", gap dx 0.5: " << gap_coarse << ", dx 0.25: " << gap_fine
                    << ", sigma_ss(v_behind) - sigma_d: " << coarse.scalars.at("sigma_ss_at_v_behind") - sd);
    CHECK(std::abs(gap_coarse) < 2e-3);
    CHECK(std::abs(gap_fine) < std::abs(gap_coarse));
    CHECK(gap_coarse / gap_fine > 1.6);
    CHECK(gap_coarse / gap_fine < 2.5);
    CHECK(std::abs(coarse.scalars.at("sigma_ss_at_v_behind") - sd) < 1e-3);
    CHECK(std::abs(continuum::steady_sliding(p, coarse.events.v_behind).sigma - sd) < 1e-3);
    CHECK(coarse.events.v_behind > continuum::steady_minimum_velocity(p));  // the strengthening branch
  }
}

TEST_CASE("steady front runs: a kicked front returns to the branch", "[fronts]") {
  // A slip-rate kick of +2 (about the slip rate behind) over 20 length units behind the tip at σ_d = 0.25: the
  // measured speed (middle half of the run) differs from the unkicked run's by less than 3e-4 — the front
  // returns to the branch (docs/model.md §6; the whole branch tried is stable, docs/fronts.md).
  const auto base = run_from_front(0.25, 0.5), kicked = run_from_front(0.25, 0.5, 2.0);
  const double c = base.scalars.at("steady_front_c");
  WARN("kick: " << kicked.events.c_front / c - 1.0 << ", unkicked " << base.events.c_front / c - 1.0);
  CHECK(std::abs(kicked.events.c_front - base.events.c_front) / c < 3e-4);
  CHECK(kicked.series.at("max_v") != base.series.at("max_v"));  // the kick did something
}

TEST_CASE("steady front runs: no front to start from is refused naming sigma_d", "[fronts]") {
  compare::Scene s = testing::homogeneous_scene(0.2, 0.0, 1.0);  // below sigma_c^d = 0.2166
  s.bulk.length = 100.0;
  s.drive.start = "steady_front";
  s.drive.front_x = 50.0;
  s.validate();
  const auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  CHECK(out[0].status == slipfront::compare::RunStatus::failed);
  CHECK(out[0].message.find("drive.sigma_d") != std::string::npos);
}

TEST_CASE("fronts verb: writes the branch to its end and its profiles", "[fronts][cli]") {
  // `slipfront fronts` on the homogeneous scene: exit 0, /branch ends at sigma_c^d with c_min = 11.28108
  // (docs/fronts.md, to 1e-6), c increasing with sigma_d along it, profiles present; a non-homogeneous scene
  // is refused with exit 2.
  testing::TempDir tmp("fronts");
  const std::string cfg = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/homogeneous_front.toml";
  REQUIRE(std::system((std::string(SLIPFRONT_BINARY) + " fronts " + cfg + " --out " + tmp.path.string() + " > /dev/null").c_str()) == 0);
  const std::string file = (tmp.path / "fronts.h5").string();
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  double c_min = 0.0, sd_min = 0.0;
  const hid_t b = H5Gopen2(f, "branch", H5P_DEFAULT);
  REQUIRE(b >= 0);
  for (auto [name, out] : {std::pair{"c_min", &c_min}, std::pair{"sigma_d_at_c_min", &sd_min}}) {
    const hid_t a = H5Aopen(b, name, H5P_DEFAULT);
    REQUIRE(a >= 0);
    REQUIRE(H5Aread(a, H5T_NATIVE_DOUBLE, out) >= 0);
    H5Aclose(a);
  }
  CHECK(c_min == Approx(11.28108382).epsilon(1e-6));
  CHECK(sd_min == Approx(continuum::steady_minimum_stress(testing::paper_interface())).epsilon(1e-6));
  auto read = [&](const char* name) {
    const hid_t d = H5Dopen2(b, name, H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(sp);
    H5Dclose(d);
    return v;
  };
  const auto sd = read("sigma_d"), c = read("c");
  REQUIRE(sd.size() >= 10);
  for (std::size_t k = 1; k < sd.size(); ++k) CHECK((sd[k] - sd[k - 1]) * (c[k] - c[k - 1]) > 0.0);
  CHECK(H5Lexists(f, "profiles/0/v", H5P_DEFAULT) > 0);
  H5Gclose(b);
  H5Fclose(f);
  const std::string edge = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1.toml";
  CHECK(WEXITSTATUS(std::system((std::string(SLIPFRONT_BINARY) + " fronts " + edge + " --out " + tmp.path.string() +
                                 " --force > /dev/null 2>&1").c_str())) == 2);
}
