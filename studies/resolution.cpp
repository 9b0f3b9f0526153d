#include "studies/resolution.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "compare/fit.hpp"
#include "studies/study.hpp"

namespace slipfront::studies {

namespace {

using core::KeyDomain;
using K = core::KeyKind;
constexpr KeyDomain resolution_domains[] = {
    {"resolution.levels", K::integer, 0.0, 6.0, false, false, false, "", "(refined levels beyond the scene's own)"},
    {"resolution.coarser", K::integer, 0.0, 4.0, false, false, false, "", "(coarser levels than the scene's own)"},
    {"resolution.ratio", K::number, 1.0, 4.0, true, false, false, "", "(refinement ratio between levels)"},
    {"resolution.tolerance", K::number, 0.0, 1.0, true, true, false, "",
     "(relative error each event must meet at the scene's own level)"},
    {"resolution.tolerance_order", K::number, 0.0, 8.0, true, false, false, "",
     "(tolerances are divided by ratio^tolerance_order per level)"},
    {"resolution.seeds", K::integer, 0.0, 10000.0, false, false, false, "",
     "(runs of a stochastic model at the scene's own level; 0: none)"},
};

// The events the check follows (docs/output.md `events`): each that the scene's own level measures is reported.
// c_slow_alt: the slow front on the A_tip_alt front, as fig1 reports it (its A_tip front exists only late).
struct CheckedEvent {
  const char* name;
  double Events::*field;
  bool alt;
};
constexpr CheckedEvent checked_events[] = {
    {"t_star", &Events::t_star, false},           {"t_hat", &Events::t_hat, false},
    {"c_slow", &Events::c_slow, false},           {"c_slow_alt", &Events::c_slow, true},
    {"c_transient", &Events::c_transient, false}, {"c_transient_peak", &Events::c_transient_peak, false},
    {"x_arrest", &Events::x_arrest, false},       {"t_arrest", &Events::t_arrest, false},
    {"c_front", &Events::c_front, false},         {"v_behind", &Events::v_behind, false}};
constexpr const char* model_order[] = {"continuum", "mean_field", "discrete"};

double event_of(const ModelResult& r, const CheckedEvent& e) { return (e.alt ? r.events_alt : r.events).*e.field; }

// A number as --set reads it back exactly (the shortest text that round-trips; a float stays a float).
std::string number_text(double x) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

bool stochastic(const Scene& s) { return s.lists("discrete") && s.discrete.noise; }

// A scene on a grid (edge or homogeneous loading: the chain or the strip), not a 0D one.
bool one_dimensional(const Scene& s) {
  return s.drive.loading == core::Loading::edge || s.drive.loading == core::Loading::homogeneous;
}

// The overrides that make level k (h = r^-k of the scene's) from the base scene: the grid refined by r^k, the fixed
// step with it (explicit with time.cfl: the step follows dx through the stability limit; 0D: cfl itself), the
// integrator's tolerances by r^(q k).
std::vector<std::pair<std::string, std::vector<std::string>>> level_overrides(const Scene& s, const ResolutionOptions& o,
                                                                             int k) {
  const double f = std::pow(o.ratio, k), ft = std::pow(o.ratio, o.tolerance_order * k);
  std::vector<std::pair<std::string, std::vector<std::string>>> v;
  const auto set = [&](const char* key, double x) { v.push_back({key, {number_text(x)}}); };
  const bool bulk = one_dimensional(s);
  if (bulk) set("grid.dx", s.grid.dx / f);
  if (bulk && s.bulk.body() != core::BodyKind::chain) set("grid.dy", s.grid.row_spacing() / f);
  const bool ensemble = s.lists("discrete") || s.lists("mean_field");
  switch (s.time.integrator) {
    case core::Integrator::central_difference:
      if (s.time.dt > 0.0) set("time.dt", s.time.dt / f);
      else if (!bulk) set("time.cfl", s.time.cfl / f);
      break;
    case core::Integrator::implicit_trapezoidal:
      set("time.dt", s.time.dt / f);
      if (s.time.implicit_tolerance > 0.0) set("time.implicit_tolerance", s.time.implicit_tolerance / ft);
      break;
    case core::Integrator::adaptive_rosenbrock:
      set("time.rtol", s.time.rtol / ft);
      set("time.atol", s.time.atol / ft);
      if (ensemble) set("time.leap_epsilon", s.time.leap_epsilon / ft);
      if (ensemble && s.time.implicit_tolerance > 0.0) set("time.implicit_tolerance", s.time.implicit_tolerance / ft);
      break;
  }
  v.push_back({"output.compare_dt", {"0.0"}});  // events only: the continuum is then shared between a level's runs
  return v;
}

std::string level_name(int k, bool noise_off) { return "level" + std::to_string(k) + (noise_off ? "_noise_off" : ""); }

// The level of a group named by level_name (false for any other name).
bool parse_level(const std::string& group, int& k, bool& noise_off) {
  if (group.rfind("level", 0) != 0) return false;
  const char* first = group.data() + 5;
  const char* last = group.data() + group.size();
  const auto r = std::from_chars(first, last, k);
  if (r.ec != std::errc() || r.ptr == first) return false;
  const std::string rest(r.ptr, last);
  noise_off = rest == "_noise_off";
  return rest.empty() || noise_off;
}

}  // namespace

std::span<const KeyDomain> resolution_key_domains() { return resolution_domains; }

void check_resolution_options(const ResolutionOptions& o) {
  if (o.levels + o.coarser < 2)
    throw core::ParamError("resolution.levels",
                           "the check needs at least three levels (the scene's own and two more) for an observed order: "
                           "levels + coarser must be >= 2, got " + std::to_string(o.levels) + " + " +
                               std::to_string(o.coarser));
}

RichardsonEstimate richardson(std::span<const double> f, std::size_t base, double ratio) {
  RichardsonEstimate e;
  const std::size_t n = f.size();
  if (n < 3 || base >= n || !(ratio > 1.0)) return e;
  for (double x : f)
    if (!std::isfinite(x)) return e;  // "missing"
  double scale = 0.0, scatter = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    scale = std::max(scale, std::abs(f[j]));
    scatter = std::max(scatter, std::abs(f[base] - f[j]));
  }
  const double d1 = f[n - 3] - f[n - 2], d2 = f[n - 2] - f[n - 1];
  if (scatter <= 1e-12 * scale) {
    e.method = "exact";
    e.extrapolated = f[n - 1];
    e.error = e.rel_error = 0.0;
    return e;
  }
  if (d1 * d2 > 0.0 && std::abs(d1) > std::abs(d2)) e.order = std::log(std::abs(d1 / d2)) / std::log(ratio);
  if (e.order >= order_band_low && e.order <= order_band_high) {
    e.method = "richardson";
    e.extrapolated = f[n - 1] - d2 / (std::pow(ratio, e.order) - 1.0);
    e.error = std::abs(f[base] - e.extrapolated);
    e.rel_error = e.error / std::abs(e.extrapolated);
    return e;
  }
  e.method = "scatter";
  e.error = scatter;
  e.rel_error = scatter / std::abs(f[base]);
  return e;
}

