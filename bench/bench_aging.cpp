// The age cohorts of the mean field with aging (discrete::AgeCohorts, docs/model.md §11.3): the kept logarithms
// (step + area, the law's path) against the path before them (step_recomputing + area_recomputed: one std::log1p per
// cohort and step), the baseline, in one process on fig1_aging's work: its step Δt = 1.4417e-3 (configs/fig1_aging.toml:
// dx 0.5, cfl 0.5, c_s = 173.2), τ_a = 1, b = 0.05, one threshold class per site. The sites start stuck (A = 1, no new
// contacts: one cohort), site i first slides at t = 1 + i (T/2)/S, then slides for 2 time units every 40 (at v = 1,
// κ = 8: the attached fraction relaxes at rate 1 + κv and keeps e^{−κvΔt} of its contacts a step; at rest it heals at
// rate 1), as fig1_aging's sites do between fronts: hundreds of cohorts per site.
// Both paths step the same cohorts in blocks of 500 steps, timed block by block (new, then old), so a change in the
// machine's load falls on both. After every block the areas are compared: the largest |A_new − A_old| per unit mass,
// against the bound of docs/model.md §11.3.
//
//   ./bench_aging                              32 sites to T = 100 (69 000 steps)
//   SLIPFRONT_BENCH_QUICK=1 ./bench_aging      8 sites to T = 20 (the default test tier)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/params.hpp"
#include "discrete/aging.hpp"

using namespace slipfront;

namespace {

constexpr double dt = 1.4417e-3, kappa = 8.0, slide_v = 1.0;

// The attached fraction n of a site over one step at slip rate v (the mean field's class update with T = 1, w = 0),
// and the surviving share of the attached contacts.
struct SiteStep {
  double n_new, survive;
};
SiteStep site_step(double n, double v) {
  const double d = kappa * std::abs(v), r = 1.0 + d;
  const double n_new = n * std::exp(-r * dt) + (1.0 - std::exp(-r * dt)) / r;
  return {n_new, std::exp(-d * dt)};
}

// What a step gives a site's cohorts: the contacts attached during it that survive it, and the survivors' share.
struct Drive {
  double fresh, survive;
};

bool sliding(std::size_t i, std::size_t sites, double T, double t) {
  const double first = 1.0 + static_cast<double>(i) * 0.5 * T / static_cast<double>(sites);
  return t >= first && std::fmod(t - first, 40.0) < 2.0;
}

}  // namespace

int main() {
  const bool quick = std::getenv("SLIPFRONT_BENCH_QUICK") != nullptr;
  const std::size_t sites = quick ? 8 : 32;
  const double T = quick ? 20.0 : 100.0;
  const auto steps = static_cast<long>(T / dt);
  constexpr long block = 500;
  core::InterfaceParams p;
  p.aging_b = 0.05;
  p.aging_tau = 1.0;

  std::vector<discrete::AgeCohorts> kept(sites), old(sites);
  std::vector<double> n(sites, 1.0);
  for (std::size_t i = 0; i < sites; ++i) {
    kept[i].reset(1.0);
    old[i].reset(1.0);
  }
  std::vector<double> area_kept(sites), area_old(sites);
    double t_kept = 0.0, t_old = 0.0, max_err = 0.0, cohort_steps = 0.0, checksum = 0.0;
  std::size_t max_cohorts = 0;
  using clock = std::chrono::steady_clock;
  for (long k0 = 0; k0 < steps; k0 += block) {
    const long k1 = std::min(steps, k0 + block);
    // the site histories of this block (the same for both paths)
    std::vector<std::vector<Drive>> hist(sites);
    for (std::size_t i = 0; i < sites; ++i)
      for (long k = k0; k < k1; ++k) {
        const SiteStep st = site_step(n[i], sliding(i, sites, T, static_cast<double>(k) * dt) ? slide_v : 0.0);
        hist[i].push_back({std::max(0.0, st.n_new - n[i] * st.survive), st.survive});
        n[i] = st.n_new;
      }
    auto t0 = clock::now();
    for (std::size_t i = 0; i < sites; ++i)
      for (const Drive& st : hist[i]) {
        kept[i].step(dt, st.survive, st.fresh, p.aging_tau);
        area_kept[i] = kept[i].area(p);
      }
    auto t1 = clock::now();
    for (std::size_t i = 0; i < sites; ++i)
      for (const Drive& st : hist[i]) {
        old[i].step_recomputing(dt, st.survive, st.fresh, p.aging_tau);
        area_old[i] = old[i].area_recomputed(p);
      }
    auto t2 = clock::now();
    t_kept += std::chrono::duration<double>(t1 - t0).count();
    t_old += std::chrono::duration<double>(t2 - t1).count();
    for (std::size_t i = 0; i < sites; ++i) {
      const double mass = kept[i].mass();
      if (mass > 0.0) max_err = std::max(max_err, std::abs(area_kept[i] - area_old[i]) / mass);
      max_cohorts = std::max(max_cohorts, kept[i].size());
      cohort_steps += static_cast<double>(kept[i].size()) * static_cast<double>(k1 - k0);
      checksum += area_kept[i] + area_old[i];
    }
  }
  const double per = 1e9 / cohort_steps;
  std::printf("bench_aging: %zu sites, %ld steps of %g to T = %g, tau_a = %g, b = %g: %.3g cohort-steps, "
              "%.1f cohorts per site on average, at most %zu (checksum %.6f)\n",
              sites, steps, dt, T, p.aging_tau, p.aging_b, cohort_steps,
              cohort_steps / static_cast<double>(sites * static_cast<std::size_t>(steps)), max_cohorts, checksum);
  std::printf("  old (log1p of every cohort, every step): %.3f s, %.2f ns per cohort-step\n", t_old, t_old * per);
  std::printf("  new (kept logarithms):                   %.3f s, %.2f ns per cohort-step\n", t_kept, t_kept * per);
  std::printf("  new/old time ratio %.3f (speed-up %.2fx); largest |A_new - A_old| per unit mass %.2e "
              "(the merging's own bound b eps^2/8 = %.2e)\n",
              t_kept / t_old, t_old / t_kept, max_err, p.aging_b * discrete::cohort_merge_width * discrete::cohort_merge_width / 8.0);
  return 0;
}
