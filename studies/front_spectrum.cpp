#include "studies/front_spectrum.hpp"

#include <algorithm>
#include <cmath>

#include "continuum/inplane_front.hpp"

namespace slipfront::studies {

WaveSpeeds wave_speeds(const core::BulkParams& bulk) {
  if (bulk.body() == core::BodyKind::inplane) {
    const auto m = continuum::inplane_material(bulk);
    return {m.shear_speed, m.pressure_speed, m.rayleigh_speed};
  }
  return {std::sqrt(bulk.mu / bulk.rho), nan, nan};
}

PeakSpeed front_peak_speed(const ModelResult& r, double x_end, double span) {
  const auto t = r.series.find("t"), tip = r.series.find("tip_x");
  if (t == r.series.end() || tip == r.series.end()) return {nan, nan, nan};
  std::vector<double> ts, xs;
  for (std::size_t i = 0; i < std::min(t->second.size(), tip->second.size()); ++i) {
    const double x = tip->second[i];
    if (!std::isfinite(x)) {
      if (xs.empty()) continue;  // before the first tip
      break;                     // the front healed: its run ended
    }
    if (x > x_end) break;  // the far end's zone (as c_front's fit: up to the last sample at or before x_end)
    ts.push_back(t->second[i]);
    xs.push_back(x);
  }
  return peak_tip_speed(ts, xs, span);
}

namespace {

// The series value of `name` at time `at`, interpolated linearly (NaN outside the series or without it).
double series_at(const ModelResult& r, const std::string& name, double at) {
  const auto t = r.series.find("t"), y = r.series.find(name);
  if (t == r.series.end() || y == r.series.end() || !std::isfinite(at)) return nan;
  const auto& ts = t->second;
  const auto k = static_cast<std::size_t>(std::lower_bound(ts.begin(), ts.end(), at) - ts.begin());
  if (k == 0 || k >= std::min(ts.size(), y->second.size())) return nan;
  const double f = (at - ts[k - 1]) / (ts[k] - ts[k - 1]);
  return y->second[k - 1] + f * (y->second[k] - y->second[k - 1]);
}

// Elastic energy per unit length of the homogeneous stuck state at σ_d: the strip's shear σ_d²H/(2μ') (μ' the
// body's shear modulus per height: μ/H antiplane, μ(1 − ν)/(2H) in-plane) and the interface's σ_d²/(2α).
double stored_energy(const Scene& s) {
  const double sd = s.drive.sigma_d, H = s.bulk.height;
  const double mu_strip = s.bulk.body() == core::BodyKind::inplane ? s.bulk.mu * (1.0 - s.bulk.poisson) / (2.0 * H)
                                                                   : s.bulk.mu / H;
  return sd * sd * ((H > 0.0 ? H / (2.0 * mu_strip) : 0.0) + 1.0 / (2.0 * s.interface.alpha));
}

// One run's row: its peak and settled speeds (homogeneous: c_peak from the series, c_front; edge: the transient's
// c_transient_peak and c_transient, the drive force at t^).
void add_row(Columns& t, const Scene& s, const ModelResult* c) {
  const bool homogeneous = s.drive.loading == core::Loading::homogeneous;
  const WaveSpeeds w = wave_speeds(s.bulk);
  PeakSpeed peak{nan, nan, nan};
  double settled = nan, force = nan;
  if (c && homogeneous) {
    peak = front_peak_speed(*c, s.bulk.length - s.measure.settle_end_zone, 0.5);
    settled = c->events.c_front;
  } else if (c) {
    peak.c = c->events.c_transient_peak;
    settled = c->events.c_transient;
    force = series_at(*c, "drive_force", c->events.t_hat);
  }
  t["homogeneous"].push_back(homogeneous ? 1.0 : 0.0);
  t["sigma_d"].push_back(homogeneous ? s.drive.sigma_d : nan);
  t["K"].push_back(homogeneous ? nan : s.drive.K);
  t["v_d"].push_back(homogeneous ? nan : s.drive.v_d);
  t["stored_energy"].push_back(homogeneous ? stored_energy(s) : nan);
  t["drive_force_at_t_hat"].push_back(force);
  t["c_peak"].push_back(peak.c);
  t["x_peak"].push_back(peak.x);
  t["c_settled"].push_back(settled);
  t["c_peak_over_cs"].push_back(peak.c / w.c_s);
  t["c_settled_over_cs"].push_back(settled / w.c_s);
  t["c_s"].push_back(w.c_s);
  t["c_p"].push_back(w.c_p);
  t["c_R"].push_back(w.c_R);
}

void define_columns(StudyReport& rep) {
  const std::string p = "front_spectrum_speeds/";
  rep.definitions[p + "homogeneous"] = "1: homogeneous loading (a front from the nucleation patch); 0: edge loading";
  rep.definitions[p + "stored_energy"] =
      "elastic energy per unit length of the homogeneous stuck state: sigma_d^2 (H/(2 mu') + 1/(2 alpha)), mu' the "
      "shear modulus per height (docs/fronts.md §12)";
  rep.definitions[p + "drive_force_at_t_hat"] = "edge loading: the drive force F at the instability t^ (the load at nucleation)";
  rep.definitions[p + "c_peak"] =
      "peak tip speed over 0.5 time units: homogeneous, from the series tip_x between the first tip and L - "
      "measure.settle_end_zone (compare::peak_tip_speed); edge, c_transient_peak (docs/model.md §3)";
  rep.definitions[p + "x_peak"] = "homogeneous: the tip position where the fastest window starts";
  rep.definitions[p + "c_settled"] = "homogeneous: c_front (docs/model.md §3.1); edge: c_transient";
  rep.definitions[p + "c_peak_over_cs"] = "c_peak / c_s";
  rep.definitions[p + "c_settled_over_cs"] = "c_settled / c_s";
  rep.definitions[p + "c_s"] = "shear wave speed of the run's body: sqrt(mu'/rho') (docs/model.md §10.2, §9.1)";
  rep.definitions[p + "c_p"] = "in-plane strip: P wave speed c_s sqrt(2(1 - nu)/(1 - 2 nu)); NaN on an antiplane body";
  rep.definitions[p + "c_R"] = "in-plane strip: Rayleigh wave speed rayleigh_ratio(nu) c_s; NaN on an antiplane body";
}

// The value every entry of `v` shares (NaN when they differ or there are none).
double common(const std::vector<double>& v) {
  if (v.empty()) return nan;
  for (double x : v)
    if (!(x == v.front())) return nan;
  return v.front();
}

}  // namespace

void add_spectrum_speeds(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                         const std::vector<std::vector<ModelResult>>& res) {
  Columns t;
  for (std::size_t i = 0; i < runs.size(); ++i) add_row(t, scenes[i], find_model(res[i], "continuum"));
  rep.tables["front_spectrum_speeds"] = t;
  define_columns(rep);
  double max_peak = nan, max_settled = nan, sub = nan, super = nan;
  int supershear = 0;
  for (std::size_t k = 0; k < t["c_s"].size(); ++k) {
    const double p = t["c_peak_over_cs"][k], s = t["c_settled_over_cs"][k];
    if (!(p <= max_peak)) max_peak = std::isfinite(p) ? p : max_peak;
    if (!(s <= max_settled)) max_settled = std::isfinite(s) ? s : max_settled;
    if (p > 1.0 || s > 1.0) ++supershear;
    if (s < 1.0 && !(s <= sub)) sub = s;
    if (s > 1.0 && !(s >= super)) super = s;
  }
  rep.scalars["spectrum_c_s"] = common(t["c_s"]);
  rep.scalars["spectrum_c_p"] = common(t["c_p"]);
  rep.scalars["spectrum_c_R"] = common(t["c_R"]);
  rep.definitions["spectrum_c_s"] = "the runs' shear wave speed c_s (NaN when the runs' bodies differ); _c_p, _c_R likewise";
  rep.scalars["spectrum_max_peak_over_cs"] = max_peak;
  rep.scalars["spectrum_max_settled_over_cs"] = max_settled;
  rep.definitions["spectrum_max_peak_over_cs"] = "largest c_peak / c_s over the runs (continuum); _settled_: of c_settled";
  rep.scalars["spectrum_supershear_runs"] = supershear;
  rep.definitions["spectrum_supershear_runs"] = "runs whose peak or settled tip speed exceeds c_s (continuum)";
  rep.scalars["spectrum_fastest_subshear"] = sub;
  rep.scalars["spectrum_slowest_supershear"] = super;
  rep.definitions["spectrum_fastest_subshear"] =
      "largest c_settled / c_s below 1 and (spectrum_slowest_supershear) smallest above 1: the settled speeds nearest "
      "c_s from either side; a gap of speeds at c_s would show as a wide interval between them at adjacent sigma_d "
      "(docs/fronts.md §12)";
}

}  // namespace slipfront::studies
