// The antiplane strip (docs/model.md §9) run end to end: the stuck phase's decay from the loaded edge against
// the smallest root of λ tan(λH) = αH/μ (§9.3), the thin limit H → 0 against the 1D chain (§9.2, §9.6), the
// noise-off identity of the discrete count law (§2), checkpoint and restart, the implicit integrator against
// the explicit one on fig1_strip, the energy budget, and the configuration keys of the strip (§9.1).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/fit.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/strip.hpp"
#include "identical.hpp"
#include "scenes.hpp"

using namespace slipfront;
using testing::require_identical;

namespace {

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// fig1 (testing::fig1_scene: μ = 300, α = 1.05, K = 2.5, v_d = 0.3, ρ = 0.01, η = 0.1, κ = 8, L = 300,
/// dx = 0.5) on the strip of height H, row spacing dy (H = 0: the chain).
compare::Scene fig1_strip(double H, double dy) {
  compare::Scene s = testing::fig1_scene();
  s.name = "fig1_strip_test";
  s.bulk.height = H;
  s.grid.dy = H > 0.0 ? dy : 0.0;
  return s;
}

compare::ModelResult run_one(const compare::Scene& s) {
  s.validate();
  auto out = compare::run_scene(s, {});
  REQUIRE(out.size() == 1);
  INFO(out[0].message);
  REQUIRE(out[0].status == compare::RunStatus::complete);
  return std::move(out[0]);
}

/// The n-th root (n = 0: the smallest) of λ tan(λH) = αH/μ, in (nπ/H, (n + ½)π/H), by bisection of
/// f(λ) = λ sin(λH) − (αH/μ) cos(λH) (no poles; f changes sign across the interval).
double strip_root(double alpha, double mu, double H, int n) {
  const double a = alpha * H / mu;
  auto f = [&](double l) { return l * std::sin(l * H) - a * std::cos(l * H); };
  double lo = n * std::numbers::pi / H, hi = (n + 0.5) * std::numbers::pi / H;
  double flo = f(lo);
  REQUIRE(flo * f(hi) < 0.0);
  for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm < 0.0) == (flo < 0.0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

double log_cosh(double z) { return std::abs(z) + std::log1p(std::exp(-2.0 * std::abs(z))) - std::log(2.0); }

/// Least-squares fit of log y(x) = c + log cosh(λ(L − x)) over the nodes with x_lo ≤ x ≤ x_hi (the
/// quasi-static stuck mode with the free far end at L): the λ minimising the residual sum of squares (c is
/// the mean for each λ), golden-section search in [lam_lo, lam_hi].
double fit_cosh_decay(const std::vector<double>& x, const std::vector<double>& y, double L, double x_lo, double x_hi,
                      double lam_lo, double lam_hi) {
  std::vector<double> xs, ly;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= x_lo && x[i] <= x_hi) {
      REQUIRE(y[i] > 0.0);
      xs.push_back(x[i]);
      ly.push_back(std::log(y[i]));
    }
  REQUIRE(xs.size() >= 10);
  auto sse = [&](double lam) {
    double mean = 0.0;
    for (std::size_t i = 0; i < xs.size(); ++i) mean += ly[i] - log_cosh(lam * (L - xs[i]));
    mean /= static_cast<double>(xs.size());
    double s = 0.0;
    for (std::size_t i = 0; i < xs.size(); ++i) s += std::pow(ly[i] - log_cosh(lam * (L - xs[i])) - mean, 2);
    return s;
  };
  const double lam = compare::golden_section_minimum(sse, lam_lo, lam_hi, 1e-13 * lam_hi);
  REQUIRE(lam > lam_lo * 1.001);  // an interior minimum, not the bracket's end
  REQUIRE(lam < lam_hi * 0.999);
  return lam;
}

/// Plain least-squares slope of log y over x_lo ≤ x ≤ x_hi (−slope: the decay rate), for the print.
double fit_exp_decay(const std::vector<double>& x, const std::vector<double>& y, double x_lo, double x_hi) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] >= x_lo && x[i] <= x_hi && y[i] > 0.0) {
      const double ly = std::log(y[i]);
      n += 1;
      sx += x[i];
      sy += ly;
      sxx += x[i] * x[i];
      sxy += x[i] * ly;
    }
  if (n < 3) return std::nan("");
  return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

