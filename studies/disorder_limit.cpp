#include "studies/disorder_limit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <span>
#include <string>
#include <tuple>
#include <utility>

#include "compare/fit.hpp"
#include "core/params.hpp"

namespace slipfront::studies {
namespace {

// The observables: fig1's events (c_slow on the A_tip_alt front, as fig1 reports it) for a bulk scene, the
// steady law for an imposed-rate sweep.
struct Observable {
  const char* name;
  double Events::*field;  ///< nullptr: the steady law
  bool alt;
  const char* what;
};
constexpr Observable fig1_observables[] = {
    {"t_star", &Events::t_star, false, "first yield t*"},
    {"t_hat", &Events::t_hat, false, "instability t^"},
    {"c_slow", &Events::c_slow, true, "slow-front speed (the A_tip_alt front, fig1's c_slow_alt)"},
    {"c_transient", &Events::c_transient, false, "transient front speed"},
    {"x_arrest", &Events::x_arrest, false, "arrest position of the transient"}};
constexpr Observable law_observables[] = {
    {"sigma", nullptr, false, "steady friction sigma_ss(v) (RMS over the swept rates)"},
    {"sigma_min", nullptr, false, "minimum of the tabulated steady law (the weakening branch's bottom)"}};

// Threshold laws and renewals as table codes (a table holds numbers).
constexpr const char* law_names[] = {"delta", "uniform", "gaussian", "weibull"};
constexpr const char* renewal_names[] = {"fresh", "quenched"};
template <std::size_t K>
double code_of(const char* const (&names)[K], const std::string& s) {
  for (std::size_t k = 0; k < K; ++k)
    if (s == names[k]) return static_cast<double>(k);
  return -1.0;
}

const std::vector<double>& sigma_of(const ModelResult& m) {
  static const std::vector<double> empty;
  const auto it = m.friction_law.find("sigma");
  return it == m.friction_law.end() ? empty : it->second;
}

// The observable's value for one model (the steady law: NaN for `sigma`, a curve, the minimum for sigma_min).
double value_of(const Observable& o, const ModelResult& m) {
  if (o.field) return (o.alt ? m.events_alt : m.events).*o.field;
  if (std::string(o.name) == "sigma_min") {
    const auto& s = sigma_of(m);
    return s.empty() ? nan : *std::min_element(s.begin(), s.end());
  }
  return nan;
}

// Relative difference of model a to model b: (a - b)/b for a scalar, RMS over v of (a_k - b_k)/b_k for the law.
double relative(const Observable& o, const ModelResult& a, const ModelResult& b) {
  if (o.field || std::string(o.name) != "sigma") {
    const double va = value_of(o, a), vb = value_of(o, b);
    return (va - vb) / vb;
  }
  const auto& sa = sigma_of(a);
  const auto& sb = sigma_of(b);
  const std::size_t n = std::min(sa.size(), sb.size());
  if (n == 0) return nan;
  double s2 = 0.0;
  for (std::size_t k = 0; k < n; ++k) s2 += std::pow((sa[k] - sb[k]) / sb[k], 2);
  return std::sqrt(s2 / static_cast<double>(n));
}

// The steady law per seed: the mean over v of (a_k - b_k)/b_k (signed: its spread over seeds is the random part).
double signed_mean(const ModelResult& a, const ModelResult& b) {
  const auto& sa = sigma_of(a);
  const auto& sb = sigma_of(b);
  const std::size_t n = std::min(sa.size(), sb.size());
  double s = 0.0;
  for (std::size_t k = 0; k < n; ++k) s += (sa[k] - sb[k]) / sb[k];
  return n ? s / static_cast<double>(n) : nan;
}


using Key = std::tuple<double, double, double>;  // law, renewal, w

std::string label(const Key& k) {
  const auto [l, r, w] = k;
  return std::string(l >= 0 ? law_names[static_cast<std::size_t>(l)] : "other") + "_" +
         (r >= 0 ? renewal_names[static_cast<std::size_t>(r)] : "other");
}

// The runs of the study by (law, renewal, w): -> N -> the runs with the discrete model (and mean_field); -> the run
// with mean_field and the continuum (one without the discrete model where there is one: the N runs may be cut down,
// e.g. fewer swept rates).
struct DisorderRuns {
  std::map<Key, std::map<double, std::vector<std::size_t>>> with_discrete;
  std::map<Key, std::size_t> with_both;
};

DisorderRuns group_runs(const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                        const std::vector<std::vector<ModelResult>>& res) {
  DisorderRuns g;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& d = scenes[i].discrete;
    const Key key{code_of(law_names, d.threshold), code_of(renewal_names, d.renewal), d.width};
    const bool mf = find_model(res[i], "mean_field") != nullptr;
    if (mf && find_model(res[i], "discrete"))
      g.with_discrete[key][static_cast<double>(d.contacts_per_site)].push_back(i);
    if (mf && find_model(res[i], "continuum")) {
      const auto it = g.with_both.find(key);
      if (it == g.with_both.end() || (find_model(res[it->second], "discrete") && !find_model(res[i], "discrete")))
        g.with_both[key] = i;
    }
  }
  return g;
}

// One observable at one (key, N) over the seeds `idx`: the row's columns of `tn`; returns the RMS and the standard
// deviation over seeds of the relative difference (the steady law's random part: per seed the signed mean over v).
std::pair<double, double> seed_statistics(Columns& tn, const Observable& o, const std::vector<std::size_t>& idx,
                                          const std::vector<std::vector<ModelResult>>& res) {
  double s2 = 0.0, s1 = 0.0, dsum = 0.0, mfv = nan;
  std::vector<double> es;
  for (std::size_t i : idx) {
    const auto* m = find_model(res[i], "mean_field");
    const auto* d = find_model(res[i], "discrete");
    mfv = value_of(o, *m);
    const double e = relative(o, *d, *m);
    if (!std::isfinite(e)) continue;
    s2 += e * e;
    s1 += e;
    dsum += value_of(o, *d);
    es.push_back(o.field || std::string(o.name) != "sigma" ? e : signed_mean(*d, *m));
  }
  const int n = static_cast<int>(es.size());
  const std::string c = o.name;
  const double rms = n ? std::sqrt(s2 / n) : nan;
  double sd = nan;
  if (n > 1) {
    double m = 0.0, v = 0.0;
    for (double e : es) m += e / n;
    for (double e : es) v += (e - m) * (e - m) / (n - 1);
    sd = std::sqrt(v);
  }
  tn[c + "_mean_field"].push_back(mfv);
  tn[c + "_discrete_mean"].push_back(n ? dsum / n : nan);
  tn[c + "_mean_rel"].push_back(n ? s1 / n : nan);
  tn[c + "_rms_rel"].push_back(rms);
  tn[c + "_sd_rel"].push_back(sd);
  tn[c + "_finite"].push_back(n);
  return {rms, sd};
}

// The N-rates at one (law, renewal, w) from the RMS and the spread over seeds at each N (at least 3 N).
void fit_N_rates(StudyReport& rep, const StudySpec& spec, std::span<const Observable> obs, const Key& key,
                 const std::vector<double>& Ns, std::map<std::string, std::vector<double>>& rms_of,
                 std::map<std::string, std::vector<double>>& sd_of) {
  const double w = std::get<2>(key);
  for (const Observable& o : obs) {
    const auto& y = rms_of[o.name];
    const std::string name = std::string("disorder_N_") + o.name + "_" + label(key) + "_w" + core::format_number(w) +
                             "_exponent";
    if (std::all_of(y.begin(), y.end(), [](double v) { return v == 0.0; })) {
      rep.notes.push_back(std::string(o.name) + " (" + label(key) + ", w = " + core::format_number(w) +
                          "): the discrete model equals mean_field at every N (no random draw decides it: the "
                          "event comes before any contact detaches); no N-rate");
      continue;
    }
    const std::string at = " (" + label(key) + ", w = " + core::format_number(w) + ")";
    put_fits(rep, name, Ns, y, spec.fit_from,
             std::string("exponent p of the RMS over seeds of (discrete - mean_field)/mean_field of ") + o.what +
                 " ~ N^p" + at + ": random part and bias together");
    const std::string sd_name = name.substr(0, name.size() - std::string("_exponent").size()) + "_sd_exponent";
    put_fits(rep, sd_name, Ns, sd_of[o.name], spec.fit_from,
             std::string("exponent p of the standard deviation over seeds of (discrete - mean_field)/mean_field of ") +
                 o.what + " ~ N^p" + at + ": the random part, N^(-1/2) in the mean-field limit (docs/model.md §2.1)");
  }
}

// (a) discrete -> mean_field as N grows, at each (law, renewal, w): the table disorder_limit_N and the N-rates.
void discrete_to_mean_field(StudyReport& rep, const StudySpec& spec, std::span<const Observable> obs,
                            const DisorderRuns& g, const std::vector<std::vector<ModelResult>>& res) {
  Columns tn;
  for (const char* c : {"threshold", "renewal", "w", "N", "seeds"}) tn[c];  // the key columns, even without rows
  for (const auto& [key, byN] : g.with_discrete) {
    const auto [l, r, w] = key;
    std::vector<double> Ns;
    std::map<std::string, std::vector<double>> rms_of, sd_of;
    for (const auto& [N, idx] : byN) {
      tn["threshold"].push_back(l);
      tn["renewal"].push_back(r);
      tn["w"].push_back(w);
      tn["N"].push_back(N);
      tn["seeds"].push_back(static_cast<double>(idx.size()));
      Ns.push_back(N);
      for (const Observable& o : obs) {
        const auto [rms, sd] = seed_statistics(tn, o, idx, res);
        rms_of[o.name].push_back(rms);
        sd_of[o.name].push_back(sd);
      }
    }
    if (Ns.size() >= 3) fit_N_rates(rep, spec, obs, key, Ns, rms_of, sd_of);
  }
  rep.tables["disorder_limit_N"] = tn;
  rep.definitions["disorder_limit_N/threshold"] = "threshold law: 0 delta, 1 uniform, 2 gaussian, 3 weibull";
  rep.definitions["disorder_limit_N/renewal"] = "renewal: 0 fresh, 1 quenched";
  for (const Observable& o : obs) {
    const std::string c = o.name;
    rep.definitions["disorder_limit_N/" + c + "_rms_rel"] =
        "RMS over seeds of the discrete model's relative difference to mean_field of " + std::string(o.what) +
        (o.field ? "" : " (per seed: RMS over v)");
    rep.definitions["disorder_limit_N/" + c + "_mean_rel"] = "mean over seeds of that relative difference (the bias)";
  }
}

// Per (law, renewal): the widths and, per observable, |mean_field - continuum|/continuum at each.
using WidthCurves =
    std::map<std::pair<double, double>, std::pair<std::vector<double>, std::map<std::string, std::vector<double>>>>;

// (b) mean_field -> continuum: the table disorder_limit_w; returns its curves in w.
WidthCurves mean_field_to_continuum(StudyReport& rep, std::span<const Observable> obs, const DisorderRuns& g,
                                    const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  Columns tw;
  for (const char* c : {"threshold", "renewal", "w", "dt"}) tw[c];
  WidthCurves curves;
  for (const auto& [key, i] : g.with_both) {
    const auto [l, r, w] = key;
    const auto* m = find_model(res[i], "mean_field");
    const auto* c = find_model(res[i], "continuum");
    tw["threshold"].push_back(l);
    tw["renewal"].push_back(r);
    tw["w"].push_back(w);
    tw["dt"].push_back(scenes[i].time.dt);
    auto& [ws, rels] = curves[{l, r}];
    ws.push_back(w);
    for (const Observable& o : obs) {
      const std::string n = o.name;
      const double rel = std::abs(relative(o, *m, *c));
      tw[n + "_mean_field"].push_back(value_of(o, *m));
      tw[n + "_continuum"].push_back(value_of(o, *c));
      tw[n + "_rel_diff"].push_back(rel);
      rels[n].push_back(rel);
    }
  }
  rep.tables["disorder_limit_w"] = tw;
  rep.definitions["disorder_limit_w/threshold"] = "threshold law: 0 delta, 1 uniform, 2 gaussian, 3 weibull";
  rep.definitions["disorder_limit_w/renewal"] = "renewal: 0 fresh, 1 quenched";
  rep.definitions["disorder_limit_w/dt"] = "the run's fixed time step (time.dt; 0: the scene's own)";
  for (const Observable& o : obs)
    rep.definitions["disorder_limit_w/" + std::string(o.name) + "_rel_diff"] =
        "|mean_field - continuum| / continuum of " + std::string(o.what) + (o.field ? "" : " (RMS over v)");
  return curves;
}

// The w -> 0 rates and the 1 % crossings of the curves. The rate is fitted over w <= alpha - 1 (`w_fit_max`): once
// the threshold spread reaches the margin of the contact stress above the mean threshold, the departure jumps (the
// steady law's tau = alpha + eta v/A, docs/studies.md).
void fit_w_rates(StudyReport& rep, std::span<const Observable> obs, const WidthCurves& curves, double w_fit_max) {
  for (const auto& [lr, wc] : curves) {
    const auto& [ws, rels] = wc;
    const std::string lab = label(Key{lr.first, lr.second, 0.0});
    for (const Observable& o : obs) {
      const auto& y = rels.at(o.name);
      std::vector<double> fx, fy;
      for (std::size_t k = 0; k < ws.size(); ++k)
        if (ws[k] > 0 && ws[k] <= w_fit_max && y[k] > 1e-12) { fx.push_back(ws[k]); fy.push_back(y[k]); }
      const std::string base = std::string(o.name) + "_" + lab;
      if (fx.size() >= 3)
        put_fit(rep, "disorder_w_" + base + "_exponent", fit_power_law(fx, fy),
                 std::string("exponent p of |mean_field - continuum|/continuum of ") + o.what + " ~ w^p over w <= alpha - 1 = " +
                     core::format_number(w_fit_max) + " (" + lab + "; widths with a difference below 1e-12 left out)");
      else
        rep.notes.push_back(base + ": fewer than 3 widths w <= alpha - 1 = " + core::format_number(w_fit_max) +
                            " with a mean_field - continuum difference above round-off: no w-rate");
      const LevelCrossing x = crossing_in_log_w(ws, y, disorder_limit_level);
      const std::string name = "disorder_w1pct_" + base;
      rep.scalars[name] = x.w;
      rep.scalars[name + "_status"] = x.status;
      rep.definitions[name] = std::string("the w at which |mean_field - continuum|/continuum of ") + o.what +
                              " first exceeds 1 %, interpolated linearly in log w (" + lab +
                              "); _status: 0 crossed, -1 above 1 % already at the smallest w, +1 within 1 % at every w";
      if (x.status != 0)
        rep.notes.push_back(base + ": " + (x.status < 0 ? "mean_field differs from the continuum by more than 1 % "
                                                          "already at the smallest w"
                                                        : "mean_field is within 1 % of the continuum at every w"));
    }
  }
}

}  // namespace

