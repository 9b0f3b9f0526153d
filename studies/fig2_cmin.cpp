#include "studies/fig2_cmin.hpp"

#include "compare/fit.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <map>
#include <limits>
#include <tuple>

#include "continuum/steady_front.hpp"
#include "continuum/strip_front.hpp"
#include "core/params.hpp"

namespace slipfront::studies {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// One material column: the law, the integrated μ, ρ (docs/model.md §9.1) and the strip's body (in-plane with ν and p,
// §10.2: its μ is E'H); its heights, increasing.
using ColumnKey = std::tuple<double, double, double, double, double, bool, double, double>;  // α, κ, η, μ, ρ, in-plane, ν, p

ColumnKey column_key(const Scene& s) {
  const bool inplane = s.bulk.body() == core::BodyKind::inplane;
  return {s.interface.alpha, s.interface.kappa, s.interface.eta, s.bulk.mu, s.bulk.rho, inplane,
          inplane ? s.bulk.poisson : 0.0, inplane ? s.bulk.normal_load : 0.0};
}

// The column of `key` at height 0 (the chain; continue_strip_height_at_column keeps its body at every H > 0).
core::BulkParams column_bulk(const ColumnKey& key) {
  const auto [a, k, e, mu, rho, inplane, nu, p] = key;
  core::BulkParams b{rho, mu, 1000.0, 0.0};
  if (inplane) {
    b.body_name = "inplane";
    b.poisson = nu;
    b.normal_load = p;
  }
  return b;
}

struct ColumnResult {
  std::map<double, double> c_min;        // H -> c_min (H = 0: the chain's)
  std::map<double, double> error;        // H -> its estimated error (NaN: none)
  std::map<double, std::string> why;     // H -> why there is none
};

// The chain's c_min: the end of the 1D branch (docs/fronts.md §4); the strip's: the limiting front continued in
// H at the fixed column from a thin strip (§10.16; on the in-plane strip its own, §11.9), 8 rows and 200 intervals
// (within 1e-3 of 12 rows, §10.13).
ColumnResult column_speeds(const core::InterfaceParams& law, const core::BulkParams& column, const std::vector<double>& heights) {
  ColumnResult out;
  if (heights.front() == 0.0) {
    const auto b = continuum::continue_steady_fronts(law, {column.rho, column.mu, 1000.0, 0.0});
    if (b.end == continuum::BranchEnd::saddle_node && std::isfinite(b.c_min)) {
      out.c_min[0.0] = b.c_min;
      out.error[0.0] = nan;
      for (const auto& p : b.points)
        if (p.c == b.c_min) out.error[0.0] = p.speed_error;
    } else {
      out.why[0.0] = "the 1D branch ends without a limiting front: " + b.reason;
    }
  }
  std::vector<double> strip(heights.begin() + (heights.front() == 0.0 ? 1 : 0), heights.end());
  if (strip.empty()) return out;
  continuum::StripHeightOptions o;
  o.heights.push_back(std::min(0.5, strip.front()));
  for (double H : strip)
    if (H > o.heights.back()) o.heights.push_back(H);
  o.front.rows = 8;
  o.front.intervals = 200;
  o.front.max_newton = 12;
  const auto path = continuum::continue_strip_height_at_column(law, column, o);
  for (const auto& f : path.fronts) {
    out.c_min[f.bulk.height] = f.c;
    if (std::find(strip.begin(), strip.end(), f.bulk.height) == strip.end()) continue;  // the path's start only
    // the front's own meshes (the path's: they follow its tip zone) for its estimate
    auto mesh = continuum::following_tip(o.front, continuum::strip_tip_zone(law, f.c, f.v_behind), o.tip_resolution,
                                         o.row_resolution);
    mesh.row_grading = f.row_grading;  // its own rows exactly (every other one of them for the estimate)
    out.error[f.bulk.height] = continuum::estimate_strip_speed_error(f, mesh).total;
  }
  for (double H : strip)
    if (!out.c_min.count(H)) out.why[H] = "the path in H stopped before H = " + core::format_number(H) + ": " + path.reason;
  return out;
}

}  // namespace

std::vector<double> minimal_front_speeds(const std::vector<Scene>& scenes, std::vector<std::string>& why,
                                         std::vector<double>* error) {
  std::map<ColumnKey, std::vector<double>> columns;
  for (const auto& s : scenes) columns[column_key(s)].push_back(s.bulk.height);
  std::map<ColumnKey, std::future<ColumnResult>> jobs;
  for (auto& [key, hs] : columns) {
    std::sort(hs.begin(), hs.end());
    hs.erase(std::unique(hs.begin(), hs.end()), hs.end());
    const auto [a, k, e, mu, rho, inplane, nu, p] = key;
    jobs[key] = std::async(std::launch::async, column_speeds, core::InterfaceParams{a, k, e}, column_bulk(key), hs);
  }
  std::map<ColumnKey, ColumnResult> done;
  for (auto& [key, job] : jobs) done[key] = job.get();
  std::vector<double> out;
  why.assign(scenes.size(), "");
  if (error) error->assign(scenes.size(), nan);
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const auto& s = scenes[i];
    const auto& r = done.at(column_key(s));
    const auto it = r.c_min.find(s.bulk.height);
    out.push_back(it == r.c_min.end() ? nan : it->second);
    if (error && r.error.count(s.bulk.height)) (*error)[i] = r.error.at(s.bulk.height);
    if (it == r.c_min.end()) why[i] = r.why.count(s.bulk.height) ? r.why.at(s.bulk.height) : "no c_min";
  }
  return out;
}

