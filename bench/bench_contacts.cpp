// Cost of the contact statistics of issue 12 (docs/contacts.md §6), all in one run, plain main:
//   1. the continuum's mean-age field (output.ages) on fig1 with each integrator: wall time with it
//      off and on, and the ratio;
//   2. the contacts scene (fig1, agent N = $SLIPFRONT_BENCH_N or 10⁴, w = 0, implicit dt = 0.02, both
//      models in lockstep): discrete.contact_statistics off against on (with the continuum's prediction
//      and /compare/contacts), contact snapshots every 5 (the scene's setting) and every 0.5 (the field
//      snapshot cadence), and the ratio; the memory the statistics hold.
// Runs alternate off/on and each setting keeps its fastest of $SLIPFRONT_BENCH_REPEATS (default 3)
// runs (the machine is shared). SLIPFRONT_BENCH_T_END shortens fig1 (default 140).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "bench/scenes.hpp"
#include "compare/alongside.hpp"
#include "compare/runner.hpp"

using namespace slipfront;

namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

double wall_of(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Fastest of `repeats` runs of each of two settings, alternating.
std::pair<double, double> alternate(int repeats, const std::function<void()>& off, const std::function<void()>& on) {
  double a = std::numeric_limits<double>::infinity(), b = a;
  for (int k = 0; k < repeats; ++k) {
    a = std::min(a, wall_of(off));
    b = std::min(b, wall_of(on));
  }
  return {a, b};
}

std::size_t doubles_in(const compare::ModelResult& r) {
  std::size_t n = 0;
  for (const auto& [name, col] : r.contacts) n += col.size();
  for (const auto& [name, t] : r.contacts_2d) n += t.data.size();
  return n;
}

}  // namespace

int main() {
  const int repeats = env_int("SLIPFRONT_BENCH_REPEATS", 3);
  const compare::Scene base = bench::fig1_scene(140.0);
  std::printf("bench_contacts: fig1 to t_end = %g, fastest of %d alternating runs per setting\n\n", base.time.t_end, repeats);

  std::printf("1. continuum, output.ages off vs on (wall seconds)\n");
  std::printf("%-10s %10s %10s %8s\n", "integrator", "off", "on", "on/off");
  for (const auto integ : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal,
                           core::Integrator::adaptive_rosenbrock}) {
    compare::Scene s = base;
    s.time.integrator = integ;
    if (integ == core::Integrator::implicit_trapezoidal) s.time.dt = 0.02;
    compare::Scene on = s;
    on.output.ages = true;
    auto run = [](const compare::Scene& sc) { return [&sc] { testing::run_continuum(sc); }; };
    const auto [a, b] = alternate(repeats, run(s), run(on));
    std::printf("%-10s %10.4f %10.4f %8.3f\n", core::to_string(integ), a, b, b / a);
  }

  const long n = env_int("SLIPFRONT_BENCH_N", 10000);
  std::printf("\n2. contacts scene: continuum + agent N = %ld in lockstep, implicit dt = 0.02, output.ages = true\n", n);
  compare::Scene s = base;
  s.models = {"continuum", "discrete"};
  s.time.integrator = core::Integrator::implicit_trapezoidal;
  s.time.dt = 0.02;
  s.output.snapshot_dt = 0.5;
  s.output.ages = true;
  s.discrete.representation = "agent";
  s.discrete.contacts_per_site = n;
  s.discrete.seed = 2;
  s.validate();
  std::printf("%-34s %10s %10s %8s\n", "contact_statistics", "off", "on", "on/off");
  for (const double every : {5.0, 0.5}) {
    compare::Scene on = s;
    on.discrete.contact_statistics = true;
    on.output.contact_snapshot_dt = every;
    compare::SceneResult last;
    const auto [a, b] = alternate(
        repeats, [&] { compare::run_scene_alongside(s, compare::RunControl{}); },
        [&] { last = compare::run_scene_alongside(on, compare::RunControl{}); });
    std::printf("%-34s %10.3f %10.3f %8.3f\n", ("contact snapshots every " + std::to_string(every).substr(0, 3)).c_str(), a,
                b, b / a);
    if (every == 5.0) {
      const auto& c = last.models[0];
      const auto& d = last.models[1];
      const double cohorts = c.scalars.at("contact_prediction_max_cohorts");
      const std::size_t sites = c.x.size();
      std::printf("   memory: agent statistics %zu doubles written (%zu contact snapshots), continuum prediction %zu "
                  "doubles written;\n   prediction cohorts: at most %.0f per site (%zu sites, %.0f bytes each: at most "
                  "%.2f MB), bound ln(1e4/dt)/ln(1.05) + 2 = %.0f per site\n",
                  doubles_in(d), d.contacts.at("snapshot_t").size(), doubles_in(c), cohorts, sites, 32.0,
                  cohorts * 32.0 * static_cast<double>(sites) / 1e6, std::log(1e4 / 0.02) / std::log(1.05) + 2.0);
    }
  }
  return 0;
}