LevelCrossing crossing_in_log_w(const std::vector<double>& w, const std::vector<double>& rel, double level) {
  std::vector<std::pair<double, double>> p;
  for (std::size_t k = 0; k < std::min(w.size(), rel.size()); ++k)
    if (w[k] > 0 && std::isfinite(rel[k])) p.emplace_back(w[k], rel[k]);
  std::sort(p.begin(), p.end());
  if (p.empty()) return {nan, 1};
  if (p.front().second > level) return {nan, -1};
  for (std::size_t k = 1; k < p.size(); ++k)
    if (p[k].second > level) {
      const auto [w0, r0] = p[k - 1];
      const auto [w1, r1] = p[k];
      const double f = (level - r0) / (r1 - r0);
      return {std::exp(std::log(w0) + f * (std::log(w1) - std::log(w0))), 0};
    }
  return {nan, 1};
}

void analyse_disorder_limit(StudyReport& rep, const StudySpec& spec, const std::vector<StudyRun>& runs,
                            const std::vector<Scene>& scenes, const std::vector<std::vector<ModelResult>>& res) {
  const bool law = !scenes.empty() && scenes[0].drive.loading == core::Loading::imposed_rate;
  const std::span<const Observable> obs = law ? std::span<const Observable>(law_observables)
                                              : std::span<const Observable>(fig1_observables);
  const DisorderRuns g = group_runs(runs, scenes, res);
  discrete_to_mean_field(rep, spec, obs, g, res);
  const WidthCurves curves = mean_field_to_continuum(rep, obs, g, scenes, res);
  fit_w_rates(rep, obs, curves, scenes.empty() ? 0.0 : scenes[0].interface.alpha - 1.0);
}

}  // namespace slipfront::studies