std::vector<double> row_of(const compare::ModelResult& r, const char* field, std::size_t k) {
  const auto row = testing::snapshot_row(r, field, k);
  return {row.begin(), row.end()};
}

double rel(double a, double b) { return std::abs(a / b - 1.0); }

/// A small strip: fig1 on L = 60, dx = 1, H = 4, dy = 1 (5 rows) to t = 60: first yield and the slow front.
compare::Scene small_strip(core::Integrator integ) { return testing::small_strip_scene(integ, "small_strip"); }

using testing::same;


}  // namespace

// ---------------------------------------------------------------------------------------------
// 1. The stuck phase decays from the loaded edge at the smallest root of λ tan(λH) = αH/μ (§9.3)
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: the stuck phase decays from the edge at the smallest root of lambda tan(lambda H) = alpha H/mu",
          "[strip][stuck]") {
  // Physics (docs/model.md §9.3): before first yield (t* = 25.7 ... 35.6 for these H) every site sticks,
  // σ̄ = α u(x, 0), and with inertia and ηv neglected the strip is a Laplace problem with a Robin interface:
  // beyond a few H/π from the edge only the smallest root λ₀ of λ tan(λH) = αH/μ remains, and with the
  // free far end the interface profile is ∝ cosh(λ₀(L − x)) (fitted as such: the reflection is accounted
  // for, not windowed out). The fit window starts where the second mode has decayed by 1e-4 against the
  // first, exp(−(λ₁ − λ₀) x) < 1e-4. Under the drive ramp F ∝ t the quasi-static response is
  // u = G₀(x) t + G₁(x) (G₁: the ηv correction, constant in time). The 1% assertion fits the snapshot
  // σ̄(20) (G₁ biases its slope by ~+0.2%). Printed beside it: the increment σ̄(20) − σ̄(10) = α G₀(x)·10,
  // which removes G₁ (−4e-5, −2e-6, −1e-4 at H = 0, 5, 17) but at H = 34 is +2.7% off: the increment doubles
  // whatever start-up motion has not decayed by t = 10 in the thick strip (not investigated further).
  // The 1D chain (H = 0) must give sqrt(α/μ) the same way: the fit's own check.
  const double alpha = 1.05, mu = 300.0, L = 300.0;
  const double ell_e = std::sqrt(mu / alpha);
  for (const double H : {0.0, 5.0, 17.0, 34.0}) {
    compare::Scene s = fig1_strip(H, 0.5);
    s.time.t_end = 20.0;
    s.output.snapshot_dt = 10.0;
    s.output.series_dt = 1.0;
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = run_one(s);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO("H = " << H);
    REQUIRE(std::isnan(r.events.t_star));  // still stuck at t = 20
    REQUIRE(r.snapshot_t.size() == 3);
    REQUIRE(r.snapshot_t[1] == Approx(10.0).margin(0.01));  // the first step at or after the time
    REQUIRE(r.snapshot_t[2] == Approx(20.0).margin(0.01));
    const auto sb10 = row_of(r, "sigma_bar", 1), sb20 = row_of(r, "sigma_bar", 2), u20 = row_of(r, "u", 2);
    for (std::size_t i = 0; i < sb20.size(); ++i) REQUIRE(sb20[i] == Approx(alpha * u20[i]).epsilon(1e-10));  // stuck
    std::vector<double> inc(sb20.size());
    for (std::size_t i = 0; i < inc.size(); ++i) inc[i] = sb20[i] - sb10[i];

    const double lam = H > 0.0 ? strip_root(alpha, mu, H, 0) : std::sqrt(alpha / mu);
    const double lam1 = H > 0.0 ? strip_root(alpha, mu, H, 1) : 0.0;
    // window: the second mode down by 1e-4 (the chain has none: a few nodes off the edge)
    const double x_lo = H > 0.0 ? std::log(1e4) / (lam1 - lam) : 5.0;
    // the window ends where the increment falls to 1e-6 of the edge's (well above round-off and the
    // start-up transient's remains)
    double x_hi = 0.0;
    for (std::size_t i = 0; i < inc.size(); ++i)
      if (inc[i] > 1e-6 * inc.front() && sb20[i] > 1e-6 * sb20.front()) x_hi = r.x[i];
    REQUIRE(x_hi > x_lo + 50.0);
    const double fit_inc = fit_cosh_decay(r.x, inc, L, x_lo, x_hi, 0.5 * lam, 2.0 * lam);
    const double fit_one = fit_cosh_decay(r.x, sb20, L, x_lo, x_hi, 0.5 * lam, 2.0 * lam);
    // a plain exponential slope where the far end's reflection e^{−2λ(L−x)} < 1e-4 too (if such a window exists)
    const double x_hi_exp = L - std::log(1e4) / (2.0 * lam);
    const double slope = x_hi_exp > x_lo + 5.0 ? fit_exp_decay(r.x, inc, x_lo, x_hi_exp) : std::nan("");
    std::printf("strip stuck decay H = %4.1f (H/l_e = %.4f): lambda root %.6f (lambda l_e = %.5f, lambda_1 = %.5f), "
                "window x in [%.1f, %.1f]; fit of sigma_bar(20)-sigma_bar(10): %.6f (rel %+.2e); of sigma_bar(20): "
                "%.6f (rel %+.2e); plain exp slope on [%.1f, %.1f]: %.6f; %.2f s\n",
                H, H / ell_e, lam, lam * ell_e, lam1, x_lo, x_hi, fit_inc, fit_inc / lam - 1.0, fit_one,
                fit_one / lam - 1.0, x_lo, x_hi_exp, slope, secs);
    CHECK(std::abs(fit_one / lam - 1.0) < 0.01);
  }
}

