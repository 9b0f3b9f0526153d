// Cost of the contact statistics of issue 12 (docs/contacts.md §6), all in one run, plain main:
//   1. the continuum's mean-age field (output.ages) on fig1 with each integrator: wall time with it
//      off and on, and the ratio;
//   2. the contacts scene (fig1, agent N = $SLIPFRONT_BENCH_N or 10⁴, w = 0, implicit dt = 0.02, both
//      models in lockstep): discrete.contact_statistics off against on (with the continuum's prediction
//      and /compare/contacts), contact snapshots every 5 (the scene's setting) and every 0.5 (the field
//      snapshot cadence), and the ratio; the memory the statistics hold.
//   3. the contact prediction per threshold class (docs/contacts.md §3, §6): the contacts_disorder scene
//      (the contacts scene with uniform thresholds of width w = 0.2, fresh renewal, 64 classes; agent
//      statistics on): (a) each reference model alone, its prediction off against on — the continuum's
//      (w = 0, one class per site) and the mean field's (64 classes per site) — and the ratio of the two
//      predictions' costs; (b) the scene as it runs, [continuum, mean_field, discrete] against
//      [continuum, discrete] in lockstep, and the ratio (what the mean field adds to the scene). Section 3 is
//      timed in CPU seconds of the process (single-threaded), SLIPFRONT_BENCH_SECTIONS=3 runs it alone.
// Runs alternate off/on and each setting keeps its fastest of $SLIPFRONT_BENCH_REPEATS (default 3)
// runs (the machine is shared). SLIPFRONT_BENCH_T_END shortens fig1 (default 140).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "bench/scenes.hpp"
#include "compare/alongside.hpp"
#include "compare/laws.hpp"
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

// CPU seconds of this process spent in f (single-threaded runs: the work, whatever else the shared machine runs).
double cpu_of(const std::function<void()>& f) {
  timespec a{}, b{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &a);
  f();
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &b);
  return static_cast<double>(b.tv_sec - a.tv_sec) + 1e-9 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

// Fastest of `repeats` runs of each of two settings, alternating, in CPU seconds.
std::pair<double, double> alternate_cpu(int repeats, const std::function<void()>& off, const std::function<void()>& on) {
  double a = std::numeric_limits<double>::infinity(), b = a;
  for (int k = 0; k < repeats; ++k) {
    a = std::min(a, cpu_of(off));
    b = std::min(b, cpu_of(on));
  }
  return {a, b};
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

  const char* sections = std::getenv("SLIPFRONT_BENCH_SECTIONS");
  const bool only3 = sections && std::string(sections) == "3";
  if (!only3) {
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
  }

  const long n = env_int("SLIPFRONT_BENCH_N", 10000);
  if (!only3) std::printf("\n2. contacts scene: continuum + agent N = %ld in lockstep, implicit dt = 0.02, output.ages = true\n", n);
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
  if (!only3) {
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

  }
  // 3. the prediction per threshold class: contacts_disorder (configs/contacts_disorder.toml)
  compare::Scene d = s;
  d.models = {"continuum", "mean_field", "discrete"};
  d.discrete.threshold = "uniform";
  d.discrete.width = 0.2;
  d.discrete.contact_statistics = true;
  d.output.contact_snapshot_dt = 5.0;
  d.output.compare_dt = 1.0;
  d.validate();
  compare::Scene d_off = d;  // no agent statistics: no prediction is made
  d_off.discrete.contact_statistics = false;
  std::printf("\n3. contact prediction per threshold class: contacts_disorder (w = %g uniform, fresh, %g classes)\n",
              d.discrete.width, static_cast<double>(d.discrete.bins));
  std::printf("(CPU seconds of the process: the machine is shared)\n");
  std::printf("%-34s %10s %10s %10s\n", "model alone (a)", "off", "on", "on - off");
  auto continuum_run = [](const compare::Scene& sc) {
    return [&sc] {
      auto make = [&sc](std::size_t k) { return continuum::FrictionLaw(sc.interface, k); };
      compare::run_model<continuum::FrictionLaw>(sc, make, "continuum", compare::RunControl{});
    };
  };
  auto mean_field_run = [](const compare::Scene& sc) {
    return [&sc] {
      auto make = [&sc](std::size_t k) { return compare::mean_field_law(sc, k); };
      compare::run_model<discrete::MeanFieldLaw>(sc, make, "mean_field", compare::RunControl{});
    };
  };
  const auto [c_off, c_on] = alternate_cpu(repeats, continuum_run(d_off), continuum_run(d));
  const auto [m_off, m_on] = alternate_cpu(repeats, mean_field_run(d_off), mean_field_run(d));
  std::printf("%-34s %10.3f %10.3f %10.3f\n", "continuum (1 class)", c_off, c_on, c_on - c_off);
  std::printf("%-34s %10.3f %10.3f %10.3f\n", "mean_field (64 classes)", m_off, m_on, m_on - m_off);
  std::printf("   mean-field prediction / continuum prediction: %.2f\n", (m_on - m_off) / (c_on - c_off));
  compare::Scene before = d;  // the scene before it listed mean_field
  before.models = {"continuum", "discrete"};
  const auto [b_all, d_all] = alternate_cpu(
      repeats, [&] { compare::run_scene_alongside(before, compare::RunControl{}); },
      [&] { compare::run_scene_alongside(d, compare::RunControl{}); });
  std::printf("%-34s %10s %10s %8s\n", "scene (b)", "without", "with", "ratio");
  std::printf("%-34s %10.3f %10.3f %8.3f\n", "mean_field in the models", b_all, d_all, d_all / b_all);
  return 0;
}
