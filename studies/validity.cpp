#include "studies/validity.hpp"

#include <boost/math/distributions/normal.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "compare/fit.hpp"
#include "core/params.hpp"

namespace slipfront::studies {
namespace {

constexpr double nan_v = std::numeric_limits<double>::quiet_NaN();

// Bias (RMS over v of the seed-mean relative error, with the random share var/S removed), random part (RMS
// over v of the seed spread) and total, of errors e[seed][v] — the estimators of the friction_law study.
struct ErrorParts {
  double bias = nan_v, random = nan_v, total = nan_v;
};
ErrorParts error_parts(const std::vector<std::vector<double>>& e) {
  ErrorParts p;
  const std::size_t S = e.size();
  if (S == 0 || e[0].empty()) return p;
  const std::size_t K = e[0].size();
  double bias = 0, var_sum = 0, tot = 0;
  for (std::size_t k = 0; k < K; ++k) {
    double m = 0;
    for (std::size_t s = 0; s < S; ++s) m += e[s][k];
    m /= static_cast<double>(S);
    double v = 0;
    for (std::size_t s = 0; s < S; ++s) {
      v += (e[s][k] - m) * (e[s][k] - m);
      tot += e[s][k] * e[s][k];
    }
    v = S > 1 ? v / static_cast<double>(S - 1) : 0.0;
    var_sum += v;
    bias += std::max(0.0, m * m - v / static_cast<double>(S));
  }
  const double Kd = static_cast<double>(K), Sd = static_cast<double>(S);
  p.bias = std::sqrt(bias / Kd);
  p.random = std::sqrt(var_sum / Kd);
  p.total = std::sqrt(tot / (Kd * Sd));
  return p;
}

double value_of(const Scene& s, const char* what) {
  if (std::string(what) == "alpha") return s.interface.alpha;
  if (std::string(what) == "width") return s.discrete.width;
  if (std::string(what) == "N") return static_cast<double>(s.discrete.contacts_per_site);
  if (std::string(what) == "kappa") return s.interface.kappa;
  if (std::string(what) == "eta") return s.interface.eta;
  // "dt": the step setting of the discrete model's integrator — the fixed implicit step, the leap condition's ε of
  // the step-controlled one (time.integrator = adaptive, docs/numerics.md §9; smaller is finer), 0 for the explicit
  // reference scheme
  if (s.time.integrator == core::Integrator::implicit_trapezoidal) return s.time.dt;
  if (s.time.integrator == core::Integrator::adaptive_rosenbrock) return s.time.leap_epsilon;
  return 0.0;
}

// Power-law fit of N* against α − 1 over the finite points: the collapse exponent.
void put_collapse(StudyReport& rep, const std::string& name, const std::vector<double>& am1, const std::vector<double>& nstar,
                  const std::string& what) {
  std::vector<double> x, y;
  for (std::size_t k = 0; k < am1.size(); ++k)
    if (std::isfinite(nstar[k]) && nstar[k] > 0) {
      x.push_back(am1[k]);
      y.push_back(nstar[k]);
    }
  if (x.size() < 3) {
    rep.notes.push_back(name + ": fewer than 3 finite crossovers, no exponent fitted");
    return;
  }
  const LineFit f = fit_power_law(x, y);
  rep.scalars[name] = f.slope;
  rep.scalars[name + "_ci_low"] = f.slope_ci_low;
  rep.scalars[name + "_ci_high"] = f.slope_ci_high;
  rep.scalars[name + "_points"] = f.n;
  rep.scalars[name + "_prefactor"] = std::exp(f.intercept);
  rep.definitions[name] = what + " (least-squares slope in log-log; _ci_low/_ci_high: 95% Student-t interval)";
}

// ---------------------------------------------------------------------------------------------
// Shared by both analyses.

// Calls f(i, continuum, discrete) for each run i that has the results of both models.
template <class F>
void for_each_compared_run(const std::vector<StudyRun>& runs, const std::vector<std::vector<ModelResult>>& res, F&& f) {
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto* c = find_model(res[i], "continuum");
    const auto* d = find_model(res[i], "discrete");
    if (c && d) f(i, *c, *d);
  }
}

// The α columns of one row.
void put_alpha(Columns& t, double alpha) {
  t["alpha"].push_back(alpha);
  t["alpha_minus_1"].push_back(alpha - 1.0);
}

// One crossover of a row: N_star_<tag>, and whether the error was below the level from the smallest N.
void put_crossover(Columns& x, const std::string& tag, const Crossover& c) {
  const std::string n = "N_star_" + tag;
  x[n].push_back(c.n_star);
  x[n + "_valid_everywhere"].push_back(c.below_at_start ? 1.0 : 0.0);
}

// ---------------------------------------------------------------------------------------------
// validity_friction: the steady friction law against N, α, w, κ and η (docs/validity.md §2).

// errors[(α, w, κ, η)][N] = per seed, the relative error of the steady friction at each v
using FrictionKey = std::tuple<double, double, double, double>;
using FrictionErrors = std::map<FrictionKey, std::map<double, std::vector<std::vector<double>>>>;

FrictionErrors gather_friction_errors(const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                                      const std::vector<std::vector<ModelResult>>& res) {
  FrictionErrors errors;
  for_each_compared_run(runs, res, [&](std::size_t i, const ModelResult& c, const ModelResult& d) {
    if (!c.friction_law.count("sigma") || !d.friction_law.count("sigma")) return;
    const auto &sc = c.friction_law.at("sigma"), &sd = d.friction_law.at("sigma");
    std::vector<double> e;
    for (std::size_t k = 0; k < std::min(sc.size(), sd.size()); ++k) e.push_back(sd[k] / sc[k] - 1.0);
    const Scene& s = scenes[i];
    errors[{value_of(s, "alpha"), value_of(s, "width"), value_of(s, "kappa"), value_of(s, "eta")}][value_of(s, "N")]
        .push_back(e);
  });
  return errors;
}

// The levels of the bias at which N* is read (1% and 5%), with the tags of their columns.
constexpr std::array<std::pair<double, const char*>, 2> bias_levels{{{0.01, "1"}, {0.05, "5"}}};

// One (α, w, κ, η) point of the study: the error parts at each N of its grid (ascending), and N* at each
// of the bias levels.
struct FrictionPoint {
  double alpha = 0.0, width = 0.0, kappa = 0.0, eta = 0.0;
  std::vector<double> n, seeds;
  std::vector<ErrorParts> parts;
  std::array<Crossover, bias_levels.size()> n_star;
};

std::vector<FrictionPoint> friction_points(const FrictionErrors& errors) {
  std::vector<FrictionPoint> points;
  for (const auto& [key, byN] : errors) {
    FrictionPoint p;
    std::tie(p.alpha, p.width, p.kappa, p.eta) = key;
    std::vector<double> bias;
    for (const auto& [N, e] : byN) {
      p.n.push_back(N);
      p.seeds.push_back(static_cast<double>(e.size()));
      p.parts.push_back(error_parts(e));
      bias.push_back(p.parts.back().bias);
    }
    for (std::size_t l = 0; l < bias_levels.size(); ++l) p.n_star[l] = crossover_n(p.n, bias, bias_levels[l].first);
    points.push_back(std::move(p));
  }
  return points;
}

// The interval of N*: the grid points the crossing lies between (the bias falls from a few % to ~1e-4
// within one factor of 3 in N — the re-sticking stops — so the grid, not the seeds, bounds N*); (0, N_min)
// when valid everywhere, (N_max, inf) when valid nowhere.
std::pair<double, double> crossover_interval(const std::vector<double>& n, const Crossover& c) {
  double lo = nan_v, hi = nan_v;
  for (std::size_t k = 0; k + 1 < n.size(); ++k)
    if (std::isfinite(c.n_star) && n[k] <= c.n_star && c.n_star <= n[k + 1]) lo = n[k], hi = n[k + 1];
  if (c.below_at_start) lo = 0.0, hi = n.front();
  if (c.never_below) lo = n.back(), hi = std::numeric_limits<double>::infinity();
  return {lo, hi};
}

// The tables validity_friction (one row per point and N: the error parts) and validity_crossover (one row
// per point: N* and its interval at each level), with their definitions.
void put_friction_tables(StudyReport& rep, const std::vector<FrictionPoint>& points) {
  Columns t, x;
  for (const auto& p : points) {
    for (std::size_t k = 0; k < p.n.size(); ++k) {
      put_alpha(t, p.alpha);
      t["width"].push_back(p.width);
      t["kappa"].push_back(p.kappa);
      t["eta"].push_back(p.eta);
      t["N"].push_back(p.n[k]);
      t["bias"].push_back(p.parts[k].bias);
      t["random"].push_back(p.parts[k].random);
      t["total"].push_back(p.parts[k].total);
      t["seeds"].push_back(p.seeds[k]);
    }
    put_alpha(x, p.alpha);
    x["width"].push_back(p.width);
    x["kappa"].push_back(p.kappa);
    x["eta"].push_back(p.eta);
    for (std::size_t l = 0; l < bias_levels.size(); ++l) {
      const Crossover& c = p.n_star[l];
      const auto [lo, hi] = crossover_interval(p.n, c);
      const std::string n = std::string("N_star_") + bias_levels[l].second;
      put_crossover(x, bias_levels[l].second, c);
      x[n + "_low"].push_back(lo);
      x[n + "_high"].push_back(hi);
      x[n + "_valid_nowhere"].push_back(c.never_below ? 1.0 : 0.0);
    }
  }
  rep.tables["validity_friction"] = t;
  rep.definitions["validity_friction/bias"] =
      "RMS over v of the seed-mean relative error of the discrete steady friction against the continuum, the random "
      "share var/S removed: the systematic error of the mean-field limit";
  rep.definitions["validity_friction/random"] = "RMS over v of the spread over seeds of the relative error";
  rep.tables["validity_crossover"] = x;
  rep.definitions["validity_crossover/N_star_1"] =
      "N from which the bias stays below 1% (log-log interpolation); NaN with valid_everywhere = 1 (below at the "
      "smallest N: _low/_high = 0, N_min) or valid_nowhere = 1 (above at the largest: N_max, inf); _low/_high: the grid "
      "points the crossing lies between";
  rep.definitions["validity_crossover/N_star_5"] = "the same for 5%";
}

// The reference (κ, η): the pair most (α, w) points were run at; the α collapse uses it, the κ and η
// dependence is read where one of them differs from it. Recorded as scalars.
struct Reference {
  double kappa = 0.0, eta = 0.0;
};
Reference put_reference(StudyReport& rep, const std::vector<FrictionPoint>& points) {
  std::map<std::pair<double, double>, int> pairs;
  for (const auto& p : points) ++pairs[{p.kappa, p.eta}];
  const auto [kappa0, eta0] =
      std::max_element(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.second < b.second; })->first;
  rep.scalars["validity_friction_kappa_ref"] = kappa0;
  rep.scalars["validity_friction_eta_ref"] = eta0;
  return {kappa0, eta0};
}

