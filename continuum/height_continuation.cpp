// The continuation of the strip's fronts in the height H (docs/fronts.md §10.11, §10.16): at a fixed strip material
// (continue_strip_height; the in-plane strip's: continue_inplane_height, §11.8) or a fixed column
// (continue_strip_height_at_column, either body). Declared in continuum/strip_front.hpp;
// every solve is solve_strip_front_stretched on meshes that follow the predicted front.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "continuum/friction_law.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/strip_front.hpp"

namespace slipfront::continuum {

double strip_tip_zone(const core::InterfaceParams& law, double c, double v_behind) {
  return c / (1.0 + law.kappa * v_behind);
}

// The continuation in H at fixed material (docs/fronts.md §10.11): steps in ln H with the secant predictor
// of ln c, the last front stretched by c_p/c as the guess, the meshes scaled with the predicted tip zone;
// a failed step is halved in ln H, the step grows by 1.5 after a quick solve and shrinks after a slow one.
namespace {

// The path itself: `bulk_at(H)` the scene's bulk at height H, c_s its shear wave speed (the same at every H on
// both paths), `slope0` the predictor's d ln c/d ln H until two steps are known (the thin strip's value).
// Each member is one stage of continue_height.
class HeightPath {
 public:
  HeightPath(const core::InterfaceParams& law, const std::function<core::BulkParams(double)>& bulk_at, double cs,
             double slope0, const StripHeightOptions& o)
      : law_(law), bulk_at_(bulk_at), cs_(cs), slope0_(slope0), o_(o), sigma_c_(steady_minimum_stress(law)),
        sd_(o.limiting ? sigma_c_ : o.sigma_d),
        vb_(o.limiting ? steady_minimum_velocity(law) : strengthening_branch_velocity(law, sd_)) {}

  bool valid_heights();
  bool first_front();
  bool advance_to(double target);
  StripHeightPath take() { return std::move(out_); }
  void finish_height() { out_.fronts.push_back(cur_); }
  void complete() { out_.complete = true; }

 private:
  StripFront solve_at(double H, double c_p, const StripFront& from) const;
  std::optional<StripFront> cold_first_front();
  bool stopped();
  double predicted_speed(double H, double Hn) const;
  void control_step(double c_p, const StripFront& next);