std::vector<StudyGroup> resolution_groups(const StudySpec& spec, const Scene& base) {
  const ResolutionOptions o = kind_options<ResolutionOptions>(spec);
  const bool noisy = stochastic(base);
  std::vector<StudyGroup> groups;
  for (int k = o.levels; k >= -o.coarser; --k) {  // finest first: the pool starts the longest runs
    const auto refine = level_overrides(base, o, k);
    if (noisy && k == 0 && o.seeds > 0) {
      StudyGroup g{level_name(0, false), refine};
      std::vector<std::string> seeds;
      for (int j = 0; j < o.seeds; ++j) seeds.push_back(std::to_string(base.discrete.seed + static_cast<std::uint64_t>(j)));
      g.vary.push_back({"discrete.seed", seeds});
      groups.push_back(g);
    }
    StudyGroup g{level_name(k, noisy), refine};
    if (noisy) {  // the skeleton: the count representation's step with every draw replaced by its expectation
      g.vary.push_back({"discrete.noise", {"false"}});
      if (base.discrete.representation != "count") g.vary.push_back({"discrete.representation", {"\"count\""}});
      if (base.discrete.contact_statistics) g.vary.push_back({"discrete.contact_statistics", {"false"}});
      if (base.output.ages && !base.lists("continuum")) g.vary.push_back({"output.ages", {"false"}});
    }
    groups.push_back(g);
  }
  return groups;
}

void check_resolution_scene(const StudySpec& spec, const Scene& base) {
  check_resolution_options(kind_options<ResolutionOptions>(spec));
  if (base.drive.loading == core::Loading::imposed_rate)
    throw core::ParamError("drive.loading",
                           "an imposed slip rate has no events (t*, t^, front speeds) for the resolution check to "
                           "follow; its steady law's accuracy is docs/numerics.md §1 (exact updates)");
}