// A point without threshold disorder at the reference (κ, η).
bool at_reference(const FrictionPoint& p, const Reference& ref) {
  return p.width == 0.0 && p.kappa == ref.kappa && p.eta == ref.eta;
}

// The collapse (docs/validity.md §2): N* ∝ (α − 1)^p at w = 0 and the reference (κ, η), at each bias
// level; the noise-over-margin argument predicts p = −3/2 for the steady law over a sweep that contains
// v* ≈ sqrt((α − 1)/(3ηκ)), −2 at a fixed small v.
void fit_alpha_exponents(StudyReport& rep, const std::vector<FrictionPoint>& points, const Reference& ref) {
  for (std::size_t l = 0; l < bias_levels.size(); ++l) {
    const char* tag = bias_levels[l].second;
    std::vector<double> am1, ns;
    for (const auto& p : points)
      if (at_reference(p, ref)) {
        am1.push_back(p.alpha - 1.0);
        ns.push_back(p.n_star[l].n_star);
      }
    put_collapse(rep, std::string("validity_friction_Nstar") + tag + "_exponent", am1, ns,
                 std::string("exponent p of N* (bias < ") + tag + "%) ~ (alpha - 1)^p at w = 0 (theory: -3/2)");
  }
}

// κ or η as the parameter varied at fixed α: its name, where a point and the reference keep it, and the
// exponent of N* in it that the argument predicts (§1: N* ∝ (κ/η)^{1/2} (α − 1)^{−3/2}).
struct Varied {
  const char* name;
  double FrictionPoint::*value;
  double Reference::*ref;
  const char* theory;
};
constexpr Varied kappa_varied{"kappa", &FrictionPoint::kappa, &Reference::kappa, "+1/2"};
constexpr Varied eta_varied{"eta", &FrictionPoint::eta, &Reference::eta, "-1/2"};

