// The located leap integrator's fig1 event distributions against the small-step explicit reference (issue 36 item 3,
// core/leap.hpp, docs/numerics.md §9.4–§9.7), slow tier.
//
// The reference is stored (tests/data/leap_fig1_reference.csv, the command that made it in its header): the count law
// on the explicit scheme at cfl = 0.125, at N = 10³ (seeds 1–401, ~2 s a run) and at N = 10⁴ (seeds 101–196, ~12 s a
// run; since 2026-11-28: the 48 runs at cfl = 0.25 it replaced were not converged in t^ to better than ~0.7). Its first
// run of each N is computed again here and must match the file (else the file is stale: remake it). The leap runs use
// other seeds (1001–1288 at N = 10³, 1–96 at N = 10⁴): independent samples. ~3 min (2 cores, loaded).
//
// At N = 10³ fig1 is bimodal (docs/numerics.md §9.1: an early transient, c_transient < 20, or a late one): which mode a
// run takes is decided by a rare first re-sticking at the loaded edge (§9.6). The law's yield test made only at each
// step's start saw it too seldom: the leap put the late mode's t^ 3.5 ± 0.7 later than the reference (§9.4) and, with
// the ε/4 share that removed that, still the early mode in 0.29–0.31 of the runs against the reference's 0.190 (this test
// failed on it, p = 0.0019). Since issue 36 the count law watches a site near its threshold at every count event of the
// leap's step (discrete::CountLaw::advance_watched, §9.7) and those sites keep ε unshared; on this test's seeds: early
// 70/288 (0.243, p = 0.11), late-mode t^ 118.94 ± 0.34 against 119.79 ± 0.32 (z = −1.8), KS p 0.053, 0.048, 0.0064
// (t^, x_arrest, c_transient): every check passes, the KS on c_transient the closest (seeds 1–288: 69/288, KS p 0.27,
// 0.28, 0.09, z = +0.4). The battery at each N, each test at α = 0.005:
//   two-sample KS on t^, x_arrest, c_transient, a run with no transient (no arrest) by t_end counted as beyond every
//   measured one; the no-transient tail on its own and the early fraction on its own (Fisher exact on the runs without
//   a transient, and on those with c_transient < 20: conservative tests, false alarms ≤ α each); a Welch z test on the
//   mean t^ of the late mode at N = 10³ and of the runs with t^ < 115 at N = 10⁴. False alarms ≤ 3 % at each N (six
//   tests), ≤ 6 % for the two together (Bonferroni).
// Power at N = 10³, simulated with 288 + 288 runs (the 401 reference runs raise it a little) drawn from the reference's
// runs, the leap's late-mode t^ shifted: 0.997 against a shift of 2.75 (the bias issue 36 reported), 0.60 against 1.5;
// of the early fraction's Fisher test (binomial samples about the reference's fraction): 0.41 against 0.29, 0.62
// against 0.31, 0.91 against 0.35
// (the default before the watched step, 0.29–0.31, failed it).
//
// At N = 10⁴ (unimodal: t^ ≈ 108.8 with sd 2.5, a few late runs; early = c_transient < 20 in 92 of the reference's 96
// runs), 96 leap runs against 96 reference runs; with the watched step: KS p 0.65, 0.65, 0.42, early 92/96 against 92/96,
// t^ < 115 108.29 ± 0.24 (87 runs) against 108.77 ± 0.26 (89), z = −1.4. Power of the mean test (both samples drawn from the reference's runs,
// the leap's t^ shifted, 4000 draws): 0.30 against a shift of 1.0, 0.81 against 1.5, 0.98 against 2.0 (its false alarms
// there 0.005). Simulated with the 48-run reference at cfl = 0.25 (96 runs raise them): of the KS on t^ against a shift
// of one sd (2.0), 0.98; of the early fraction's test, 0.68 against a late transient in one run of four, 0.22 against one
// in six; against one run in six without a transient, 0.08 only.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "tests/discrete_agent_helpers.hpp"
#include "tests/leap_scenes.hpp"

using namespace slipfront;

