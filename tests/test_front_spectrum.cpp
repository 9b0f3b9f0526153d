// The spectrum of fronts against the wave speeds (issue 39 item 4, docs/fronts.md §12): the peak tip speed
// (compare::peak_tip_speed, the one function behind c_transient_peak and the front_spectrum study's c_peak) on
// synthetic tips with a known peak, the homogeneous run's c_peak from its series (the far end's zone and a healed
// tip left out), the bodies' wave speeds against closed forms, and the study's table and scalars on synthetic runs.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "compare/peak_speed.hpp"
#include "studies/front_spectrum.hpp"

using namespace slipfront;

namespace {

// A tip at speed c0 with a burst at speed c1 over [t1, t2]: x(t) = x0 + c0 t + (c1 − c0) |[0, t] ∩ [t1, t2]|.
struct Burst {
  double x0 = 150.0, c0 = 50.0, c1 = 150.0, t1 = 2.0, t2 = 3.0;
  double x(double t) const { return x0 + c0 * t + (c1 - c0) * std::clamp(std::min(t, t2) - t1, 0.0, t2 - t1); }
};

void sample(const Burst& b, double dt, double t_end, std::vector<double>& t, std::vector<double>& x) {
  for (int k = 0; k * dt <= t_end + 1e-12; ++k) {
    t.push_back(k * dt);
    x.push_back(b.x(k * dt));
  }
}

compare::Scene inplane_scene() {
  compare::Scene s;
  s.bulk = core::BulkParams(0.01, 300.0, 1000.0, 17.0);
  s.bulk.body_name = "inplane";
  s.bulk.poisson = 1.0 / 3.0;
  s.drive.loading = core::Loading::homogeneous;
  s.drive.sigma_d = 0.9;
  return s;
}

}  // namespace

TEST_CASE("peak_tip_speed finds a burst's speed, where it starts, and nothing from too short a series") {
  const Burst b;
  std::vector<double> t, x;
  sample(b, 0.05, 6.0, t, x);
  const auto p = compare::peak_tip_speed(t, x, 0.5);
  CHECK(p.c == Approx(150.0).epsilon(1e-12));  // windows inside [2, 3] run at the burst's speed
  CHECK(p.t >= 2.0 - 1e-9);
  CHECK(p.t <= 2.5 + 1e-9);
  CHECK(p.x == Approx(b.x(p.t)).epsilon(1e-12));
  // a window longer than the burst averages it: (c1 · 1 + c0 · 1)/2 over 2 time units
  CHECK(compare::peak_tip_speed(t, x, 2.0).c == Approx(100.0).epsilon(1e-12));
  // no pair of samples 0.5 apart: NaN
  const std::vector<double> t1{0.0, 0.2}, x1{0.0, 10.0};
  CHECK(std::isnan(compare::peak_tip_speed(t1, x1, 0.5).c));
}

TEST_CASE("front_peak_speed leaves out the far end's zone and stops where the tip is lost") {
  // speed 80 from x = 150 until x = 900, then 400 (the tip racing to the free end); x_end = 950 - 50 = 900
  compare::ModelResult r;
  auto& ts = r.series["t"];
  auto& tip = r.series["tip_x"];
  for (int k = 0; k < 3; ++k) { ts.push_back(-0.15 + 0.05 * k); tip.push_back(std::nan("")); }  // no tip yet
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.05 * k, xs = 150.0 + 80.0 * t;
    ts.push_back(t);
    tip.push_back(xs <= 900.0 ? xs : 900.0 + 400.0 * (t - 750.0 / 80.0));
  }
  const auto p = studies::front_peak_speed(r, 900.0, 0.5);
  CHECK(p.c == Approx(80.0).epsilon(1e-9));            // not the race to the end
  CHECK(studies::front_peak_speed(r, 2000.0, 0.5).c > 300.0);  // which is there when the zone is not left out
  // a tip that heals (NaN) and a second one later: only the first run counts
  compare::ModelResult h;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.05 * k;
    h.series["t"].push_back(t);
    h.series["tip_x"].push_back(k < 40 ? 150.0 + 30.0 * t : k < 60 ? std::nan("") : 150.0 + 500.0 * t);
  }
  CHECK(studies::front_peak_speed(h, 900.0, 0.5).c == Approx(30.0).epsilon(1e-9));
}

