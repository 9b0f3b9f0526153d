// Strip fronts in time (issue 20 item 3, docs/fronts.md §10.15): the time-dependent strip run started from the
// solved strip front (drive.start = steady_front on a scene with bulk.height: u and v of every row from the
// front solved on the scene's own rows, rear traction μ v_b/c) keeps the solved speed, and its interface
// fields stay on the traveling profile.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "compare/initial.hpp"
#include "compare/runner.hpp"
#include "continuum/strip_front.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

/// Homogeneous loading at σ_d on the strip of height H (paper material, μ = 300 and ρ = 0.01 integrated over
/// the height), grid dx, dy, started from the solved strip front, tip at 100 on [0, 400], run until the tip
/// has run `travel` length units, continuum alone (explicit).
compare::Scene strip_front_scene(double H, double sigma_d, double dx, double dy, double travel, double c_guess) {
  compare::Scene s = testing::homogeneous_scene(sigma_d, 0.0, 1.0);
  s.name = "strip_front_run";
  s.models = {"continuum"};
  s.bulk.height = H;
  s.bulk.length = 400.0;
  s.grid.dx = dx;
  s.grid.dy = dy;
  s.drive.start = "steady_front";
  s.drive.front_x = 100.0;
  s.time.t_end = travel / c_guess;
  s.measure.behind_tip_fraction = 0.7;
  s.output.snapshot_dt = s.time.t_end;  // t = 0 and the end
  s.output.series_dt = 0.05;
  return s;
}

struct StripRun {
  double c_solved = 0.0, gap = 0.0;  // gap: c_front/c − 1
  double profile_error = 0.0;        // max |v − v_front(x − tip)| / v_tip over [tip − 150, tip + 20] at the end
                                     // (tip: the measured tip less its offset at t = 0)
  double area_error = 0.0;           // the same for A (absolute), at that shift
  double shift = 0.0;                // the best shift of the profile from the solved position
  double seconds = 0.0;
};

StripRun run_strip_front(double H, double sigma_d, double dx, double dy, double travel, double kick = 0.0) {
  compare::Scene s = strip_front_scene(H, sigma_d, dx, dy, travel, 1.0);
  s.drive.kick_dv = kick;
  const auto front = compare::front_start(s);  // the same solve the run makes
  REQUIRE(front);
  REQUIRE(front->strip);
  s.time.t_end = travel / front->c;
  s.output.snapshot_dt = s.time.t_end;
  s.validate();
  const auto t0 = std::chrono::steady_clock::now();
  auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  INFO(out[0].message);
  REQUIRE(out[0].status == compare::RunStatus::complete);
  const auto& r = out[0];
  StripRun res;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.c_solved = r.scalars.at("steady_front_c");
  CHECK(res.c_solved == front->c);
  res.gap = r.events.c_front / res.c_solved - 1.0;
  // the interface at the end against the front at the measured tip
  const std::size_t nx = r.x.size();
  const auto& v = r.snapshots.at("v");
  const auto& A = r.snapshots.at("A");
  REQUIRE(v.size() >= 2 * nx);
  // the front's tip at the end: the solved position front_x + c t moved by the best shift δ (|δ| ≤ 3, steps of
  // 0.01) of the profile onto the run's v (max norm over [tip − 150, tip + 20])
  const double tip0 = s.drive.front_x + res.c_solved * s.time.t_end;
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < nx; ++i)
    if (r.x[i] >= tip0 - 150.0 && r.x[i] <= tip0 + 20.0) idx.push_back(i);
  res.profile_error = 1e300;
  for (int k = -300; k <= 300; ++k) {
    const double d = 0.01 * k;
    std::vector<double> xi;
    for (auto i : idx) xi.push_back(r.x[i] - tip0 - d);
    const auto f = continuum::sample_strip_interface(*front->strip, xi);
    double ev = 0.0, ea = 0.0;
    for (std::size_t m = 0; m < idx.size(); ++m) {
      ev = std::max(ev, std::abs(v[v.size() - nx + idx[m]] - f.slip_rate[m]) / front->v_tip);
      ea = std::max(ea, std::abs(A[A.size() - nx + idx[m]] - f.area[m]));
    }
    if (ev < res.profile_error) {
      res.profile_error = ev;
      res.area_error = ea;
      res.shift = d;
    }
  }
  std::printf("strip front run H = %g, sigma_d = %g, dx = %g, dy = %g, kick %g: c = %.6f, c_front/c - 1 = %+.3e, "
              "profile v %.3e, A %.3e, shift %.2f, %.2f s\n",
              H, sigma_d, dx, dy, kick, res.c_solved, res.gap, res.profile_error, res.area_error, res.shift, res.seconds);
  return res;
}

}  // namespace

