#pragma once
// A stochastic test law in one file (issue 9: "a stochastic one on the two fixed-step integrators"): the
// continuum law of docs/model.md §1 whose yield threshold at each site is drawn afresh every step from
// U[1 − w, 1 + w] with the site's own random stream (discrete/streams.hpp): Θ = θ(|σ̄ + ηv|/A − s). It
// implements core::InterfaceLaw only (no rates: the adaptive integrator does not take it; the
// runner then steps it explicitly). With w = 0 it is the continuum law, operation for operation.
#include <cmath>
#include <span>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "discrete/streams.hpp"

namespace slipfront::testing {

class RedrawnThresholdLaw {
 public:
  static constexpr core::LawHooks hooks{};  // the contract only
  RedrawnThresholdLaw(const core::InterfaceParams& p, double width, std::uint64_t seed, std::size_t sites)
      : p_(p), w_(width), area_(sites, 1.0), sigma_bar_(sites, 0.0), s_(sites, 1.0),
        engines_(discrete::site_engines(seed, sites)) {}
  std::size_t size() const { return area_.size(); }
  const core::InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }
  void set_site(std::size_t i, double a, double s) {
    area_[i] = a;
    sigma_bar_[i] = s;
  }
  core::LawStepInfo advance(double dt, std::span<const double> v) {
    bool any = false;
    for (std::size_t i = 0; i < size(); ++i) {
      if (w_ > 0.0) s_[i] = 1.0 + w_ * (2.0 * discrete::uniform01(engines_[i]) - 1.0);
      const double a = area_[i], sb = sigma_bar_[i];
      const bool theta = core::contact_stress(sb + p_.eta * v[i], a) > s_[i];
      any |= theta;
      const double speed = theta ? std::abs(v[i]) : 0.0;
      const double a_new = core::relax(a, 1.0, 1.0 + p_.kappa * speed, dt);
      sigma_bar_[i] = core::relax(sb, p_.alpha * 0.5 * (a + a_new) * v[i], speed, dt);
      area_[i] = a_new;
    }
    return {any};
  }
  // y = Θ with the threshold of the last step.
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(p_, dt)](std::size_t i, double w, double& c0, double& c1) {
      const double y = w != 0.0 && core::contact_stress(sigma_bar_[i] + p_.eta * w, area_[i]) > s_[i] ? 1.0 : 0.0;
      core::linearise_stress(area_[i], sigma_bar_[i], y, w, k, c0, c1);
    };
  }

 private:
  core::InterfaceParams p_;
  double w_;
  std::vector<double> area_, sigma_bar_, s_;
  std::vector<discrete::Engine> engines_;
};

}  // namespace slipfront::testing