void fig2_against_cmin(StudyReport& rep, Columns& all, const std::vector<Scene>& scenes) {
  std::vector<std::string> why;
  std::vector<double> c_min_error;
  const auto c_min = minimal_front_speeds(scenes, why, &c_min_error);
  const char* models[] = {"continuum", "discrete"};
  std::map<double, std::vector<std::size_t>> by_height;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    all["H"].push_back(scenes[i].bulk.height);
    all["inplane"].push_back(scenes[i].bulk.body() == core::BodyKind::inplane ? 1.0 : 0.0);
    all["c_min"].push_back(c_min[i]);
    all["c_min_error"].push_back(c_min_error[i]);
    for (const char* m : models) {
      const double c = all[std::string("c_") + m][i];
      all[std::string("ratio_") + m].push_back(c / c_min[i]);
    }
    by_height[scenes[i].bulk.height].push_back(i);
    if (!why[i].empty()) rep.notes.push_back("run " + std::to_string(i) + ": no c_min: " + why[i]);
  }
  Columns h;
  for (const auto& [H, idx] : by_height) {
    // the lengths of the paper's 2D argument (docs/fronts.md §10.12): l = mu' = mu/H, l_kappa = mu' kappa/(eta alpha),
    // their range over the height's runs
    double l_lo = inf, l_hi = 0, lk_lo = inf, lk_hi = 0;
    for (std::size_t i : idx) {
      const auto& s = scenes[i];
      const double r = H > 0 ? H * H / s.bulk.mu : 0.0;
      const double rk = r * s.interface.eta * s.interface.alpha / s.interface.kappa;
      l_lo = std::min(l_lo, r), l_hi = std::max(l_hi, r), lk_lo = std::min(lk_lo, rk), lk_hi = std::max(lk_hi, rk);
    }
    h["H"].push_back(H);
    h["H_over_l_min"].push_back(l_lo);
    h["H_over_l_max"].push_back(l_hi);
    h["H_over_l_kappa_min"].push_back(lk_lo);
    h["H_over_l_kappa_max"].push_back(lk_hi);
    h["runs"].push_back(static_cast<double>(idx.size()));
    for (const char* m : models) {
      std::vector<double> x, X, y, r, rX;
      for (std::size_t i : idx) {
        x.push_back(c_min[i]);
        X.push_back(all["X"][i]);
        y.push_back(all[std::string("c_") + m][i]);
        r.push_back(all[std::string("ratio_") + m][i]);
        rX.push_back(y.back() / X.back());
      }
      const double mean = mean_of(r), rsd = sd_of(r) / mean, rsd_X = sd_of(rX) / mean_of(rX);
      const int n = finite_count(r);
      h[std::string("slope_") + m].push_back(slope_through_origin(x, y));
      h[std::string("ratio_mean_") + m].push_back(mean);
      h[std::string("ratio_rsd_") + m].push_back(rsd);
      h[std::string("slope_X_") + m].push_back(slope_through_origin(X, y));
      h[std::string("ratio_X_rsd_") + m].push_back(rsd_X);
      h[std::string("measured_") + m].push_back(static_cast<double>(n));
    }
  }
  rep.tables["fig2_heights"] = h;
  rep.definitions["fig2_all/H"] = "bulk.height of the run (0: the 1D chain)";
  rep.definitions["fig2_all/inplane"] = "1: the run's body is the in-plane strip (its c_min the in-plane strip's, "
                                        "docs/fronts.md §11.9); 0: the chain or the antiplane strip";
  rep.definitions["fig2_all/c_min"] =
      "minimal steady front speed of the run's own scene: the end of the 1D branch (chain) or the strip's limiting "
      "front at the run's H, continued in H at fixed mu, rho (docs/fronts.md §10.16)";
  rep.definitions["fig2_all/c_min_error"] =
      "estimated error of c_min (docs/fronts.md §10.20): the 1D solver's own on the chain; on the strip the front re-solved "
      "on every other row (order 1.5 assumed) plus its xi part (8 rows, 200 intervals: ~1 % at H = 100, §10.16); NaN: none";
  rep.definitions["fig2_all/ratio_continuum"] = "c_transient / c_min (continuum)";
  rep.definitions["fig2_all/ratio_discrete"] = "c_transient / c_min (discrete)";
  rep.definitions["fig2_heights/H_over_l_min"] =
      "smallest H/l over the height's runs, l = mu/H (mu' antiplane, E' in-plane; docs/fronts.md §10.12, §11.9); _max: the largest";
  rep.definitions["fig2_heights/H_over_l_kappa_min"] =
      "smallest H/l_kappa over the height's runs, l_kappa = mu' kappa/(eta alpha); _max: the largest";
  rep.definitions["fig2_heights/slope_continuum"] =
      "least-squares slope through the origin of c_transient vs c_min over the height's runs (continuum)";
  rep.definitions["fig2_heights/slope_X_continuum"] =
      "least-squares slope through the origin of c_transient vs sqrt(mu alpha/(eta kappa)) over the height's runs";
  rep.definitions["fig2_heights/ratio_X_rsd_continuum"] =
      "relative standard deviation of c_transient/sqrt(mu alpha/(eta kappa)) over the height's runs";
  rep.definitions["fig2_heights/ratio_rsd_continuum"] =
      "relative standard deviation of c_transient/c_min over the height's runs: the scatter about the collapse";
}

}  // namespace slipfront::studies