namespace {

constexpr double kAlpha = 0.005;

struct Events {
  double t_hat, x_arrest, c_transient;
};

compare::Scene count_fig1(core::Integrator integ, long n, unsigned seed, double cfl) {
  compare::Scene s = testing::count_fig1_scene(integ, n, seed);
  s.time.cfl = cfl;
  return s;
}

Events run_events(const compare::Scene& scene) {
  compare::Scene s = scene;
  s.validate();
  auto out = compare::run_scene(s, compare::RunControl{});
  REQUIRE(!out.empty());
  REQUIRE(out.back().status == compare::RunStatus::complete);
  const auto& e = out.back().events;
  return {e.t_hat, e.x_arrest, e.c_transient};
}

// The stored reference runs of contacts_per_site n, by seed (NaN where the run had no such event).
std::map<unsigned, Events> reference(long n) {
  std::ifstream in(std::string(SLIPFRONT_SOURCE_DIR) + "/tests/data/leap_fig1_reference.csv");
  REQUIRE(in);
  std::map<unsigned, Events> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line.rfind("contacts", 0) == 0) continue;
    std::istringstream row(line);
    std::string f[6];
    for (auto& x : f) std::getline(row, x, ',');
    if (std::stol(f[0]) != n) continue;
    out[static_cast<unsigned>(std::stoul(f[2]))] = {std::stod(f[3]), std::stod(f[4]), std::stod(f[5])};
  }
  return out;
}

// Two-sided Fisher exact test of a out of n1 against b out of n2: with the margins fixed (the hypergeometric law), the
// probability of a table no more likely than the observed one.
double fisher_exact(int a, int n1, int b, int n2) {
  const auto lchoose = [](int n, int k) { return std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0); };
  const int k = a + b;
  const auto logp = [&](int x) { return lchoose(n1, x) + lchoose(n2, k - x) - lchoose(n1 + n2, k); };
  const double observed = logp(a);
  double p = 0.0;
  for (int x = std::max(0, k - n2); x <= std::min(k, n1); ++x)
    if (logp(x) <= observed + 1e-7) p += std::exp(logp(x));
  return std::min(1.0, p);
}

// A missing event (no transient, no arrest by t_end) counts as beyond every one measured.
double or_beyond(double x) { return std::isfinite(x) ? x : 1e9; }

struct Sample {
  std::vector<double> t_hat, x_arrest, c_transient, late_t_hat;  // late: c_transient ≥ 20 (the late mode)
  int missing = 0, early = 0;                                     // early: c_transient < 20
  int size() const { return static_cast<int>(t_hat.size()); }
  void add(const Events& e) {
    if (e.c_transient < 20.0) ++early;
    t_hat.push_back(or_beyond(e.t_hat));
    x_arrest.push_back(or_beyond(e.x_arrest));
    c_transient.push_back(or_beyond(e.c_transient));
    if (std::isfinite(e.c_transient) && e.c_transient >= 20.0 && std::isfinite(e.t_hat)) late_t_hat.push_back(e.t_hat);
    if (!std::isfinite(e.t_hat)) ++missing;
  }
};

double ulp_rel(double a, double b) { return std::isnan(a) && std::isnan(b) ? 0.0 : std::abs(a - b) / std::abs(b); }

// The first stored reference run of contacts_per_site n, computed again: the file is what the code computes.
void check_reference_current(const std::map<unsigned, Events>& ref, long n, double cfl) {
  const auto& [seed, stored] = *ref.begin();
  const Events now = run_events(count_fig1(core::Integrator::central_difference, n, seed, cfl));
  INFO("N = " << n << ", seed " << seed << ": t^ stored " << stored.t_hat << ", now " << now.t_hat);
  CHECK(ulp_rel(now.t_hat, stored.t_hat) < 1e-9);
  CHECK(ulp_rel(now.x_arrest, stored.x_arrest) < 1e-9);
  CHECK(ulp_rel(now.c_transient, stored.c_transient) < 1e-9);
}

