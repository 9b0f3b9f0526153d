// Slow tier (ctest label "slow"): the longer convergence and budget studies of the continuum scheme
// (docs/numerics.md). Each case runs 20–60 s in Release on one core.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "compare/runner.hpp"
#include "scenes.hpp"

namespace compare = slipfront::compare;
namespace testing = slipfront::testing;

namespace {

double rel_err(double a, double b) { return std::abs(a - b) / std::abs(b); }

compare::ModelResult run_fig1(double dx, double dt, double T, double snapshot_dt, bool energy = false) {
  auto s = testing::fig1_scene();
  s.grid.dx = dx;
  s.time.dt = dt;
  s.time.t_end = T;
  s.output.snapshot_dt = snapshot_dt;
  s.output.series_dt = snapshot_dt > 0 ? snapshot_dt : 0.05;
  s.output.energy = energy;
  const auto r = testing::run_continuum(s);
  REQUIRE(r.status == slipfront::compare::RunStatus::complete);
  return r;
}

std::vector<double> last_row(const compare::ModelResult& r, const char* f) {
  const auto row = testing::snapshot_row(r, f, r.snapshot_t.size() - 1);
  return {row.begin(), row.end()};
}

// Σ_k Σ_i |f − f_ref| dx Δt_snap over snapshots with t ≥ t_from, same grid and snapshot times.
double space_time_l1(const compare::ModelResult& a, const compare::ModelResult& ref, const char* field, double t_from) {
  REQUIRE(a.snapshot_t.size() == ref.snapshot_t.size());
  const double dx = a.x[1] - a.x[0], dts = a.snapshot_t[1] - a.snapshot_t[0];
  double e = 0.0;
  for (std::size_t k = 0; k < a.snapshot_t.size(); ++k) {
    if (a.snapshot_t[k] < t_from) continue;
    const auto fa = testing::snapshot_row(a, field, k), fr = testing::snapshot_row(ref, field, k);
    for (std::size_t i = 0; i < fa.size(); ++i) e += std::abs(fa[i] - fr[i]) * dx * dts;
  }
  return e;
}

// L1 error Σ_i |a_i − b_j(i)| dx_a over the coarse nodes, b on a finer grid containing them.
double l1_shared(const std::vector<double>& xa, const std::vector<double>& a, const std::vector<double>& xb,
                 const std::vector<double>& b) {
  const double dxa = xa[1] - xa[0], dxb = xb[1] - xb[0];
  const auto stride = static_cast<std::size_t>(std::lround(dxa / dxb));
  REQUIRE(std::abs(static_cast<double>(stride) * dxb - dxa) < 1e-12);
  double e = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) e += std::abs(a[i] - b[i * stride]) * dxa;
  return e;
}

}  // namespace

TEST_CASE("continuum slow: temporal order through the switching at dx = 0.5 (dt = c..c/8 against c/64)", "[slow][convergence]") {
  // Same study as test_continuum_convergence's, one grid finer and one more halving, with a 64× finer
  // reference. Expected order 1 (Θ from the start-of-step state). Assertions on the overall order
  // c → c/8 (three halvings): u, σ̄ max norm at t = 40 ≥ 0.8; A space-time L1 over [20, 40] ≥ 0.8.
  // c = 0.002 (≈ 0.69 stable_dt); snapshots every 1.0 (a multiple of every dt).
  const double T = 40.0, dx = 0.5, c = 0.002;
  const auto ref = run_fig1(dx, c / 64.0, T, 1.0);
  const auto ru = last_row(ref, "u"), rs = last_row(ref, "sigma_bar");
  std::vector<double> eu, es, ea;
  for (double d : {1.0, 2.0, 4.0, 8.0}) {
    const auto r = run_fig1(dx, c / d, T, 1.0);
    eu.push_back(testing::max_diff_shared(r.x, last_row(r, "u"), ref.x, ru));
    es.push_back(testing::max_diff_shared(r.x, last_row(r, "sigma_bar"), ref.x, rs));
    ea.push_back(space_time_l1(r, ref, "A", 20.0));
  }
  for (std::size_t k = 0; k + 1 < eu.size(); ++k)
    WARN("dx 0.5, dt c/" << (1 << k) << " -> c/" << (2 << k) << ": u (max) " << eu[k] << " -> " << eu[k + 1] << " (order "
                         << testing::observed_order(eu[k], eu[k + 1]) << "), sigma_bar order "
                         << testing::observed_order(es[k], es[k + 1]) << ", A space-time L1 " << ea[k] << " -> " << ea[k + 1]
                         << " (order " << testing::observed_order(ea[k], ea[k + 1]) << ")");
  const double pu = testing::observed_order(eu[0], eu[3], 8.0), ps = testing::observed_order(es[0], es[3], 8.0);
  const double pa = testing::observed_order(ea[0], ea[3], 8.0);
  WARN("dx 0.5, overall order c -> c/8: u " << pu << ", sigma_bar " << ps << ", A (space-time L1) " << pa);
  CHECK(pu >= 0.8);
  CHECK(ps >= 0.8);
  CHECK(pa >= 0.8);
}

