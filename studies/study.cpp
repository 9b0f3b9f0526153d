#include "studies/study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "compare/difference.hpp"
#include "studies/disorder_limit.hpp"
#include "studies/fig2_cmin.hpp"
#include "studies/front_spectrum.hpp"
#include "compare/fit.hpp"
#include "compare/fronts.hpp"
#include "studies/resolution.hpp"
#include "studies/strip_cmin_height.hpp"
#include "studies/strip_height.hpp"
#include "studies/validity.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/steady_front.hpp"

namespace slipfront::studies {

void put_fit(StudyReport& rep, const std::string& name, const LineFit& f, const std::string& what) {
  rep.scalars[name] = f.slope;
  rep.scalars[name + "_ci_low"] = f.slope_ci_low;
  rep.scalars[name + "_ci_high"] = f.slope_ci_high;
  rep.scalars[name + "_points"] = f.n;
  rep.definitions[name] = what + " (least-squares slope in log-log; _ci_low/_ci_high: 95% Student-t interval)";
}

// Power-law fit over every point, and (name + "_from") over x >= from when that leaves >= 3 points.
void put_fits(StudyReport& rep, const std::string& name, const std::vector<double>& x, const std::vector<double>& y,
              double from, const std::string& what) {
  if (x.size() >= 3) put_fit(rep, name, fit_power_law(x, y), what + ", all points");
  if (from <= 0) return;
  std::vector<double> fx, fy;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (x[k] >= from) { fx.push_back(x[k]); fy.push_back(y[k]); }
  if (fx.size() >= 3)
    put_fit(rep, name + "_from", fit_power_law(fx, fy), what + ", points with N >= " + core::format_number(from) +
                                                             " (study key fit_from: the mean-field regime)");
}

namespace {

// Runs grouped by one varied key's numeric value (seeds pooled), in increasing order of the value.
std::map<double, std::vector<std::size_t>> by_value(const std::vector<StudyRun>& runs, const std::string& key) {
  std::map<double, std::vector<std::size_t>> g;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto it = runs[i].point.find(key);
    if (it != runs[i].point.end()) g[std::stod(it->second)].push_back(i);
  }
  return g;
}

const std::vector<double>& column(const Columns& c, const std::string& name) {
  static const std::vector<double> empty;
  const auto it = c.find(name);
  return it == c.end() ? empty : it->second;
}

// ---------------------------------------------------------------------------------------------
// friction_law: discrete steady friction vs the continuum as N grows (noise on, w = 0).
void friction_law_vs_N(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                       const std::vector<Scene>&, const std::vector<std::vector<ModelResult>>& res) {
  const std::string key = "discrete.contacts_per_site";
  Columns t;
  for (const auto& [N, idx] : by_value(runs, key)) {
    // e[s][k] = (σ_disc − σ_cont)/σ_cont at rate v_k for seed s; se[s][k] its batch-means error.
    std::vector<std::vector<double>> e, se;
    for (std::size_t i : idx) {
      const auto* c = find_model(res[i], "continuum");
      const auto* d = find_model(res[i], "discrete");
      if (!c || !d) continue;
      const auto& sc = column(c->friction_law, "sigma");
      const auto& sd = column(d->friction_law, "sigma");
      const auto& ss = column(d->friction_law, "sigma_stderr");
      std::vector<double> ei, si;
      for (std::size_t k = 0; k < std::min(sc.size(), sd.size()); ++k) {
        ei.push_back((sd[k] - sc[k]) / sc[k]);
        si.push_back(ss[k] / sc[k]);
      }
      e.push_back(ei);
      se.push_back(si);
    }
    if (e.empty()) continue;
    const std::size_t S = e.size(), K = e[0].size();
    double var_sum = 0, bias_sum = 0, tot = 0, se_sum = 0;
    for (std::size_t k = 0; k < K; ++k) {
      std::vector<double> col;
      for (std::size_t s = 0; s < S; ++s) { col.push_back(e[s][k]); tot += e[s][k] * e[s][k]; se_sum += se[s][k] * se[s][k]; }
      const double m = mean_of(col), v = S > 1 ? sd_of(col) * sd_of(col) : 0.0;
      var_sum += v;
      bias_sum += std::max(0.0, m * m - v / static_cast<double>(S));
    }
    const double Kd = static_cast<double>(K), Sd = static_cast<double>(S);
    t["N"].push_back(N);
    t["random"].push_back(S > 1 ? std::sqrt(var_sum / Kd) : std::sqrt(se_sum / (Kd * Sd)));
    t["bias"].push_back(std::sqrt(bias_sum / Kd));
    t["total"].push_back(std::sqrt(tot / (Kd * Sd)));
    t["batch_stderr"].push_back(std::sqrt(se_sum / (Kd * Sd)));
    t["seeds"].push_back(static_cast<double>(S));
  }
  rep.tables["friction_law_error"] = t;
  rep.definitions["friction_law_error/random"] =
      "RMS over v of the standard deviation over seeds of (sigma_discrete - sigma_continuum)/sigma_continuum "
      "(one seed: RMS of the batch-means standard error)";
  rep.definitions["friction_law_error/bias"] =
      "RMS over v of the seed-mean relative error, with the random part's share var/S removed";
  rep.definitions["friction_law_error/total"] = "RMS over v and seeds of the relative error";
  rep.definitions["friction_law_error/batch_stderr"] = "RMS over v and seeds of the relative batch-means standard error";
  put_fits(rep, "friction_law_random_exponent", t["N"], t["random"], spec.fit_from,
           "exponent p of random(N) ~ N^p (mean-field limit predicts -1/2)");
}

// threshold_width: noise off, the distance of the discrete model to the continuum vs w: on the
// steady law for an imposed-rate sweep, on the friction history (and the static peak) otherwise.
void friction_law_vs_width(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs,
                           const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  Columns t;
  int identical = 0;
  for (const auto& [w, idx] : by_value(runs, "discrete.width")) {
    const auto* c = find_model(res[idx[0]], "continuum");
    const auto* d = find_model(res[idx[0]], "discrete");
    if (!c || !d) continue;
    double dist = nan;
    if (!d->friction_law.empty()) {
      const auto& sc = column(c->friction_law, "sigma");
      const auto& sd = column(d->friction_law, "sigma");
      double s2 = 0;
      for (std::size_t k = 0; k < std::min(sc.size(), sd.size()); ++k) {
        const double e = (sd[k] - sc[k]) / sc[k];
        s2 += e * e;
      }
      dist = std::sqrt(s2 / static_cast<double>(std::max<std::size_t>(1, sc.size())));
      t["sigma_at_vmin"].push_back(sd.empty() ? nan : sd.front());
      t["sigma_min"].push_back(sd.empty() ? nan : *std::min_element(sd.begin(), sd.end()));
    } else {
      const char* col = scenes[idx[0]].drive.loading == core::Loading::imposed_rate ? "sigma" : "drive_force";
      dist = relative_rms_distance(column(c->series, col), column(d->series, col));
      const auto& pk = column(d->cycles, "F_peak");
      const auto& pc = column(c->cycles, "F_peak");
      t["F_peak_first"].push_back(pk.empty() ? nan : pk.front());
      t["F_peak_first_continuum"].push_back(pc.empty() ? nan : pc.front());
    }
    // Below ~1e-12 the two models agree to round-off: the disorder does not reach the loads met.
    if (dist < 1e-12) ++identical;
    t["width"].push_back(w);
    t["distance"].push_back(dist);
  }
  rep.tables["threshold_width"] = t;
  rep.definitions["threshold_width/distance"] =
      "noise off: RMS over v of (sigma_discrete - sigma_continuum)/sigma_continuum (steady law), or the relative "
      "RMS distance of the friction history sigma(t) / F(t) (other scenes)";
  rep.definitions["threshold_width/sigma_at_vmin"] = "discrete steady friction at the smallest v (static peak side)";
  rep.definitions["threshold_width/sigma_min"] = "smallest tabulated discrete steady friction (weakening branch bottom)";
  rep.definitions["threshold_width/F_peak_first"] = "first stick-slip peak of the drive force (static peak), discrete";
  if (identical)
    rep.notes.push_back(std::to_string(identical) +
                        " width(s) give results identical to the continuum to round-off (distance < 1e-12): the "
                        "contact stress never comes within the threshold spread (for steady sliding tau = alpha + "
                        "eta v/A stays above every threshold when w << alpha - 1); they are left out of the fit");
  std::vector<double> fw, fd;
  for (std::size_t k = 0; k < t["width"].size(); ++k)
    if (t["distance"][k] >= 1e-12) { fw.push_back(t["width"][k]); fd.push_back(t["distance"][k]); }
  if (fw.size() >= 3)
    put_fit(rep, "threshold_width_exponent", fit_power_law(fw, fd), "exponent p of distance(w) ~ w^p");
  else
    rep.notes.push_back("fewer than 3 widths with a non-zero distance: no rate fitted");
  if (t.count("F_peak_first")) {
    std::vector<double> dp;
    for (std::size_t k = 0; k < t["width"].size(); ++k)
      dp.push_back(std::abs(t["F_peak_first"][k] - t["F_peak_first_continuum"][k]));
    t["F_peak_shift"] = dp;
    rep.tables["threshold_width"] = t;
    rep.definitions["threshold_width/F_peak_shift"] = "|first static peak (discrete) - first static peak (continuum)|";
    if (t["width"].size() >= 3)
      put_fit(rep, "threshold_width_peak_exponent", fit_power_law(t["width"], dp),
              "exponent p of the static-peak shift ~ w^p");
  }
}

// transient_friction: curve distance between discrete and continuum friction histories vs N.
void transient_vs_N(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                    const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  Columns t;
  for (const auto& [N, idx] : by_value(runs, "discrete.contacts_per_site")) {
    std::vector<double> d;
    for (std::size_t i : idx) {
      const auto* c = find_model(res[i], "continuum");
      const auto* m = find_model(res[i], "discrete");
      if (!c || !m) continue;
      const char* col = scenes[i].drive.loading == core::Loading::imposed_rate ? "sigma" : "drive_force";
      d.push_back(relative_rms_distance(column(c->series, col), column(m->series, col)));
    }
    t["N"].push_back(N);
    t["distance_mean"].push_back(mean_of(d));
    t["distance_sd"].push_back(sd_of(d));
    t["seeds"].push_back(static_cast<double>(d.size()));
  }
  rep.tables["transient_friction"] = t;
  rep.definitions["transient_friction/distance_mean"] =
      "mean over seeds of the relative RMS distance of the friction history (sigma(t) for an imposed rate, "
      "F(t) for the spring block) between the discrete and the continuum model";
  put_fits(rep, "transient_distance_exponent", t["N"], t["distance_mean"], spec.fit_from,
           "exponent p of distance_mean(N) ~ N^p");
}

// RMS over the finite values of (x - reference) / reference; NaN when none is finite.
double rms_relative_difference(const std::vector<double>& xs, double reference) {
  double ms = 0.0;
  int k = 0;
  for (double x : xs) {
    const double r = (x - reference) / reference;
    if (std::isfinite(r)) { ms += r * r; ++k; }
  }
  return k ? std::sqrt(ms / k) : nan;
}

// front_speeds: fig1 event times and speeds of the discrete model over seeds vs N.
void fronts_vs_N(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs, const std::vector<Scene>&,
                 const std::vector<std::vector<ModelResult>>& res) {
  struct Obs { const char* name; double Events::*field; bool alt; };
  const Obs obs[] = {{"t_star", &Events::t_star, false},          {"t_hat", &Events::t_hat, false},
                     {"c_slow_alt", &Events::c_slow, true},         {"c_transient", &Events::c_transient, false},
                     {"c_transient_peak", &Events::c_transient_peak, false}, {"x_arrest", &Events::x_arrest, false}};
  Columns t;
  for (const auto& [N, idx] : by_value(runs, "discrete.contacts_per_site")) {
    t["N"].push_back(N);
    for (const Obs& o : obs) {
      std::vector<double> d;
      double cont = nan;
      for (std::size_t i : idx) {
        const auto* c = find_model(res[i], "continuum");
        const auto* m = find_model(res[i], "discrete");
        if (c) cont = (o.alt ? c->events_alt : c->events).*o.field;
        if (m) d.push_back((o.alt ? m->events_alt : m->events).*o.field);
      }
      const std::string n = o.name;
      t[n + "_continuum"].push_back(cont);
      t[n + "_mean"].push_back(mean_of(d));
      t[n + "_sd"].push_back(sd_of(d));
      t[n + "_finite"].push_back(finite_count(d));
      t[n + "_rel_diff"].push_back((mean_of(d) - cont) / cont);
      t[n + "_rms_rel_diff"].push_back(rms_relative_difference(d, cont));
    }
  }
  for (const Obs& o : obs) {
    const std::string n = o.name;
    rep.definitions["front_speeds/" + n + "_mean"] = "mean over seeds of the discrete " + n + " (docs/model.md §3)";
    rep.definitions["front_speeds/" + n + "_sd"] = "standard deviation over seeds of the discrete " + n;
    rep.definitions["front_speeds/" + n + "_rel_diff"] = "(mean - continuum) / continuum";
    rep.definitions["front_speeds/" + n + "_rms_rel_diff"] =
        "RMS over seeds of (discrete - continuum) / continuum: the seed mean's bias and the spread together";
    put_fits(rep, "front_" + n + "_rms_exponent", t["N"], t[n + "_rms_rel_diff"], spec.fit_from,
             "exponent p of the RMS over seeds of |discrete - continuum|/continuum of " + n + " ~ N^p");
    put_fits(rep, "front_" + n + "_sd_exponent", t["N"], t[n + "_sd"], spec.fit_from,
             "exponent p of the seed spread of " + n + " ~ N^p");
    std::vector<double> absdiff;
    for (double x : t[n + "_rel_diff"]) absdiff.push_back(std::abs(x));
    put_fits(rep, "front_" + n + "_bias_exponent", t["N"], absdiff, spec.fit_from,
             "exponent p of |mean - continuum|/continuum of " + n + " ~ N^p");
  }
  rep.tables["front_speeds"] = t;
}

// fig2: transient front speed against sqrt(mu alpha/(eta kappa)), one group per varied parameter.
void fig2(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
          const std::vector<std::vector<ModelResult>>& res) {
  std::map<std::string, Columns> groups;
  Columns all;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& s = scenes[i];
    const double X = std::sqrt(s.bulk.mu * s.interface.alpha / (s.interface.eta * s.interface.kappa));
    const auto* c = find_model(res[i], "continuum");
    const auto* d = find_model(res[i], "discrete");
    Columns& g = groups[runs[i].group];
    const double value = runs[i].point.empty() ? nan : std::stod(runs[i].point.begin()->second);
    for (Columns* t : {&g, &all}) {
      (*t)["X"].push_back(X);
      (*t)["value"].push_back(value);
      (*t)["c_continuum"].push_back(c ? c->events.c_transient : nan);
      (*t)["c_discrete"].push_back(d ? d->events.c_transient : nan);
      (*t)["x_arrest_continuum"].push_back(c ? c->events.x_arrest : nan);
    }
  }
  for (auto& [name, g] : groups) {
    for (const char* m : {"continuum", "discrete"}) {
      const std::string col = std::string("c_") + m;
      rep.scalars["fig2_slope_" + name + "_" + m] = slope_through_origin(g["X"], g[col]);
      rep.definitions["fig2_slope_" + name + "_" + m] =
          "least-squares slope through the origin of c_transient (" + std::string(m) + ") vs sqrt(mu alpha/(eta kappa)), varying " + name;
    }
    rep.tables["fig2_" + name] = g;
  }
  for (const char* m : {"continuum", "discrete"}) {
    const std::string col = std::string("c_") + m;
    rep.scalars[std::string("fig2_slope_all_") + m] = slope_through_origin(all["X"], all[col]);
    rep.definitions[std::string("fig2_slope_all_") + m] =
        "least-squares slope through the origin of c_transient vs sqrt(mu alpha/(eta kappa)), all runs";
    int missing = 0;
    for (double c : all[col]) missing += std::isfinite(c) ? 0 : 1;
    if (missing && col == "c_continuum")
      rep.notes.push_back(std::to_string(missing) + " run(s) had no measurable transient front (" + m + "); see fig2_* tables");
  }
  fig2_against_cmin(rep, all, scenes);  // c_transient against the run's own c_min, per height
  rep.tables["fig2_all"] = all;
  rep.definitions["fig2_all/X"] = "sqrt(mu alpha/(eta kappa)), the scaling estimate of the minimal steady front speed";
}

