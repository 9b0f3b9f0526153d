#include "compare/scene.hpp"

#include <algorithm>
#include <cmath>

#include "core/bulk.hpp"
#include "core/implicit.hpp"
#include "compare/estimate.hpp"
#include "compare/models.hpp"

namespace slipfront::compare {

namespace {
using core::KeyDomain;
using K = core::KeyKind;
const KeyDomain limit_domains[] = {
    {"limits.max_steps", K::number, 1.0, 1e15, false, false, false, "",
     "(time steps of any model; step counts stay exact in doubles and int64)"},
    {"limits.max_memory_gib", K::number, 0.0, 1e6, true},
    {"limits.max_hours", K::number, 0.0, 1e6, true},
    {"limits.max_checkpoint_gib", K::number, 0.0, 1e6, true, false, false, "",
     "(the data all checkpoints of a run write together: --checkpoint-every)"},
    {"limits.min_nodes_per_elastic_length", K::number, 0.0, 1e6, false, false, false, "", "(0: no resolution check)"},
};
const KeyDomain bulk_output_domains[] = {
    {"output.bulk_dt", K::number, 0.0, core::parameter_cap, false, false, false, "",
     "(0: no bulk snapshots; used on the strip, bulk.height)"},
    {"output.bulk_stride", K::integer, 1.0, 1e9, false, false, false, "",
     "(keep every k-th node in x and y; the last column and the top row always)"},
};

// The model names: known, at least one, none twice.
void check_models(const std::vector<std::string>& models) {
  using core::ParamError;
  if (models.empty()) throw ParamError("models", "must list at least one model");
  for (std::size_t k = 0; k < models.size(); ++k) {
    const auto& m = models[k];
    if (!find_model_kind(m)) throw ParamError("models", "unknown model '" + m + "' (expected " + model_names() + ")");
    if (std::find(models.begin(), models.begin() + static_cast<std::ptrdiff_t>(k), m) != models.begin() + static_cast<std::ptrdiff_t>(k))
      throw ParamError("models", "lists '" + m + "' twice (each model runs once)");
  }
}

// The mean-field law's rules (docs/model.md §2.2): it reads the threshold law's keys only (checked here when the
// discrete model, whose validate() checks them, does not run). Its state is the attached fraction per threshold
// class, not a rate law on [A | σ̄]: with time.integrator = adaptive it runs on the step-controlled implicit
// integrator (core/leap.hpp), as the discrete model does.
void check_mean_field(const Scene& s) {
  if (!s.lists("discrete")) s.discrete.validate_threshold_law();
}

// Too few rows (docs/numerics.md §8.2): the y profile under the interface is not resolved; lifted with the
// grid's other resolution check (limits.min_nodes_per_elastic_length = 0). Measured on the antiplane strip; the
// in-plane strip (docs/model.md §10) takes the same rule (its thin limit has the same elastic length sqrt(mu/alpha),
// mu = E'H), not yet measured there.
void check_strip_rows(const Scene& s) {
  if (!(s.limits.min_nodes_per_elastic_length > 0.0)) return;
  const double dy = s.grid.row_spacing(), H = s.bulk.height, dy_max = strip_max_row_spacing(s.bulk.mu, s.interface.alpha, H);
  if (dy <= dy_max * (1.0 + 1e-12)) return;
  const double le = std::sqrt(s.bulk.mu / s.interface.alpha);
  const auto rows = static_cast<long long>(std::llround(H / dy));
  const auto need = static_cast<long long>(std::ceil(H / dy_max * (1.0 - 1e-12)));
  throw core::ParamError(
      "grid.dy",
      core::format_number(dy) + (s.grid.dy == 0.0 ? " (grid.dy absent: grid.dx)" : "") + " gives " +
          std::to_string(rows) + " row interval" + (rows == 1 ? "" : "s") + " over bulk.height = " +
          core::format_number(H) + ": too few rows to resolve the strip for the measurements; (dy/l_e)^2 (H/l_e) = " +
          core::format_number((dy / le) * (dy / le) * (H / le), 3) + " > 1/30 (l_e = sqrt(bulk.mu/interface.alpha) = " +
          core::format_number(le, 4) + "), where fig1's event times and front speeds are off by more than ~1% "
          "(docs/numerics.md §8.2); use grid.dy <= " + core::format_number(dy_max, 4) + " (bulk.height/grid.dy >= " +
          std::to_string(need) + " rows), or set limits.min_nodes_per_elastic_length = 0 to run it anyway");
}

// Contact aging (docs/model.md §11): the models that carry what it needs. The count and naive representations keep
// no ages; the steady-front and nucleation starts and the Rosenbrock state [A | σ̄] know no aging yet.
void check_aging(const Scene& s) {
  using core::ParamError;
  if (!s.interface.ages_contacts()) return;
  if (s.lists("discrete") && s.discrete.representation != "agent")
    throw ParamError("discrete.representation",
                     "the " + s.discrete.representation + " representation keeps no contact ages, so it cannot age its "
                     "contacts (interface.aging_b = " + core::format_number(s.interface.aging_b) +
                     "): use representation = \"agent\", or the model mean_field (the age-structured balance, docs/model.md §11)");
  if (s.drive.loading == core::Loading::homogeneous)
    throw ParamError("drive.loading", "homogeneous loading with interface.aging_b > 0: the nucleation patch and the "
                                      "steady-front start are the non-aging steady state (not yet for aging, docs/model.md §11)");
  if (s.drive.loading != core::Loading::imposed_rate && s.time.integrator == core::Integrator::adaptive_rosenbrock)
    throw ParamError("time.integrator", "adaptive with interface.aging_b > 0: the aging laws' extra state (the closure's "
                                        "mean age, the contacts' age cohorts) is not in the adaptive integrators' state "
                                        "(not yet, docs/model.md §11); use explicit or implicit");
}

// What a normal load of either kind (a profile, the in-plane coupling) is not built with yet (docs/model.md §12).
void check_normal_load_carriers(const Scene& s) {
  using core::ParamError;
  if (s.interface.ages_contacts())
    throw ParamError("interface.aging_b", "contact aging together with a normal-load profile or coupling "
                                          "(interface.load_p, load_coupling) is not built yet (docs/model.md §12): set "
                                          "one of them");
  if (s.output.ages)
    throw ParamError("output.ages", "the mean contact age with a normal load: the age equation of docs/model.md "
                                    "§7.1 knows no spontaneous detachment (the re-attachment channel's 1 - a), not yet");
  if (s.lists("discrete") && s.discrete.representation == "naive")
    throw ParamError("discrete.representation",
                     "the naive representation does not carry a normal load: use representation = \"count\" or "
                     "\"agent\", or the model mean_field (docs/model.md §12)");
  if (s.lists("discrete") && s.discrete.contact_statistics)
    throw ParamError("discrete.contact_statistics", "contact statistics with a normal load: their prediction "
                                                    "(docs/model.md §7.2) knows no spontaneous detachment, not yet");
}

// A prescribed normal load (docs/model.md §12): on an edge-loaded chain or antiplane strip, with the models and
// integrators that carry it; everything else is refused before any work.
void check_normal_load(const Scene& s) {
  using core::ParamError;
  const auto& ip = s.interface;
  if (!ip.has_load_profile()) return;
  if (s.drive.loading != core::Loading::edge)
    throw ParamError("interface.load_p",
                     std::string("a normal-load profile p(x) needs an interface along x: drive.loading = \"edge\" (") +
                         (core::is_one_dimensional(s.drive.loading)
                              ? "homogeneous loading's nucleation patch and steady-front start are the unloaded steady "
                                "state: not yet"
                              : "a 0D scene has one site and no x") +
                         ", docs/model.md §12)");
  if (s.bulk.body() == core::BodyKind::inplane)
    throw ParamError("interface.load_p", "the in-plane strip's normal stress comes from its body (sigma_yy), not from "
                                         "a prescribed profile (docs/model.md §12): use the chain or the antiplane strip");
  // The adaptive integrators carry a profile (docs/model.md §12.8): the continuum's rates relax A towards (p/p_0)^m, the
  // other laws take their own loaded step on leap steps; the agent's leap steps under a load are not measured yet.
  if (s.time.integrator == core::Integrator::adaptive_rosenbrock && s.lists("discrete") &&
      s.discrete.representation == "agent")
    throw ParamError("time.integrator", "adaptive with a normal-load profile and the agent representation: its leap "
                                        "steps under a load are not measured yet (docs/model.md §12.8); use "
                                        "representation = \"count\", or the explicit or implicit integrator");
  check_normal_load_carriers(s);
  if (ip.load_exponent == 0.0) return;  // (p/p_0)^0 = 1 everywhere: today's model
  for (std::size_t k = 0; k < ip.load_p.size(); ++k) {
    if (ip.instantaneous_load() && !(ip.load_p[k] > 0.0))
      throw ParamError("interface.load_p", "p = 0 under load_channel = \"instantaneous\": a site with no load has no "
                                           "contact area to scale (entry " + std::to_string(k + 1) + ")");
    if (!ip.instantaneous_load() && ip.load_p[k] > 1.0 && (s.lists("discrete") || s.lists("mean_field")))
      throw ParamError("interface.load_p", "p/p_0 = " + core::format_number(ip.load_p[k]) + " > 1 (entry " +
                                               std::to_string(k + 1) + ") under load_channel = \"reattachment\": a "
                                               "site's N contacts are its capacity at p_0, so the discrete and "
                                               "mean_field models need p <= p_0 (docs/model.md §12.2)");
  }
}

// The in-plane strip's own normal load (docs/model.md §12.5): p(x, t) = −σ_yy(x, 0, t) against p_0 = bulk.normal_load,
// on the models and integrators that take a changing load; everything else is refused before any work.
void check_load_coupling(const Scene& s) {
  using core::ParamError;
  const auto& ip = s.interface;
  if (!ip.couples_load()) return;
  if (s.bulk.body() != core::BodyKind::inplane)
    throw ParamError("interface.load_coupling", "\"sigma_yy\" needs the in-plane strip (bulk.body = \"inplane\"): the chain "
                                                "and the antiplane strip have no interface normal stress (use "
                                                "interface.load_p for a prescribed profile, docs/model.md §12)");
  if (!(s.bulk.normal_load > 0.0))
    throw ParamError("bulk.normal_load", "must be > 0 with interface.load_coupling = \"sigma_yy\": it is the reference "
                                         "load p_0 of p = p_0 - sigma_yy (docs/model.md §12.5), got " + core::format_number(s.bulk.normal_load));
  if (ip.has_load_profile())
    throw ParamError("interface.load_p", "a prescribed profile and interface.load_coupling = \"sigma_yy\" together: the "
                                         "in-plane strip's load is its own sigma_yy (docs/model.md §12.5); set one of them");
  if (s.time.integrator != core::Integrator::central_difference && s.time.integrator != core::Integrator::implicit_trapezoidal)
    throw ParamError("time.integrator", "adaptive with interface.load_coupling: the Rosenbrock stages would need the load "
                                        "p(u) inside the step, its Jacobian couples each site's A to the strip's "
                                        "displacements (the site-by-site elimination does not hold), and the "
                                        "instantaneous channel's A = a phi needs phi as state (not built, docs/model.md "
                                        "§12.5); use explicit or implicit");
  check_normal_load_carriers(s);
}

}  // namespace

std::span<const KeyDomain> limit_key_domains() { return limit_domains; }
std::span<const KeyDomain> bulk_output_key_domains() { return bulk_output_domains; }

void BulkOutputParams::validate() const {
  core::check_in_domain(*core::find_key_domain(bulk_output_key_domains(), "output.bulk_dt"), dt);
  core::check_in_domain(*core::find_key_domain(bulk_output_key_domains(), "output.bulk_stride"), stride);
}

std::vector<std::size_t> kept_indices(std::size_t n, std::size_t stride) {
  std::vector<std::size_t> out;
  if (n == 0) return out;
  stride = std::max<std::size_t>(stride, 1);
  for (std::size_t k = 0; k < n; k += stride) out.push_back(k);
  if (out.back() != n - 1) out.push_back(n - 1);
  return out;
}

std::vector<KeyDomain> all_key_domains() {
  std::vector<KeyDomain> out;
  for (const auto table : {core::key_domains(), discrete::key_domains(), bulk_output_key_domains(), limit_key_domains()})
    out.insert(out.end(), table.begin(), table.end());
  return out;
}

const KeyDomain* find_key_domain(std::string_view key) {
  for (const auto table : {core::key_domains(), discrete::key_domains(), bulk_output_key_domains(), limit_key_domains()})
    if (const KeyDomain* d = core::find_key_domain(table, key)) return d;
  return nullptr;
}

void LimitParams::validate() const {
  for (const auto& [key, value] : {std::pair{"limits.max_steps", max_steps}, {"limits.max_memory_gib", max_memory_gib},
                                   {"limits.max_hours", max_hours}, {"limits.max_checkpoint_gib", max_checkpoint_gib},
                                   {"limits.min_nodes_per_elastic_length", min_nodes_per_elastic_length}})
    core::check_in_domain(*core::find_key_domain(limit_key_domains(), key), value);
}

void Scene::validate() const {
  using core::ParamError;
  check_models(models);
  const bool one_d = core::is_one_dimensional(drive.loading);
  interface.validate();
  bulk.validate(one_d);
  drive.validate();
  grid.validate(bulk, one_d);
  time.validate(drive.loading);
  measure.validate();
  output.validate();
  bulk_output.validate();
  limits.validate();
  const bool continuum_runs = lists("continuum");
  const bool discrete_runs = lists("discrete");
  if (discrete_runs) discrete.validate();
  if (lists("mean_field")) check_mean_field(*this);
  check_aging(*this);
  check_normal_load(*this);
  check_load_coupling(*this);
  // (scene rules, not DiscreteParams::validate, which every law's constructor runs on its own parameters)
  if (discrete_runs && discrete.contact_statistics && discrete.representation == "count")  // would record nothing
    throw ParamError("discrete.contact_statistics",
                     "the count representation keeps counts per threshold bin, not contacts: it has no lifetimes, ages or "
                     "thresholds to record (use discrete.representation = \"agent\")");
  // Only the continuum law and the agent representation carry contact ages (docs/model.md §7.1): a run that
  // asks for them and has neither would end "complete" with none (a run with the continuum and count or
  // naive gets the continuum's, and a note says so: compare::estimate).
  if (output.ages && !continuum_runs && (!discrete_runs || discrete.representation != "agent"))
    throw ParamError("output.ages", (discrete_runs ? "the " + discrete.representation + " representation carries"
                                                   : std::string("the mean_field model carries")) +
                                        " no contact age and the continuum model does not run: no "
                                        "age would be written (use discrete.representation = \"agent\", or add \"continuum\" "
                                        "to models)");
  if (bulk.body() != core::BodyKind::chain) check_strip_rows(*this);
  if (drive.loading == core::Loading::imposed_rate && drive.sweep_points == 0 && drive.v_times.back() >= time.t_end)
    throw ParamError("drive.switch_times", "every switch time must be before time.t_end (" +
                                              core::format_number(time.t_end) + "), got " +
                                              core::format_number(drive.v_times.back()));
  if (drive.loading != core::Loading::imposed_rate && time.integrator == core::Integrator::implicit_trapezoidal &&
      time.implicit_resolution_check) {
    const core::Bulk b(bulk, drive, interface, grid.dx);
    const auto r = core::implicit_resolution(b, interface, measure.v_event, time.dt);
    using R = core::ImplicitResolution;
    // both values are proportional to dt: the largest admissible step is dt · bound / value
    auto check = [&](const char* what, double value, double bound, const char* why) {
      if (value > bound)
        throw ParamError("time.dt", std::string("too large for the implicit integrator: ") + what + " = " +
                                        core::format_number(value, 4) + " > " + core::format_number(bound) + " (" +
                                        why + "); use time.dt <= " + core::format_number(time.dt * bound / value, 4) +
                                        ", the explicit or adaptive integrator, or time.implicit_resolution_check = false");
    };
    check("dt sqrt(K/(rho w_0))", r.drive, R::drive_bound,
          "the drive spring's oscillation of the edge node is neither resolved nor damped");
    check("dt (1 + kappa v_event)", r.detach, R::detach_bound,
          "the contact turnover at the event slip rate is not resolved: spurious or missed events");
  }
  if (drive.loading != core::Loading::imposed_rate && time.dt > 0 && time.integrator != core::Integrator::implicit_trapezoidal) {
    const double stable = explicit_stable_dt(*this);
    if (time.dt > stable)
      throw ParamError("time.dt", "exceeds the explicit stability limit " + core::format_number(stable) +
                                      " of this grid (use time.cfl <= 1, a smaller dt, or time.integrator = \"implicit\")");
  }
  check_limits(*this, estimate(*this));
}

double strip_max_row_spacing(double mu, double alpha, double height) {
  const double le = std::sqrt(mu / alpha);
  return le * std::sqrt(strip_row_rule_bound * le / height);
}

bool Scene::lists(std::string_view model) const { return std::find(models.begin(), models.end(), model) != models.end(); }

const char* discrete_reference(const Scene& s) {
  const auto& refs = find_model_kind("discrete")->references;  // compare/models.hpp: the first one listed, else the last
  for (const auto& r : refs)
    if (!r.empty() && s.lists(r)) return r.data();
  return refs.back().data();
}

bool runs_in_lockstep(const Scene& s) {
  const auto listed = std::count_if(model_kinds.begin(), model_kinds.end(), [&](const ModelKind& k) { return s.lists(k.name); });
  return listed >= 2 && s.drive.loading != core::Loading::imposed_rate &&
         s.time.integrator != core::Integrator::adaptive_rosenbrock;
}

std::vector<double> sweep_rates(const core::DriveParams& d) {
  std::vector<double> v(static_cast<std::size_t>(d.sweep_points));
  const double a = std::log(d.v_min), b = std::log(d.v_max);
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = std::exp(a + (b - a) * static_cast<double>(k) / static_cast<double>(v.size() - 1));
  return v;
}

}  // namespace slipfront::compare