TEST_CASE("continuum slow: spatial convergence through the first yield (fig1, t = 40, dt proportional to dx)", "[slow][convergence]") {
  // Through yield the spatial and temporal switching errors mix (dt = dx/500 ∝ dx): the first-order
  // switching error dominates. The max-norm error at one instant is erratic (the tip sits at a
  // different place relative to the nodes of each grid), so the measure is the L1 error of u over the
  // shared nodes against dx = 0.125. Assertion: overall order dx = 2 → 0.5 ≥ 0.8 (expected ~1).
  const double T = 40.0;
  const auto ref = run_fig1(0.125, 0.125 / 500.0, T, T);
  REQUIRE(std::isfinite(ref.events.t_star));
  const auto ru = last_row(ref, "u");
  std::vector<double> e1, emax;
  for (double dx : {2.0, 1.0, 0.5}) {
    const auto r = run_fig1(dx, dx / 500.0, T, T);
    e1.push_back(l1_shared(r.x, last_row(r, "u"), ref.x, ru));
    emax.push_back(testing::max_diff_shared(r.x, last_row(r, "u"), ref.x, ru));
  }
  for (std::size_t k = 0; k + 1 < e1.size(); ++k)
    WARN("space through yield, dx " << 2.0 / (1 << k) << " -> " << 1.0 / (1 << k) << ": L1(u) " << e1[k] << " -> " << e1[k + 1]
                                     << " (order " << testing::observed_order(e1[k], e1[k + 1]) << "), max|u| order "
                                     << testing::observed_order(emax[k], emax[k + 1]));
  const double p = testing::observed_order(e1[0], e1[2], 4.0);
  WARN("space through yield, overall L1 order dx 2 -> 0.5: " << p);
  CHECK(p >= 0.8);
}

TEST_CASE("continuum slow: energy budget through the fast transient (fig1 to t = 120), residual O(dt^2)", "[slow][energy]") {
  // The budget of test_continuum_bulk carried through the fast transient (t^ ≈ 108.7, max v ≈ 1.8, Θ
  // switching at every site the transient crosses within ~5 time units). Each switching adds a kink in
  // σ̄(t) inside one step: an O(dt²) local quadrature error per site, so the residual stays second order. Tolerances: relative
  // residual < 1e-6 at every dx ≤ 2 (dt ≤ 4e-3); successive ratios ≥ 3.
  std::vector<double> rel;
  for (double dx : {2.0, 1.0, 0.5}) {
    const auto r = run_fig1(dx, dx / 500.0, 120.0, 0.0, /*energy=*/true);
    REQUIRE(std::isfinite(r.events.t_hat));
    REQUIRE(r.events.t_hat < 115.0);
    rel.push_back(std::abs(r.series.at("energy_residual").back()) / r.series.at("energy_drive_work").back());
    CHECK(rel.back() < 1e-6);
  }
  for (std::size_t k = 0; k + 1 < rel.size(); ++k) {
    WARN("energy residual / drive work at t = 120, dx " << 2.0 / (1 << k) << " -> " << 1.0 / (1 << k) << ": " << rel[k]
                                                         << " -> " << rel[k + 1] << " (ratio " << rel[k] / rel[k + 1] << ")");
    CHECK(rel[k] / rel[k + 1] >= 3.0);
  }
}

