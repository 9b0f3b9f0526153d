#include "compare/fronts.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <optional>

#include "continuum/friction_law.hpp"
#include "continuum/inplane_front.hpp"
#include "core/strip.hpp"

namespace slipfront::compare {
namespace {

// The interface fields every front has (the chain's SteadyFront, the strip's StripFront).
template <class Front>
FrontProfile interface_profile(const Front& f) {
  FrontProfile p;
  p.sigma_d = f.sigma_d;
  p.c = f.c;
  p.v_tip = f.v_tip;
  p.v_behind = f.v_behind;
  p.limiting = f.saddle_node_limit;
  p.c_error = f.speed_error;
  p.fields["xi"] = f.xi;
  p.fields["A"] = f.area;
  p.fields["sigma_bar"] = f.sigma_bar;
  p.fields["v"] = f.slip_rate;
  p.fields["u"] = f.slip;
  return p;
}

FrontProfile profile_of(const continuum::SteadyFront& f) { return interface_profile(f); }

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

// CPU seconds of this thread (the cost model's unit: continuum::strip_solve_cost).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// The estimate of a branch's c_min: its point's speed_error (NaN when there is no c_min).
template <class Branch>
double min_point_error(const Branch& b) {
  for (const auto& p : b.points)
    if (std::isfinite(b.c_min) && p.c == b.c_min) return p.speed_error;
  return nan_value;
}

// (a) The branch: its points as columns, c_min and the law's numbers as scalars, its end and reason. What
// was not computed (c_min of a branch not followed to its end) stays NaN.
template <class Branch>
void store_branch(const Scene& s, const Branch& branch, FrontsResult& r) {
  for (const auto& p : branch.points) {
    r.branch["sigma_d"].push_back(p.sigma_d);
    r.branch["c"].push_back(p.c);
    r.branch["v_tip"].push_back(p.v_tip);
    r.branch["v_behind"].push_back(p.v_behind);
    r.branch["area_behind"].push_back(p.area_behind);
    r.branch["overstress_margin"].push_back(p.overstress_margin);
    r.branch["min_slip_rate"].push_back(p.min_slip_rate);
    r.branch["stable_eigenvalue"].push_back(p.stable_eigenvalue);
    r.branch["residual_norm"].push_back(p.residual_norm);
    r.branch["speed_error"].push_back(p.speed_error);
  }
  const auto& ip = s.interface;
  const double scale = std::sqrt(s.bulk.mu * ip.alpha / (ip.eta * ip.kappa));
  r.scalars["c_min"] = branch.c_min;
  r.scalars["sigma_d_at_c_min"] = branch.sigma_d_at_c_min;
  r.scalars["sigma_c_d"] = continuum::steady_minimum_stress(ip);
  r.scalars["scale"] = scale;
  r.scalars["c_min_over_scale"] = branch.c_min / scale;
  r.scalars["c_s"] = std::sqrt(s.bulk.mu / s.bulk.rho);
  r.scalars["folds"] = static_cast<double>(branch.folds.size());
  r.scalars["c_min_at_end"] = std::isnan(branch.c_min) ? nan_value : branch.c_min_at_end ? 1.0 : 0.0;
  r.labels["end"] = continuum::to_string(branch.end);
  r.labels["reason"] = branch.reason;
}

// (b) Profiles: the front at the scene's σ_d (reported on its own, profile 0 when there is one), a few along
// the branch and the limiting front at its end. Each is a cold solve; a stop request skips the rest (false).
bool solve_profiles(const Scene& s, const continuum::FrontBranch& branch, const std::function<bool()>& stop,
                    FrontsResult& r) {
  const auto& ip = s.interface;
  std::vector<double> wanted{s.drive.sigma_d};
  const double lo = r.scalars["sigma_c_d"];
  if (!branch.points.empty())
    for (double f : {0.01, 0.05, 0.15, 0.35, 0.6}) wanted.push_back(lo + f * (0.99 - lo));
  r.scalars["scene_sigma_d"] = s.drive.sigma_d;
  r.scalars["c_at_scene_sigma_d"] = nan_value;
  r.labels["scene_front"] = "not solved (stopped)";
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    if (stop && stop()) return false;
    const auto f = continuum::solve_steady_front(ip, s.bulk, wanted[k]);
    const bool converged = f.status == continuum::FrontStatus::converged;
    if (k == 0) {
      r.scalars["c_at_scene_sigma_d"] = converged ? f.c : nan_value;
      r.scalars["c_at_scene_sigma_d_error"] = converged ? f.speed_error : nan_value;
      r.labels["scene_front"] = converged ? std::string("converged")
                                          : std::string(continuum::to_string(f.status)) + ": " + f.reason;
    }
    if (converged) r.profiles.push_back(profile_of(f));
  }
  if (branch.last.saddle_node_limit) r.profiles.push_back(profile_of(branch.last));
  return true;
}

// The 1D chain's estimates (its own: every solve re-solved on every other node, docs/fronts.md §3): c_min's is
// its point's; the tolerance checked over every speed reported (the mesh is fixed, 600 intervals).
void store_chain_accuracy(const continuum::FrontBranch& branch, double rtol, FrontsResult& r) {
  auto& sc = r.scalars;
  sc["c_min_error"] = min_point_error(branch);
  sc["c_min_over_scale_error"] = sc["c_min_error"] / sc["scale"];
  double worst = 0.0;
  int missing = 0, checked = 0;
  auto add = [&](double c, double e) {
    ++checked;
    if (!std::isfinite(e)) ++missing;
    else worst = std::max(worst, e / c);
  };
  for (const auto& p : branch.points) add(p.c, p.speed_error);
  for (const auto& p : r.profiles) add(p.c, p.c_error);
  if (r.scaling_points.count("c_min"))
    for (std::size_t k = 0; k < r.scaling_points["c_min"].size(); ++k)
      if (std::isfinite(r.scaling_points["c_min"][k])) add(r.scaling_points["c_min"][k], r.scaling_points["c_min_error"][k]);
  const bool met = missing == 0 && checked > 0 && worst <= rtol;
  sc["rtol"] = rtol;
  sc["rtol_met"] = met ? 1.0 : 0.0;
  sc["largest_relative_error"] = checked > missing ? worst : nan_value;
  r.labels["resolution"] = "fixed: the 1D solver's mesh, 600 intervals (docs/fronts.md §3)";
  r.labels["accuracy"] = std::string(met ? "met" : "NOT met") + ": largest estimated error " +
                         core::format_number(100.0 * worst, 3) + " % of c over " + std::to_string(checked - missing) +
                         " speeds (rtol " + core::format_number(100.0 * rtol, 3) + " %)" +
                         (missing ? "; " + std::to_string(missing) + " without an estimate" : std::string());
}

// (c) The minimal-speed scaling study: every point (c_min NaN where its branch has none), every fit with
// the points it fitted and tried, and why a fit was refused.
continuum::ScalingStudy run_scaling(const Scene& s, const std::function<bool()>& stop, FrontsResult& r) {
  continuum::ScalingOptions options;
  options.continuation.stop = stop;
  const auto study = continuum::minimal_speed_scaling(s.interface, s.bulk, options);
  auto index = [&](const std::string& name) {
    for (std::size_t k = 0; k < r.scaling_parameters.size(); ++k)
      if (r.scaling_parameters[k] == name) return static_cast<double>(k);
    r.scaling_parameters.push_back(name);
    return static_cast<double>(r.scaling_parameters.size() - 1);
  };
  for (const auto& p : study.points) {
    r.scaling_points["parameter_index"].push_back(index(p.parameter));
    r.scaling_points["value"].push_back(p.value);
    r.scaling_points["c_min"].push_back(p.c_min);
    r.scaling_points["sigma_d_at_c_min"].push_back(p.sigma_d_at_c_min);
    r.scaling_points["scale"].push_back(p.scale);
    r.scaling_points["c_min_error"].push_back(p.c_min_error);
  }
  for (const auto& f : study.fits) {
    r.scaling_fits["parameter_index"].push_back(f.parameter == "all" ? -1.0 : index(f.parameter));
    r.scaling_fits["prefactor"].push_back(f.prefactor);
    r.scaling_fits["spread"].push_back(f.spread);
    r.scaling_fits["rms_relative"].push_back(f.rms_relative);
    r.scaling_fits["points"].push_back(static_cast<double>(f.points));
    r.scaling_fits["tried"].push_back(static_cast<double>(f.tried));
    r.scaling_refused.push_back(f.refused);
    if (f.parameter == "all") {
      r.scalars["scaling_prefactor"] = f.prefactor;
      r.scalars["scaling_spread"] = f.spread;
      r.scalars["scaling_points"] = static_cast<double>(f.points);
      r.scalars["scaling_tried"] = static_cast<double>(f.tried);
    }
  }
  return study;
}

// (d) The status: interrupted on a stop; failed with the reason when no front was found, the branch was not
// followed to its end (c_min not computed) or the pooled scaling fit was refused; complete otherwise.
template <class Branch>
void judge(const Branch& branch, const continuum::ScalingStudy* study, bool stopped, FrontsResult& r) {
  using continuum::BranchEnd;
  if (stopped || branch.end == BranchEnd::stopped || (study && study->stopped)) {
    r.status = RunStatus::interrupted;
    r.message = branch.end == BranchEnd::stopped
                    ? "stopped on request during the continuation: " + branch.reason
                    : std::string("stopped on request after the branch (c_min = ") + core::format_number(branch.c_min) +
                          ")" + (study && study->stopped ? ", during the scaling study (partial)"
                                                         : ", before the profiles and the scaling study were done");
  } else if (branch.points.empty()) {
    r.status = RunStatus::failed;
    r.message = "no steady front found (" + std::string(continuum::to_string(branch.end)) + "): " + branch.reason;
  } else if (!continuum::followed_to_end(branch.end)) {
    r.status = RunStatus::failed;
    r.message = "the branch was not followed to its end (" + std::string(continuum::to_string(branch.end)) +
                " after " + std::to_string(branch.points.size()) + " fronts): " + branch.reason +
                "; c_min not computed (NaN)";
  } else if (study && !study->fits.empty() && !study->fits.back().refused.empty()) {
    r.status = RunStatus::failed;
    r.message = "scaling: no fit of c_min = a sqrt(mu alpha/(eta kappa)): " + study->fits.back().refused;
  }
}


// ---------------------------------------------------------------------------------------------------
// The strip (bulk.height > 0, docs/fronts.md §10.14): the same stages with continuum/strip_front.hpp.

// Every reported speed's estimate (docs/fronts.md §10.20): each branch point, profile and scaling point
// re-solved on every other row (continuum::estimate_strip_speed_error). Counts the numbers over rtol·c and
// those without an estimate (with the first reason).
struct Accuracy {
  int over = 0, missing = 0, checked = 0;
  std::string first_missing;
  double worst = 0.0;  // largest error/c
  void add(double c, double err, const std::string& why) {
    ++checked;
    if (!std::isfinite(err)) {
      if (missing++ == 0) first_missing = why;
      return;
    }
    worst = std::max(worst, err / c);
  }
};

double error_of(const continuum::StripFront& f, const continuum::StripFrontOptions& fo, Accuracy& acc) {
  const auto e = continuum::estimate_strip_speed_error(f, fo);
  acc.add(f.c, e.total, e.note);
  return e.total;
}

// The front at σ_d on `fo`, solved from the front of `kept` nearest to σ_d (not the limiting one). Where Newton does
// not converge from it (docs/fronts.md §10.20: at H = 200 on the chosen 32 rows, the profile at σ_d = 0.2244 from its
// neighbours 0.0037 and 0.0063 away, c 4 % and 6 % off, crept for 40 iterations), σ_d is reached from that front by
// sub-steps (a quarter of the way each, halved on failure, 20 iterations each, at most strip_profile_substeps solves),
// each from the last. Measured there: from the 32-row front at 0.2198 the direct solve crept (c 9.20 -> 9.30 of ~9.74
// in 40 iterations), a quarter step failed in 12, eighths converged in 11-12 each.
constexpr int strip_profile_substeps = 16;
continuum::StripFront strip_front_at(const Scene& s, double sigma_d, const std::vector<continuum::StripFront>& kept,
                                     continuum::StripFrontOptions fo) {
  fo.max_newton = std::max(fo.max_newton, 40);  // from a neighbour far in sigma_d (the path's meshes allow 12)
  const continuum::StripFront* guess = nullptr;
  for (const auto& f : kept)
    if (!f.saddle_node_limit && (!guess || std::abs(f.sigma_d - sigma_d) < std::abs(guess->sigma_d - sigma_d))) guess = &f;
  continuum::StripFront direct = continuum::solve_strip_front(s.interface, s.bulk, sigma_d, fo, guess);
  if (direct.status != continuum::FrontStatus::newton_failed || !guess) return direct;
  continuum::StripFrontOptions so = fo;
  so.max_newton = 20;  // measured 11-12 per eighth of the way at H = 200 (Newton converges slowly there, not the step)
  continuum::StripFront cur = *guess;
  double step = (sigma_d - guess->sigma_d) / 4.0;
  for (int n = 0; n < strip_profile_substeps && cur.sigma_d != sigma_d; ++n) {
    const double next = std::abs(sigma_d - cur.sigma_d) <= std::abs(step) * (1.0 + 1e-9) ? sigma_d : cur.sigma_d + step;
    continuum::StripFront f = continuum::solve_strip_front(s.interface, s.bulk, next, so, &cur);
    if (f.status == continuum::FrontStatus::stopped) return f;
    if (f.status == continuum::FrontStatus::converged) cur = std::move(f);
    else step *= 0.5;
  }
  if (cur.sigma_d == sigma_d) return cur;
  direct.reason += "; by sub-steps from sigma_d = " + core::format_number(guess->sigma_d) + ": stalled at " +
                   core::format_number(cur.sigma_d);
  return direct;
}

// The same front on `fo` (other rows or intervals), from itself.
continuum::StripFront resolve_on(const continuum::StripFront& f, continuum::StripFrontOptions fo) {
  fo.max_newton = std::max(fo.max_newton, 40);  // from other rows: more than a continuation step needs (the path's 12)
  return f.saddle_node_limit ? continuum::solve_strip_saddle_node_front(f.law, f.bulk, fo, f)
                             : continuum::solve_strip_front(f.law, f.bulk, f.sigma_d, fo, &f);
}

FrontProfile profile_of(const continuum::StripFront& f) {
  FrontProfile p = interface_profile(f);
  p.fields["tau"] = f.traction;
  p.y = f.y;
  p.u_xy = f.u;
  p.lift_xy = f.lift;
  p.uy_xy = f.uy;  // the in-plane strip's (empty on the antiplane strip)
  if (!f.normal_stress.empty()) p.fields["sigma_yy"] = f.normal_stress;
  return p;
}

// The strip's shear modulus per unit height μ': μ/H on the antiplane strip, μ(1 − ν)/(2H) on the in-plane strip.
double shear_modulus(const core::BulkParams& b) {
  return b.body() == core::BodyKind::inplane ? continuum::inplane_material(b).mu : core::Strip::modulus(b);
}

// The strip's lengths and speeds of the paper's 2D argument, and the 1D c_min of the same column stiffness.
void store_strip_scalars(const Scene& s, double c_min, const std::function<bool()>& stop, FrontsResult& r) {
  const auto& ip = s.interface;
  const double H = s.bulk.height, mus = shear_modulus(s.bulk);
  r.scalars["height"] = H;
  if (s.bulk.body() == core::BodyKind::inplane) {  // docs/fronts.md §11.6
    const auto m = continuum::inplane_material(s.bulk);
    r.scalars["poisson"] = m.nu;
    r.scalars["normal_load"] = s.bulk.normal_load;
    r.scalars["shear_speed"] = m.shear_speed;
    r.scalars["pressure_speed"] = m.pressure_speed;
    r.scalars["rayleigh_speed"] = m.rayleigh_speed;
    r.scalars["plate_speed"] = m.plate_speed;
  }
  r.scalars["mu_strip"] = mus;
  r.scalars["rho_strip"] = s.bulk.rho / H;
  r.scalars["ell"] = mus;
  r.scalars["ell_kappa"] = mus * ip.kappa / (ip.eta * ip.alpha);
  r.scalars["s"] = mus / ip.eta;
  continuum::ContinuationOptions co;
  co.stop = stop;
  const auto b1 = continuum::continue_steady_fronts(ip, {s.bulk.rho, s.bulk.mu, s.bulk.length, 0.0}, co);
  r.scalars["c_min_1d"] = b1.c_min;
  r.scalars["c_min_1d_error"] = min_point_error(b1);
  r.scalars["c_min_over_1d"] = c_min / b1.c_min;
  if (!std::isfinite(b1.c_min)) r.labels["c_min_1d"] = std::string("not computed: ") + continuum::to_string(b1.end) + ": " + b1.reason;
}

// The in-plane strip's fronts stop at c_s (docs/fronts.md §11.2): where the 1D front of the scene's μ (the plate
// modulus) at σ_d runs at c_s or faster, the in-plane front there is not solved; why, or "" (solve it).
std::string supershear(const Scene& s, double sigma_d) {
  if (s.bulk.body() != core::BodyKind::inplane) return "";
  const double cs = continuum::inplane_material(s.bulk).shear_speed;
  const auto f1 = continuum::solve_steady_front(s.interface, {s.bulk.rho, s.bulk.mu, s.bulk.length, 0.0}, sigma_d);
  if (f1.status == continuum::FrontStatus::converged && f1.c < cs) return "";
  return "not solved: the 1D front of mu = E'H at sigma_d = " + core::format_number(sigma_d) + " runs at " +
         core::format_number(f1.c) + " >= c_s = " + core::format_number(cs) +
         " (or has none): supershear in-plane fronts are not solved (docs/fronts.md §11.2)";
}

// Profiles of the strip: at each wanted σ_d one Newton solve from the branch's front nearest to it (the
// branch's fronts are kept by on_front); the limiting front as it is. Each with its speed's estimate.
bool solve_strip_profiles(const Scene& s, const continuum::StripBranch& branch,
                          const std::vector<continuum::StripFront>& kept, const continuum::StripFrontOptions& fo,
                          const std::function<bool()>& stop, Accuracy& acc, FrontsResult& r) {
  std::vector<double> wanted{s.drive.sigma_d};
  const double lo = r.scalars["sigma_c_d"];
  // along the branch: up to 0.99, or to its first front where that was retried below 0.8 (the in-plane strip's
  // branch starts below the σ_d at which its fronts reach c_s, docs/fronts.md §11.2)
  double hi = 0.99;
  if (!branch.points.empty() && branch.points.front().sigma_d < 0.8) hi = branch.points.front().sigma_d;
  if (!branch.points.empty())
    for (double f : {0.01, 0.05, 0.15, 0.35, 0.6}) wanted.push_back(lo + f * (hi - lo));
  r.scalars["scene_sigma_d"] = s.drive.sigma_d;
  r.scalars["c_at_scene_sigma_d"] = nan_value;
  r.scalars["c_at_scene_sigma_d_error"] = nan_value;
  r.labels["scene_front"] = "not solved (stopped)";
  auto add = [&](const continuum::StripFront& f) {
    r.profiles.push_back(profile_of(f));
    r.profiles.back().c_error = error_of(f, fo, acc);
    return r.profiles.back().c_error;
  };
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    if (stop && stop()) return false;
    if (const std::string why = supershear(s, wanted[k]); !why.empty()) {  // the in-plane strip: not a failure
      if (k == 0) r.labels["scene_front"] = why;
      continue;
    }
    const auto f = strip_front_at(s, wanted[k], kept, fo);
    if (f.status == continuum::FrontStatus::stopped) return false;
    const bool converged = f.status == continuum::FrontStatus::converged;
    const double err = converged ? add(f) : nan_value;
    if (f.status == continuum::FrontStatus::newton_failed) {  // a front that should exist: a speed without estimate
      const std::string why = "no convergence at sigma_d = " + core::format_number(wanted[k]) + ": " + f.reason;
      acc.add(1.0, nan_value, why);
      r.labels["profiles_failed"] += (r.labels["profiles_failed"].empty() ? "" : "; ") + why;  // every one, stored and printed
    }
    if (k == 0) {
      r.scalars["c_at_scene_sigma_d"] = converged ? f.c : nan_value;
      r.scalars["c_at_scene_sigma_d_error"] = err;
      r.labels["scene_front"] = converged ? std::string("converged")
                                          : std::string(continuum::to_string(f.status)) + ": " + f.reason;
    }
  }
  if (branch.last.saddle_node_limit) add(branch.last);
  return !(stop && stop());
}