// At each α run at several values of q (w = 0, the other parameter at its reference), the ratio
// N*/N*(κ0, η0) against q/q0, pooled over α, fitted as a power law with a free prefactor (prefactor 1 in
// theory; the reference points themselves are not in the fit: they are 1 by construction).
void fit_parameter_exponent(StudyReport& rep, const std::vector<FrictionPoint>& points, const Reference& ref,
                            const Varied& q, const Varied& fixed) {
  const double q0 = ref.*q.ref;
  std::vector<double> ratio, nratio;
  for (const auto& p : points) {
    if (p.width != 0.0 || p.*fixed.value != ref.*fixed.ref || p.*q.value == q0 || !std::isfinite(p.n_star[0].n_star))
      continue;
    for (const auto& r : points)
      if (at_reference(r, ref) && r.alpha == p.alpha && std::isfinite(r.n_star[0].n_star)) {
        ratio.push_back(p.*q.value / q0);
        nratio.push_back(p.n_star[0].n_star / r.n_star[0].n_star);
      }
  }
  put_collapse(rep, std::string("validity_friction_Nstar1_") + q.name + "_exponent", ratio, nratio,
               std::string("exponent q of N*(bias < 1%) ~ ") + q.name + "^q at fixed alpha, w = 0 (the ratio to N* at the "
               "reference " + q.name + ", pooled over alpha; theory " + q.theory + ")");
}

