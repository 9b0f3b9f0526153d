#include "studies/strip_height.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <string>
#include <utility>

#include "compare/fit.hpp"
#include "core/params.hpp"

namespace slipfront::studies {
namespace {

// The events of fig1 the study follows (docs/output.md `events`): c_slow on the A_tip_alt front, as fig1
// reports it (its A_tip = 0.5 front exists only late in the slow phase: docs/scenes.md fig1).
struct Observable {
  const char* name;
  double Events::*field;
  bool alt;
  const char* what;
};
constexpr Observable observables[] = {
    {"t_star", &Events::t_star, false, "first yield t*"},
    {"t_hat", &Events::t_hat, false, "instability t^ (max v exceeds v_event)"},
    {"c_slow", &Events::c_slow, true, "slow-front speed (the A_tip_alt front, fig1's c_slow_alt)"},
    {"c_transient", &Events::c_transient, false, "transient front speed"},
    {"x_arrest", &Events::x_arrest, false, "arrest position of the transient"}};
constexpr const char* model_names[] = {"continuum", "discrete"};

// The thin heights, H/l_e at most this (docs/model.md §9.3: the strip is 1D to 1.5 % up to H ~ 0.3 l_e;
// beyond it the crossover bends the power law): the H -> 0 check needs the smallest height among them, the
// observed order in H is fitted over them.
constexpr double thin_fit_limit = 0.35;

double mean_finite(const std::vector<double>& v) {
  double s = 0.0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) { s += x; ++n; }
  return n ? s / n : nan;
}

std::string key(const Observable& o, const char* model) { return std::string(o.name) + "_" + model; }

std::string pct(double x) { return core::format_number(100.0 * x, 3) + " %"; }

double event_of(const ModelResult& r, const Observable& o) { return (o.alt ? r.events_alt : r.events).*o.field; }

// One point of the study: a height and a row spacing (the chain: 0, 0), its runs and their events per
// observable and model (mean over seeds).
struct Point {
  double H = 0.0, dy = 0.0, ell_e = nan;
  std::vector<std::size_t> runs;
  std::map<std::string, double> value;  ///< "<obs>_<model>"
};
/// By (H, dy): in map order the chain first, then each height's finest dy first.
using Points = std::map<std::pair<double, double>, Point>;

// One strip body's table: the antiplane strip's is `strip_height` (its names as before the in-plane strip), the
// in-plane strip's `inplane_height` (tables, scalars and definitions under that prefix; its notes say which body).
struct BodyTable {
  core::BodyKind kind;
  const char* prefix;  ///< table and scalar names
  const char* label;   ///< leads its notes ("" for the antiplane strip)
  const char* thin;    ///< the docs/model.md section of its thin limit
};
constexpr BodyTable body_tables[] = {{core::BodyKind::strip, "strip_height", "", "§9.2"},
                                     {core::BodyKind::inplane, "inplane_height", "in-plane strip: ", "§10.2"}};

// The points of the chain (H = 0) and of the one strip body `body`.
Points collect_points(const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res,
                      core::BodyKind body) {
  Points points;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const Scene& s = scenes[i];
    const core::BodyKind kind = s.bulk.body();
    if (kind != core::BodyKind::chain && kind != body) continue;
    const double H = s.bulk.height, dy = H > 0.0 ? (s.grid.dy > 0.0 ? s.grid.dy : s.grid.dx) : 0.0;
    Point& p = points[{H, dy}];
    p.H = H;
    p.dy = dy;
    p.ell_e = std::sqrt(s.bulk.mu / s.interface.alpha);
    p.runs.push_back(i);
  }
  for (auto& [hd, p] : points)
    for (const Observable& o : observables)
      for (const char* m : model_names) {
        std::vector<double> v;
        for (std::size_t i : p.runs)
          if (const auto* r = find_model(res[i], m)) v.push_back(event_of(*r, o));
        p.value[key(o, m)] = mean_finite(v);
      }
  return points;
}