// One parameter of the scaling study (0: μ' with ρ', c_s fixed; 1: α; 2: η; 3: κ) at f times the scene's.
struct ScaledProblem {
  const Scene& s;
  std::size_t p;

  std::pair<core::InterfaceParams, core::BulkParams> at(double f) const {
    core::InterfaceParams ip = s.interface;
    core::BulkParams b = s.bulk;
    if (p == 0) b.mu *= f, b.rho *= f;
    if (p == 1) ip.alpha *= f;
    if (p == 2) ip.eta *= f;
    if (p == 3) ip.kappa *= f;
    return {ip, b};
  }
  /// The 1D scale sqrt(μ'H α/(ηκ)) (μ'H = bulk.mu) at f.
  double scale(double f) const {
    const auto [ip, b] = at(f);
    return std::sqrt(b.mu * ip.alpha / (ip.eta * ip.kappa));
  }
  /// The parameter's value at f (μ' = bulk.mu/H).
  double value(double f) const {
    const auto [ip, b] = at(f);
    return p == 0 ? shear_modulus(b) : p == 1 ? ip.alpha : p == 2 ? ip.eta : ip.kappa;
  }
};

// The meshes of a scaling solve: the branch's (`fo`), or with `follow_tip` ones that follow the solve's predicted
// tip zone.
struct ScalingMeshes {
  const continuum::StripFrontOptions& fo;
  bool follow_tip;