// front_spectrum: nucleated fronts of homogeneous loading vs sigma_d, against the solved branch.
void spectrum(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
              const std::vector<std::vector<ModelResult>>& res) {
  Columns t;
  double limit_started = nan, limit_failed = nan;  // lowest σ_d with a front; highest without
  for (const auto& [sd, idx] : by_value(runs, "drive.sigma_d")) {
    const auto* c = find_model(res[idx[0]], "continuum");
    const auto* d = find_model(res[idx[0]], "discrete");
    const auto& s = scenes[idx[0]];
    // the 1D solver's front is the chain's; on a strip it would be the thin limit, not this body's front
    const bool chain = s.bulk.body() == core::BodyKind::chain;
    const double solved = chain ? solved_front_speed(s, sd) : nan;
    t["sigma_d"].push_back(sd);
    t["c_front_continuum"].push_back(c ? c->events.c_front : nan);
    t["c_front_discrete"].push_back(d ? d->events.c_front : nan);
    t["front_settled_continuum"].push_back(c ? c->events.front_settled : nan);
    t["c_solved"].push_back(solved);
    t["c_front_continuum_rel_solved"].push_back(c ? c->events.c_front / solved - 1.0 : nan);
    t["v_behind_continuum"].push_back(c ? c->events.v_behind : nan);
    t["v_behind_discrete"].push_back(d ? d->events.v_behind : nan);
    t["sigma_c_d"].push_back(continuum::steady_minimum_stress(s.interface));
    if (c && std::isfinite(c->events.c_front)) {
      if (!(sd >= limit_started)) limit_started = sd;
    } else if (c && !(sd <= limit_failed)) {
      limit_failed = sd;
    }
  }
  rep.tables["front_spectrum"] = t;
  rep.definitions["front_spectrum/c_front_continuum"] =
      "c_front of the run (docs/model.md §3.1): the tip's speed fitted where it has settled, else over the middle half "
      "of its run (front_settled_continuum = 0)";
  rep.definitions["front_spectrum/c_solved"] = "speed of the steady front at sigma_d solved directly (docs/fronts.md)";
  rep.definitions["front_spectrum/v_behind_continuum"] =
      "mean slip rate over [x_tip - behind_far, x_tip - behind_near] when the tip passes behind_tip_fraction L";
  // The lower end of what a nucleation patch starts, against the branch's own end.
  double cmin = nan, sdmin = nan;
  for (std::size_t k = 0; k < t["sigma_d"].size(); ++k)
    if (std::isfinite(t["c_front_continuum"][k]) && !(t["c_front_continuum"][k] >= cmin)) {
      cmin = t["c_front_continuum"][k];
      sdmin = t["sigma_d"][k];
    }
  rep.scalars["spectrum_slowest_front"] = cmin;
  rep.scalars["spectrum_slowest_front_sigma_d"] = sdmin;
  rep.definitions["spectrum_slowest_front"] = "slowest nucleated front measured (continuum) and its sigma_d";
  rep.scalars["nucleation_limit_sigma_d"] = limit_started;
  rep.definitions["nucleation_limit_sigma_d"] =
      "lowest sigma_d at which the nucleation patch started a front (continuum): a property of the start, not of the branch";
  add_spectrum_speeds(rep, runs, scenes, res);  // peak and settled speeds against c_s, c_R, c_p (docs/fronts.md §12)
  if (!scenes.empty() && scenes[0].bulk.body() != core::BodyKind::chain)
    rep.notes.push_back("a strip: c_solved and the solved branch are not computed (the 1D solver's fronts are the thin "
                        "limit; `slipfront fronts` on the scene solves the strip's branch, docs/fronts.md §10.14, §11.6)");
  else if (!scenes.empty()) {
    const auto branch = continuum::continue_steady_fronts(scenes[0].interface, scenes[0].bulk);
    Columns b;
    for (const auto& p : branch.points) {
      b["sigma_d"].push_back(p.sigma_d);
      b["c"].push_back(p.c);
      b["v_behind"].push_back(p.v_behind);
    }
    rep.tables["front_branch"] = b;
    rep.definitions["front_branch/c"] = "the branch c(sigma_d) of steady fronts by continuation (docs/fronts.md)";
    rep.scalars["branch_c_min"] = branch.c_min;
    rep.scalars["branch_sigma_d_at_c_min"] = branch.sigma_d_at_c_min;
    rep.definitions["branch_c_min"] = "minimal steady front speed: the end of the solved branch, and its sigma_d";
    rep.notes.push_back("the solved branch ends at sigma_d = " + core::format_number(branch.sigma_d_at_c_min, 6) +
                        " with c_min = " + core::format_number(branch.c_min, 6) + " (" + branch.reason + ")");
    if (std::isfinite(limit_started))
      rep.notes.push_back("nucleation limit: the patch starts fronts down to sigma_d = " + core::format_number(limit_started, 4) +
                          (std::isfinite(limit_failed) ? " and none at " + core::format_number(limit_failed, 4) : std::string()) +
                          "; below it the patch's leading edge heals before it loads the stuck interface to the threshold. "
                          "Steady fronts exist down to sigma_c^d (start them with drive.start = steady_front)");
  }
}