// The scatter of the full collapse: RMS of the natural-log residuals of its points about the fitted line
// (when one was fitted).
void put_collapse_scatter(StudyReport& rep, const std::vector<double>& am1, const std::vector<double>& scaled) {
  const auto it = rep.scalars.find("validity_friction_collapse_exponent");
  if (it == rep.scalars.end()) return;
  const double p = it->second, a = std::log(rep.scalars["validity_friction_collapse_exponent_prefactor"]);
  double ss = 0;
  int n = 0;
  for (std::size_t k = 0; k < am1.size(); ++k)
    if (std::isfinite(scaled[k]) && scaled[k] > 0) {
      const double r = std::log(scaled[k]) - a - p * std::log(am1[k]);
      ss += r * r;
      ++n;
    }
  rep.scalars["validity_friction_collapse_log_rms"] = n ? std::sqrt(ss / n) : nan_v;
  rep.definitions["validity_friction_collapse_log_rms"] =
      "RMS of the natural-log residuals of the collapse fit (ln 3 = 1.10 is one step of the factor-3 N grid)";
}

// The full collapse: N* (η κ0/(κ η0))^{1/2} against α − 1 over every w = 0 point, and its scatter.
void fit_full_collapse(StudyReport& rep, const std::vector<FrictionPoint>& points, const Reference& ref) {
  std::vector<double> am1, scaled;
  for (const auto& p : points)
    if (p.width == 0.0) {
      am1.push_back(p.alpha - 1.0);
      scaled.push_back(p.n_star[0].n_star * std::sqrt((p.eta / ref.eta) / (p.kappa / ref.kappa)));
    }
  put_collapse(rep, "validity_friction_collapse_exponent", am1, scaled,
               "exponent p of N*(bias < 1%) (eta kappa0/(kappa eta0))^(1/2) ~ (alpha - 1)^p over every w = 0 point, all "
               "kappa and eta (theory -3/2: the points of every kappa and eta on one line)");
  if (!scaled.empty()) put_collapse_scatter(rep, am1, scaled);
}