  continuum::StripFrontOptions at(const core::InterfaceParams& ip, double c) const {
    return follow_tip ? continuum::following_tip(fo, continuum::strip_tip_zone(ip, c, continuum::steady_minimum_velocity(ip)))
                      : fo;
  }
};

// From the limiting front `cur` (f = 1) to f = target on meshes that follow the tip, as the path in H (docs/fronts.md
// §10.11): the predictor the secant in (ln p, ln c) through the last two fronts (the 1D exponent at the first step: at
// large H it is not the 1D one), a failed step halved in ln p down to a factor 1.01, the step grown by 1.5 (at most
// √2) after a success. Returns the front at the target, or the failed solve; `used`: the meshes of its last solve.
continuum::StripFront walk_following_tip(const ScaledProblem& pr, const ScalingMeshes& meshes, continuum::StripFront cur,
                                         double target, continuum::StripFrontOptions& used) {
  const double h_max = std::log(std::sqrt(2.0)), h_min = std::log(1.01);
  double f = 1.0, h = h_max, f_prev = 0.0, c_prev = 0.0;
  while (std::abs(std::log(f / target)) > 1e-9) {
    const double fn = target > 1.0 ? std::min(target, f * std::exp(h)) : std::max(target, f * std::exp(-h));
    const double slope = f_prev > 0.0 ? std::log(cur.c / c_prev) / std::log(f / f_prev)
                                      : std::log(pr.scale(fn) / pr.scale(f)) / std::log(fn / f);
    const double c_guess = cur.c * std::pow(fn / f, slope);
    const auto [ip, b] = pr.at(fn);
    used = meshes.at(ip, c_guess);
    auto next = continuum::solve_strip_saddle_node_front(ip, b, used, cur, c_guess);
    if (next.status == continuum::FrontStatus::converged) {
      f_prev = f, c_prev = cur.c;
      cur = std::move(next);
      f = fn;
      h = std::min(h_max, 1.5 * h);
    } else if ((h *= 0.5) < h_min) {
      return next;
    }
  }
  return cur;
}