// steady_fronts: runs started from the solved front (drive.start = steady_front), possibly kicked, with
// the continuum and the discrete model: their speed against the solved one, v_behind against
// sigma_ss(v_behind) = sigma_d, and, when N varies, the discrete front speed's convergence.
void steady_fronts(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                   const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  Columns t;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto* c = find_model(res[i], "continuum");
    const auto* d = find_model(res[i], "discrete");
    const auto& s = scenes[i];
    const auto* any = c ? c : d;
    if (!any) continue;
    const auto it = any->scalars.find("steady_front_c");
    const double solved = it == any->scalars.end() ? nan : it->second;
    t["sigma_d"].push_back(s.drive.sigma_d);
    t["kick_dv"].push_back(s.drive.kick_dv);
    t["N"].push_back(static_cast<double>(s.discrete.contacts_per_site));
    t["seed"].push_back(static_cast<double>(runs[i].seed));
    t["c_solved"].push_back(solved);
    t["c_continuum"].push_back(c ? c->events.c_front : nan);
    t["c_discrete"].push_back(d ? d->events.c_front : nan);
    t["rel_continuum"].push_back(c ? c->events.c_front / solved - 1.0 : nan);
    t["rel_discrete"].push_back(d ? d->events.c_front / solved - 1.0 : nan);
    t["discrete_vs_continuum"].push_back(c && d ? d->events.c_front / c->events.c_front - 1.0 : nan);
    t["sigma_ss_error_continuum"].push_back(c && c->scalars.count("sigma_ss_at_v_behind")
                                                ? c->scalars.at("sigma_ss_at_v_behind") - s.drive.sigma_d
                                                : nan);
  }
  rep.tables["steady_fronts"] = t;
  rep.definitions["steady_fronts/rel_continuum"] = "c_front (continuum run started from the solved front) / c_solved - 1";
  rep.definitions["steady_fronts/rel_discrete"] = "the same for the discrete model";
  rep.definitions["steady_fronts/discrete_vs_continuum"] = "c_front(discrete) / c_front(continuum) - 1, same grid and step";
  rep.definitions["steady_fronts/sigma_ss_error_continuum"] = "sigma_ss(v_behind) - sigma_d of the continuum run";
  // Stability: a kicked front returns to the branch when its speed matches the unkicked run's.
  double worst = 0.0;
  for (std::size_t k = 0; k < t["kick_dv"].size(); ++k) {
    if (t["kick_dv"][k] == 0.0) continue;
    for (std::size_t j = 0; j < t["kick_dv"].size(); ++j)
      if (t["kick_dv"][j] == 0.0 && t["sigma_d"][j] == t["sigma_d"][k] && t["N"][j] == t["N"][k] && t["seed"][j] == t["seed"][k])
        worst = std::max(worst, std::abs(t["rel_continuum"][k] - t["rel_continuum"][j]));
  }
  if (std::find_if(t["kick_dv"].begin(), t["kick_dv"].end(), [](double x) { return x != 0.0; }) != t["kick_dv"].end()) {
    rep.scalars["kick_max_speed_change"] = worst;
    rep.definitions["kick_max_speed_change"] =
        "max over kicked runs of |c/c_solved (kicked) - c/c_solved (unkicked)|: 0 when every kicked front returns to the branch";
  }
  // N convergence of the discrete front speed (when N varies): RMS over seeds of the discrete vs the
  // continuum speed on the same grid (which removes the grid error), and the seed-mean against the solved speed.
  Columns n;
  for (const auto& [N, idx] : by_value(runs, "discrete.contacts_per_site")) {
    std::vector<double> dc, ds;
    for (std::size_t i : idx) {
      const auto* c = find_model(res[i], "continuum");
      const auto* d = find_model(res[i], "discrete");
      if (!c || !d) continue;
      dc.push_back(d->events.c_front / c->events.c_front - 1.0);
      const auto sc = d->scalars.find("steady_front_c");
      ds.push_back(sc == d->scalars.end() ? nan : d->events.c_front / sc->second - 1.0);
    }
    double ms = 0.0;
    int k = 0;
    for (double x : dc)
      if (std::isfinite(x)) { ms += x * x; ++k; }
    n["N"].push_back(N);
    n["rms_discrete_vs_continuum"].push_back(k ? std::sqrt(ms / k) : nan);
    n["mean_discrete_vs_solved"].push_back(mean_of(ds));
    n["sd_discrete_vs_solved"].push_back(sd_of(ds));
    n["fronts"].push_back(static_cast<double>(finite_count(dc)));
    n["seeds"].push_back(static_cast<double>(dc.size()));
  }
  if (n["N"].size() >= 2) {
    rep.tables["steady_front_N"] = n;
    rep.definitions["steady_front_N/rms_discrete_vs_continuum"] =
        "RMS over seeds of c_front(discrete)/c_front(continuum) - 1 (same grid and step)";
    rep.definitions["steady_front_N/fronts"] = "seeds whose discrete front kept running (a finite c_front)";
    put_fits(rep, "steady_front_speed_exponent", n["N"], n["rms_discrete_vs_continuum"], spec.fit_from,
             "exponent p of the discrete front speed error rms(N) ~ N^p");
  }
}