// The exponents left free: N*(1%) = C (α − 1)^p κ^q η^r over every w = 0 point, to compare with the argument's
// (−3/2, +1/2, −1/2).
void fit_free_exponents(StudyReport& rep, const std::vector<FrictionPoint>& points) {
  std::vector<std::vector<double>> f(3);
  std::vector<double> ns;
  for (const auto& p : points)
    if (p.width == 0.0) {
      f[0].push_back(p.alpha - 1.0);
      f[1].push_back(p.kappa);
      f[2].push_back(p.eta);
      ns.push_back(p.n_star[0].n_star);
    }
  const PowerLawFit fit = fit_power_law_multi(f, ns);
  if (fit.exponents.size() == 3) {
    const char* names[] = {"alpha_minus_1", "kappa", "eta"};
    const char* theory[] = {"-3/2", "+1/2", "-1/2"};
    for (int c = 0; c < 3; ++c) {
      const std::string n = std::string("validity_friction_free_fit_") + names[c] + "_exponent";
      rep.scalars[n] = fit.exponents[c];
      rep.scalars[n + "_ci_low"] = fit.ci_low[c];
      rep.scalars[n + "_ci_high"] = fit.ci_high[c];
      rep.definitions[n] = std::string("exponent of ") + names[c] + " in N*(bias < 1%) = C (alpha - 1)^p kappa^q eta^r, "
                           "least squares in log over every w = 0 point with a finite N* (theory " + theory[c] +
                           "; _ci_low/_ci_high: 95% Student-t interval; N* interpolated on the grid, so the interval "
                           "understates the grid's share of the error)";
    }
    rep.scalars["validity_friction_free_fit_log_rms"] = fit.log_rms;
    rep.scalars["validity_friction_free_fit_points"] = fit.n;
  } else if (fit.n > 0) {
    rep.notes.push_back("validity_friction: kappa and eta not varied (or too few finite N*): no free three-exponent fit");
  }
}


// ---------------------------------------------------------------------------------------------
// validity_fig1: the modes of fig1 runs against N and α, and the integrator's step (docs/validity.md §3–§4).

using Fig1Key = std::tuple<double, double, double>;  // α, implicit dt (0: explicit), N

// The runs of one (α, dt, N) point: per run the classifier's ratio and shift and the discrete events; the
// continuum's transient speed and t^.
struct Fig1Group {
  std::vector<double> ratio, t_hat_rel, c, t_hat, x_arrest;
  double c_cont = nan_v, t_cont = nan_v;
};

struct Fig1Runs {
  std::map<Fig1Key, Fig1Group> groups;
  Columns per_run;  // every run with its mode: the event distributions per mode
};

Fig1Runs gather_fig1_runs(const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& res) {
  Fig1Runs out;
  Columns& per_run = out.per_run;
  for_each_compared_run(runs, res, [&](std::size_t i, const ModelResult& c, const ModelResult& d) {
    const double alpha = value_of(scenes[i], "alpha"), dt = value_of(scenes[i], "dt"), N = value_of(scenes[i], "N");
    Fig1Group& g = out.groups[{alpha, dt, N}];
    g.c_cont = c.events.c_transient;
    g.t_cont = c.events.t_hat;
    const double r = d.events.c_transient / c.events.c_transient, sh = d.events.t_hat / c.events.t_hat - 1.0;
    g.ratio.push_back(r);
    g.t_hat_rel.push_back(sh);
    g.c.push_back(d.events.c_transient);
    g.t_hat.push_back(d.events.t_hat);
    g.x_arrest.push_back(d.events.x_arrest);
    per_run["run"].push_back(static_cast<double>(i));
    per_run["seed"].push_back(runs[i].seed);
    per_run["alpha"].push_back(alpha);
    per_run["dt"].push_back(dt);
    per_run["N"].push_back(N);
    per_run["continuum_like"].push_back(continuum_like(r, sh) ? 1.0 : 0.0);
    per_run["c_ratio"].push_back(r);
    per_run["t_hat_shift"].push_back(sh);
    for (const auto& f : event_fields) per_run[f.name].push_back(d.events.*f.member);
  });
  return out;
}

void put_fig1_runs_table(StudyReport& rep, Columns per_run) {
  rep.tables["validity_fig1_runs"] = std::move(per_run);
  rep.definitions["validity_fig1_runs"] =
      "one row per run: its mode (continuum_like 1/0), c_ratio = c_transient(discrete)/c_transient(continuum), "
      "t_hat_shift = t^(discrete)/t^(continuum) - 1 and the discrete run's events (docs/model.md §3)";
}