// From the limiting front `cur` (f = 1) to f = target on the branch's meshes `fo`, by steps of √2, each guess the
// last front's speed stretched by the ratio of the 1D scales. Returns the front at the target, or the failed solve.
continuum::StripFront walk_on_branch_meshes(const ScaledProblem& pr, const continuum::StripFrontOptions& fo,
                                            continuum::StripFront cur, double target) {
  const double step = target > 1.0 ? std::sqrt(2.0) : 1.0 / std::sqrt(2.0);
  double f = 1.0;
  while (cur.status == continuum::FrontStatus::converged && std::abs(std::log(f / target)) > 1e-9) {
    const double fn = target > 1.0 ? std::min(target, f * step) : std::max(target, f * step);
    const auto [ip, b] = pr.at(fn);
    cur = continuum::solve_strip_saddle_node_front(ip, b, fo, cur, cur.c * pr.scale(fn) / pr.scale(f));
    f = fn;
  }
  return cur;
}

// The point of parameter `name` at f = target in r.scaling_points (NaN without a limiting front: then the reason
// in `dropped`). True when it has one.
bool record_scaling_point(const ScaledProblem& pr, const std::string& name, double target, const continuum::StripFront& cur,
                          const continuum::StripFrontOptions& used, Accuracy& acc, std::string& dropped, FrontsResult& r) {
  const bool ok = cur.status == continuum::FrontStatus::converged;
  if (!ok)
    dropped += name + " = " + core::format_number(pr.value(target)) + ": no limiting front (" +
               continuum::to_string(cur.status) + ": " + cur.reason + ")\n";
  r.scaling_points["c_min_error"].push_back(ok ? error_of(cur, used, acc) : nan_value);
  r.scaling_points["parameter_index"].push_back(static_cast<double>(pr.p));
  r.scaling_points["value"].push_back(pr.value(target));
  r.scaling_points["c_min"].push_back(ok ? cur.c : nan_value);
  r.scaling_points["sigma_d_at_c_min"].push_back(ok ? cur.sigma_d : nan_value);
  r.scaling_points["scale"].push_back(pr.scale(target));
  return ok;
}

