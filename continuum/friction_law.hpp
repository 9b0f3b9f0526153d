#pragma once
// The continuum friction law of MODEL §1 as an interface law.
//
// Step contract shared by every interface law (continuum here, the ensembles in discrete/):
//   law.advance(dt, v)     advance A and σ̄ from t to t + dt with the slip rates v (one per site)
//                          frozen over the step; returns whether any site yielded at t.
//   law.contact_area()     A   per site
//   law.sigma_bar()        σ̄   per site
//   law.size()             number of sites
// The bulk stepper is a template on the law, so nothing here is a virtual call.
#include <cstddef>
#include <span>
#include <vector>

#include "continuum/exact_update.hpp"
#include "continuum/params.hpp"

namespace slipfront::continuum {

struct LawStepInfo {
  bool any_yield = false;  ///< some site had Θ = 1 (or an overloaded contact) at the start of the step
};

class FrictionLaw {
 public:
  FrictionLaw(const InterfaceParams& p, std::size_t sites)
      : p_(p), area_(sites, 1.0), sigma_bar_(sites, 0.0) {}

  std::size_t size() const { return area_.size(); }
  const InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }

  /// Set the state of one site (initial conditions).
  void set_site(std::size_t i, double area, double sigma_bar) {
    area_[i] = area;
    sigma_bar_[i] = sigma_bar;
  }

  /// MODEL §1 friction law over [t, t+dt], v frozen; Θ evaluated from the start-of-step state:
  ///   Θ = θ(|σ̄ + η v|/A − 1),  r = 1 + Θκ|v|,  A' = A e^{−r dt} + (1 − e^{−r dt})/r,
  ///   σ̄' = exact solution of dσ̄/dt = α Ā v − Θ|v| σ̄ with Ā = (A + A')/2.
  LawStepInfo advance(double dt, std::span<const double> v) {
    bool any = false;
    const double alpha = p_.alpha, kappa = p_.kappa, eta = p_.eta;
    // A stuck site (Θ = 0) relaxes A at rate 1 and σ̄ at rate 0: relax() with these rates is
    // a e^{−dt} + (1 − e^{−dt}) and σ̄ + source·dt, computed once per dt (bit for bit the same values).
    if (dt != cached_dt_) {
      cached_dt_ = dt;
      stuck_exp_ = std::exp(-dt);
      stuck_weight_ = relax_weight(1.0, dt);
    }
    const std::size_t n = area_.size();
    for (std::size_t i = 0; i < n; ++i) {
      const double vi = v[i], a = area_[i], sb = sigma_bar_[i];
      const bool theta = contact_stress(sb + eta * vi, a) > 1.0;
      any |= theta;
      if (!theta) {
        const double a_new = a * stuck_exp_ + stuck_weight_;
        sigma_bar_[i] = sb + alpha * 0.5 * (a + a_new) * vi * dt;
        area_[i] = a_new;
        continue;
      }
      const double speed = std::abs(vi);
      const double a_new = relax(a, 1.0, 1.0 + kappa * speed, dt);
      sigma_bar_[i] = relax(sb, alpha * 0.5 * (a + a_new) * vi, speed, dt);
      area_[i] = a_new;
    }
    return {any};
  }

 private:
  InterfaceParams p_;
  std::vector<double> area_;
  std::vector<double> sigma_bar_;
  double cached_dt_ = -1.0, stuck_exp_ = 1.0, stuck_weight_ = 0.0;
};

// Closed forms of MODEL §1 (tests and the comparison layer check against these).
struct SteadyState {
  double area, sigma_bar, sigma;
};
inline SteadyState steady_sliding(const InterfaceParams& p, double v) {
  const double s = std::abs(v);
  const double area = 1.0 / (1.0 + p.kappa * s);
  const double sb = p.alpha * area * (v >= 0 ? 1.0 : -1.0);
  return {area, sb, sb + p.eta * v};
}
/// Velocity of the minimum of σ_ss(v): v_m = (sqrt(ακ/η) − 1)/κ.
inline double steady_minimum_velocity(const InterfaceParams& p) {
  return (std::sqrt(p.alpha * p.kappa / p.eta) - 1.0) / p.kappa;
}
/// σ_c^d = 2 sqrt(αη/κ) − η/κ.
inline double steady_minimum_stress(const InterfaceParams& p) {
  return 2.0 * std::sqrt(p.alpha * p.eta / p.kappa) - p.eta / p.kappa;
}
/// Slip rate on the strengthening branch (v > v_m) with σ_ss(v) = σ_d; NaN if σ_d < σ_c^d.
double strengthening_branch_velocity(const InterfaceParams& p, double sigma_d);

}  // namespace slipfront::continuum
