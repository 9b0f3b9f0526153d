#include "compare/fronts.hpp"

#include <chrono>
#include <cmath>
#include <limits>

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

}  // namespace

double solved_front_speed(const Scene& s, double sigma_d) {
  const auto f = continuum::solve_steady_front(s.interface, s.bulk, sigma_d);
  return f.status == continuum::FrontStatus::converged ? f.c : std::numeric_limits<double>::quiet_NaN();
}

FrontsResult compute_fronts(const Scene& s, bool scaling) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (s.drive.loading != core::Loading::homogeneous)
    throw core::ParamError("drive.loading", "steady fronts are solved for homogeneous loading (docs/model.md §6)");
  FrontsResult r;
  const auto branch = continuum::continue_steady_fronts(s.interface, s.bulk);
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
  r.scalars["c_min_at_end"] = branch.c_min_at_end ? 1.0 : 0.0;
  r.labels["end"] = continuum::to_string(branch.end);
  r.labels["reason"] = branch.reason;
  // Profiles: the scene's σ_d, a few along the branch, and the limiting front at its end.
  std::vector<double> wanted{s.drive.sigma_d};
  const double lo = r.scalars["sigma_c_d"];
  for (double f : {0.01, 0.05, 0.15, 0.35, 0.6}) wanted.push_back(lo + f * (0.99 - lo));
  for (double sd : wanted) {
    const auto f = continuum::solve_steady_front(ip, s.bulk, sd);
    if (f.status == continuum::FrontStatus::converged) r.profiles.push_back(profile_of(f));
  }
  if (branch.last.saddle_node_limit) r.profiles.push_back(profile_of(branch.last));
  if (scaling) {
    const auto study = continuum::minimal_speed_scaling(ip, s.bulk);
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
      if (f.parameter == "all") {
        r.scalars["scaling_prefactor"] = f.prefactor;
        r.scalars["scaling_spread"] = f.spread;
      }
    }
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

}  // namespace slipfront::compare