// One (α, dt, N) point classified: the fraction of continuum-like runs, and each mode's events.
struct Fig1Point {
  double alpha = 0.0, dt = 0.0, n = 0.0;
  ModeSplit split;
  double c_continuum = nan_v, t_hat_continuum = nan_v;
  std::map<std::string, std::vector<double>> by_mode;  // "<mode>/<event>" -> values
};

std::vector<Fig1Point> fig1_points(const std::map<Fig1Key, Fig1Group>& groups) {
  std::vector<Fig1Point> points;
  for (const auto& [key, g] : groups) {
    Fig1Point p;
    std::tie(p.alpha, p.dt, p.n) = key;
    p.split = classify_modes(g.ratio, g.t_hat_rel);
    p.c_continuum = g.c_cont;
    p.t_hat_continuum = g.t_cont;
    for (std::size_t k = 0; k < g.ratio.size(); ++k) {
      const std::string mode = continuum_like(g.ratio[k], g.t_hat_rel[k]) ? "continuum_like" : "other";
      p.by_mode[mode + "/c_transient"].push_back(g.c[k]);
      p.by_mode[mode + "/t_hat_shift"].push_back(g.t_hat_rel[k]);
      p.by_mode[mode + "/x_arrest"].push_back(g.x_arrest[k]);
    }
    points.push_back(std::move(p));
  }
  return points;
}

// The q-quantile (linear interpolation) of one mode's finite values; NaN when there are none.
double quantile(std::vector<double> v, double q) {
  std::erase_if(v, [](double y) { return !std::isfinite(y); });
  if (v.empty()) return nan_v;
  std::sort(v.begin(), v.end());
  const double pos = q * static_cast<double>(v.size() - 1);
  const auto k = static_cast<std::size_t>(pos);
  return k + 1 < v.size() ? v[k] + (pos - static_cast<double>(k)) * (v[k + 1] - v[k]) : v[k];
}

// The table validity_fig1: one row per point, its continuum-like fraction and the 10/50/90% quantiles of
// each mode's events, with its definitions.
void put_fig1_point_table(StudyReport& rep, const std::vector<Fig1Point>& points) {
  Columns t;
  for (const auto& p : points) {
    put_alpha(t, p.alpha);
    t["dt"].push_back(p.dt);
    t["N"].push_back(p.n);
    t["runs"].push_back(p.split.runs);
    t["continuum_like"].push_back(p.split.continuum_like);
    t["fraction"].push_back(p.split.fraction);
    t["fraction_low"].push_back(p.split.low);
    t["fraction_high"].push_back(p.split.high);
    t["c_continuum"].push_back(p.c_continuum);
    t["t_hat_continuum"].push_back(p.t_hat_continuum);
    for (const char* mode : {"continuum_like", "other"})
      for (const char* ev : {"c_transient", "t_hat_shift", "x_arrest"})
        for (const auto& [q, tag] : {std::pair{0.1, "q10"}, std::pair{0.5, "q50"}, std::pair{0.9, "q90"}}) {
          const auto it = p.by_mode.find(std::string(mode) + "/" + ev);
          t[std::string(ev) + "_" + mode + "_" + tag].push_back(it == p.by_mode.end() ? nan_v : quantile(it->second, q));
        }
  }
  rep.tables["validity_fig1"] = t;
  rep.definitions["validity_fig1/fraction"] =
      "fraction of continuum-like runs: c_transient(discrete)/c_transient(continuum) < 1.2 (the gap between the "
      "continuum-like mode near 1 and the others at 1.24 and above) and |t^(discrete)/t^(continuum) - 1| < 0.1; _low/_high: 95% Wilson interval";
  rep.definitions["validity_fig1/c_transient_continuum_like_q50"] =
      "the median of c_transient over the continuum-like runs of the point; q10/q90: the 10% and 90% quantiles; the "
      "same for the other runs (_other_) and for t_hat_shift and x_arrest: the event distributions per mode";
}

// The study's step: the largest dt of the points (0 when there are none); finer settings check it.
double reference_step(const std::vector<Fig1Point>& points) {
  std::vector<double> dt;
  for (const auto& p : points) dt.push_back(p.dt);
  return dt.empty() ? 0.0 : *std::max_element(dt.begin(), dt.end());
}