TEST_CASE("strip front runs: the sampled front is the solved front at its nodes and matches the strip's rows",
          "[strip][fronts]") {
  // sample_strip_front at the front's own nodes returns its stored u(ξ, y_j) and −c ∂ξ u; ahead of the tip the
  // modes tend to the stuck state (u_j → σ_d/α + σ_d y_j/μ', v → 0), beyond −L every row moves at v_b.
  compare::Scene s = strip_front_scene(2.0, 0.5, 0.5, 0.5, 100.0, 60.0);
  const auto o = compare::strip_start_options(s);
  CHECK(o.rows == 4);
  const auto f = continuum::solve_strip_front(s.interface, s.bulk, 0.5, o);
  REQUIRE(f.status == continuum::FrontStatus::converged);
  REQUIRE(f.y.size() == 5);
  for (std::size_t j = 0; j < f.y.size(); ++j) CHECK(f.y[j] == Approx(0.5 * static_cast<double>(j)).margin(1e-12));
  const auto at = continuum::sample_strip_front(f, f.xi);
  const std::size_t ro = f.y.size();
  double err_u = 0.0, err_v = 0.0;
  for (std::size_t i = 0; i < f.xi.size(); ++i)
    for (std::size_t j = 0; j < ro; ++j) {
      err_u = std::max(err_u, std::abs(at.u[i * ro + j] - f.u_at(i, j)));
      err_v = std::max(err_v, std::abs(at.velocity[i * ro + j] + f.c * f.strain[i * ro + j]));
    }
  CHECK(err_u < 1e-9);
  CHECK(err_v < 1e-9);
  const std::vector<double> far = {40.0 / f.slowest_ahead, -f.domain_length - 50.0};  // e^{-40} ahead
  const auto fs = continuum::sample_strip_front(f, far);
  const double mu_s = s.bulk.mu / s.bulk.height;
  for (std::size_t j = 0; j < ro; ++j) {
    CHECK(fs.u[j] == Approx(0.5 / s.interface.alpha + 0.5 * f.y[j] / mu_s).epsilon(1e-9));
    CHECK(std::abs(fs.velocity[j]) < 1e-9);
    CHECK(fs.velocity[ro + j] == f.v_behind);
  }
}

TEST_CASE("strip front runs: started from the solved strip front, the front keeps its speed", "[strip][fronts]") {
  // H = 2 (dy = 0.5, 5 rows) and H = 17 (dy = 1, 18 rows), σ_d = 0.3 and 0.5, dx = 0.5, 200 units of travel:
  // the measured speed (docs/model.md §3 c_front, fit behind_tip_fraction 0.7 of the run) within 0.5% of the
  // solved one (issue 20's bound; the 1D runs are within 0.2% at this dx, tests/test_steady_front_runs.cpp),
  // and at the end the interface's v within 0.5% of v_tip and A within 0.02 of the solved profile moved by its best
  // shift (|δ| < 0.5 of the solved position; measured: gaps −0.7e−3 … −1.1e−3, v 0.07–0.2%, A 0.3–0.9%,
  // δ −0.16 … −0.27, i.e. the gap × the travel).
  for (const auto& [H, dy] : {std::pair{2.0, 0.5}, std::pair{17.0, 1.0}})
    for (double sd : {0.3, 0.5}) {
      const auto r = run_strip_front(H, sd, 0.5, dy, 200.0);
      INFO("H = " << H << ", sigma_d = " << sd << ": gap " << r.gap << ", profile " << r.profile_error);
      CHECK(std::abs(r.gap) < 5e-3);
      CHECK(r.profile_error < 5e-3);
      CHECK(r.area_error < 2e-2);
      CHECK(std::abs(r.shift) < 0.5);  // the tip has not wandered from the solved position by a grid spacing
    }
}

TEST_CASE("strip front runs: kicked strip fronts return to the branch", "[strip][fronts]") {
  // Issue 20 item 3: the 1D kicks of docs/fronts.md §8a on the strip of H = 17 (dy = 1, dx = 0.5): a slip-rate
  // kick drive.kick_dv of -0.5 or +2 over 20 length units behind the tip (interface row) at t = 0, 200 units of
  // travel. A stable front returns to the branch: its fitted speed (the last 0.7 of the run) equals the unkicked
  // run's within 1e-3 (1D: within 1.6e-4), and its profile at the end is the solved one as unkicked (v within
  // 0.5 % of v_tip). An unstable part of the branch would drift away from the unkicked speed.
  for (double sd : {0.3, 0.5}) {
    const auto plain = run_strip_front(17.0, sd, 0.5, 1.0, 200.0);
    for (double kick : {-0.5, 2.0}) {
      const auto r = run_strip_front(17.0, sd, 0.5, 1.0, 200.0, kick);
      INFO("sigma_d = " << sd << ", kick " << kick << ": gap " << r.gap << " (unkicked " << plain.gap << ")");
      CHECK(std::abs((1.0 + r.gap) / (1.0 + plain.gap) - 1.0) < 1e-3);
      CHECK(r.profile_error < 5e-3);
    }
  }
}

TEST_CASE("strip front runs: no strip front to start from is refused naming sigma_d", "[strip][fronts]") {
  compare::Scene s = strip_front_scene(2.0, 0.2, 0.5, 0.5, 100.0, 10.0);  // below sigma_c^d = 0.2166
  s.validate();
  const auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  CHECK(out[0].status == compare::RunStatus::failed);
  CHECK(out[0].message.find("drive.sigma_d") != std::string::npos);
  CHECK(out[0].message.find("strip") != std::string::npos);
}