TEST_CASE("wave_speeds: the in-plane strip's c_s, c_p, c_R and the antiplane strip's c_s (docs/model.md §9.1, §10.2)") {
  // in-plane, mu = E'H = 300, rho = 0.01, H = 17, nu = 1/3: mu' = mu (1 - nu)/(2H), rho' = rho/H
  const auto s = inplane_scene();
  const auto w = studies::wave_speeds(s.bulk);
  const double mu_p = 300.0 * (2.0 / 3.0) / 34.0, rho_p = 0.01 / 17.0;
  CHECK(w.c_s == Approx(std::sqrt(mu_p / rho_p)).epsilon(1e-12));
  CHECK(w.c_s == Approx(100.0).epsilon(1e-12));
  CHECK(w.c_p == Approx(2.0 * w.c_s).epsilon(1e-12));  // sqrt(2(1 - nu)/(1 - 2 nu)) = 2 at nu = 1/3
  CHECK(w.c_R / w.c_s == Approx(0.93253).margin(5e-6));  // docs/model.md §10.3
  // the antiplane twin: mu' H = 100 on the same H and rho
  const auto a = studies::wave_speeds(core::BulkParams(0.01, 100.0, 1000.0, 17.0));
  CHECK(a.c_s == Approx(100.0).epsilon(1e-12));
  CHECK(std::isnan(a.c_p));
  CHECK(std::isnan(a.c_R));
}

TEST_CASE("add_spectrum_speeds: each run's peak and settled speed over c_s, the stored energy and the gap") {
  // three runs on the in-plane body (c_s = 100): homogeneous at sigma_d = 0.9 with a burst to 150 and c_front = 120
  // (supershear), homogeneous at 0.5 at a steady 60, edge with c_transient_peak = 25, c_transient = 21
  std::vector<compare::Scene> scenes{inplane_scene(), inplane_scene(), inplane_scene()};
  scenes[1].drive.sigma_d = 0.5;
  scenes[2].drive.loading = core::Loading::edge;
  scenes[2].drive.K = 10.0;
  std::vector<std::vector<compare::ModelResult>> res(3, std::vector<compare::ModelResult>(1));
  for (auto& r : res) r[0].model = "continuum";
  std::vector<double> t, x;
  sample(Burst{}, 0.05, 6.0, t, x);
  res[0][0].series["t"] = t;
  res[0][0].series["tip_x"] = x;
  res[0][0].events.c_front = 120.0;
  std::vector<double> x1;
  for (double ti : t) x1.push_back(150.0 + 60.0 * ti);
  res[1][0].series["t"] = t;
  res[1][0].series["tip_x"] = x1;
  res[1][0].events.c_front = 60.0;
  res[2][0].events.c_transient_peak = 25.0;
  res[2][0].events.c_transient = 21.0;
  res[2][0].events.t_hat = 1.025;
  res[2][0].series["t"] = t;
  for (double ti : t) res[2][0].series["drive_force"].push_back(2.0 * ti);
  std::vector<compare::StudyRun> runs(3);
  studies::StudyReport rep;
  studies::add_spectrum_speeds(rep, runs, scenes, res);
  const auto& tab = rep.tables.at("front_spectrum_speeds");
  CHECK(tab.at("c_peak_over_cs")[0] == Approx(1.5).epsilon(1e-12));
  CHECK(tab.at("c_settled_over_cs")[0] == Approx(1.2).epsilon(1e-12));
  CHECK(tab.at("c_peak_over_cs")[1] == Approx(0.6).epsilon(1e-12));
  CHECK(tab.at("c_peak_over_cs")[2] == Approx(0.25).epsilon(1e-12));
  CHECK(tab.at("c_settled_over_cs")[2] == Approx(0.21).epsilon(1e-12));
  CHECK(tab.at("drive_force_at_t_hat")[2] == Approx(2.05).epsilon(1e-12));
  CHECK(std::isnan(tab.at("stored_energy")[2]));
  // the stuck state's energy per length: sigma_d^2 (H/(2 mu') + 1/(2 alpha)), H/(2 mu') = H^2/(mu (1 - nu)) in-plane
  const double alpha = scenes[0].interface.alpha;
  CHECK(tab.at("stored_energy")[0] == Approx(0.81 * (289.0 / 200.0 + 0.5 / alpha)).epsilon(1e-12));
  CHECK(rep.scalars.at("spectrum_c_s") == Approx(100.0).epsilon(1e-12));
  CHECK(rep.scalars.at("spectrum_c_p") == Approx(200.0).epsilon(1e-12));
  CHECK(rep.scalars.at("spectrum_max_peak_over_cs") == Approx(1.5).epsilon(1e-12));
  CHECK(rep.scalars.at("spectrum_supershear_runs") == 1.0);
  CHECK(rep.scalars.at("spectrum_fastest_subshear") == Approx(0.6).epsilon(1e-12));
  CHECK(rep.scalars.at("spectrum_slowest_supershear") == Approx(1.2).epsilon(1e-12));
  // bodies that differ: no common c_s
  scenes[1].bulk = core::BulkParams(0.01, 100.0, 1000.0, 17.0);
  scenes[1].bulk.mu = 400.0;
  studies::StudyReport rep2;
  studies::add_spectrum_speeds(rep2, runs, scenes, res);
  CHECK(std::isnan(rep2.scalars.at("spectrum_c_s")));
}