// Least-squares slope of y against x (NaN below two points).
double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() < 2) return nan_value;
  double mx = 0.0, my = 0.0, sxx = 0.0, sxy = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) mx += x[k], my += y[k];
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) sxx += (x[k] - mx) * (x[k] - mx), sxy += (x[k] - mx) * (y[k] - my);
  return sxy / sxx;
}

// One row of r.scaling_fits: c_min = a · scale through the points (c, sc), its spread and RMS relative departure,
// `index` the parameter's (-1: pooled), `tried` the points attempted, `exponent` the local exponent.
void add_scaling_fit(FrontsResult& r, const std::vector<double>& c, const std::vector<double>& sc, double index,
                     double exponent, std::size_t tried) {
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) num += c[k] * sc[k], den += sc[k] * sc[k];
  const double a = c.size() ? num / den : nan_value;
  double spread = 0.0, rms = 0.0;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double d = c[k] / (a * sc[k]) - 1.0;
    spread = std::max(spread, std::abs(d));
    rms += d * d;
  }
  rms = c.size() ? std::sqrt(rms / static_cast<double>(c.size())) : nan_value;
  r.scaling_fits["parameter_index"].push_back(index);
  r.scaling_fits["prefactor"].push_back(a);
  r.scaling_fits["spread"].push_back(c.size() ? spread : nan_value);
  r.scaling_fits["rms_relative"].push_back(rms);
  r.scaling_fits["points"].push_back(static_cast<double>(c.size()));
  r.scaling_fits["tried"].push_back(static_cast<double>(tried));
  r.scaling_fits["exponent"].push_back(exponent);
  r.scaling_refused.push_back(c.size() < 2 ? "fewer than two points with a limiting front" : "");
}

// The strip's collapse at the scene's H (--scaling): μ' (bulk.mu at fixed H), α, η, κ each at four values
// (the scene's × 0.5, 1, 2, 4), c_min the limiting front at σ_c^d, reached from the scene's limiting front by
// steps of √2 in the parameter (each from the last, its guess stretched by the ratio of the 1D scales). Fits:
// per parameter the local exponent d ln c_min/d ln p (the 1D line: +1/2 for μ', α and −1/2 for η, κ) and
// c_min = a sqrt(μ'H α/(ηκ)); pooled, the same line through every point. A poor collapse is a result (the
// paper's 2D regimes), not a failure: nothing is refused.
//
// `follow_tip` (a branch started from the path in H, docs/fronts.md §10.19): every solve's meshes follow its
// predicted tip zone ℓ_tip = c/(1 + κ v_m) as on that path (ξ spacing at the tip ℓ_tip/30, first row ℓ_tip/10),
// the scene's limiting front first re-solved so, so that all 16 points have the same resolution of their own
// front; otherwise the branch's meshes throughout (as before).
bool run_strip_scaling(const Scene& s, const continuum::StripFront& scene_limiting, const continuum::StripFrontOptions& fo,
                       bool follow_tip, const std::function<bool()>& stop, Accuracy& acc, FrontsResult& r) {
  const ScalingMeshes meshes{fo, follow_tip};
  continuum::StripFront limiting = scene_limiting;
  if (follow_tip) {  // (kept on the branch's meshes if this re-solve fails)
    auto own = continuum::solve_strip_saddle_node_front(s.interface, s.bulk, meshes.at(s.interface, scene_limiting.c),
                                                        scene_limiting, scene_limiting.c);
    if (own.status == continuum::FrontStatus::converged) limiting = std::move(own);
  }
  const std::vector<std::string> names{"mu", "alpha", "eta", "kappa"};
  // α stays in its domain α ≥ 1 (core/params.cpp): below 2 the four values are × 1, √2, 2, 2√2 instead
  const std::vector<double> factors{0.5, 1.0, 2.0, 4.0}, alpha_factors{1.0, std::sqrt(2.0), 2.0, 2.0 * std::sqrt(2.0)};
  std::string dropped;
  std::vector<double> all_c, all_scale;
  for (std::size_t p = 0; p < names.size(); ++p) {
    r.scaling_parameters.push_back(names[p]);
    const ScaledProblem pr{s, p};
    std::vector<double> lx, ly, cs, sc;
    for (double target : p == 1 && 0.5 * s.interface.alpha < 1.0 ? alpha_factors : factors) {
      if (stop && stop()) return false;
      continuum::StripFrontOptions used = fo;
      const continuum::StripFront cur = follow_tip ? walk_following_tip(pr, meshes, limiting, target, used)
                                                   : walk_on_branch_meshes(pr, fo, limiting, target);
      if (cur.status == continuum::FrontStatus::stopped) return false;
      if (!record_scaling_point(pr, names[p], target, cur, used, acc, dropped, r)) continue;
      lx.push_back(std::log(target));
      ly.push_back(std::log(cur.c));
      cs.push_back(cur.c);
      sc.push_back(pr.scale(target));
    }
    r.labels["scaling_dropped"] = dropped;
    add_scaling_fit(r, cs, sc, static_cast<double>(p), least_squares_slope(lx, ly), factors.size());
    all_c.insert(all_c.end(), cs.begin(), cs.end());
    all_scale.insert(all_scale.end(), sc.begin(), sc.end());
  }
  add_scaling_fit(r, all_c, all_scale, -1.0, nan_value, names.size() * factors.size());
  const std::size_t last = r.scaling_fits["prefactor"].size() - 1;
  r.scalars["scaling_prefactor"] = r.scaling_fits["prefactor"][last];
  r.scalars["scaling_spread"] = r.scaling_fits["spread"][last];
  r.scalars["scaling_points"] = r.scaling_fits["points"][last];
  r.scalars["scaling_tried"] = r.scaling_fits["tried"][last];
  return true;
}

