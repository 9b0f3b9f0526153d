#include "compare/fronts.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "continuum/friction_law.hpp"

namespace slipfront::compare {
namespace {

FrontProfile profile_of(const continuum::SteadyFront& f) {
  FrontProfile p;
  p.sigma_d = f.sigma_d;
  p.c = f.c;
  p.v_tip = f.v_tip;
  p.v_behind = f.v_behind;
  p.limiting = f.saddle_node_limit;
  p.fields["xi"] = f.xi;
  p.fields["A"] = f.area;
  p.fields["sigma_bar"] = f.sigma_bar;
  p.fields["v"] = f.slip_rate;
  p.fields["u"] = f.slip;
  return p;
}

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

// (a) The branch: its points as columns, c_min and the law's numbers as scalars, its end and reason. What
// was not computed (c_min of a branch not followed to its end) stays NaN.
void store_branch(const Scene& s, const continuum::FrontBranch& branch, FrontsResult& r) {
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
      r.labels["scene_front"] = converged ? std::string("converged")
                                          : std::string(continuum::to_string(f.status)) + ": " + f.reason;
    }
    if (converged) r.profiles.push_back(profile_of(f));
  }
  if (branch.last.saddle_node_limit) r.profiles.push_back(profile_of(branch.last));
  return true;
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
void judge(const continuum::FrontBranch& branch, const continuum::ScalingStudy* study, bool stopped, FrontsResult& r) {
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

}  // namespace

double solved_front_speed(const Scene& s, double sigma_d) {
  const auto f = continuum::solve_steady_front(s.interface, s.bulk, sigma_d);
  return f.status == continuum::FrontStatus::converged ? f.c : std::numeric_limits<double>::quiet_NaN();
}

FrontsResult compute_fronts(const Scene& s, bool scaling, const std::function<bool()>& stop) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (s.drive.loading != core::Loading::homogeneous)
    throw core::ParamError("drive.loading", "steady fronts are solved for homogeneous loading (docs/model.md §6)");
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
  judge(branch, study ? &*study : nullptr, stopped || !profiles || scaling_skipped, r);   // (d) the status
  if (scaling && !study && r.status == RunStatus::failed) r.message += "; the scaling study was not run";
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace slipfront::compare