// ---------------------------------------------------------------------------------------------
// 2. The thin limit H → 0: the strip's fig1 events tend to the chain's (§9.2, §9.6)
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: H -> 0: fig1's events on the strip tend to the chain's, at second order in H", "[strip][thin]") {
  // Physics (docs/model.md §9.2, §9.6): the column mean obeys the chain's equation exactly; the law reads row 0
  // instead, which lags the mean by O(H²) (one row interval: −(H²/4μ)(σ̄ + ηv)). So the events converge to
  // the chain's at second order in H, with relative size (H/ℓ)²/3 (ℓ the shortest length of the fields;
  // fig1's ℓ_e = 16.9). All runs share dx = 0.5 and one explicit step dt = 5e-4 (below the stable step of
  // every grid here: 7.0e-4 at dy = 0.125), so the differences are the height's alone, not a step's.
  // Assertions: at H = 0.25 (dy = H and H/2) every event within 0.5% of the chain's; the observed order of
  // every event's difference, H = 4 -> 2 -> 1 with one row interval, > 1.5. Measured (dt = 5e-4): orders
  // 1.87/1.92 (t*), 2.18/2.10 (t^), 2.23/2.39 (c_transient), 1.93/1.96 (x_arrest), 2.18/2.09 (t_arrest);
  // at H = 0.25 the largest difference is c_transient's, +5.5e-4 (dy = H) and +9.6e-4 (dy = H/2).
  struct Run {
    double H, dy;
    compare::Events e;
  };
  auto scene = [](double H, double dy) {
    compare::Scene s = fig1_strip(H, dy);
    s.time.t_end = 125.0;  // through t^ (108.7 on the chain) and the arrest (t = 113.9)
    s.time.dt = 5e-4;
    s.output.snapshot_dt = 25.0;
    return s;
  };
  const auto t0 = std::chrono::steady_clock::now();
  const compare::Events chain = run_one(scene(0.0, 0.0)).events;
  REQUIRE(std::isfinite(chain.t_star));
  REQUIRE(std::isfinite(chain.t_hat));
  REQUIRE(std::isfinite(chain.c_transient));
  REQUIRE(std::isfinite(chain.x_arrest));
  std::vector<Run> runs;
  for (const auto& [H, dy] : std::vector<std::pair<double, double>>{{4.0, 4.0}, {2.0, 2.0}, {1.0, 1.0}, {0.5, 0.5}, {0.25, 0.25}, {0.5, 0.25}, {0.25, 0.125}})
    runs.push_back({H, dy, run_one(scene(H, dy)).events});
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const char* names[] = {"t_star", "t_hat", "c_transient", "x_arrest", "t_arrest"};
  const double compare::Events::*fields[] = {&compare::Events::t_star, &compare::Events::t_hat,
                                             &compare::Events::c_transient, &compare::Events::x_arrest,
                                             &compare::Events::t_arrest};
  std::printf("strip thin limit (dx = 0.5, dt = 5e-4, %.1f s): chain t* %.5f t^ %.5f c_transient %.5f x_arrest %.5f "
              "t_arrest %.5f\n",
              secs, chain.t_star, chain.t_hat, chain.c_transient, chain.x_arrest, chain.t_arrest);
  for (const auto& r : runs) {
    std::printf("  H = %.3g, dy = %.3g:", r.H, r.dy);
    for (std::size_t k = 0; k < 5; ++k) std::printf(" %s %+.3e", names[k], r.e.*fields[k] / (chain.*fields[k]) - 1.0);
    std::printf("\n");
  }
  // observed orders with one row interval, H = 4 -> 2 -> 1 -> 0.5 -> 0.25
  for (std::size_t k = 0; k < 5; ++k) {
    std::printf("  order in H of |%s - chain| (dy = H):", names[k]);
    for (std::size_t m = 0; m + 1 < 5; ++m)
      std::printf(" %g->%g: %.3f", runs[m].H, runs[m + 1].H,
                  testing::observed_order(std::abs(runs[m].e.*fields[k] - chain.*fields[k]),
                                          std::abs(runs[m + 1].e.*fields[k] - chain.*fields[k])));
    std::printf("\n");
  }
  for (const auto& r : runs) {
    if (r.H > 0.25) continue;
    INFO("H = " << r.H << ", dy = " << r.dy);
    for (std::size_t k = 0; k < 5; ++k) {
      INFO(names[k]);
      CHECK(std::abs(r.e.*fields[k] / (chain.*fields[k]) - 1.0) < 0.005);
    }
  }
  // The order is measured where the differences stand above the measurement's floor: from H = 4 to 2 to 1
  // (below H ~ 1 they reach ~3e-5 in t^ and ~5e-4 in c_transient, the LS slope's resolution, and stop
  // shrinking; t* is quantised to one step, 2e-5 relative).
  for (std::size_t k = 0; k < 5; ++k)
    for (std::size_t m = 0; m < 2; ++m) {
      INFO(names[k] << ", H = " << runs[m].H << " -> " << runs[m + 1].H);
      CHECK(testing::observed_order(std::abs(runs[m].e.*fields[k] - chain.*fields[k]),
                                    std::abs(runs[m + 1].e.*fields[k] - chain.*fields[k])) > 1.5);
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Noise-off identity of the discrete count law on the strip (docs/model.md §2, hierarchy item 1)
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: the discrete count law with w = 0 and noise off is the continuum law on the strip",
          "[strip][discrete][identity]") {
  // tests/test_discrete_identity.cpp asserts the 1D identity to 1e-12 relative (it allows for differently
  // grouped but algebraically equal updates). On the strip the fields come out bit-identical (measured: 0
  // of 3172 snapshot values differ, explicit and implicit), and that is what is required here: every
  // snapshot value, every series value and every event equal.
  for (const auto integ : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal}) {
    compare::Scene s = testing::noise_off_count(small_strip(integ));
    s.validate();
    INFO(core::to_string(integ));
    const auto r = compare::run_scene(s, {});
    REQUIRE(r.size() == 2);
    REQUIRE(r[0].status == compare::RunStatus::complete);
    REQUIRE(r[1].status == compare::RunStatus::complete);
    REQUIRE(std::isfinite(r[0].events.t_star));  // through first yield
    REQUIRE(r[0].snapshot_t == r[1].snapshot_t);
    const std::size_t nx = r[0].x.size();
    double worst = 0.0;
    std::size_t bits_differ = 0, values = 0;
    for (const char* field : {"A", "sigma_bar", "u", "v"}) {
      const auto &a = r[0].snapshots.at(field), &b = r[1].snapshots.at(field);
      REQUIRE(a.size() == b.size());
      for (std::size_t k = 0; k < r[0].snapshot_t.size(); ++k) {
        INFO(field << " at t = " << r[0].snapshot_t[k]);
        const std::vector<double> ra(a.begin() + k * nx, a.begin() + (k + 1) * nx), rb(b.begin() + k * nx, b.begin() + (k + 1) * nx);
        const double e = testing::max_relative_difference(ra, rb);
        CHECK(e <= 1e-12);
        worst = std::max(worst, e);
      }
      for (std::size_t i = 0; i < a.size(); ++i) bits_differ += a[i] != b[i];
      values += a.size();
    }
    for (const auto& [name, col] : r[0].series) {
      INFO("series " << name);
      REQUIRE(r[1].series.count(name) == 1);
      const double e = testing::max_relative_difference(col, r[1].series.at(name));
      CHECK(e <= 1e-12);
      worst = std::max(worst, e);
    }
    for (const auto& [name, field] : compare::event_fields) {
      INFO("event " << name);
      CHECK(same(r[0].events.*field, r[1].events.*field));
    }
    // the slow front is under way at t = 60: A < 1 behind it
    const auto& A = r[1].snapshots.at("A");
    CHECK(*std::min_element(A.end() - static_cast<std::ptrdiff_t>(nx), A.end()) < 0.99);
    CHECK(bits_differ == 0);
    CHECK(same(r[0].series, r[1].series));
    std::printf("strip identity (%s): max relative difference %.3g; snapshot values not bit-identical: %zu of %zu; "
                "t* = %.6f\n",
                core::to_string(integ), worst, bits_differ, values, r[0].events.t_star);
  }
}