// N*_fig1(α): where the continuum-like fraction reaches 0.5 and 0.9 (log N interpolation), reference dt
// only; and the collapse of N* at 0.5 against α − 1.
void fit_fig1_crossovers(StudyReport& rep, const std::vector<Fig1Point>& points, double dt_ref) {
  std::map<double, std::pair<std::vector<double>, std::vector<double>>> byAlpha;
  for (const auto& p : points)
    if (p.dt == dt_ref) {
      byAlpha[p.alpha].first.push_back(p.n);
      byAlpha[p.alpha].second.push_back(1.0 - p.split.fraction);  // the re-stuck fraction falls with N
    }
  Columns x;
  for (const auto& [alpha, ne] : byAlpha) {
    put_alpha(x, alpha);
    for (const auto& [level, tag] : {std::pair{0.5, "50"}, std::pair{0.1, "90"}})
      put_crossover(x, tag, crossover_n(ne.first, ne.second, level));
  }
  rep.tables["validity_fig1_crossover"] = x;
  rep.definitions["validity_fig1_crossover/N_star_50"] =
      "N at which the continuum-like fraction of fig1 runs reaches 0.5 (log N interpolation; N_star_90: 0.9)";
  put_collapse(rep, "validity_fig1_Nstar50_exponent", x["alpha_minus_1"], x["N_star_50"],
               "exponent p of N* (half of the fig1 runs continuum-like) ~ (alpha - 1)^p (theory: -2)");
}

// Two-sided p-value of the two-proportion z test of fractions p1 of n1 runs and p2 of n2 runs.
double two_proportion_pvalue(double p1, double n1, double p2, double n2) {
  const double p = (p1 * n1 + p2 * n2) / (n1 + n2), se = std::sqrt(p * (1 - p) * (1 / n1 + 1 / n2));
  const double z = se > 0 ? (p1 - p2) / se : 0.0;
  const boost::math::normal unit;
  return 2 * boost::math::cdf(boost::math::complement(unit, std::abs(z)));
}

// The step: where the same (α, N) ran at the study's step and at a finer one (or the explicit reference,
// dt 0 here), the continuum-like fractions compared (two-proportion z test): the fixed-step implicit
// integrator's step error against the statistical error of the fraction. One row per finer setting; the
// scalars repeat the row of the finest implicit step.
void put_fig1_step_table(StudyReport& rep, const std::vector<Fig1Point>& points, double dt_ref) {
  Columns st;
  for (const auto& a : points)
    for (const auto& b : points)
      if (a.alpha == b.alpha && a.n == b.n && a.dt == dt_ref && b.dt < dt_ref) {
        const double n1 = a.split.runs, n2 = b.split.runs, p1 = a.split.fraction, p2 = b.split.fraction;
        const double pv = two_proportion_pvalue(p1, n1, p2, n2);
        st["alpha"].push_back(a.alpha);
        st["N"].push_back(a.n);
        st["dt"].push_back(dt_ref);
        st["dt_fine"].push_back(b.dt);
        st["runs"].push_back(n1);
        st["runs_fine"].push_back(n2);
        st["fraction"].push_back(p1);
        st["fraction_fine"].push_back(p2);
        st["difference"].push_back(p1 - p2);
        st["pvalue"].push_back(pv);
        st["c_continuum"].push_back(a.c_continuum);
        st["c_continuum_fine"].push_back(b.c_continuum);
        if (b.dt > 0 && !(rep.scalars.count("validity_fig1_dt_fine") && rep.scalars["validity_fig1_dt_fine"] < b.dt)) {
          rep.scalars["validity_fig1_dt_fraction_difference"] = p1 - p2;
          rep.scalars["validity_fig1_dt_pvalue"] = pv;
          rep.scalars["validity_fig1_dt_ref"] = dt_ref;
          rep.scalars["validity_fig1_dt_fine"] = b.dt;
        }
      }
  if (st["alpha"].empty()) return;
  rep.tables["validity_fig1_step"] = st;
  rep.definitions["validity_fig1_step"] =
      "the continuum-like fraction at the study's step against a finer setting at the same alpha and N (dt_fine 0: "
      "the explicit reference integrator): difference and two-sided p-value of a two-proportion z test (large: the "
      "step's error is below the fraction's statistical error); c_continuum: the continuum's transient speed at both";
  rep.definitions["validity_fig1_dt_pvalue"] =
      "the validity_fig1_step row of the finest step setting (dt: time.dt of the implicit integrator, or "
      "time.leap_epsilon of the leap integrator under time.integrator = adaptive; 0: the explicit scheme)";
}

}  // namespace