// Events not measured: one note per run and model, with the measurement's reasons; runs without one common
// fixed step: a note (the events then differ by the step's jitter, docs/numerics.md, and the discrete model
// is another realisation at another step, as its random stream is drawn per step).
void note_runs(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
               const std::vector<std::vector<ModelResult>>& res) {
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (const char* m : model_names) {
      const auto* r = find_model(res[i], m);
      if (!r) continue;
      std::string missing;
      for (const Observable& o : observables) {
        if (std::isfinite(event_of(*r, o))) continue;
        const auto& reasons = (o.alt ? r->events_alt : r->events).reasons;
        const auto why = reasons.find(o.name);
        missing += (missing.empty() ? "" : "; ") + std::string(o.name) +
                   (why == reasons.end() ? std::string() : " (" + why->second + ")");
      }
      if (!missing.empty())
        rep.notes.push_back("run " + runs[i].id + " (" +
                            (scenes[i].bulk.body() == core::BodyKind::inplane ? "in-plane strip, " : "") +
                            "H = " + core::format_number(scenes[i].bulk.height) + ", " + m +
                            "): not measured: " + missing);
    }
  bool one_step = !scenes.empty();
  for (const Scene& s : scenes) one_step = one_step && s.time.dt > 0.0 && s.time.dt == scenes.front().time.dt;
  if (!scenes.empty() && !one_step)
    rep.notes.push_back("the runs do not share one fixed time.dt: their events differ by the step's jitter too "
                        "(docs/numerics.md) and the discrete model's by its realisation; set time.dt in the study's set");
}

// event / (the chain's) - 1; NaN without a chain.
double rel_1d(const Point* chain, const Point& p, const std::string& k) {
  if (!chain) return nan;
  const double ref = chain->value.at(k);
  return ref != 0.0 ? p.value.at(k) / ref - 1.0 : nan;
}

void put_table(StudyReport& rep, const BodyTable& b, const Points& points, const Point* chain) {
  const std::string P = b.prefix;
  Columns t;
  for (const auto& [hd, p] : points) {
    t["H"].push_back(p.H);
    t["H_over_le"].push_back(p.H / p.ell_e);
    t["eps"].push_back((p.H / p.ell_e) * (p.H / p.ell_e));
    t["dy"].push_back(p.dy);
    t["row_intervals"].push_back(p.H > 0.0 ? std::round(p.H / p.dy) : 0.0);
    t["runs"].push_back(static_cast<double>(p.runs.size()));
    for (const Observable& o : observables)
      for (const char* m : model_names) {
        const std::string k = key(o, m);
        t[k].push_back(p.value.at(k));
        t[k + "_rel_1d"].push_back(rel_1d(chain, p, k));
      }
  }
  rep.tables[P] = t;
  auto& def = rep.definitions;
  def[P + "/H"] = "bulk.height: the strip's height (0: the 1D chain, the H -> 0 line)";
  def[P + "/H_over_le"] = "H / l_e, l_e = sqrt(bulk.mu / interface.alpha) the elastic length (docs/model.md §9.3)";
  def[P + "/eps"] = "(H/l_e)^2 = alpha H^2/mu: the 1D model's relative error is O(eps) (docs/model.md " +
                    std::string(b.thin) + "); _rel_1d / eps constant over the heights is second order in H";
  def[P + "/dy"] = "grid.dy: the row spacing of the run (0 for the chain)";
  def[P + "/row_intervals"] = "H / dy, the strip's row intervals (0 for the chain)";
  def[P + "/runs"] = "runs at this height and dy (seeds; the events are their mean)";
  for (const Observable& o : observables)
    for (const char* m : model_names) {
      const std::string k = key(o, m);
      def[P + "/" + k] = std::string(o.what) + " of the " + m + " model (docs/output.md events)";
      def[P + "/" + k + "_rel_1d"] = k + " / (the same on the 1D chain) - 1";
    }
  if (chain)
    for (const Observable& o : observables)
      for (const char* m : model_names) {
        const std::string k = key(o, m);
        rep.scalars[P + "_1d_" + k] = chain->value.at(k);
        def[P + "_1d_" + k] = std::string(o.what) + " of the 1D chain (" + m + ")";
      }
}

