#pragma once
// The in-plane strip's own normal load (docs/model.md §12.5, interface.load_coupling = "sigma_yy"): before every step
// the run layer reads the interface normal stress σ_yy(x, 0, t) of the body (core::InPlane::interface_normal_stress,
// the reaction that holds u_y = 0) and gives the law the resting areas a_i = (p_i/p_0)^m through its normal-load hook
// (core::LawHooks::normal_load). Superposition: the body is built without its top load (compare::DynamicRun) and
// p_i = p_0 − σ_yy(x_i, 0, t), p_0 = bulk.normal_load — the uniform confined compression under p_0, in which the
// contacts formed, plus the stress the run makes. The load is frozen over the step
// (the implicit step's linearisation too). Where the load leaves the range a law can take:
//   - m = 0: a = 1 at every site whatever the load (no load dependence: today's law, bit for bit);
//   - tension, p ≤ 0 (m > 0): no contact forms there; under re-attachment a = 0 (the contacts detach spontaneously at rate 1,
//     counted in tension_site_steps); under the instantaneous channel a contact of zero area has no area to scale back
//     from, so the run ends failed (LoadCouplingError) naming the site, the time and the load;
//   - p > p_0 under re-attachment: a site's N contacts are the ensembles' capacity at p_0 (docs/model.md §12.2), so
//     the ensembles (count, agent, mean_field) take a = min(a, 1), counted in clamped_site_steps (with the largest
//     p/p_0 seen, stored in the file), while the continuum takes any a. Why clamp and not refuse: the friction torque
//     compresses the edge-loaded interface ahead of the edge from the first yield on (σ_yy = (H/2) ∂x σ_xy, §10.3),
//     so a refusal would end every edge-loaded ensemble run under re-attachment; the count says where the ensemble
//     is a capped law and the continuum is not.
// The regularised instantaneous channel (docs/model.md §12.7, interface.load_relaxation_length L > 0): the law sees
// p_eff, ṗ_eff = −((|v| + v*)/L)(p_eff − p) (Prakash–Clifton), stepped exactly with p and |v| frozen at the step's
// start: p_eff ← p + (p_eff − p) e^{−(|v| + v*)Δt/L}, p_eff = p at the first step. As L → 0 the factor underflows to 0
// and p_eff = p exactly (today's channel). The tension checks apply to p_eff (what the law sees); the range stored is
// that of p.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/params.hpp"

namespace slipfront::compare {

/// A load the law cannot take (the instantaneous channel under tension): the run ends failed with this message.
struct LoadCouplingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class LoadCoupling {
 public:
  LoadCoupling() = default;
  /// p_0 = bulk.normal_load; `capacity`: the law's contacts at p_0 are all it has (the ensembles under re-attachment).
  LoadCoupling(const core::InterfaceParams& ip, double p0, bool capacity)
      : p0_(p0), m_(ip.load_exponent), length_(ip.load_relaxation_length), speed_(ip.load_relaxation_speed),
        instantaneous_(ip.instantaneous_load()), capacity_(capacity && !instantaneous_) {}

  /// The resting areas of the sites from σ_yy(x_i, 0) for the step [t, t + dt] (x: the sites' positions, for the
  /// message; v: the slip rates at the step's start, for the regularisation).
  std::span<const double> resting_areas(std::span<const double> sigma_yy, std::span<const double> x, double t,
                                        std::span<const double> v, double dt) {
    factor_.resize(sigma_yy.size());
    const bool relax = length_ > 0.0, first = relaxed_.empty();
    if (relax) relaxed_.resize(sigma_yy.size());
    for (std::size_t i = 0; i < sigma_yy.size(); ++i) {
      const double load = 1.0 - sigma_yy[i] / p0_;  // p = p_0 − σ_yy of the body without its top load
      max_ratio_ = std::max(max_ratio_, load);
      min_ratio_ = std::min(min_ratio_, load);
      if (relax)  // p_eff/p_0, exact over the step with p and |v| frozen (first step: p_eff = p)
        relaxed_[i] = first ? load : load + (relaxed_[i] - load) * std::exp(-(std::abs(v[i]) + speed_) * dt / length_);
      const double ratio = relax ? relaxed_[i] : load;
      if (m_ == 0.0) {  // no load dependence, tension included: today's law (a = 1 enters as 1 · w = w)
        factor_[i] = 1.0;
        continue;
      }
      if (!(ratio > 0.0)) {
        if (instantaneous_)
          throw LoadCouplingError("interface.load_coupling: the interface opens at x = " + core::format_number(x[i]) +
                                  " (t = " + core::format_number(t) + (relax ? ", p_eff/p_0 = " : ", p/p_0 = 1 - sigma_yy/p_0 = ") +
                                  core::format_number(ratio) + " <= 0): under load_channel = \"instantaneous\" a contact "
                                  "of zero area has no area to scale back from (docs/model.md §12.5); use the "
                                  "reattachment channel or a larger bulk.normal_load");
        ++tension_;
        factor_[i] = 0.0;
        continue;
      }
      double a = std::pow(ratio, m_);
      if (capacity_ && a > 1.0) {
        a = 1.0;
        ++clamped_;
      }
      factor_[i] = a;
    }
    for (const double a : factor_) min_factor_ = std::min(min_factor_, a);
    return factor_;
  }
  /// The resting areas last given (empty before the first): a restored run installs them before the law's state.
  std::span<const double> last_factors() const { return factor_; }
  /// p_eff/p_0 at every site (the regularised channel; empty without it or before the first step).
  std::span<const double> relaxed_load() const { return relaxed_; }
  /// Start the regularised load at p_eff/p_0 = `ratio` instead of p at the first step (a seeded mode's own δp_eff).
  void start_relaxed_load(std::span<const double> ratio) { relaxed_.assign(ratio.begin(), ratio.end()); }
  double min_resting_area() const { return min_factor_; }  ///< the smallest a given (+inf before the first step)
  double max_ratio() const { return max_ratio_; }  ///< the largest p/p_0 met (−inf before the first step)
  double min_ratio() const { return min_ratio_; }  ///< the smallest
  std::int64_t clamped_site_steps() const { return clamped_; }
  std::int64_t tension_site_steps() const { return tension_; }

  template <class Ar>
  void serialize(Ar& ar) {
    ar(max_ratio_, min_ratio_, min_factor_, clamped_, tension_, factor_);
    if (length_ > 0.0) ar(relaxed_);  // the regularised load's state (docs/model.md §12.7)
  }

 private:
  double p0_ = 1.0, m_ = 1.0, length_ = 0.0, speed_ = 0.0;
  bool instantaneous_ = false, capacity_ = false;
  std::vector<double> factor_, relaxed_;
  double max_ratio_ = -std::numeric_limits<double>::infinity(), min_ratio_ = std::numeric_limits<double>::infinity();
  double min_factor_ = std::numeric_limits<double>::infinity();
  std::int64_t clamped_ = 0, tension_ = 0;
};

}  // namespace slipfront::compare