// The validity map (studies/validity.hpp) under the signature of every analysis.
void validity_friction(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs,
                       const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  analyse_validity_friction(rep, runs, scenes, res);
}
void validity_fig1(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs,
                   const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  analyse_validity_fig1(rep, runs, scenes, res);
}
// fig1 on the strip against its height, the chain as the H -> 0 line (studies/strip_height.hpp).
void strip_height(StudyReport& rep, const StudySpec&, const std::vector<StudyRun>& runs,
                  const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  analyse_strip_height(rep, runs, scenes, res);
}

// Every study kind, in the order they are listed: adding a kind is adding a row. The third column: the
// models the analysis needs in every run (a study whose runs do not list them is refused at load).
constexpr ModelsNeeded both{.continuum = true, .discrete = true};
constexpr ModelsNeeded continuum_model{.continuum = true};
constexpr ModelsNeeded any_model{};
constexpr ModelsNeeded continuum_mean_field{.continuum = true, .mean_field = true};
constexpr StudyKind study_kind_table[] = {
    {"friction_law", "steady friction of the discrete model vs the continuum as contacts_per_site grows", both,
     friction_law_vs_N},
    {"threshold_width", "noise off: distance of the discrete steady law to the continuum vs the threshold width", both,
     friction_law_vs_width},
    {"transient_friction", "velocity_step / spring_block friction histories, discrete vs continuum, vs N", both,
     transient_vs_N},
    {"front_speeds", "fig1 event times and front speeds of the discrete model over seeds vs N, against the continuum",
     both, fronts_vs_N},
    {"fig2", "transient front speed vs sqrt(mu alpha/(eta kappa)), one group per varied parameter (the discrete "
     "model's too when it runs)", continuum_model, fig2},
    {"front_spectrum", "nucleated fronts of homogeneous loading vs sigma_d, against the solved branch (the discrete "
     "model's too when it runs)", continuum_model, spectrum},
    {"validity_friction",
     "the validity map of the mean-field limit on the steady law: bias vs N, alpha, w; N* and its collapse", both,
     validity_friction},
    {"validity_fig1", "the validity map on fig1: the fraction of continuum-like runs vs N and alpha; N* and its collapse",
     both, validity_fig1},
    {"steady_fronts", "runs started from the solved steady front (kicked or not), either model or both, vs sigma_d and N",
     any_model, steady_fronts},
    {"strip_height", "fig1 on the strip vs its height H: t*, t^, c_slow, c_transient, x_arrest of both models against "
     "H/l_e, the 1D chain (bulk.height = 0) as the H -> 0 line", both, strip_height},
    {"disorder_limit", "threshold disorder w: the discrete model -> mean_field as N grows at each w, and mean_field -> "
     "the continuum as w -> 0 with the w of a 1 % departure, on fig1's events or the steady law", continuum_mean_field,
     analyse_disorder_limit},
    {"strip_cmin_height", "no scene runs: c_min(H) of the strip at the base scene's material (mu' = bulk.mu/bulk.height) "
     "over the heights of [paths], the limiting front continued in H, against the 1D c_min of mu' H (docs/fronts.md "
     "§10.12); also strip_cmin_height.csv", continuum_model, nullptr, strip_cmin_height_study, check_strip_cmin_study},
    {"resolution", "the scene at its own resolution and refined ones ([resolution]): each event's discretisation error "
     "(Richardson) and observed order against a tolerance; a stochastic model on its noise-off skeleton, its seeds apart "
     "(docs/studies.md)", any_model, analyse_resolution, nullptr, check_resolution_scene, resolution_groups},
    {"runs", "no analysis: just run every point", any_model, nullptr}};

}  // namespace