namespace {

// One level of the check: its deterministic result per model (the stochastic model's noise-off skeleton) and the
// stochastic model's seeds (the scene's own level).
struct Level {
  int k = 0;
  double h = 1.0;                                    ///< r^-k: the level's resolution over the scene's
  const Scene* scene = nullptr;                      ///< a run's scene (its grid and step)
  std::map<std::string, const ModelResult*> model;   ///< complete results only
  std::vector<const ModelResult*> seeds;             ///< the discrete model with noise (complete results only)
  double dt = nan;                                   ///< the fixed step the runs took (NaN: adaptive)
  int runs = 0;
  bool skeleton = false;                             ///< the discrete model's result is its noise-off skeleton
};
using Levels = std::map<int, Level>;  // by k: coarsest first

Levels collect_levels(const ResolutionOptions& o, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                      const std::vector<std::vector<ModelResult>>& res) {
  Levels levels;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    int k = 0;
    bool noise_off = false;
    if (!parse_level(runs[i].group, k, noise_off)) continue;
    Level& l = levels[k];
    l.k = k;
    l.h = std::pow(o.ratio, -k);
    l.scene = &scenes[i];
    ++l.runs;
    l.skeleton = l.skeleton || noise_off;
    const bool noisy = !noise_off && stochastic(scenes[i]);
    for (const ModelResult& m : res[i]) {
      if (m.status != RunStatus::complete) continue;
      if (const auto it = m.scalars.find("dt"); it != m.scalars.end() && !std::isfinite(l.dt)) l.dt = it->second;
      if (noisy && m.model == "discrete") l.seeds.push_back(&m);
      else if (!l.model.count(m.model)) l.model[m.model] = &m;
    }
  }
  return levels;
}

std::string fixed(double x, int digits = 6) { return core::format_number(x, digits); }
std::string percent(double x) { return std::isfinite(x) ? core::format_number(100.0 * x, 3) + " %" : "-"; }

// The terminal table's row: model, event, value at the scene's level, its estimated error (absolute and relative),
// the observed order, the method, the verdict.
std::string table_row(const std::string& model, const std::string& event, double value, const RichardsonEstimate& e,
                      const std::string& verdict) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-11s %-17s %13s %11s %10s %7s  %-10s  %s", model.c_str(), event.c_str(),
                fixed(value).c_str(), std::isfinite(e.error) ? fixed(e.error, 3).c_str() : "-",
                percent(e.rel_error).c_str(), std::isfinite(e.order) ? fixed(e.order, 3).c_str() : "-", e.method,
                verdict.c_str());
  return buf;
}

// The tally over every event of every model: the worst relative error and the events that miss the tolerance.
struct Verdict {
  int checked = 0, unmet = 0, missing = 0;
  double worst = 0.0;
  std::string worst_name;
};

// One event of one model's deterministic values over the levels: scalars, definitions, the table row, the tally.
void put_event(StudyReport& rep, const std::string& model, bool stoch, const CheckedEvent& ev, const std::vector<double>& f,
               std::size_t base, const ResolutionOptions& o, Verdict& v) {
  const RichardsonEstimate e = richardson(f, base, o.ratio);
  const std::string n = model + "_" + ev.name;
  const std::string what = stoch ? "the discrete model's noise-off skeleton" : "the " + model + " model";
  rep.scalars[n] = f[base];
  rep.scalars[n + "_error"] = e.error;
  rep.scalars[n + "_rel_error"] = e.rel_error;
  rep.scalars[n + "_order"] = e.order;
  rep.scalars[n + "_extrapolated"] = e.extrapolated;
  const bool measured = std::string(e.method) != "missing";
  rep.scalars[n + "_meets"] = measured ? (e.rel_error <= o.tolerance ? 1.0 : 0.0) : nan;
  rep.definitions[n] = std::string(ev.name) + " of " + what + " at the scene's own resolution";
  rep.definitions[n + "_error"] =
      "estimated discretisation error of " + n + ": |value - Richardson extrapolate| (method richardson), or the "
      "largest distance to another level's value (scatter); NaN where a level did not measure it";
  rep.definitions[n + "_rel_error"] = n + "_error / |extrapolate| (scatter: / |value|)";
  rep.definitions[n + "_order"] = "observed order p = log(|d1/d2|)/log(ratio) of the finest three levels' differences "
                                  "(NaN unless they shrink monotonically)";
  rep.definitions[n + "_extrapolated"] = "Richardson extrapolate f_fine - d2/(ratio^p - 1) (NaN unless method richardson)";
  rep.definitions[n + "_meets"] = "1 if " + n + "_rel_error <= the tolerance " + core::format_number(o.tolerance) +
                                  ", 0 if not, NaN if not measured at every level";
  std::string verdict = "not measured at every level";
  if (measured) {
    ++v.checked;
    const bool ok = e.rel_error <= o.tolerance;
    verdict = ok ? "yes" : "NO";
    if (!ok) ++v.unmet;
    if (e.rel_error >= v.worst) { v.worst = e.rel_error; v.worst_name = n; }
  } else {
    ++v.missing;
    rep.notes.push_back(n + ": measured at the scene's own level but not at every level: no error estimate");
  }
  rep.summary.push_back(table_row(stoch ? "discrete*" : model, ev.name, f[base], e, verdict));
}