TEST_CASE("continuum slow: fig1 events converge, dx = 0.5, 0.25, 0.125 (dt halved with dx)", "[slow][fig1]") {
  // The events of the paper's sequence under two refinements (dx and dt halved together). Tolerances:
  // every change < 1% (docs/model.md §4 asks t* within 1%; the same for the transient); t* and x_arrest changes
  // shrink with refinement. (c_transient, a LS slope on interpolated tip samples, carries ~1e-3 of
  // sampling noise, so only its size is checked.)
  const auto s = testing::fig1_scene();
  const double dt0 = compare::dynamic_time_step(s);
  std::vector<compare::Events> ev;
  for (double f : {1.0, 0.5, 0.25}) {
    const auto r = run_fig1(s.grid.dx * f, dt0 * f, s.time.t_end, 0.0);
    ev.push_back(r.events);
    WARN("fig1 dx " << s.grid.dx * f << ": t* " << r.events.t_star << ", t^ " << r.events.t_hat << ", c_transient "
                    << r.events.c_transient << ", x_arrest " << r.events.x_arrest << ", c_slow(A<0.9) "
                    << r.events_alt.c_slow << ", wall " << r.wall_seconds << " s");
  }
  for (std::size_t k = 0; k + 1 < ev.size(); ++k) {
    CHECK(rel_err(ev[k].t_star, ev[k + 1].t_star) < 0.01);
    CHECK(rel_err(ev[k].t_hat, ev[k + 1].t_hat) < 0.01);
    CHECK(rel_err(ev[k].c_transient, ev[k + 1].c_transient) < 0.01);
    CHECK(rel_err(ev[k].x_arrest, ev[k + 1].x_arrest) < 0.01);
  }
  CHECK(std::abs(ev[2].t_star - ev[1].t_star) < std::abs(ev[1].t_star - ev[0].t_star));
  CHECK(std::abs(ev[2].x_arrest - ev[1].x_arrest) < std::abs(ev[1].x_arrest - ev[0].x_arrest));
}

TEST_CASE("continuum slow: halving v_d doubles t* and slows the slow front", "[slow][fig1]") {
  // Physics (docs/model.md §1): t* = (K + sqrt(αμ))/(α K v_d) ∝ 1/v_d (within 1%); the slow front is driven by
  // the loading, so it is slower at smaller v_d (the paper: speed proportional to v_d; here the ratio
  // is reported, and only its direction and the existence of the whole sequence are asserted).
  auto s = testing::fig1_scene();
  s.time.t_end = 320.0;  // the transient comes at t^ ≈ 297 for v_d = 0.15
  s.output.snapshot_dt = 0.0;
  s.drive.v_d = 0.15;
  const auto r = testing::run_continuum(s);
  auto f = testing::fig1_scene();
  f.output.snapshot_dt = 0.0;
  const auto r0 = testing::run_continuum(f);
  REQUIRE(r.status == slipfront::compare::RunStatus::complete);
  const double ts = (s.drive.K + std::sqrt(s.interface.alpha * s.bulk.mu)) / (s.interface.alpha * s.drive.K * s.drive.v_d);
  CHECK(rel_err(r.events.t_star, ts) < 0.01);
  REQUIRE(std::isfinite(r.events_alt.c_slow));
  REQUIRE(std::isfinite(r0.events_alt.c_slow));
  WARN("slow front (A < 0.9): c_slow = " << r.events_alt.c_slow << " at v_d = 0.15, " << r0.events_alt.c_slow
                                         << " at v_d = 0.3 (ratio " << r.events_alt.c_slow / r0.events_alt.c_slow
                                         << ", proportionality would give 0.5); t^ " << r.events.t_hat << ", x_arrest "
                                         << r.events.x_arrest);
  CHECK(r.events_alt.c_slow < r0.events_alt.c_slow);
  REQUIRE(std::isfinite(r.events.t_hat));
  CHECK(r.events.x_arrest < s.bulk.length);
}