// (a) The strip's branch on the meshes `front` (rows, intervals, grading). Its first front (docs/fronts.md §10.19,
// the rule at continuum::strip_start_needs_height_path): up to H = 10 ℓ the cold start, the path in H at the
// strip's material only if it finds no front; above, the path (then the cold start only if the path does not
// arrive). From the path, the branch and the scaling study work on meshes that follow the front's tip zone, as
// the path does. With `start` (a front of the same problem on other meshes) neither: the branch starts from it.
struct StripBranchRun {
  continuum::StripBranch branch;
  std::vector<continuum::StripFront> kept;  // the branch's fronts, one per point
  continuum::StripFrontOptions front;       // the meshes the branch was solved on
  std::string start;
  bool from_path = false;
  long iterations = 0;                      // the Newton iterations spent (its solves' stop polls), the path's included
  long path_iterations = 0;                 // those of the path in H to the first front
};

StripBranchRun strip_branch(const Scene& s, const continuum::StripFrontOptions& front, const std::function<bool()>& stop,
                            const continuum::StripFront* start = nullptr, const std::string& start_label = "") {
  StripBranchRun out;
  long iterations = 0;  // the solver polls the stop before every Newton iteration: counted there
  continuum::StripContinuationOptions o;
  o.front = front;
  const std::function<bool()> counted = [&iterations, stop] { return ++iterations, stop && stop(); };
  o.front.stop = counted;
  o.stop = stop;
  o.on_front = [&](const continuum::StripFront& f) { out.kept.push_back(f); };
  auto done = [&] {
    out.front = o.front;
    out.front.stop = stop;
    out.iterations = iterations;
    return out;
  };
  if (start) {
    o.start = start;
    out.branch = continuum::continue_strip_fronts(s.interface, s.bulk, o);
    out.start = start_label;
    return done();
  }
  const bool thick = continuum::strip_start_needs_height_path(s.bulk);
  auto& branch = out.branch;
  out.start = "cold start: the 1D front, the strip grown at fixed mu (docs/fronts.md §10.4)";
  if (!thick) branch = continuum::continue_strip_fronts(s.interface, s.bulk, o);
  const bool cold_failed = !thick && branch.points.empty() && branch.end != continuum::BranchEnd::stopped;
  const std::string cold_reason = cold_failed ? branch.reason : std::string();
  if ((thick || cold_failed) && !(stop && stop())) {
    const long before = iterations;
    const continuum::StripPathStart path_start = continuum::strip_start_from_height_path(s.interface, s.bulk, o);
    out.path_iterations = iterations - before;
    if (path_start.front.status == continuum::FrontStatus::converged) {
      out.kept.clear();
      o.front = path_start.options;
      o.front.stop = counted;
      o.start = &path_start.front;
      branch = continuum::continue_strip_fronts(s.interface, s.bulk, o);
      out.from_path = true;
      out.start = (cold_failed ? "cold start found no front (" + cold_reason + "); " : std::string()) + path_start.reason;
    } else if (thick && !(stop && stop())) {
      branch = continuum::continue_strip_fronts(s.interface, s.bulk, o);
      out.start = "cold start, after the path in H failed: " + path_start.reason;
    } else if (cold_failed) {
      out.start += "; the path in H failed too: " + path_start.reason;
    } else {
      branch.end = continuum::BranchEnd::stopped;
      branch.reason = "stopped on request in the path in H to the first front: " + path_start.reason;
    }
  } else if (thick) {
    branch.end = continuum::BranchEnd::stopped;
    branch.reason = "stopped on request before the first front";
  }
  return done();
}

// What a branch costs on other meshes (docs/fronts.md §10.20), in CPU seconds of continuum::strip_solve_cost: the
// pilot's Newton iterations (the path in H apart: the branch on finer meshes starts from the pilot's first front)
// at the finer meshes' price, times the share of the branch in the whole computation (its profiles and every speed's
// estimate on half the rows add 0.85 of the branch: 714 against 292 iterations' worth at H = 17 on 8 rows, 12.0 s
// against 6.5 s of CPU).
constexpr double branch_share = 1.9;
double predicted_seconds(const StripBranchRun& pilot, int rows, int intervals, int components) {
  return branch_share * static_cast<double>(pilot.iterations - pilot.path_iterations) *
         continuum::strip_solve_cost(rows, intervals, components).iteration_seconds;
}

struct MeshChoice {
  continuum::StripFrontOptions front;
  std::string how;        // how they were chosen, and where the choice stopped
  std::string limited;    // "" (met), "budget" (the cost budget), "limit" (a mesh limit), "no convergence", "stopped"
  double spent = 0.0;     // CPU seconds spent so far (the pilot, the control fronts' re-solves), strip_solve_cost's
};