Crossover crossover_n(std::span<const double> n, std::span<const double> error, double level) {
  Crossover c;
  c.n_star = nan_v;
  const std::size_t m = std::min(n.size(), error.size());
  if (m == 0) return c;
  // the last grid point at or above the level; the crossing lies after it
  std::size_t last_above = m;
  for (std::size_t k = 0; k < m; ++k)
    if (!(error[k] < level)) last_above = k;
  if (last_above == m) {
    c.below_at_start = true;
    return c;
  }
  if (last_above + 1 == m) {
    c.never_below = true;
    return c;
  }
  const std::size_t k = last_above;
  const double x0 = std::log(n[k]), x1 = std::log(n[k + 1]);
  const double y0 = std::log(std::max(error[k], 1e-300)), y1 = std::log(std::max(error[k + 1], 1e-300));
  const double t = (std::log(level) - y0) / (y1 - y0);
  c.n_star = std::exp(x0 + std::clamp(t, 0.0, 1.0) * (x1 - x0));
  return c;
}

bool continuum_like(double c_ratio, double t_hat_shift, double c_threshold, double t_threshold) {
  return std::isfinite(c_ratio) && c_ratio < c_threshold && std::abs(t_hat_shift) < t_threshold;
}

ModeSplit classify_modes(std::span<const double> c_ratio, std::span<const double> t_hat_shift, double c_threshold,
                         double t_threshold) {
  ModeSplit m;
  for (std::size_t k = 0; k < c_ratio.size(); ++k) {
    ++m.runs;
    if (continuum_like(c_ratio[k], k < t_hat_shift.size() ? t_hat_shift[k] : 0.0, c_threshold, t_threshold)) ++m.continuum_like;
  }
  if (m.runs == 0) {
    m.fraction = m.low = m.high = nan_v;
    return m;
  }
  const double n = m.runs, p = m.continuum_like / n, z = 1.959963984540054;
  m.fraction = p;
  const double centre = (p + z * z / (2 * n)) / (1 + z * z / n);
  const double half = z * std::sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n);
  m.low = std::max(0.0, centre - half);
  m.high = std::min(1.0, centre + half);
  return m;
}

void analyse_validity_friction(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                               const std::vector<std::vector<ModelResult>>& res) {
  // Per (α, w, κ, η) point: the error parts at each N and N* at 1% and 5% (docs/validity.md §2).
  const std::vector<FrictionPoint> points = friction_points(gather_friction_errors(runs, scenes, res));
  put_friction_tables(rep, points);
  if (points.empty()) return;
  // The exponents of N* in α − 1, κ and η, one at a time about the reference (κ, η), then together.
  const Reference ref = put_reference(rep, points);
  fit_alpha_exponents(rep, points, ref);
  fit_parameter_exponent(rep, points, ref, kappa_varied, eta_varied);
  fit_parameter_exponent(rep, points, ref, eta_varied, kappa_varied);
  fit_full_collapse(rep, points, ref);
  fit_free_exponents(rep, points);
}

void analyse_validity_fig1(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                           const std::vector<std::vector<ModelResult>>& res) {
  // Per run its mode; per (α, dt, N) point the continuum-like fraction and each mode's events (docs/validity.md §3).
  Fig1Runs gathered = gather_fig1_runs(runs, scenes, res);
  put_fig1_runs_table(rep, std::move(gathered.per_run));
  const std::vector<Fig1Point> points = fig1_points(gathered.groups);
  put_fig1_point_table(rep, points);
  // N* against α at the study's step, and the step against finer ones (docs/validity.md §4).
  const double dt_ref = reference_step(points);
  fit_fig1_crossovers(rep, points, dt_ref);
  put_fig1_step_table(rep, points, dt_ref);
}

}  // namespace slipfront::studies