// ---------------------------------------------------------------------------------------------
// 4. Checkpoint and restart on the strip (testing::require_identical, tests/identical.hpp)
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: a restarted strip run is the uninterrupted run bit for bit (explicit and implicit, both models)",
          "[strip][checkpoint]") {
  // As tests/test_checkpoint.cpp on the chain: the checkpoint holds every row of the body (the energy budget,
  // recorded here, reads all dofs: a row not restored would change it), the law's state and the records.
  for (const auto integ : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal}) {
    compare::Scene s = small_strip(integ);
    s.models = {"continuum", "discrete"};
    s.discrete.representation = "count";
    s.discrete.contacts_per_site = 50;
    s.discrete.seed = 3;
    s.output.energy = true;
    s.validate();
    INFO(core::to_string(integ));
    const auto whole = compare::run_scene_alongside(s, {});
    REQUIRE(whole.models.size() == 2);
    REQUIRE(std::isfinite(whole.models[0].events.t_star));
    struct Saved {
      double t;
      std::string state;
    };
    std::vector<Saved> saved;
    compare::RunControl ctl;
    ctl.checkpoint_every = 12.0;
    ctl.checkpoint = [&](const std::string& state, double t) { saved.push_back({t, state}); };
    const auto with = compare::run_scene_alongside(s, ctl);
    require_identical(whole, with);
    REQUIRE(saved.size() >= 4);
    for (const std::size_t k : {std::size_t{0}, saved.size() / 2, saved.size() - 1}) {
      INFO("restarted from the checkpoint at t = " << saved[k].t);
      compare::RunControl rc;
      rc.restart = saved[k].state;
      require_identical(whole, compare::run_scene_alongside(s, rc));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 5. The implicit integrator against the explicit one on fig1_strip
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: fig1_strip: the implicit integrator at dt = 0.02 against the explicit reference",
          "[strip][implicit]") {
  // configs/fig1_strip.toml (H = 17, dx = dy = 0.5, implicit dt = 0.02), continuum, to t = 120 (t^ = 104.5,
  // arrest at t = 109.6). The explicit reference at cfl 0.5 (dt ≈ 1.4e-3). Asserted within 1%: t*, t^,
  // x_arrest and the slow front's speed (on the A_tip_alt front, where fig1 measures it).
  // Finding (not asserted, printed): c_transient at dt = 0.02 is 1.3% below the explicit reference (15.114 vs
  // 15.316), 0.8% at dt = 0.01 (measured with the program; the 1D test, tests/test_implicit.cpp, checks it at
  // dt = 0.01: -0.4% there). The step's error on the transient's speed is first order (Θ switched once per
  // step), and at the scene's dt = 0.02 it is above 1%.
  compare::Scene s = fig1_strip(17.0, 0.5);
  s.time.t_end = 120.0;
  s.output.snapshot_dt = 10.0;
  compare::Scene ex = s;
  const auto t0 = std::chrono::steady_clock::now();
  const auto e = run_one(ex);
  const auto t1 = std::chrono::steady_clock::now();
  compare::Scene im = s;
  im.time.integrator = core::Integrator::implicit_trapezoidal;
  im.time.dt = 0.02;
  const auto r = run_one(im);
  const auto t2 = std::chrono::steady_clock::now();
  REQUIRE(r.labels.at("integrator") == "implicit");
  for (const auto* ev : {&e.events, &r.events}) {
    REQUIRE(std::isfinite(ev->t_star));
    REQUIRE(std::isfinite(ev->t_hat));
    REQUIRE(std::isfinite(ev->c_transient));
    REQUIRE(std::isfinite(ev->x_arrest));
  }
  std::printf("fig1_strip explicit (%.1f s, dt %.3g) vs implicit dt = 0.02 (%.1f s): t* %.4f %.4f (%+.2e), t^ %.4f "
              "%.4f (%+.2e), c_transient %.4f %.4f (%+.2e), x_arrest %.4f %.4f (%+.2e), c_slow(alt) %.4f %.4f "
              "(%+.2e)\n",
              std::chrono::duration<double>(t1 - t0).count(), e.scalars.at("dt"),
              std::chrono::duration<double>(t2 - t1).count(), e.events.t_star, r.events.t_star,
              r.events.t_star / e.events.t_star - 1, e.events.t_hat, r.events.t_hat, r.events.t_hat / e.events.t_hat - 1,
              e.events.c_transient, r.events.c_transient, r.events.c_transient / e.events.c_transient - 1,
              e.events.x_arrest, r.events.x_arrest, r.events.x_arrest / e.events.x_arrest - 1, e.events_alt.c_slow,
              r.events_alt.c_slow, r.events_alt.c_slow / e.events_alt.c_slow - 1);
  CHECK(rel(r.events.t_star, e.events.t_star) < 0.01);
  CHECK(rel(r.events.t_hat, e.events.t_hat) < 0.01);
  CHECK(rel(r.events.x_arrest, e.events.x_arrest) < 0.01);
  CHECK(rel(r.events_alt.c_slow, e.events_alt.c_slow) < 0.01);
  // §9.3: first yield later than the chain's 25.71, near the quasi-static series' 29.04
  CHECK(e.events.t_star == Approx(29.039).epsilon(0.01));
}

// ---------------------------------------------------------------------------------------------
// 6. The energy budget closes on the strip
// ---------------------------------------------------------------------------------------------

TEST_CASE("strip runs: the energy budget closes on the strip, explicit and implicit, edge and homogeneous loading",
          "[strip][energy]") {
  // Drive work = kinetic + elastic (+ spring) + viscous + interfacial work, over every dof of the strip.
  // Tolerances as on the chain: implicit < 1e-9 of the drive work at any dt (the trapezoidal identity to
  // round-off, tests/test_implicit.cpp; the strip's CG solves to a relative residual of 1e-12); explicit
  // < 1e-8 at dt = dx/500 on fig1 through first yield (the budget's O(dt²) quadrature error,
  // tests/test_continuum_bulk.cpp). Homogeneous loading, explicit: the chain itself has 7.9e-7 at
  // dt = dx/500 (a front at v ~ 1 from the patch; the 1D test never checked this scene), so there the strip
  // is asserted to match the chain's residual (within 10%) and to fall like dt² (×≥3 when dt is halved).
  compare::Scene edge = fig1_strip(4.0, 0.5);  // L = 300, dx = 0.5, through first yield and the slow front
  edge.time.t_end = 40.0;
  compare::Scene homo = testing::homogeneous_scene(0.5, 150.0, 5.0);  // σ_d = 0.5, patch 0 ≤ x < 150
  homo.bulk.height = 4.0;
  homo.grid.dy = 0.5;
  compare::Scene homo_chain = testing::homogeneous_scene(0.5, 150.0, 5.0);
  auto residual = [](compare::Scene s, core::Integrator integ, double dt) {
    s.time.integrator = integ;
    s.time.dt = dt;
    s.output.energy = true;
    s.output.series_dt = 0.5;
    s.output.snapshot_dt = s.time.t_end;
    const auto r = run_one(s);
    const double worst = testing::worst_energy_residual(r);
    for (const char* term : {"energy_mechanical", "energy_viscous", "energy_interfacial"})
      CHECK(r.series.at(term).back() > 0.0);  // every term takes part
    std::printf("strip energy %s (H = %g), %s, dt %g: max |residual| / drive work = %.3g\n", s.name.c_str(),
                s.bulk.height, core::to_string(integ), dt, worst);
    return worst;
  };
  using core::Integrator;
  CHECK(residual(edge, Integrator::central_difference, edge.grid.dx / 500.0) < 1e-8);
  CHECK(residual(edge, Integrator::implicit_trapezoidal, 0.01) < 1e-9);
  CHECK(residual(homo, Integrator::implicit_trapezoidal, 0.01) < 1e-9);
  const double strip1 = residual(homo, Integrator::central_difference, homo.grid.dx / 500.0);
  const double chain1 = residual(homo_chain, Integrator::central_difference, homo.grid.dx / 500.0);
  const double strip2 = residual(homo, Integrator::central_difference, homo.grid.dx / 1000.0);
  std::printf("strip energy homogeneous explicit: strip/chain %.4f, dt halved: ratio %.3f\n", strip1 / chain1,
              strip1 / strip2);
  CHECK(strip1 == Approx(chain1).epsilon(0.1));
  CHECK(strip1 / strip2 >= 3.0);
}

// ---------------------------------------------------------------------------------------------
// 7. The strip's configuration keys refused where they do not apply
// ---------------------------------------------------------------------------------------------

namespace {
std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}
// parse_scene(text) must throw a ConfigError naming `key` (its key, or in its message).
void require_refused(const std::string& text, const std::string& key) {
  try {
    (void)app::parse_scene(text, "strip.toml", {});
    FAIL("accepted:\n" << text);
  } catch (const app::ConfigError& e) {
    INFO(e.what());
    CHECK(std::string(e.what()).find(key) != std::string::npos);
    CHECK(e.key == key);
  }
}
}  // namespace