// The choice of the meshes by the tolerance (docs/fronts.md §10.20): the control fronts (the branch's first
// front, the scene's front, the limiting front) re-solved with the rows doubled (same grading) until the
// Richardson estimate |c_2M − c_M|/(2^p − 1) of the finer one is below 0.9 rtol·c for all of them, then the
// intervals doubled until the ξ estimate (twice the intervals) is below 0.1 rtol·c; each from the last, one Newton
// solve each (the ξ check re-solves on half the rows). A refinement whose predicted cost (spent, its control
// re-solves at ~8 iterations each and the branch on it: predicted_seconds) is above st.budget_seconds is not made.
MeshChoice choose_meshes(const Scene& s, const StripBranchRun& pilot, const StripFrontsSettings& st) {
  const double H = s.bulk.height, rtol = st.rtol, two_p = std::pow(2.0, continuum::strip_row_order);
  MeshChoice out{pilot.front, "rows " + std::to_string(pilot.front.rows), "", 0.0};
  auto& fo = out.front;
  auto price = [&st](const continuum::StripFrontOptions& o) {
    return continuum::strip_solve_cost(o.rows, o.intervals, st.components).iteration_seconds;
  };
  const continuum::StripFront scene_front = strip_front_at(s, s.drive.sigma_d, pilot.kept, pilot.front);
  out.spent = static_cast<double>(pilot.iterations + scene_front.newton_iterations) * price(fo);
  std::vector<continuum::StripFront> control{pilot.branch.first, scene_front};
  if (pilot.branch.last.saddle_node_limit) control.push_back(pilot.branch.last);
  std::erase_if(control, [](const continuum::StripFront& f) { return f.status != continuum::FrontStatus::converged; });
  if (control.empty()) return {fo, "no control front converged: the first meshes kept", "no convergence", out.spent};
  auto stop_at = [&](const std::string& why, const std::string& line) {
    out.limited = why;
    out.how += " (" + line + ")";
    return out;
  };
  // the refinement to `fine`, or why not: the mesh limits and the budget
  auto refusal = [&](const continuum::StripFrontOptions& fine) -> std::pair<std::string, std::string> {
    if (fine.rows > st.max_rows || fine.intervals > st.max_intervals)
      return {"limit", "limit: max " + std::to_string(st.max_rows) + " rows, " + std::to_string(st.max_intervals) + " intervals"};
    if (price(fine) > continuum::strip_max_iteration_seconds)
      return {"limit", "limit: " + std::to_string(fine.rows) + " rows, " + std::to_string(fine.intervals) +
                           " intervals exceed the Newton iteration limit"};
    const double total = out.spent + 8.0 * static_cast<double>(control.size()) * price(fine) +
                         predicted_seconds(pilot, fine.rows, fine.intervals, st.components);
    if (total > st.budget_seconds)
      return {"budget", "budget: " + std::to_string(fine.rows) + " rows, " + std::to_string(fine.intervals) + " intervals predicted at " +
                            core::format_number(total, 3) + " s of CPU in all, over --budget " + core::format_number(st.budget_seconds) + " s"};
    return {"", ""};
  };
  auto refine = [&](const continuum::StripFrontOptions& fine) {  // the control fronts on `fine`; false: one failed
    for (auto& f : control) {
      f = resolve_on(f, fine);
      out.spent += static_cast<double>(f.newton_iterations) * price(fine);
      if (f.status != continuum::FrontStatus::converged) return false;
    }
    return true;
  };
  if (st.rows > 0) out.how += " (given)";
  while (st.rows <= 0) {  // the rows, unless given (--rows: then only the intervals are chosen)
    if (fo.stop && fo.stop()) return stop_at("stopped", "stopped");
    const continuum::StripFrontOptions fine = continuum::with_rows(H, fo, 2 * fo.rows);
    if (const auto [why, line] = refusal(fine); !why.empty()) return stop_at(why, line);
    std::vector<double> before;
    for (const auto& f : control) before.push_back(f.c);
    if (!refine(fine)) return stop_at("no convergence", "no convergence on " + std::to_string(fine.rows) + " rows");
    bool met = true;
    for (std::size_t k = 0; k < control.size(); ++k)
      if (std::abs(control[k].c - before[k]) / (two_p - 1.0) > 0.9 * rtol * control[k].c) met = false;
    fo = fine;
    out.how += " -> " + std::to_string(fo.rows);
    if (met) break;
  }
  out.how += ", intervals " + std::to_string(fo.intervals);
  for (;;) {  // the intervals: the ξ part of each control front's estimate (twice the intervals, on half the rows)
    bool met = true;
    for (const auto& f : control) {
      const auto e = continuum::estimate_strip_speed_error(f, fo);
      if (std::isfinite(e.xi) && e.xi > 0.1 * rtol * f.c) met = false;
    }
    if (met) break;
    continuum::StripFrontOptions fine = fo;
    fine.intervals *= 2;
    if (const auto [why, line] = refusal(fine); !why.empty()) return stop_at(why, line);
    if (!refine(fine)) return stop_at("no convergence", "no convergence on " + std::to_string(fine.intervals) + " intervals");
    fo = fine;
    out.how += " -> " + std::to_string(fo.intervals);
  }
  return out;
}

// The branch's estimates: each point's front (kept in order) on every other row; c_min's is its point's.
void store_strip_errors(const StripBranchRun& run, FrontsResult& r, Accuracy& acc) {
  std::vector<double> err;
  for (const auto& f : run.kept) err.push_back(error_of(f, run.front, acc));
  auto& sc = r.scalars;
  if (err.size() == run.branch.points.size() && !err.empty()) r.branch["speed_error"] = err;
  sc["c_min_error"] = nan_value;
  for (std::size_t k = 0; k < run.kept.size() && k < err.size(); ++k)
    if (std::isfinite(sc["c_min"]) && run.kept[k].c == sc["c_min"]) sc["c_min_error"] = err[k];
  sc["c_min_over_scale_error"] = sc["c_min_error"] / sc["scale"];
  sc["c_min_over_1d_error"] = sc["c_min_over_1d"] * (sc["c_min_error"] / sc["c_min"] + sc["c_min_1d_error"] / sc["c_min_1d"]);
}

// The verdict on the tolerance: met when every speed has an estimate within rtol·c; not met, with what stopped
// the choice (`limited`: budget, limit, no convergence, stopped; "" when the choice ended met or was not made).
void judge_accuracy(const Accuracy& acc, double rtol, const std::string& how, const std::string& limited, bool chosen,
                    FrontsResult& r) {
  const bool met = acc.missing == 0 && acc.worst <= rtol && acc.checked > 0;
  r.scalars["rtol"] = rtol;
  r.scalars["rtol_met"] = met ? 1.0 : 0.0;
  r.scalars["largest_relative_error"] = acc.checked > acc.missing ? acc.worst : nan_value;
  r.labels["resolution"] = (chosen ? "chosen by rtol: " : "given: ") + how;
  std::string v = met ? "met" : limited.empty() || !chosen ? "NOT met" : "NOT met (" + limited + ")";
  v += ": largest estimated error " + core::format_number(100.0 * acc.worst, 3) + " % of c over " +
       std::to_string(acc.checked - acc.missing) + " speeds (rtol " + core::format_number(100.0 * rtol, 3) + " %)";
  if (acc.missing > 0)
    v += "; " + std::to_string(acc.missing) + " without an estimate (" + acc.first_missing + ")";
  if (!met && chosen) v += "; the choice stopped at " + how;
  if (!met && !chosen) v += "; refine --rows/--intervals, or leave them to --rtol";
  r.labels["accuracy"] = v;
}