// The KS tests of the three events; returns the smallest p.
double ks_events(const Sample& leap, const Sample& ref, const char* label) {
  const auto t = testing::ks_two_sample(leap.t_hat, ref.t_hat), x = testing::ks_two_sample(leap.x_arrest, ref.x_arrest),
             c = testing::ks_two_sample(leap.c_transient, ref.c_transient);
  WARN(label << ": KS p t^ " << t.p << ", x_arrest " << x.p << ", c_transient " << c.p << "; no transient: leap "
             << leap.missing << " of " << leap.t_hat.size() << ", reference " << ref.missing << " of "
             << ref.t_hat.size());
  CHECK(t.p > kAlpha);
  CHECK(x.p > kAlpha);
  CHECK(c.p > kAlpha);
  // the no-transient tail on its own: as many runs without a transient by t_end as the reference's
  const double tail = fisher_exact(leap.missing, leap.size(), ref.missing, ref.size());
  WARN(label << ": no transient by t_end, Fisher p = " << tail);
  CHECK(tail > kAlpha);
  // the mixing of the two modes on its own: as many early transients (c_transient < 20) as the reference's
  const double early = fisher_exact(leap.early, leap.size(), ref.early, ref.size());
  WARN(label << ": early transient: leap " << leap.early << " of " << leap.size() << ", reference " << ref.early
             << " of " << ref.size() << ", Fisher p = " << early);
  CHECK(early > kAlpha);
  return std::min({t.p, x.p, c.p, tail, early});
}

}  // namespace

TEST_CASE("leap slow: fig1 events at N = 1e3 are distributed as on the explicit scheme at cfl = 0.125",
          "[leap][statistics][slow]") {
  const auto stored = reference(1000);
  REQUIRE(stored.size() == 401);
  check_reference_current(stored, 1000, 0.125);
  Sample ref, leap;
  for (const auto& [seed, e] : stored) ref.add(e);
  for (unsigned k = 1001; k <= 1288; ++k) leap.add(run_events(count_fig1(core::Integrator::adaptive_rosenbrock, 1000, k, 0.5)));
  ks_events(leap, ref, "count N = 1e3, 288 leap vs 401 explicit (cfl 0.125)");
  const auto l = testing::mean_se(leap.late_t_hat), r = testing::mean_se(ref.late_t_hat);
  const double z = (l.mean - r.mean) / std::hypot(l.se, r.se), p = std::erfc(std::abs(z) / std::sqrt(2.0));
  WARN("late-mode t^: leap " << l.mean << " +- " << l.se << " (" << leap.late_t_hat.size() << " runs), reference "
                             << r.mean << " +- " << r.se << " (" << ref.late_t_hat.size() << "): z = " << z << ", p = " << p);
  CHECK(p > kAlpha);
}

TEST_CASE("leap slow: fig1 events at N = 1e4 are distributed as on the explicit scheme at cfl = 0.125",
          "[leap][statistics][slow]") {
  const auto stored = reference(10000);
  REQUIRE(stored.size() == 96);
  check_reference_current(stored, 10000, 0.125);
  Sample ref, leap;
  for (const auto& [seed, e] : stored) ref.add(e);
  for (unsigned k = 1; k <= 96; ++k) leap.add(run_events(count_fig1(core::Integrator::adaptive_rosenbrock, 10000, k, 0.5)));
  ks_events(leap, ref, "count N = 1e4, 96 leap vs 96 explicit (cfl 0.125)");
  // the mean t^ of the runs with t^ < 115 (the unimodal bulk: a few runs of either scheme come later or not at all)
  const auto bulk = [](const Sample& s) {
    std::vector<double> x;
    for (double t : s.t_hat)
      if (t < 115.0) x.push_back(t);
    return x;
  };
  const auto lb = bulk(leap), rb = bulk(ref);
  const auto l = testing::mean_se(lb), r = testing::mean_se(rb);
  const double z = (l.mean - r.mean) / std::hypot(l.se, r.se), p = std::erfc(std::abs(z) / std::sqrt(2.0));
  WARN("t^ < 115: leap " << l.mean << " +- " << l.se << " (" << lb.size() << " runs), reference " << r.mean << " +- "
                         << r.se << " (" << rb.size() << "): z = " << z << ", p = " << p);
  CHECK(p > kAlpha);
}
