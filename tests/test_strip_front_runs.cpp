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
#include "continuum/inplane_front.hpp"
#include "continuum/strip_front.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

/// Homogeneous loading at σ_d on the strip of height H (paper material, μ = 300 and ρ = 0.01 integrated over
/// the height), grid dx, dy, started from the solved strip front, tip at 100 on [0, 400], run until the tip
/// has run `travel` length units, continuum alone (explicit). `body`: "inplane" for the in-plane strip (ν = 1/3,
/// μ = E'H; docs/fronts.md §11.10), else the antiplane strip.
compare::Scene strip_front_scene(double H, double sigma_d, double dx, double dy, double travel, double c_guess,
                                 const std::string& body = "") {
  compare::Scene s = testing::strip_front_start_scene(H, sigma_d, dx, dy, body);
  s.name = "strip_front_run";
  s.time.t_end = travel / c_guess;
  s.output.snapshot_dt = s.time.t_end;  // t = 0 and the end
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

StripRun run_strip_front(double H, double sigma_d, double dx, double dy, double travel, double kick = 0.0,
                         const std::string& body = "") {
  compare::Scene s = strip_front_scene(H, sigma_d, dx, dy, travel, 1.0, body);
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
  std::printf("%s front run H = %g, sigma_d = %g, dx = %g, dy = %g, kick %g: c = %.6f, c_front/c - 1 = %+.3e, "
              "profile v %.3e, A %.3e, shift %.2f, %.2f s\n",
              body == "inplane" ? "in-plane" : "strip", H, sigma_d, dx, dy, kick, res.c_solved, res.gap, res.profile_error,
              res.area_error, res.shift, res.seconds);
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

// ---------------------------------------------------------------------------------------------------
// The in-plane strip (issue 39 items 1 and 2, docs/fronts.md §11.10): the same start on the in-plane front.

TEST_CASE("in-plane front runs: the sampled front is the solved front at its nodes, both components",
          "[inplane][fronts]") {
  // sample_inplane_front at the front's own nodes returns its stored u_x, u_y and −c ∂ξ of both; ahead of the tip the
  // modes tend to the stuck state (u_x,j → σ_d/α + σ_d y_j/μ', u_y → 0 without a normal load, v → 0); beyond −L u_x
  // of every row moves at v_b and u_y rests at its value at −L; the interface fields from the two sides of the tip
  // meet (the tip state lies on the modes ahead: continuity at ξ = 0 to the solver's tolerance).
  compare::Scene s = strip_front_scene(2.0, 0.5, 0.5, 0.5, 100.0, 60.0, "inplane");
  const auto o = compare::strip_start_options(s);
  CHECK(o.rows == 4);
  const auto f = continuum::solve_strip_front(s.interface, s.bulk, 0.5, o);
  REQUIRE(f.status == continuum::FrontStatus::converged);
  REQUIRE(f.y.size() == 5);
  REQUIRE(f.uy.size() == f.u.size());
  const auto at = continuum::sample_inplane_front(f, f.xi);
  const std::size_t ro = f.y.size();
  double err_u = 0.0, err_v = 0.0, err_uy = 0.0, err_vy = 0.0, size_uy = 0.0;
  for (std::size_t i = 0; i < f.xi.size(); ++i)
    for (std::size_t j = 0; j < ro; ++j) {
      const std::size_t k = i * ro + j;
      err_u = std::max(err_u, std::abs(at.x.u[k] - f.u_at(i, j)));
      err_v = std::max(err_v, std::abs(at.x.velocity[k] + f.c * f.strain[k]));
      err_uy = std::max(err_uy, std::abs(at.uy[k] - f.uy[k]));
      err_vy = std::max(err_vy, std::abs(at.uy_velocity[k] + f.c * f.uy_strain[k]));
      size_uy = std::max(size_uy, std::abs(f.uy[k]));
    }
  CHECK(err_u < 1e-9);
  CHECK(err_v < 1e-9);
  CHECK(err_uy < 1e-12);
  CHECK(err_vy < 1e-9);
  CHECK(size_uy > 1e-4);  // u_y is not trivially zero: the front lifts the strip (σ_yy varies with slip)
  // sample_strip_front on an in-plane front is its u_x part
  const auto sx = continuum::sample_strip_front(f, f.xi);
  CHECK(sx.u == at.x.u);
  const std::vector<double> far = {40.0 / f.slowest_ahead, -f.domain_length - 50.0, 1e-9, -1e-9};
  const auto fs = continuum::sample_inplane_front(f, far);
  const double mu_s = s.bulk.mu * (1.0 - s.bulk.poisson) / (2.0 * s.bulk.height);  // μ' = μ(1 − ν)/(2H)
  for (std::size_t j = 0; j < ro; ++j) {
    CHECK(fs.x.u[j] == Approx(0.5 / s.interface.alpha + 0.5 * f.y[j] / mu_s).epsilon(1e-9));
    CHECK(std::abs(fs.x.velocity[j]) < 1e-9);
    CHECK(std::abs(fs.uy[j]) < 1e-9);
    CHECK(fs.x.velocity[ro + j] == f.v_behind);
    CHECK(fs.uy[ro + j] == f.uy[j]);
    CHECK(fs.uy_velocity[ro + j] == 0.0);
  }
  CHECK(fs.x.interface.slip_rate[2] == Approx(fs.x.interface.slip_rate[3]).epsilon(1e-6));
  CHECK(fs.x.interface.sigma_bar[2] == Approx(fs.x.interface.sigma_bar[3]).epsilon(1e-6));
}

TEST_CASE("in-plane front runs: started from the solved in-plane front, the front keeps its speed (cheap case)",
          "[inplane][fronts]") {
  // Issue 39's test, its cheap case in the default tier (the four cases: test_slow_strip_front_runs.cpp): H = 2
  // (dy = 0.5, 5 rows, two components), σ_d = 0.5, dx = 0.5, 200 units of travel, explicit: the measured speed
  // (c_front, fit over the last 0.7 of the run) within 0.5 % of the solved one, the interface's v within 0.5 % of
  // v_tip and A within 0.02 of the solved profile moved by its best shift (|δ| < 0.5). Measured (2026-11-27): gap
  // −9.25e−4, v 1.1e−3, A 2.6e−3, δ −0.20; ~3 s of CPU.
  const auto r = run_strip_front(2.0, 0.5, 0.5, 0.5, 200.0, 0.0, "inplane");
  INFO("gap " << r.gap << ", profile " << r.profile_error);
  CHECK(std::abs(r.gap) < 5e-3);
  CHECK(r.profile_error < 5e-3);
  CHECK(r.area_error < 2e-2);
  CHECK(std::abs(r.shift) < 0.5);
}

TEST_CASE("in-plane front runs: no in-plane front to start from is refused naming sigma_d", "[inplane][fronts]") {
  // below σ_c^d (no sliding state behind), and at σ_d = 0.8, whose front would run above c_s = 100 (docs/fronts.md
  // §11.2: supershear in-plane fronts are not solved)
  for (const double sd : {0.2, 0.8}) {
    compare::Scene s = strip_front_scene(2.0, sd, 0.5, 0.5, 100.0, 10.0, "inplane");
    s.validate();
    const auto out = compare::run_scene(s, {});
    REQUIRE(out.size() == 1);
    INFO(out[0].message);
    CHECK(out[0].status == compare::RunStatus::failed);
    CHECK(out[0].message.find("drive.sigma_d") != std::string::npos);
    CHECK(out[0].message.find("in-plane strip") != std::string::npos);
  }
}