FrontsResult compute_strip_fronts(const Scene& s, bool scaling, const std::function<bool()>& stop,
                                  const StripFrontsSettings& settings) {
  FrontsResult r;
  const bool chosen = settings.rows <= 0 || settings.intervals <= 0;
  continuum::StripFrontOptions first;
  first.rows = settings.rows > 0 ? settings.rows : settings.first_rows;
  first.intervals = settings.intervals > 0 ? settings.intervals : settings.first_intervals;
  const double cpu0 = thread_cpu_seconds();
  StripBranchRun run = strip_branch(s, first, stop);  // (a) the branch, on the first meshes
  std::string how = "rows " + std::to_string(run.front.rows) + ", intervals " + std::to_string(run.front.intervals);
  std::string limited;
  // the cost model's prediction of the whole (without --scaling): what was spent and what remains on the final meshes
  const int comps = settings.components;
  double predicted = static_cast<double>(run.iterations) * continuum::strip_solve_cost(first.rows, first.intervals, comps).iteration_seconds +
                     (branch_share - 1.0) * predicted_seconds(run, first.rows, first.intervals, comps) / branch_share;
  if (chosen && continuum::followed_to_end(run.branch.end) && !(stop && stop())) {
    StripFrontsSettings st = settings;
    if (settings.rows > 0) st.max_rows = settings.rows;            // a given count is kept
    if (settings.intervals > 0) st.max_intervals = settings.intervals;
    const MeshChoice choice = choose_meshes(s, run, st);
    how = choice.how;
    limited = choice.limited;
    const auto& fo = choice.front;
    const bool resolve = fo.rows != run.front.rows || fo.intervals != run.front.intervals;
    predicted = choice.spent + predicted_seconds(run, fo.rows, fo.intervals, comps) * (resolve ? 1.0 : (branch_share - 1.0) / branch_share);
    if (resolve && !(stop && stop())) {
      const continuum::StripFront start = run.branch.first;
      const std::string label = run.start + "; re-solved on the chosen meshes from that front";
      const bool from_path = run.from_path;
      run = strip_branch(s, fo, stop, &start, label);
      run.from_path = from_path;
    }
  }
  r.scalars["budget_seconds"] = settings.budget_seconds;
  r.scalars["predicted_seconds"] = predicted;
  r.labels["start"] = run.start;
  const auto& branch = run.branch;
  store_branch(s, branch, r);
  store_strip_scalars(s, branch.c_min, stop, r);
  r.scalars["rows"] = run.front.rows;
  r.scalars["intervals"] = run.front.intervals;
  r.scalars["row_grading"] = continuum::strip_row_grading(s.bulk.height, run.front);
  const bool stopped = branch.end == continuum::BranchEnd::stopped;
  Accuracy acc;
  const bool profiles = !stopped && solve_strip_profiles(s, branch, run.kept, run.front, stop, acc, r);  // (b) profiles
  if (profiles) store_strip_errors(run, r, acc);
  const bool has_branch = continuum::followed_to_end(branch.end) && branch.last.saddle_node_limit;
  bool scaling_done = false;
  if (scaling && has_branch && profiles)
    scaling_done = run_strip_scaling(s, branch.last, run.front, run.from_path, stop, acc, r);  // (c)
  r.scalars["cpu_seconds"] = thread_cpu_seconds() - cpu0;
  judge_accuracy(acc, settings.rtol, how, limited, chosen, r);
  judge(branch, nullptr, stopped || !profiles || (scaling && has_branch && profiles && !scaling_done) || (stop && stop()),
        r);  // (d)
  if (scaling && !has_branch && r.status == RunStatus::failed) r.message += "; the scaling study was not run";
  return r;
}
}  // namespace

std::string strip_fronts_refusal(const StripFrontsSettings& st, double max_memory_gib) {
  const int rows = st.rows > 0 ? st.rows : st.first_rows, intervals = st.intervals > 0 ? st.intervals : st.first_intervals;
  const auto cost = continuum::strip_solve_cost(rows, intervals, st.components);
  const std::string key = st.rows > 0 ? "--rows" : "--intervals";
  const std::string mesh = std::to_string(rows) + " rows and " + std::to_string(intervals) + " intervals";
  if (cost.iteration_seconds > continuum::strip_max_iteration_seconds)
    return key + ": one Newton iteration of the strip solve on " + mesh + " is estimated at " +
           core::format_number(cost.iteration_seconds, 3) + " s, more than " +
           core::format_number(continuum::strip_max_iteration_seconds) +
           " s (a stop request is seen between iterations; cost ~ intervals (2 rows + 4)^2, in-plane (4 rows + 6)^2, "
           "docs/fronts.md §10.20); "
           "use fewer rows or intervals, or leave them to --rtol";
  if (cost.memory_bytes > max_memory_gib * 1073741824.0)
    return key + ": the strip solve on " + mesh + " needs about " + core::format_number(cost.memory_bytes / 1073741824.0, 3) +
           " GiB, more than limits.max_memory_gib = " + core::format_number(max_memory_gib) + "; use fewer rows or intervals";
  return "";
}

double solved_front_speed(const Scene& s, double sigma_d) {
  const auto f = continuum::solve_steady_front(s.interface, s.bulk, sigma_d);
  return f.status == continuum::FrontStatus::converged ? f.c : std::numeric_limits<double>::quiet_NaN();
}

FrontsResult compute_fronts(const Scene& s, bool scaling, const std::function<bool()>& stop,
                            const StripFrontsSettings& strip) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (s.drive.loading != core::Loading::homogeneous)
    throw core::ParamError("drive.loading", "steady fronts are solved for homogeneous loading (docs/model.md §6)");
  if (s.bulk.body() == core::BodyKind::strip || s.bulk.body() == core::BodyKind::inplane) {
    StripFrontsSettings st = strip;
    if (s.bulk.body() == core::BodyKind::inplane) st.components = 2;  // docs/fronts.md §11.6
    FrontsResult r = compute_strip_fronts(s, scaling, stop, st);
    r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    return r;
  }
  FrontsResult r;
  continuum::ContinuationOptions options;
  options.stop = stop;
  const auto branch = continuum::continue_steady_fronts(s.interface, s.bulk, options);  // (a) the branch
  store_branch(s, branch, r);
  const bool stopped = branch.end == continuum::BranchEnd::stopped;
  const bool profiles = !stopped && solve_profiles(s, branch, stop, r);                  // (b) profiles
  const bool has_branch = continuum::followed_to_end(branch.end) && !branch.points.empty();
  const bool scaling_skipped = scaling && has_branch && profiles && stop && stop();
  std::optional<continuum::ScalingStudy> study;
  if (scaling && has_branch && profiles && !scaling_skipped) study = run_scaling(s, stop, r);  // (c) scaling
  store_chain_accuracy(branch, strip.rtol, r);
  judge(branch, study ? &*study : nullptr, stopped || !profiles || scaling_skipped, r);   // (d) the status
  if (scaling && !study && r.status == RunStatus::failed) r.message += "; the scaling study was not run";
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace slipfront::compare