// The H -> 0 check at the smallest height (when it is thin): its largest difference to the chain, a note
// that it is within strip_height_thin_tolerance or a flag. Returns whether the study has a thin end.
bool check_thin_end(StudyReport& rep, const BodyTable& b, const Points& points, const Point& chain) {
  const std::string P = b.prefix, L = b.label, sec = b.thin;
  const Point* thin = nullptr;  // the smallest height, at its finest dy
  for (const auto& [hd, p] : points)
    if (p.H > 0.0 && (!thin || p.H < thin->H)) thin = &p;
  if (!thin) return false;
  const std::string where = "the smallest height H = " + core::format_number(thin->H) + " (H/l_e = " +
                            core::format_number(thin->H / thin->ell_e, 3) + ")";
  if (thin->H / thin->ell_e > thin_fit_limit) {
    rep.notes.push_back(L + "no H -> 0 check: " + where + " is not thin (H/l_e > " + core::format_number(thin_fit_limit) + ")");
    return false;
  }
  double worst = 0.0;
  std::string worst_name;
  bool all_finite = true;
  for (const Observable& o : observables)
    for (const char* m : model_names) {
      const double r = rel_1d(&chain, *thin, key(o, m));
      if (!std::isfinite(r)) { all_finite = false; continue; }
      if (std::abs(r) >= worst) { worst = std::abs(r); worst_name = key(o, m); }
    }
  rep.scalars[P + "_thin_H"] = thin->H;
  rep.scalars[P + "_thin_max_rel_diff"] = all_finite ? worst : nan;
  rep.definitions[P + "_thin_H"] = "the smallest height of the study (its H -> 0 end)";
  rep.definitions[P + "_thin_max_rel_diff"] =
      "largest |event / 1D event - 1| over t*, t^, c_slow, c_transient, x_arrest and both models at the smallest "
      "height (NaN if an event is missing there or on the chain)";
  if (!all_finite)
    rep.notes.push_back("FLAG: " + L + "at " + where + " or on the chain an event was not measured: the H -> 0 check is incomplete");
  else if (worst <= strip_height_thin_tolerance)
    rep.notes.push_back(L + "H -> 0: at " + where + " every event of both models is within " + pct(strip_height_thin_tolerance) +
                        " of the 1D chain's (largest: " + worst_name + ", " + pct(worst) + ")");
  else
    rep.notes.push_back("FLAG: " + L + "H -> 0: at " + where + " " + worst_name + " differs from the 1D chain's by " + pct(worst) +
                        ", more than " + pct(strip_height_thin_tolerance) + " (docs/model.md " + sec + " predicts O(H^2))");
  return true;
}

// The observed order: |rel_1d| ~ H^p over the thin heights (the finest dy of each), per event and model.
void fit_orders(StudyReport& rep, const BodyTable& b, const Points& points, const Point& chain) {
  const std::string P = b.prefix, sec = b.thin;
  std::map<double, const Point*> finest;
  for (const auto& [hd, p] : points)
    if (p.H > 0.0 && p.H / p.ell_e <= thin_fit_limit && !finest.count(p.H)) finest[p.H] = &p;
  for (const Observable& o : observables)
    for (const char* m : model_names) {
      std::vector<double> h, d;
      for (const auto& [H, p] : finest) {
        const double r = std::abs(rel_1d(&chain, *p, key(o, m)));
        if (std::isfinite(r) && r > 0.0) { h.push_back(H); d.push_back(r); }
      }
      if (h.size() < 3) continue;
      const LineFit f = fit_power_law(h, d);
      const std::string name = P + "_order_" + key(o, m);
      rep.scalars[name] = f.slope;
      rep.scalars[name + "_ci_low"] = f.slope_ci_low;
      rep.scalars[name + "_ci_high"] = f.slope_ci_high;
      rep.scalars[name + "_points"] = f.n;
      rep.definitions[name] = "observed order p of |" + key(o, m) + " / 1D - 1| ~ H^p over the heights with H/l_e <= " +
                              core::format_number(thin_fit_limit) +
                              " (docs/model.md " + sec + " predicts 2; least-squares slope in log-log; _ci_low/_ci_high: 95% "
                              "Student-t interval)";
    }
}