// The stochastic model's sampling part at the scene's own level: the spread over seeds, and the seed mean's offset
// from the noise-off skeleton on the same grid (its N -> infinity limit: a property of N, not of the resolution).
void put_seeds(StudyReport& rep, const Level& l0, const CheckedEvent& ev, double skeleton, const ResolutionOptions& o) {
  std::vector<double> x;
  for (const ModelResult* m : l0.seeds) x.push_back(event_of(*m, ev));
  const double mean = mean_of(x), sd = sd_of(x);
  const int n = finite_count(x);
  const double se = sd / std::sqrt(static_cast<double>(n)), bias = mean - skeleton;
  const std::string name = std::string("discrete_") + ev.name;
  rep.scalars[name + "_seed_mean"] = mean;
  rep.scalars[name + "_seed_sd"] = sd;
  rep.scalars[name + "_seeds"] = n;
  rep.scalars[name + "_noise_bias"] = bias;
  rep.scalars[name + "_noise_bias_se"] = se;
  rep.definitions[name + "_seed_mean"] = std::string(ev.name) + " of the discrete model (noise on) at the scene's own "
                                         "resolution, mean over the seeds that measured it (_seeds of them)";
  rep.definitions[name + "_seed_sd"] = "standard deviation over seeds: the sampling error of one run (set by N, not by the resolution)";
  rep.definitions[name + "_noise_bias"] = "seed mean - the noise-off skeleton on the same grid and step";
  rep.definitions[name + "_noise_bias_se"] = "standard error of the seed mean, seed_sd/sqrt(seeds)";
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-11s %-17s %13s  sd %s (%s) over %d of %zu seeds; mean - noise-off %s +- %s",
                "  (noise)", ev.name, fixed(mean).c_str(), std::isfinite(sd) ? fixed(sd, 3).c_str() : "-",
                percent(sd / std::abs(mean)).c_str(), n, x.size(), fixed(bias, 3).c_str(),
                std::isfinite(se) ? fixed(se, 2).c_str() : "-");
  rep.summary.push_back(buf);
  if (n >= 2 && std::abs(sd / mean) > o.tolerance)
    rep.notes.push_back(name + ": the spread over seeds is " + percent(sd / std::abs(mean)) + " of the mean, above the "
                        "tolerance " + percent(o.tolerance) + ": one run's value is a sample; N sets it, not the resolution");
}

// One model: its values per level (table resolution_<model>), every event the scene's own level measured.
void analyse_model(StudyReport& rep, const Levels& levels, const std::string& model, const ResolutionOptions& o,
                   Verdict& v) {
  std::vector<const Level*> ls;
  std::size_t base = 0;
  for (const auto& [k, l] : levels) {
    if (k == 0) base = ls.size();
    ls.push_back(&l);
  }
  const Level& l0 = *ls[base];
  const bool skeleton = model == "discrete" && l0.skeleton, noisy = model == "discrete" && !l0.seeds.empty();
  const std::string table = "resolution_" + model + (skeleton ? "_noise_off" : "");
  Columns t;
  for (const Level* l : ls) {
    t["level"].push_back(l->k);
    t["h"].push_back(l->h);
  }
  for (const CheckedEvent& ev : checked_events) {
    std::vector<double> f;
    for (const Level* l : ls) {
      const auto it = l->model.find(model);
      f.push_back(it == l->model.end() ? nan : event_of(*it->second, ev));
    }
    if (!std::isfinite(f[base])) continue;  // not an event of this scene
    t[ev.name] = f;
    rep.definitions[table + "/" + ev.name] = std::string(ev.name) + " at each level";
    put_event(rep, model, skeleton, ev, f, base, o, v);
    if (noisy) put_seeds(rep, l0, ev, f[base], o);
  }
  rep.tables[table] = t;
  rep.definitions[table + "/h"] = "the level's resolution over the scene's: ratio^-level (dx, dy and the step or the "
                                  "tolerance^(1/tolerance_order) in proportion)";
}