  const core::InterfaceParams& law_;
  const std::function<core::BulkParams(double)>& bulk_at_;
  const double cs_, slope0_;
  const StripHeightOptions& o_;
  const double sigma_c_, sd_, vb_;
  StripHeightPath out_;
  StripFront cur_;                         ///< the last front of the path
  double step_ = std::log(o_.max_factor);  ///< in ln H
};

bool HeightPath::valid_heights() {
  if (o_.heights.empty() || !(o_.heights.front() > 0.0) || !std::is_sorted(o_.heights.begin(), o_.heights.end())) {
    out_.reason = "heights must be positive and increasing";
    return false;
  }
  return true;
}

// One solve at H from `from` stretched by c_p/from.c, on meshes scaled with c_p (the tip zone follows the front).
StripFront HeightPath::solve_at(double H, double c_p, const StripFront& from) const {
  const StripFrontOptions f = following_tip(o_.front, strip_tip_zone(law_, c_p, vb_), o_.tip_resolution, o_.row_resolution);
  return solve_strip_front_stretched(law_, bulk_at_(H), sd_, f, from, c_p, o_.limiting);
}

bool HeightPath::stopped() {
  if (!o_.stop || !o_.stop()) return false;
  out_.reason = "stopped on request at H = " + core::format_number(out_.steps.empty() ? 0.0 : out_.steps.back().height);
  return true;
}

// The first front when none is given: at σ_d, cold; for the limiting front, from the front just above the end of
// the branch (cold from the 1D front at the same σ_d), or, where that fails, from the strip's branch to its end
// (it costs ~30 solves). None (the reason in the path) when the branch has no limiting front.
std::optional<StripFront> HeightPath::cold_first_front() {
  const double H0 = o_.heights.front();
  if (!o_.limiting) return solve_strip_front(law_, bulk_at_(H0), sd_, o_.front);
  StripFront first;
  const double near = sigma_c_ + 0.02 * (1.0 - sigma_c_);
  const StripFront close = solve_strip_front(law_, bulk_at_(H0), near, o_.front);
  if (close.status == FrontStatus::converged) first = solve_strip_saddle_node_front(law_, bulk_at_(H0), o_.front, close);
  if (first.status == FrontStatus::converged && first.saddle_node_limit) return first;
  StripContinuationOptions co;
  co.front = o_.front;
  co.stop = o_.stop;
  StripBranch br = continue_strip_fronts(law_, bulk_at_(H0), co);
  if (br.end != BranchEnd::saddle_node || !br.last.saddle_node_limit) {
    out_.reason = "no limiting front at H = " + core::format_number(H0) + ": " + br.reason;
    return std::nullopt;
  }
  return std::move(br.last);
}

// The first front (given, or cold), then re-solved on the meshes of the path: the path's first step.
bool HeightPath::first_front() {
  const double H0 = o_.heights.front();
  const std::optional<StripFront> found = o_.start ? std::optional<StripFront>(*o_.start) : cold_first_front();
  if (!found) return false;
  const StripFront& first = *found;
  if (first.status != FrontStatus::converged) {
    out_.reason = "no first front at H = " + core::format_number(H0) + ": " + first.reason;
    return false;
  }
  cur_ = solve_at(H0, first.c, first);
  if (cur_.status != FrontStatus::converged) {
    out_.reason = "the first front did not converge on the path's meshes at H = " + core::format_number(H0) + ": " + cur_.reason;
    return false;
  }
  out_.steps.push_back({H0, cur_.c, first.c, cur_.newton_iterations, 0});
  out_.fronts.push_back(cur_);
  return true;
}

// The secant predictor in (ln H, ln c) from the last two steps (the thin strip's slope before), capped halfway
// to c_s.
double HeightPath::predicted_speed(double H, double Hn) const {
  double slope = slope0_;
  if (out_.steps.size() >= 2) {
    const auto& p = out_.steps[out_.steps.size() - 2];
    const auto& q = out_.steps.back();
    slope = std::log(q.c / p.c) / std::log(q.height / p.height);
  }
  return std::min(cur_.c * std::pow(Hn / H, slope), 0.5 * (cur_.c + cs_));
}

// Step control by the predictor's error (the iteration count is no guide at the round-off floor of thick
// strips, where Newton takes 5-9 iterations from a prediction good to 1e-6).
void HeightPath::control_step(double c_p, const StripFront& next) {
  const double miss = std::abs(c_p / next.c - 1.0);
  if (miss < o_.target_miss || next.newton_iterations <= o_.target_newton) step_ = std::min(std::log(o_.max_factor), 1.5 * step_);
  else if (miss > 5.0 * o_.target_miss) step_ *= 0.6;
}

// Steps in ln H up to `target`, each failed one halved; false when the path stalls or is stopped.
bool HeightPath::advance_to(double target) {
  int rejected = 0;
  while (cur_.bulk.height < target * (1.0 - 1e-12)) {
    if (stopped()) return false;
    const double H = cur_.bulk.height, Hn = std::min(target, H * std::exp(step_));
    const double c_p = predicted_speed(H, Hn);
    StripFront next = solve_at(Hn, c_p, cur_);
    if (next.status != FrontStatus::converged) {
      ++rejected;
      step_ *= 0.5;
      if (step_ < std::log(o_.min_factor)) {
        out_.reason = "the continuation in H stalls at H = " + core::format_number(H) + " (step below min_factor): " +
                      std::string(to_string(next.status)) + ": " + next.reason;
        return false;
      }
      continue;
    }
    out_.steps.push_back({Hn, next.c, c_p, next.newton_iterations, rejected});
    rejected = 0;
    control_step(c_p, next);
    cur_ = std::move(next);
  }
  return true;
}

StripHeightPath continue_height(const core::InterfaceParams& law, const std::function<core::BulkParams(double)>& bulk_at,
                                double cs, double slope0, const StripHeightOptions& o) {
  HeightPath path(law, bulk_at, cs, slope0, o);
  if (!path.valid_heights() || !path.first_front()) return path.take();
  for (std::size_t k = 1; k < o.heights.size(); ++k) {
    if (!path.advance_to(o.heights[k])) return path.take();
    path.finish_height();  // the front at heights[k]
  }
  path.complete();
  return path.take();
}

}  // namespace

StripHeightPath continue_strip_height(const core::InterfaceParams& law, double mu_strip, double rho_strip,
                                      const StripHeightOptions& o, double length) {
  // fixed material: the thin strip's c_min is the 1D one of μ = μ'H, c ∝ sqrt(μ'H) (slope ½)
  return continue_height(
      law, [&](double H) { return core::BulkParams{rho_strip * H, mu_strip * H, length, H}; },
      std::sqrt(mu_strip / rho_strip), 0.5, o);
}

StripHeightPath continue_strip_height_at_column(const core::InterfaceParams& law, const core::BulkParams& column,
                                                const StripHeightOptions& o) {
  // fixed column (μ, ρ integrated over the height): the thin strip's c_min is the 1D one of μ (slope 0)
  // the column's body (bulk.body, bulk.poisson, bulk.normal_load) at every H: an in-plane column stays in-plane
  return continue_height(
      law,
      [&](double H) {
        core::BulkParams b = column;
        b.height = H;
        return b;
      },
      std::sqrt(column.mu / column.rho), 0.0, o);
}

StripHeightPath continue_inplane_height(const core::InterfaceParams& law, double mu_strip, double rho_strip, double poisson,
                                        double normal_load, const StripHeightOptions& o, double length) {
  // fixed material (μ', ρ', ν): the scene's μ = E'H, E' = 2μ'/(1 − ν) (docs/model.md §10.2), ρ = ρ'H; the thin strip's
  // c_min is the 1D one of μ = E'H, c ∝ sqrt(H) (slope ½)
  const double plate = 2.0 * mu_strip / (1.0 - poisson);
  const auto bulk_at = [&](double H) {
    core::BulkParams b{rho_strip * H, plate * H, length, H};
    b.body_name = "inplane";
    b.poisson = poisson;
    b.normal_load = normal_load;
    return b;
  };
  return continue_height(law, bulk_at, std::sqrt(mu_strip / rho_strip), 0.5, o);
}

}  // namespace slipfront::continuum