// Heights run at several dy: each coarser dy against the finest (the dy check of docs/studies.md).
void put_dy_table(StudyReport& rep, const BodyTable& b, const Points& points) {
  const std::string P = b.prefix;
  Columns d;
  double dy_worst = 0.0;
  bool dy_missing = false;
  for (auto it = points.begin(); it != points.end(); ++it) {
    const Point& ref = it->second;  // map order: the finest dy of each H first
    if (ref.H <= 0.0 || (it != points.begin() && std::prev(it)->second.H == ref.H)) continue;
    for (auto jt = std::next(it); jt != points.end() && jt->second.H == ref.H; ++jt) {
      const Point& p = jt->second;
      d["H"].push_back(p.H);
      d["dy"].push_back(p.dy);
      d["dy_reference"].push_back(ref.dy);
      double worst = 0.0;
      for (const Observable& o : observables)
        for (const char* m : model_names) {
          const std::string k = key(o, m);
          const double r = p.value.at(k) / ref.value.at(k) - 1.0;
          d[k + "_rel_ref"].push_back(r);
          worst = std::isfinite(r) && std::isfinite(worst) ? std::max(worst, std::abs(r)) : nan;
        }
      d["max_rel_ref"].push_back(worst);
      if (std::isfinite(worst)) dy_worst = std::max(dy_worst, worst);
      else dy_missing = true;
    }
  }
  if (d.empty()) return;
  rep.tables[P + "_dy"] = d;
  rep.definitions[P + "_dy/dy_reference"] = "the finest dy run at this height";
  for (const Observable& o : observables)
    for (const char* m : model_names)
      rep.definitions[P + "_dy/" + key(o, m) + "_rel_ref"] = key(o, m) + " at dy / (the same at dy_reference) - 1";
  rep.definitions[P + "_dy/max_rel_ref"] = "largest |_rel_ref| of the row (NaN if an event is missing)";
  rep.scalars[P + "_dy_max_rel_diff"] = dy_missing ? nan : dy_worst;
  rep.definitions[P + "_dy_max_rel_diff"] =
      "largest change of an event (t*, t^, c_slow, c_transient, x_arrest; both models) from the finest dy to a coarser "
      "one at the same height";
}

}  // namespace

void analyse_strip_height(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& res) {
  note_runs(rep, runs, scenes, res);
  bool inplane = false, chain_run = false;
  for (const Scene& s : scenes) {
    inplane = inplane || s.bulk.body() == core::BodyKind::inplane;
    chain_run = chain_run || s.bulk.body() == core::BodyKind::chain;
  }
  if (!chain_run)
    rep.notes.push_back("no 1D run (bulk.height = 0, grid.dy = 0): no H -> 0 line, the _rel_1d columns are NaN; add a "
                        "group with bulk.height = 0 and grid.dy = 0");
  for (const BodyTable& b : body_tables) {
    const Points points = collect_points(scenes, res, b.kind);  // seeds pooled; the chain is H = dy = 0
    const bool present = std::any_of(points.begin(), points.end(), [](const auto& p) { return p.second.H > 0.0; });
    // the antiplane table as before (also for a study of the chain alone); the in-plane one when it ran
    if (b.kind == core::BodyKind::inplane ? !present : (!present && inplane)) continue;
    const auto chain_it = points.find({0.0, 0.0});
    const Point* chain = chain_it == points.end() ? nullptr : &chain_it->second;  // the H -> 0 line
    put_table(rep, b, points, chain);
    if (chain && check_thin_end(rep, b, points, *chain)) fit_orders(rep, b, points, *chain);
    put_dy_table(rep, b, points);
  }
}

}  // namespace slipfront::studies