std::span<const StudyKind> study_kinds() { return study_kind_table; }

std::string describe(ModelsNeeded needs) {
  if (needs.mean_field)
    return needs.discrete ? "the continuum, mean_field and the discrete model" : "the continuum and the mean_field model";
  if (needs.continuum && needs.discrete) return "the continuum and the discrete model";
  if (needs.continuum) return "the continuum model";
  if (needs.discrete) return "the discrete model";
  return "any model";
}

std::string missing_models(const StudyKind& kind, const Scene& scene) {
  std::string missing;
  if (kind.needs.continuum && !scene.lists("continuum")) missing = "continuum";
  if (kind.needs.mean_field && !scene.lists("mean_field")) {
    if (!missing.empty()) missing += " and ";
    missing += "mean_field";
  }
  if (kind.needs.discrete && !scene.lists("discrete")) missing += (missing.empty() ? "" : " and ") + std::string("discrete");
  return missing;
}

const StudyKind* find_study_kind(std::string_view name) {
  for (const StudyKind& k : study_kind_table)
    if (k.name == name) return &k;
  return nullptr;
}

const ModelResult* find_model(const std::vector<ModelResult>& r, const std::string& model) {
  for (const auto& m : r)
    if (m.model == model) return &m;
  return nullptr;
}

StudyReport analyse_study(const StudySpec& spec, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& results) {
  StudyReport rep;
  rep.notes = spec.notes;  // what loading the study file changed
  if (runs.size() != results.size() || runs.size() != scenes.size())
    throw std::invalid_argument("analyse_study: runs, scenes and results differ in length");
  for (std::size_t i = 0; i < results.size(); ++i)
    for (const auto& m : results[i])
      if (m.status != RunStatus::complete)
        rep.notes.push_back("run " + runs[i].id + " (" + m.model + "): " + to_string(m.status) + " " + m.message);
  const StudyKind* kind = find_study_kind(spec.kind);
  if (!kind) throw std::invalid_argument("unknown study kind '" + spec.kind + "'");
  if (kind->analyse) kind->analyse(rep, spec, runs, scenes, results);
  return rep;
}

}  // namespace slipfront::studies