// The levels table: each level's grid, step and tolerance, and its runs.
void put_levels(StudyReport& rep, const Levels& levels) {
  Columns t;
  for (const auto& [k, l] : levels) {
    t["level"].push_back(k);
    t["h"].push_back(l.h);
    t["dx"].push_back(one_dimensional(*l.scene) ? l.scene->grid.dx : nan);
    t["dy"].push_back(l.scene->bulk.body() != core::BodyKind::chain ? l.scene->grid.row_spacing() : nan);
    t["dt"].push_back(l.dt);
    t["rtol"].push_back(l.scene->time.integrator == core::Integrator::adaptive_rosenbrock ? l.scene->time.rtol : nan);
    t["runs"].push_back(l.runs);
  }
  rep.tables["resolution_levels"] = t;
  rep.definitions["resolution_levels/dt"] = "the fixed step the runs took (the first model's; NaN: adaptive)";
  rep.definitions["resolution_levels/rtol"] = "time.rtol of the adaptive integrator (NaN otherwise)";
  rep.definitions["resolution_levels/runs"] = "runs of the level (the seeds of a stochastic model and its noise-off skeleton)";
}

std::string levels_line(const Levels& levels, const ResolutionOptions& o) {
  std::string h, dx, dt;
  for (const auto& [k, l] : levels) {
    h += (h.empty() ? "" : ", ") + core::format_number(l.h, 4);
    dx += (dx.empty() ? "" : ", ") + core::format_number(l.scene->grid.dx, 4);
    dt += (dt.empty() ? "" : ", ") + (std::isfinite(l.dt) ? core::format_number(l.dt, 4)
                                                           : "rtol " + core::format_number(l.scene->time.rtol, 3));
  }
  const bool grid = one_dimensional(*levels.begin()->second.scene);
  return "resolution check: " + std::to_string(levels.size()) + " levels, h = " + h + " of the scene's (" +
         (grid ? "dx = " + dx + "; " : std::string()) + "step " + dt + "), ratio " + core::format_number(o.ratio) + "; tolerance " + percent(o.tolerance) +
         " relative per event";
}

}  // namespace

void analyse_resolution(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                        const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  const ResolutionOptions o = kind_options<ResolutionOptions>(spec);
  const Levels levels = collect_levels(o, runs, scenes, res);
  if (levels.size() < 3 || !levels.count(0)) {
    rep.notes.push_back("fewer than three levels, or not the scene's own, have runs: no estimate");
    return;
  }
  put_levels(rep, levels);
  rep.summary.push_back(levels_line(levels, o));
  char head[256];
  std::snprintf(head, sizeof head, "  %-11s %-17s %13s %11s %10s %7s  %-10s  %s", "model", "event", "value", "error",
                "relative", "order", "method", "within");
  rep.summary.push_back(head);
  Verdict v;
  for (const char* m : model_order)
    if (levels.at(0).scene->lists(m)) analyse_model(rep, levels, m, o, v);
  rep.scalars["resolution_events_checked"] = v.checked;
  rep.scalars["resolution_events_unmet"] = v.unmet;
  rep.scalars["resolution_worst_rel_error"] = v.checked ? v.worst : nan;
  rep.scalars["resolution_meets_tolerance"] = v.checked ? (v.unmet == 0 ? 1.0 : 0.0) : nan;
  rep.definitions["resolution_worst_rel_error"] = "the largest _rel_error over every event and model";
  rep.definitions["resolution_meets_tolerance"] = "1 if every measured event's _rel_error is within the tolerance";
  if (levels.at(0).skeleton)
    rep.summary.push_back("  discrete*: the discrete model's noise-off skeleton (its discretisation error); (noise): its "
                          "seeds at the scene's own level (the sampling part)");
  if (v.checked)
    rep.summary.push_back(std::string(v.unmet ? "  NOT within " : "  within ") + percent(o.tolerance) + ": " +
                          std::to_string(v.checked - v.unmet) + " of " + std::to_string(v.checked) +
                          " events; the largest relative error " + percent(v.worst) + " (" + v.worst_name + ")");
}

}  // namespace slipfront::studies
