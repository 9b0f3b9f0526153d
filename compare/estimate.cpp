#include "compare/estimate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "compare/initial.hpp"
#include "continuum/friction_law.hpp"
#include "core/bodies.hpp"
#include "discrete/aging.hpp"
#include "discrete/count_law.hpp"
#include "discrete/streams.hpp"

namespace slipfront::compare {
namespace {

using core::format_number;
using core::Integrator;
using core::Loading;
using core::ParamError;

constexpr double KiB = 1024.0, MiB = KiB * KiB, GiB = MiB * KiB;
constexpr double word = 8.0;                   // a double
constexpr double growth = 2.0;                 // a vector grown by push_back holds up to twice its size
// the program, its libraries and HDF5: 11.7 MiB measured for a 0D sweep (31.5 before HDF5 was linked statically), with
// a margin for what the terms below leave out (fig1 at L = 3000 peaks 2.3 MiB above them with 12)
constexpr double base_bytes = 16.0 * MiB;
constexpr double engine_bytes = static_cast<double>(sizeof(discrete::Engine));  // one stream per site: 2.5 kB
constexpr double engine_text_bytes = 6.4 * KiB;  // one stream in a checkpoint: its state as text (312 numbers)
constexpr double thread_bytes = 256.0 * KiB;   // resident part of a worker thread (stack pages touched, TLS)
constexpr double contact_stats_raw_bytes = 4.0 * 100000.0 * word;  // ContactStats::raw_cap values, 4 arrays
constexpr double contact_hist_bins = 122.0 + 101.0;  // age (log time edges) + threshold histogram bins

// Records taken at the first step at or after each multiple of `every` (0: every step): how many.
double samples(double t_end, double every, double steps) {
  if (every <= 0.0) return steps + 1.0;
  return std::min(steps + 1.0, std::floor(t_end / every + 1e-9) + 1.0);
}


std::string gib(double bytes) {
  char buf[48];
  if (bytes >= GiB) std::snprintf(buf, sizeof buf, "%.3g GiB", bytes / GiB);
  else if (bytes >= MiB) std::snprintf(buf, sizeof buf, "%.3g MiB", bytes / MiB);
  else std::snprintf(buf, sizeof buf, "%.3g KiB", bytes / KiB);
  return buf;
}

std::string duration(double seconds) {
  char buf[48];
  if (seconds < 120.0) std::snprintf(buf, sizeof buf, "%.2g s", seconds);
  else if (seconds < 7200.0) std::snprintf(buf, sizeof buf, "%.3g min", seconds / 60.0);
  else std::snprintf(buf, sizeof buf, "%.3g h", seconds / 3600.0);
  return buf;
}

std::string count(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, x < 1e6 ? "%.0f" : "%.3g", x);
  return buf;
}

// Bins of the count representation and of the agent representation's threshold index.
double count_bins(const discrete::DiscreteParams& d) {
  const bool degenerate = d.threshold == "delta" || d.width == 0.0;
  return degenerate ? 1.0 : static_cast<double>(d.bins);
}
double agent_bins(const discrete::DiscreteParams& d) {
  const bool degenerate = d.threshold == "delta" || d.width == 0.0;
  if (degenerate) return 1.0;
  const double n = static_cast<double>(d.contacts_per_site);
  return std::clamp(4.0 * std::ceil(std::sqrt(n)), 1.0, std::min(n, 4096.0));
}

// Contact state changes per contact and unit of time in steady sliding at slip rate v: detachments
// at κ|v| A_ss = κ|v|/(1 + κ|v|), each followed by an attachment.
double event_rate(const core::InterfaceParams& ip, double v) {
  const double kv = ip.kappa * std::abs(v);
  return 2.0 * kv / (1.0 + kv);
}

// Contact state changes per contact over the whole run (agent representation): exact steady rates for
// an imposed slip rate; for a bulk scene the rate at the drive's slip-rate scale (edge, spring block:
// v_d; homogeneous: the steady slip rate on the strengthening branch at σ_d) times the active fraction.
double events_per_contact(const Scene& s) {
  const auto& ip = s.interface;
  if (s.drive.loading == Loading::imposed_rate) {
    double n = 0.0;
    if (s.drive.sweep_points > 0) {
      for (const double v : sweep_rates(s.drive)) n += (s.time.t_end + s.time.slip_end / std::abs(v)) * event_rate(ip, v);
    } else {
      for (std::size_t k = 0; k < s.drive.v.size(); ++k) {
        const double end = k + 1 < s.drive.v.size() ? std::min(s.drive.v_times[k + 1], s.time.t_end) : s.time.t_end;
        if (end > s.drive.v_times[k]) n += (end - s.drive.v_times[k]) * event_rate(ip, s.drive.v[k]);
      }
    }
    return n;
  }
  double v = s.drive.v_d;
  if (s.drive.loading == Loading::homogeneous) {
    v = continuum::strengthening_branch_velocity(ip, s.drive.sigma_d);
    if (!std::isfinite(v)) v = 1.0 / std::max(ip.kappa, 1e-12);
  }
  return s.time.t_end * event_rate(ip, v) * active_fraction(s.drive.loading);
}

// Interface-law state per site (bytes) and the law's cost per site-step (ns) on top of the bulk and
// continuum law.
struct LawCost {
  double bytes_per_site = 0.0;
  double ns_per_site_step = 0.0;
  std::string what;
};
double turnover_fraction(const Scene& s);

LawCost law_cost_without_aging(const Scene& s, const std::string& model, double steps) {
  const StepCosts& c = step_costs();
  LawCost out;
  if (model == "continuum") {
    out.bytes_per_site = 2 * word;
    out.what = "continuum law";
    return out;
  }
  const auto& d = s.discrete;
  if (model == "mean_field") {  // the count representation's noise-off step without engines: B fractions, A, σ̄
    const double b = count_bins(d);
    out.bytes_per_site = word * (b + 2.0);
    out.ns_per_site_step = c.count_mean + c.count_mean_bin * b;
    out.what = "mean-field law (" + count(b) + " threshold classes)";
    return out;
  }
  const double n = static_cast<double>(d.contacts_per_site), f = turnover_fraction(s);
  if (d.representation == "count") {
    const double b = count_bins(d), det = d.renewal == "quenched" ? b : 1.0;
    const double unspread = discrete::CountLaw::keeps_unspread(d, static_cast<std::size_t>(b)) ? 1.0 : 0.0;
    out.bytes_per_site = word * (b + det + 3.0 + unspread) + engine_bytes;
    out.ns_per_site_step = d.noise ? c.count_idle + f * (c.count_active + (b > 1.0 ? c.count_bin * b : 0.0))
                                   : c.count_mean + c.count_mean_bin * b;
    out.what = "count law (" + count(b) + " bins)";
  } else if (d.representation == "agent") {
    const double b = agent_bins(d);
    // contacts in unordered arrays (attached by bin, detached): 16 B each, with the arrays' spare capacity
    out.bytes_per_site = growth * 16.0 * n + b * (3.0 * word + word) + engine_bytes + 12.0 * word;
    out.ns_per_site_step = c.agent_site + c.agent_event * n * events_per_contact(s) / std::max(1.0, steps);
    out.what = "agent law (" + count(n) + " contacts per site)";
  } else {
    out.bytes_per_site = 24.0 * n + engine_bytes + 6.0 * word;
    out.ns_per_site_step = c.naive_contact * n;
    out.what = "naive agent law (" + count(n) + " contacts per site)";
  }
  return out;
}

// The longest time one site's contacts age in a run: t_end, or a sweep's longest point (t_end + slip_end / v_min).
double longest_run(const Scene& s) {
  if (s.drive.loading == Loading::imposed_rate && s.drive.sweep_points > 0)
    return s.time.t_end + s.time.slip_end / std::max(s.drive.v_min, 1e-300);
  return s.time.t_end;
}

// Contact aging (interface.aging_b > 0, docs/model.md §11): the closure's logarithm per site-step; the age-structured
// mean field's cohorts, ~ln(1 + t/τ_a)/ε per threshold class (discrete::cohort_merge_width), each with its area every
// step (5 numbers: mass, age, the ages it spans, its kept logarithm); the agent's area summed over its contacts every step.
void add_aging_cost(const Scene& s, const std::string& model, LawCost& out) {
  if (!s.interface.ages_contacts()) return;
  const StepCosts& c = step_costs();
  if (model == "continuum") {
    out.ns_per_site_step += c.aging_closure;
    out.bytes_per_site += word;  // the mean-age state
  } else if (model == "mean_field") {
    const double cohorts =
        count_bins(s.discrete) * std::log1p(longest_run(s) / s.interface.aging_tau) / discrete::cohort_merge_width;
    out.ns_per_site_step += c.aging_cohort * cohorts;
    out.bytes_per_site += growth * 5.0 * word * cohorts;
    out.what += ", ~" + count(cohorts) + " age cohorts per site";
  } else if (s.discrete.representation == "agent" || s.discrete.representation == "naive") {
    out.ns_per_site_step += c.aging_contact * static_cast<double>(s.discrete.contacts_per_site);
  }
}

// The share of sites whose contacts turn over in a step: the loading's active fraction, or every site where a
// normal-load profile puts the resting area below 1 (they attach at rate a and detach at 1 − a at rest, docs/model.md
// §12.2: measured fig1_load_profile 28 s against fig1's 3.6 s).
double turnover_fraction(const Scene& s) {
  const auto& p = s.interface.load_p;
  const bool below = s.interface.has_load_profile() && s.interface.load_exponent != 0.0 &&
                     std::any_of(p.begin(), p.end(), [](double x) { return x < 1.0; });
  return below ? 1.0 : active_fraction(s.drive.loading);
}

LawCost law_cost(const Scene& s, const std::string& model, double steps) {
  LawCost out = law_cost_without_aging(s, model, steps);
  add_aging_cost(s, model, out);
  return out;
}

// Contact statistics (agent and naive with discrete.contact_statistics): raw values up to their cap,
// histograms and per-site counts at every contact snapshot.
double contact_stats_bytes(const Scene& s, double sites, double steps) {
  const auto& d = s.discrete;
  if (!d.contact_statistics || d.representation == "count") return 0.0;
  const double ns = s.output.snapshot_dt > 0 ? samples(s.time.t_end, s.output.snapshot_dt, steps) : 0.0;
  return contact_stats_raw_bytes + growth * word * ns * (contact_hist_bins + 2.0 * sites) + 2.0 * word * sites;
}

// The adaptive integrator's steps: an estimate, not a bound (docs/robustness.md §3). Steps are
// limited by dt_max where nothing happens, by the threshold switchings (each located switching ends a
// step: about one per node and front passage) and by accuracy in the transients, fitted on fig1 at
// rtol 1e-2 ... 1e-4 (steps ∝ rtol^-0.77 there).
double adaptive_steps(const Scene& s, double sites) {
  const double t_end = s.time.t_end;
  return std::ceil(t_end / s.time.dt_max) + sites + 8.0 * t_end * std::pow(1e-3 / s.time.rtol, 0.77);
}

// The leap integrator's steps (the discrete and mean_field models under time.integrator = adaptive, core/leap.hpp):
// an estimate, not a bound (docs/robustness.md §3), the largest of three limits fitted on the shipped scenes
// (fig1, homogeneous_front, spring_block; the chain and fig1_strip take the same steps):
//   quiet stretches and located onsets   t_end/dt_max + nodes (as the adaptive integrator's)
//   the leap condition, steps ∝ 1/ε     R t_end/ε, R the rate at which sites cross their thresholds, on edge loading
//                                        6 v_d where no count fluctuation is left unwatched (the count law's watched
//                                        step, docs/numerics.md §9.7: fig1 at ε = 0.2 1 228 steps at N = 10³, ~1 115 at
//                                        N = 10⁴, i.e. 5.3–5.9 v_d; the deterministic laws: noise off 1 160, 5.5 v_d) and
//                                        19 v_d where the ε/4 share of §9.4 holds (a noisy law the count law does not
//                                        watch: thresholds in bins, quenched, a normal load, the agent; the quenched count
//                                        3 997 steps); spring block 2.3 v_d (771 and 2 512), homogeneous 60
//                                        (homogeneous_front: 6 660 and 28 130)
//   the linearisation defect            20 t_end (1e-8/tol)^0.18 (fig1 at time.implicit_tolerance 1e-4 ... 1e-16)
double leap_steps(const Scene& s, const std::string& model, double sites) {
  const double t_end = s.time.t_end, eps = s.time.leap_epsilon, tol = s.time.implicit_tolerance;
  const auto& d = s.discrete;
  const bool noisy = model == "discrete" && d.noise;
  const bool watched = noisy && d.representation == "count" && !s.interface.ages_contacts() &&
                       discrete::CountLaw::may_watch(d, static_cast<std::size_t>(count_bins(d)), s.interface.has_normal_load());
  double rate = 60.0;
  if (s.drive.loading == Loading::edge) rate = (noisy && !watched ? 19.0 : 6.0) * s.drive.v_d;
  if (s.drive.loading == Loading::spring_block) rate = 2.3 * s.drive.v_d;
  const double quiet = std::ceil(t_end / s.time.dt_max) + sites;
  const double defect = tol > 0.0 ? 20.0 * t_end * std::pow(1e-8 / tol, 0.18) : 0.0;
  return std::max({quiet, rate * t_end / eps, defect});
}

// The implicit integrator's error control (time.implicit_tolerance, core/implicit.hpp): a step whose defect
// exceeds it is redone as two halves, at most time.implicit_max_halvings deep. Its substeps per step, an estimate:
// 1 + 1.08 (1e-6/tol)^0.65, at most 2^halvings (fig1 at dt = 0.02: 1.006, 2.08 and 51.6 at tol 1e-3, 1e-6, 1e-9).
double implicit_substeps_per_step(const Scene& s) {
  const double tol = s.time.implicit_tolerance;
  if (!(tol > 0.0) || s.time.implicit_max_halvings <= 0) return 1.0;
  return std::min(std::ldexp(1.0, s.time.implicit_max_halvings), 1.0 + 1.08 * std::pow(1e-6 / tol, 0.65));
}

// Steps of an imposed-rate history (steps aligned with the switch times, as the runner does).
double history_steps(const Scene& s) {
  const auto& vs = s.drive.v;
  const auto& ts = s.drive.v_times;
  const double dt_target = s.time.dt > 0 ? s.time.dt : s.time.t_end / s.time.steps;
  double n = 0.0;
  for (std::size_t k = 0; k < vs.size(); ++k) {
    const double end = k + 1 < vs.size() ? std::min(ts[k + 1], s.time.t_end) : s.time.t_end;
    if (end <= ts[k]) break;
    n += std::ceil((end - ts[k]) / dt_target - 1e-9);
  }
  return n;
}

// Extra steady points of the continuum sweep's golden-section search (to 1e-7 in log v).
double golden_points(const Scene& s) {
  const double span = 2.0 * std::log(s.drive.v_max / s.drive.v_min) / (s.drive.sweep_points - 1);
  return std::ceil(std::log(std::max(span, 1e-7) / 1e-7) / std::log(0.5 * (1.0 + std::sqrt(5.0)))) + 3.0;
}

// The scene's body, without building it (core::RunBody): its grid, and the values per node of its snapshot fields.
struct BodyFacts {
  core::BodyShape shape;
  std::size_t snapshot_width = 0;
};
BodyFacts body_facts(const Scene& s) {
  return core::with_body(s.bulk.body(), [&]<class B>(std::type_identity<B>) {
    BodyFacts f{B::shape(s.bulk, s.drive, s.grid)};
    for (const auto& field : B::snapshot_fields()) f.snapshot_width += field.components;
    return f;
  });
}

// The grid: its nodes (0D: one site) and, in 1D, the elastic length sqrt(μ/α) in nodes.
void put_grid(const Scene& s, Estimate& e) {
  const bool one_d = core::is_one_dimensional(s.drive.loading);
  const core::BodyShape shape = body_facts(s).shape;
  e.sites = static_cast<double>(shape.sites);
  e.rows = static_cast<double>(shape.rows);
  e.bulk_nodes = static_cast<double>(shape.dofs());
  if (one_d) {
    e.elastic_length = std::sqrt(s.bulk.mu / s.interface.alpha);
    e.nodes_per_elastic_length = e.elastic_length / s.grid.dx;
  }
}

// How a model steps: what the bulk costs per site-step (ns) and keeps per site (fields); on the strip, what
// its bulk costs per node-step and keeps per node besides (docs/performance.md §12: u, v, V, the solve's
// workspace and Eigen's CG vectors).
struct Stepping {
  double fields_per_site = 0.0;
  double bulk_ns = 0.0;
  double strip_node_ns = 0.0;
  double fields_per_node = 0.0;
};

// An imposed slip rate: the law alone in exact steps; a sweep steps every steady point (the continuum's
// golden-section points included), a history its segments.
Stepping imposed_stepping(const Scene& s, const std::string& model, ModelEstimate& m) {
  m.integrator = "exact";
  if (s.drive.sweep_points > 0) {
    const double points = s.drive.sweep_points + (model == "continuum" ? golden_points(s) : 0.0);
    m.steps = points * s.time.steps;
    m.steps_basis = count(points) + " steady points x time.steps = " + count(s.time.steps);
  } else {
    m.steps = history_steps(s);
    m.dt = s.time.dt > 0 ? s.time.dt : s.time.t_end / s.time.steps;
    m.steps_basis = "the history's segments in steps of " + format_number(m.dt);
  }
  return {0.0, step_costs().law_step};
}

// A bulk scene: adaptive steps (the continuum on the Rosenbrock integrator, the discrete and mean_field models on
// the leap integrator), or fixed steps of time.dt or time.cfl times the explicit stability limit.
Stepping bulk_stepping(const Scene& s, const std::string& model, double sites, ModelEstimate& m) {
  const StepCosts& c = step_costs();
  const double t_end = s.time.t_end;
  const double stable = explicit_stable_dt(s);
  const Integrator integ = s.time.integrator;
  // the strips: their measured costs per degree of freedom (the in-plane strip: two per node; on the leap integrator
  // the antiplane strip's)
  const bool strip = s.bulk.body() != core::BodyKind::chain, inplane = s.bulk.body() == core::BodyKind::inplane;
  if (integ == Integrator::adaptive_rosenbrock && model != "continuum") {
    m.integrator = "leap";
    m.steps = leap_steps(s, model, sites);
    // below a tolerance of 1e-5 about twice the solves a step (the trials solved again at their own rates; fig1:
    // 1.6 ... 2.5 x the time a step at 1e-6 ... 1e-14)
    const double tol = s.time.implicit_tolerance;
    m.work_steps = m.steps * (tol > 0.0 && tol < 1e-5 ? 2.0 : 1.0);
    m.steps_basis = "leap: max(t_end/dt_max + nodes, R t_end/time.leap_epsilon, 20 t_end (1e-8/time.implicit_tolerance)^0.18)"
                    " with time.leap_epsilon = " + format_number(s.time.leap_epsilon) + ", time.implicit_tolerance = " +
                    format_number(s.time.implicit_tolerance) + ", an estimate";
    // the implicit step's fields and its trial solves (about 1.6 a step), the leap tests; the strip's bulk per node
    if (strip) return {10.0, c.leap_bulk, c.strip_leap, 12.0};
    return {12.0, c.leap_bulk};
  }
  if (integ == Integrator::adaptive_rosenbrock) {
    m.integrator = "adaptive";
    m.steps = adaptive_steps(s, sites);
    m.work_steps = m.steps;
    m.steps_basis = "adaptive: t_end/dt_max + nodes + 8 t_end (rtol/1e-3)^-0.77, an estimate";
    // the strip: the law and the interface's elimination per site, the bulk per node (u, v, their ten stage
    // vectors, the masses and the u system's rhs, Strip::solve_system's workspace: docs/performance.md §13)
    // the in-plane strip: its own measured cost per dof-step and its memory, 1201 bytes a node, 600 a dof (75 words:
    // the stage vectors, the mode factors and the cache of capacitance factors; docs/performance.md §18). The strips'
    // "bulk nodes" here are their degrees of freedom (the in-plane strip has two a node).
    if (strip) return {10.0, c.explicit_bulk, inplane ? c.inplane_adaptive : c.strip_adaptive, inplane ? 75.0 : 31.0};
    return {66.0, c.adaptive_bulk};
  }
  const bool implicit = integ == Integrator::implicit_trapezoidal;
  m.integrator = implicit ? "implicit" : "explicit";
  const double dt0 = s.time.dt > 0 ? s.time.dt : s.time.cfl * stable;
  m.steps = std::max(1.0, std::ceil(t_end / dt0 - 1e-9));
  m.dt = t_end / m.steps;
  m.steps_basis = "time.t_end / dt = " + format_number(t_end) + " / " + format_number(m.dt) +
                  (s.time.dt > 0 ? " (time.dt)" : " (time.cfl x the stability limit " + format_number(stable) + ")");
  // the implicit integrator's halvings: each halved step is first solved whole, so ~2 x substeps - 1 solves a step
  const double substeps = implicit ? implicit_substeps_per_step(s) : 1.0;
  m.work_steps = m.steps * (2.0 * substeps - 1.0);
  if (substeps >= 1.5)
    m.steps_basis += "; with time.implicit_tolerance = " + format_number(s.time.implicit_tolerance) + " ~" +
                     format_number(substeps, 3) + " substeps a step (halvings, at most 2^time.implicit_max_halvings)";
  if (strip) {  // the strips: the law per site, the bulk per dof (u, v; implicit: V + 3 + 6 solve vectors)
    const double per_dof = inplane ? (implicit ? c.inplane_implicit : c.inplane_explicit)
                                   : (implicit ? c.strip_implicit : c.strip_explicit);
    // words a dof: 3 (explicit) and 12 (implicit); the in-plane strip's explicit 4 (32 bytes a dof measured,
    // docs/performance.md §18; its implicit not measured)
    const double per_node = implicit ? 12.0 : inplane ? 4.0 : 3.0;
    return {6.0, c.explicit_bulk, per_dof, per_node};
  }
  return {implicit ? 10.0 : 8.0, implicit ? c.implicit_bulk : c.explicit_bulk};
}

// What the peak memory consists of ("snapshots (continuum)", bytes).
using MemoryItems = std::vector<std::pair<std::string, double>>;

// Run time and state of one model: the bulk's and the law's cost per site-step and, on a bulk scene, the
// cost of each step; the fields, the law's state and the count law's worker threads.
void put_cost(const Scene& s, const Stepping& st, double sites, double bulk_nodes, ModelEstimate& m, MemoryItems& items) {
  if (!(m.work_steps > 0.0)) m.work_steps = m.steps;
  const LawCost law = law_cost(s, m.model, m.work_steps);
  m.site_steps = m.work_steps * sites;
  m.ns_per_site_step = st.bulk_ns + law.ns_per_site_step;
  const bool imposed = s.drive.loading == Loading::imposed_rate;
  const double nodes = st.strip_node_ns > 0.0 ? bulk_nodes : 0.0;  // the strip's bulk, costed per node
  m.node_steps = m.work_steps * nodes;
  m.seconds = m.site_steps * m.ns_per_site_step * 1e-9 + m.node_steps * st.strip_node_ns * 1e-9 +
              (imposed ? 0.0 : m.work_steps * step_costs().step * 1e-9);
  const double threads = m.model == "discrete" && s.discrete.representation == "count" && s.discrete.threads > 1
                             ? std::min<double>(s.discrete.threads, std::ceil(sites / 64.0))
                             : 0.0;
  m.state_bytes = sites * (st.fields_per_site * word + law.bytes_per_site) + nodes * st.fields_per_node * word +
                  threads * thread_bytes;
  items.emplace_back(law.what + " and fields (" + m.model + ")", m.state_bytes);
}

// What one model keeps until the end (docs/model.md §5 records), each vector up to twice its size: the
// friction law table of a sweep; series, snapshots, tip samples and contact statistics otherwise. Each
// record is listed in `items`; returns their sum.
double record_bytes(const Scene& s, const ModelEstimate& m, double sites, MemoryItems& items) {
  const double t_end = s.time.t_end;
  double rec = 0.0;
  auto add = [&](const std::string& what, double bytes) {
    if (bytes <= 0.0) return;
    rec += bytes;
    items.emplace_back(what + " (" + m.model + ")", bytes);
  };
  if (s.drive.loading == Loading::imposed_rate) {
    if (s.drive.sweep_points > 0) {
      add("friction law table", growth * 5.0 * word * s.drive.sweep_points + 4.0 * word * s.measure.batches);
    } else {
      add("series (output.series_dt)", growth * 7.0 * word * samples(t_end, s.output.series_dt, m.steps));
      add("contact statistics", contact_stats_bytes(s, 1.0, m.steps));
    }
    return rec;
  }
  const bool one_d = core::is_one_dimensional(s.drive.loading);
  const bool dense = m.integrator == "adaptive" || m.integrator == "leap";  // records at exact times, not bounded by the steps
  const double cap = dense ? std::max(m.steps, t_end / std::max(1e-300, std::min({s.output.series_dt > 0 ? s.output.series_dt : t_end,
                                                                                   s.output.snapshot_dt > 0 ? s.output.snapshot_dt : t_end,
                                                                                   s.measure.sample_dt}))) + 1.0
                           : m.steps;
  const double columns = (one_d ? 5.0 : 8.0) + (s.output.energy ? 6.0 : 0.0);
  add("series (output.series_dt)", growth * columns * word * samples(t_end, s.output.series_dt, cap));
  if (one_d) {
    if (s.output.snapshot_dt > 0)
      add("snapshots (output.snapshot_dt)", growth * word * (4.0 * sites + 1.0) * samples(t_end, s.output.snapshot_dt, cap));
    add("tip samples (measure.sample_dt)", growth * 3.0 * word * samples(t_end, s.measure.sample_dt, cap));
    const BodyFacts body = body_facts(s);
    if (body.snapshot_width > 0 && s.bulk_output.dt > 0) {  // the body's snapshot fields (the strip's u, tau_xz, tau_yz)
      const auto stride = static_cast<double>(std::max(1, s.bulk_output.stride));
      // kept_indices: ceil(n / stride) nodes, plus the last one when the stride skips it
      const auto kept = [&](double n) { return std::min(n, std::ceil(n / stride) + 1.0); };
      const double nodes = kept(sites) * kept(static_cast<double>(body.shape.rows));
      add("bulk snapshots (output.bulk_dt)",
          growth * word * (static_cast<double>(body.snapshot_width) * nodes + 1.0) * samples(t_end, s.bulk_output.dt, cap));
    }
  }
  if (m.model == "discrete") add("contact statistics", contact_stats_bytes(s, sites, m.steps));
  return rec;
}

// One model's steps, run time, state and records.
ModelEstimate model_estimate(const Scene& s, const std::string& model, double sites, double bulk_nodes,
                             MemoryItems& items) {
  ModelEstimate m;
  m.model = model;
  const Stepping st = s.drive.loading == Loading::imposed_rate ? imposed_stepping(s, model, m)
                                                               : bulk_stepping(s, model, sites, m);
  put_cost(s, st, sites, bulk_nodes, m, items);
  m.record_bytes = record_bytes(s, m, sites, items);
  return m;
}

// Output and peak memory. Records kept: every model's and, in lockstep, the field comparison. Output:
// the records as written (tip samples are not). While writing, the in-memory HDF5 image and its copy:
// two copies of the file, counted as one uncompressed copy (the fields were gzip-compressed, 2x, before
// issue 22; uncompressed by default since, output.deflate = 0: this undercounts by up to one copy). Peak: lockstep runs hold every model's state at once; sequential runs one state at a
// time. The records of every model stay until the file is written.
void put_memory(const Scene& s, Estimate& e, MemoryItems items) {
  double state_max = 0.0, state_sum = 0.0, records = 0.0;
  for (const auto& m : e.models) {
    records += m.record_bytes;
    state_max = std::max(state_max, m.state_bytes);
    state_sum += m.state_bytes;
  }
  if (runs_in_lockstep(s) && s.lists("discrete") && s.output.compare_dt > 0) {  // the discrete model vs its reference
    const double bytes = growth * 5.0 * word * samples(s.time.t_end, s.output.compare_dt, e.steps);
    records += bytes;
    items.emplace_back("field comparison (output.compare_dt)", bytes);
  }
  for (const auto& [what, bytes] : items)
    if (what.find("tip samples") == std::string::npos && what.find(" and fields ") == std::string::npos)
      e.output_bytes += bytes / growth;
  items.emplace_back("results file image while writing", e.output_bytes);
  const double run_phase = (runs_in_lockstep(s) ? state_sum : state_max) + records;
  const double write_phase = records + e.output_bytes;
  e.memory_bytes = base_bytes + std::max(run_phase, write_phase);
  std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  e.memory_items = std::move(items);
}

// Warnings that do not refuse the run: a grid that resolves the elastic length barely, a bulk too short
// for the fronts, ages asked of a representation that has none, more count-law threads than the machine.
void put_notes(const Scene& s, Estimate& e) {
  const bool one_d = core::is_one_dimensional(s.drive.loading);
  if (one_d && e.nodes_per_elastic_length < 4.0 && e.nodes_per_elastic_length >= s.limits.min_nodes_per_elastic_length)
    e.notes.push_back("grid.dx: " + format_number(e.nodes_per_elastic_length) + " nodes per elastic length sqrt(mu/alpha) = " +
                      format_number(e.elastic_length) +
                      ": event times and front speeds may be off by 1-3% (4 or more nodes: below 1%; docs/robustness.md)");
  if (one_d && s.bulk.length < 2.0 * e.elastic_length)
    e.notes.push_back("bulk.length = " + format_number(s.bulk.length) + " is shorter than 2 elastic lengths sqrt(mu/alpha) = " +
                      format_number(2.0 * e.elastic_length) +
                      ": fronts have no room to run and t* departs from the half-line formula of docs/model.md §1");
  if (s.output.ages && s.lists("discrete") && s.discrete.representation != "agent")
    e.notes.push_back("output.ages: the " + s.discrete.representation +
                      " representation carries no contact age: ages are written for the continuum model only "
                      "(discrete.representation = \"agent\" carries them)");
  if (s.output.ages && s.lists("mean_field"))
    e.notes.push_back("output.ages: the mean_field model carries no contact age (docs/model.md §2.2): none is written "
                      "under /mean_field");
  if (s.lists("mean_field") && (s.discrete.threshold == "delta" || s.discrete.width == 0.0) && !s.interface.ages_contacts())
    e.notes.push_back("mean_field with discrete.width = 0: the population balance is the continuum law (docs/model.md "
                      "§2.2); set discrete.threshold and discrete.width for a disordered interface");
  if (s.lists("discrete") && s.discrete.representation == "count" && s.discrete.threads > 1) {
    const unsigned hw = std::thread::hardware_concurrency();
    if (hw > 0 && static_cast<unsigned>(s.discrete.threads) > hw)
      e.notes.push_back("discrete.threads = " + std::to_string(s.discrete.threads) + " is more than the " +
                        std::to_string(hw) + " hardware threads of this machine (results do not depend on it)");
  }
}

// A steady-front start on the strip (issue 36 probe 3: estimated at 0.23 s, took 78 s and its solver's memory):
// the strip front's cold start, once per model (each run solves it), before the models' state exists; its
// memory is the solver's, held while it runs (the largest model state is already allocated by then).
void put_front_start(const Scene& s, Estimate& e) {
  const FrontStartCost c = front_start_cost(s);
  if (c.solves == 0) return;
  const double runs = static_cast<double>(s.models.size());
  e.start_seconds = runs * c.seconds;
  e.start_bytes = c.memory_bytes;
  e.start_basis = format_number(runs) + " x the strip front's cold start (" + std::to_string(c.solves) + " solves on " +
                  std::to_string(c.rows) + " rows x " + std::to_string(c.intervals) + " intervals, ~5 Newton iterations each)";
  e.seconds += e.start_seconds;
  double state_max = 0.0;
  for (const auto& m : e.models) state_max = std::max(state_max, m.state_bytes);
  e.memory_bytes = std::max(e.memory_bytes, base_bytes + state_max + c.memory_bytes);
  e.memory_items.emplace_back("steady-front start solve", c.memory_bytes);
  std::sort(e.memory_items.begin(), e.memory_items.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
}

}  // namespace

const StepCosts& step_costs() {
  // Measured with single runs of slipfront on fig1 and homogeneous_front (and their discrete
  // variants), scripts/estimate_accuracy.py checks them: Release build, GCC 12, one thread of the
  // shared 2-core development machine (docs/robustness.md §3).
  static const StepCosts costs{
      .explicit_bulk = 9.0,
      .implicit_bulk = 22.0,
      .adaptive_bulk = 100.0,
      .leap_bulk = 150.0,
      .count_idle = 1.0,
      .count_active = 100.0,
      .count_bin = 4.0,
      .count_mean = 20.0,
      .count_mean_bin = 1.3,
      .agent_site = 5.0,
      .agent_event = 60.0,
      .naive_contact = 1.0,
      // contact aging, fig1_aging (601 sites) to t_end = 50 ... 200 and slide_hold_slide, CPU of one run each
      // (2026-11-27): the closure 0.97 s against 0.25 s without aging at t_end = 100 (4.2e7 site-steps); the mean field
      // 1.7, 14.3, 54.4, 83.0 s at t_end = 50, 100, 150, 200 against 0.8 s without aging at 100: ~1.8 ns per cohort
      // when each cohort's area was a logarithm every step; with the kept logarithms (discrete/aging.hpp, 2026-11-28)
      // 5.98 and 31.6 s at t_end = 100 and 200 against 0.82 s: ~0.75 ns per cohort (bench_aging new/old 0.40); the
      // agent 15 s for 5.8e4 steps of 1e4 contacts
      .aging_closure = 17.0,
      .aging_cohort = 0.75,
      .aging_contact = 25.0,
      .law_step = 250.0,
      .step = 250.0,
      .strip_explicit = 2.0,
      .strip_implicit = 50.0,
      .strip_adaptive = 80.0,
      .strip_leap = 450.0,
      // fig1_inplane (601 x 35 nodes, 42070 dofs), continuum, CPU time of one run each: 2.57 s for 4920 explicit
      // steps, 14.9 s for 250 implicit steps at dt = 0.02 (its CG: ~30-40 iterations of an element loop and two
      // transforms)
      .inplane_explicit = 12.0,
      .inplane_implicit = 1400.0,
      // fig1_inplane to t = 110, continuum, adaptive (bench_inplane_work_precision, one run): 4.10 s for 395 steps at
      // rtol 5e-2 (247 ns per dof-step), 3.71 s for 341 at 1e-1 (259), capacitance factorisations included
      .inplane_adaptive = 250.0,
      .checkpoint = 7e6,
      .checkpoint_byte = 2.0,
  };
  return costs;
}

double active_fraction(Loading loading) {
  switch (loading) {
    case Loading::edge: return 0.1;
    case Loading::homogeneous: return 0.6;
    default: return 1.0;
  }
}

double explicit_stable_dt(const Scene& s) {
  if (s.drive.loading == Loading::imposed_rate) return 0.0;
  return core::with_body(s.bulk.body(), [&]<class B>(std::type_identity<B>) {
    return B::stable_time_step(s.bulk, s.drive, s.interface, s.grid);
  });
}

Estimate estimate(const Scene& s) {
  Estimate e;
  put_grid(s, e);
  MemoryItems items;  // what the peak consists of, in the order it is counted
  for (const auto& model : s.models) e.models.push_back(model_estimate(s, model, e.sites, e.bulk_nodes, items));
  for (const auto& m : e.models) {
    e.steps = std::max(e.steps, m.steps);
    e.seconds += m.seconds;
  }
  put_memory(s, e, std::move(items));
  put_front_start(s, e);
  put_notes(s, e);
  return e;
}

void check_limits(const Scene& s, const Estimate& e) {
  const auto& lim = s.limits;
  if (core::is_one_dimensional(s.drive.loading) && e.nodes_per_elastic_length < lim.min_nodes_per_elastic_length)
    throw ParamError("grid.dx",
                     format_number(s.grid.dx) + " gives " + format_number(e.nodes_per_elastic_length) +
                         " nodes per elastic length sqrt(bulk.mu/interface.alpha) = " + format_number(e.elastic_length) +
                         " (the process zone of the fronts); at least " + format_number(lim.min_nodes_per_elastic_length) +
                         " are needed for event times and front speeds within a few percent (docs/robustness.md); refine "
                         "grid.dx to at most " + format_number(e.elastic_length / lim.min_nodes_per_elastic_length) +
                         ", or set limits.min_nodes_per_elastic_length = 0 to run it anyway");
  const ModelEstimate* longest = nullptr;
  const ModelEstimate* slowest = nullptr;
  for (const auto& m : e.models) {
    if (!longest || m.steps > longest->steps) longest = &m;
    if (!slowest || m.seconds > slowest->seconds) slowest = &m;
  }
  if (longest && !(e.steps <= lim.max_steps))
    throw ParamError("limits.max_steps",
                     "the run would take " + count(e.steps) + " time steps (" + longest->model + ", " + longest->integrator +
                         ": " + longest->steps_basis + "), more than limits.max_steps = " + format_number(lim.max_steps) +
                         "; shorten time.t_end, take a larger step" +
                         (longest->integrator == "leap" ? " (time.leap_epsilon, time.implicit_tolerance)" : "") +
                         ", or raise limits.max_steps");
  if (!(e.memory_bytes <= lim.max_memory_gib * GiB)) {
    std::string what;
    for (std::size_t k = 0; k < e.memory_items.size() && k < 3; ++k)
      what += (k ? ", " : "") + e.memory_items[k].first + " " + gib(e.memory_items[k].second);
    throw ParamError("limits.max_memory_gib",
                     "the run would need about " + gib(e.memory_bytes) + " of memory (" + what +
                         "), more than limits.max_memory_gib = " + format_number(lim.max_memory_gib) +
                         "; reduce what is kept (output.snapshot_dt, output.bulk_dt, output.series_dt, measure.sample_dt), the grid, "
                         "discrete.contacts_per_site or discrete.bins, or raise limits.max_memory_gib");
  }
  if (slowest && !(e.seconds <= lim.max_hours * 3600.0))
    throw ParamError("limits.max_hours",
                     "the run would take about " + duration(e.seconds) + " (" + slowest->model + ", " + slowest->integrator +
                         ": " + count(slowest->site_steps) + " site-steps at ~" + format_number(slowest->ns_per_site_step) +
                         " ns each" +
                         (e.start_seconds > 0.0 ? "; the steady-front start ~" + duration(e.start_seconds) + ": " + e.start_basis +
                                                      ", its rows set by grid.dy"
                                                : std::string()) +
                         "), more than limits.max_hours = " + format_number(lim.max_hours) +
                         "; shorten time.t_end, coarsen the grid or the step" +
                         (slowest->integrator == "leap"       ? " (time.leap_epsilon, time.implicit_tolerance)"
                          : slowest->integrator == "implicit" ? " (time.dt, time.implicit_tolerance)"
                                                              : "") +
                         ", or raise limits.max_hours");
}

CheckpointEstimate estimate_checkpoints(const Scene& s, const Estimate& e, double every) {
  CheckpointEstimate c;
  c.every = every;
  if (s.drive.loading == Loading::imposed_rate || !(every > 0.0)) return c;
  const double multiples = std::floor(s.time.t_end / every + 1e-9);  // inf for a tiny T: bounded by the steps
  double state = 0.0, records = 0.0;
  for (const auto& m : e.models) {
    state += m.state_bytes + (m.model == "discrete" ? e.sites * (engine_text_bytes - engine_bytes) : 0.0);
    records += m.record_bytes / growth;  // as written: without the vectors' spare capacity
    if (!runs_in_lockstep(s)) c.writes += std::min(m.steps, multiples);
  }
  if (runs_in_lockstep(s)) c.writes = std::min(e.steps, multiples);
  c.largest_bytes = state + records;
  c.bytes = c.writes * (state + 0.5 * records);
  const StepCosts& cost = step_costs();
  c.seconds = (c.writes * cost.checkpoint + c.bytes * cost.checkpoint_byte) * 1e-9;
  c.memory_bytes = e.memory_bytes + 2.0 * c.largest_bytes;
  return c;
}

void check_checkpoint_limits(const Scene& s, const Estimate& e, const CheckpointEstimate& c) {
  const auto& lim = s.limits;
  const bool every_step = std::floor(s.time.t_end / c.every + 1e-9) >= e.steps;
  const std::string what = "every " + format_number(c.every) + ": " + count(c.writes) +
                           (c.writes == 1.0 ? " checkpoint" : " checkpoints") + " of up to " + gib(c.largest_bytes) +
                           (every_step ? " (one every step)" : "");
  if (!(c.bytes <= lim.max_checkpoint_gib * GiB)) {
    // the cadence at which they would write the limit (each checkpoint as large on average)
    const double allowed = lim.max_checkpoint_gib * GiB / (c.bytes / c.writes);
    const double loops = runs_in_lockstep(s) ? 1.0 : static_cast<double>(e.models.size());
    const std::string instead = allowed >= loops ? "checkpoint less often (T >= " +
                                                       format_number(1.01 * s.time.t_end * loops / allowed, 3) + ")"
                                                 : "a checkpoint alone is that large";
    throw ParamError("--checkpoint-every", what + ", about " + gib(c.bytes) + " in all, more than limits.max_checkpoint_gib = " +
                                               format_number(lim.max_checkpoint_gib) + "; " + instead +
                                               ", or raise limits.max_checkpoint_gib");
  }
  if (!(e.seconds + c.seconds <= lim.max_hours * 3600.0))
    throw ParamError("--checkpoint-every", what + ", taking about " + duration(c.seconds) + " on top of the run's " +
                                               duration(e.seconds) + ", more than limits.max_hours = " +
                                               format_number(lim.max_hours) +
                                               "; checkpoint less often, or raise limits.max_hours");
  if (!(c.memory_bytes <= lim.max_memory_gib * GiB))
    throw ParamError("--checkpoint-every", what + ": the run would need about " + gib(c.memory_bytes) +
                                               " of memory while one is written (two copies of it on top of the run's " +
                                               gib(e.memory_bytes) + "), more than limits.max_memory_gib = " +
                                               format_number(lim.max_memory_gib) + "; raise limits.max_memory_gib");
}

std::string describe(const CheckpointEstimate& c) {
  return "checkpoints (--checkpoint-every " + format_number(c.every) + "): " + count(c.writes) + " of up to " +
         gib(c.largest_bytes) + ", ~" + gib(c.bytes) + " in all, ~" + duration(c.seconds) + " to write";
}

std::vector<std::string> describe(const Estimate& e) {
  std::vector<std::string> out;
  for (const auto& m : e.models)
    out.push_back(m.model + ": " + count(m.steps) + " steps (" + m.integrator + "; " + m.steps_basis + ") x " +
                  count(e.sites) + (e.sites == 1.0 ? " site" : " sites") +
                  (e.rows > 1.0 ? " (strip: " + count(e.rows) + " rows, " + count(e.bulk_nodes) + " bulk nodes)" : "") +
                  ", ~" + duration(m.seconds));
  std::string mem = "memory: ~" + gib(e.memory_bytes) + " peak (";
  for (std::size_t k = 0; k < e.memory_items.size() && k < 3; ++k)
    mem += (k ? ", " : "") + e.memory_items[k].first + " " + gib(e.memory_items[k].second);
  out.push_back(mem + ")");
  if (e.start_seconds > 0.0)
    out.push_back("steady-front start: ~" + duration(e.start_seconds) + ", ~" + gib(e.start_bytes) + " (" + e.start_basis + ")");
  out.push_back("run time: ~" + duration(e.seconds) + " (calibrated costs: docs/robustness.md)");
  for (const auto& n : e.notes) out.push_back("note: " + n);
  return out;
}

}  // namespace slipfront::compare