TEST_CASE("strip runs: the strip's keys are refused where they do not apply, naming the key", "[strip][config]") {
  const std::string base = testing::minimal_config();  // edge, L = 20, dx = 2
  const std::string strip = replace(base, "length = 20\n", "length = 20\nheight = 4\n");
  (void)app::parse_scene(strip, "strip.toml", {});  // the control: a valid strip
  (void)app::parse_scene(replace(strip, "dx = 2\n", "dx = 2\ndy = 1\n"), "strip.toml", {});
  // a 0D scene has no body to give a height to
  require_refused(replace(strip, "loading = \"edge\"", "loading = \"spring_block\""), "bulk.height");
  // rows must tile the height
  require_refused(replace(strip, "dx = 2\n", "dx = 2\ndy = 1.5\n"), "grid.dy");
  // grid.dy without bulk.height
  require_refused(replace(base, "dx = 2\n", "dx = 2\ndy = 1\n"), "grid.dy");
  // grid.dy > H, and the default dy = dx > H
  require_refused(replace(strip, "dx = 2\n", "dx = 2\ndy = 8\n"), "grid.dy");
  require_refused(replace(base, "length = 20\n", "length = 20\nheight = 1\n"), "grid.dy");
  // the adaptive integrator runs on the strip (tests/test_strip_adaptive.cpp): no refusal
  (void)app::parse_scene(replace(strip, "t_end = 2\n", "t_end = 2\nintegrator = \"adaptive\"\n"), "strip.toml", {});
  // the steady-front start on the strip starts from the strip's own front (docs/fronts.md §10.15): accepted
  const std::string homo = replace(replace(strip, "loading = \"edge\"\nK = 2.5\nv_d = 0.3\n",
                                           "loading = \"homogeneous\"\nsigma_d = 0.3\nstart = \"steady_front\"\n"),
                                   "length = 20\n", "length = 300\n");
  CHECK(app::parse_scene(homo, "strip.toml", {}).drive.start == "steady_front");
  // heights outside the domain
  for (const char* h : {"nan", "-4", "-inf", "inf", "0.0"}) {
    INFO("height = " << h);
    const std::string text = replace(base, "length = 20\n", std::string("length = 20\nheight = ") + h + "\n");
    if (std::string(h) == "0.0") {
      // 0 is the documented spelling of "no height": the chain (params.cpp: 0 or absent)
      const auto s = app::parse_scene(text, "strip.toml", {});
      CHECK(s.bulk.height == 0.0);
    } else {
      require_refused(text, "bulk.height");
    }
  }
}

TEST_CASE("strip runs: time.cfl is a fraction of the strip's own stability limit", "[strip]") {
  // The fixed step of a scene is time.cfl × the explicit limit of its body: on the strip the limit includes
  // the rows (4c_s²/dy²), which the chain's does not — with the chain's limit cfl = 0.5 was 0.71 of the strip's.
  compare::Scene s = fig1_strip(17.0, 0.5);
  s.time.integrator = core::Integrator::central_difference;
  s.time.dt = 0.0;
  s.time.cfl = 0.5;
  s.time.t_end = 0.5;
  const auto r = run_one(s);
  const double stable = r.scalars.at("stable_dt");
  CHECK(stable == core::Strip::stable_time_step(s.bulk, s.drive, s.interface, s.grid.dx, s.grid.row_spacing()));
  CHECK(r.scalars.at("dt") <= 0.5 * stable);
  CHECK(r.scalars.at("dt") > 0.5 * stable * (1.0 - 1.0 / 200.0));  // shortened only to a whole number of steps
}