// ---------------------------------------------------------------------------------------------
// Studies (issue 18): what the study's own process holds, before any run is expanded.

namespace slipfront::compare {
namespace {

// What a run's results keep in memory until the analysis (compare::ModelResult without the fields, which
// a study's runs drop once written): the records the scene's estimate lists as series and friction-law
// tables, and the node positions, per model.
double kept_result_bytes(const Estimate& e) {
  double bytes = 0.0;
  for (const auto& [what, b] : e.memory_items)
    if (what.rfind("series (", 0) == 0 || what.rfind("friction law table (", 0) == 0) bytes += b;
  for (std::size_t k = 0; k < e.models.size(); ++k) bytes += static_cast<double>(sizeof(ModelResult)) + e.sites * word;
  return bytes;
}

// The plan's bytes for one run: the StudyRun (its overrides and point, twice: strings and map nodes),
// the Scene, its resolved TOML, and the per-run entries of the schedule and of the results.
double plan_bytes_per_run(const StudySpec& spec, const StudyRun& run, std::size_t resolved_bytes) {
  constexpr double string_bytes = sizeof(std::string), map_node = 64.0;
  double text = 0.0;
  for (const auto& o : run.overrides) text += string_bytes + static_cast<double>(o.size());
  for (const auto& [k, v] : run.point) text += map_node + 2.0 * string_bytes + static_cast<double>(k.size() + v.size());
  if (spec.seeds > 1) text += string_bytes + 24.0;  // "discrete.seed=<n>" (the samples have seed 1 only)
  return static_cast<double>(sizeof(StudyRun) + sizeof(Scene)) + text + string_bytes +
         static_cast<double>(resolved_bytes) + static_cast<double>(sizeof(std::vector<ModelResult>)) + 16.0;
}

}  // namespace

StudyEstimate estimate_study(const StudySpec& spec, const std::vector<StudyRun>& samples,
                             const std::vector<Scene>& sample_scenes, const std::vector<std::size_t>& resolved_bytes) {
  StudyEstimate e;
  e.runs = count_runs(spec);
  e.directories = e.runs + 2.0;
  // Each sample stands for the runs of its group: its points x seeds.
  for (std::size_t k = 0; k < samples.size() && k < sample_scenes.size() && k < resolved_bytes.size(); ++k) {
    double runs_of_group = std::max(1, spec.seeds);
    if (k < spec.groups.size())
      for (const auto& [key, values] : spec.groups[k].vary) runs_of_group *= static_cast<double>(values.size());
    e.plan_bytes += runs_of_group * plan_bytes_per_run(spec, samples[k], resolved_bytes[k]);
    e.results_bytes += runs_of_group * kept_result_bytes(estimate(sample_scenes[k]));
  }
  e.memory_bytes = base_bytes + e.plan_bytes + e.results_bytes;
  return e;
}

void check_study_limits(const StudySpec& spec, const StudyEstimate& e) {
  const StudyLimits& lim = spec.limits;
  if (!(e.runs <= lim.max_runs)) {
    std::string points;
    for (const StudyGroup& g : spec.groups) {
      double product = 1.0;
      for (const auto& [key, values] : g.vary) product *= static_cast<double>(values.size());
      points += (points.empty() ? "" : " + ") + count(product);
    }
    throw ParamError("limits.max_runs",
                     "the study would make " + count(e.runs) + " runs ((" + (points.empty() ? "1" : points) +
                         ") points x " + std::to_string(std::max(1, spec.seeds)) +
                         " seeds, each a directory runs/<id>/ with its results file), more than limits.max_runs = " +
                         count(lim.max_runs) +
                         "; vary fewer values, take fewer seeds, or raise limits.max_runs in the study file's [limits]");
  }
  if (!(e.memory_bytes <= lim.max_memory_gib * GiB))
    throw ParamError("limits.max_memory_gib",
                     "the study would hold about " + gib(e.memory_bytes) + " in memory (the plan of " + count(e.runs) +
                         " runs " + gib(e.plan_bytes) + ", their results kept for the analysis " + gib(e.results_bytes) +
                         "), more than limits.max_memory_gib = " + format_number(lim.max_memory_gib) +
                         "; make fewer runs, record less per run (output.series_dt), or raise limits.max_memory_gib in "
                         "the study file's [limits]");
}

std::string describe(const StudyEstimate& e) {
  return "~" + gib(e.memory_bytes) + " in memory: plan " + gib(e.plan_bytes) + ", results kept " + gib(e.results_bytes);
}

}  // namespace slipfront::compare
