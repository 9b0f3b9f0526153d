#pragma once
// A test law in one file (issue 9: "a new deterministic law is added in one file and runs on all three
// integrators"): the continuum law of docs/model.md §1 with a different detachment rate, κ v² instead of
// κ|v| (steady sliding: A_ss = 1/(1 + κv²), σ_ss = α/(1 + κv²) + ηv):
//   dA/dt = 1 − A − Θ κ v² A,   dσ̄/dt = α A v − Θ σ̄ |v|,   Θ = θ(|σ̄ + ηv|/A − 1).
// It implements core::InterfaceLaw (advance, linearise), core::SmoothLaw (fields, sliding, load, rate, jacobian)
// and its own steady state (core::LawHooks::steady_state: a nucleation patch starts in it); nothing else in the code
// base knows about it (tests/test_law_seam.cpp registers it as a model of a test model set).
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"

namespace slipfront::testing {

class QuadraticDetachmentLaw {
 public:
  static constexpr core::LawHooks hooks{.steady_state = true};
  QuadraticDetachmentLaw(const core::InterfaceParams& p, std::size_t sites)
      : p_(p), n_(sites), fields_(2 * sites, 0.0) {
    for (std::size_t i = 0; i < sites; ++i) fields_[i] = 1.0;
  }
  std::size_t size() const { return n_; }
  const core::InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return {fields_.data(), n_}; }
  std::span<const double> sigma_bar() const { return {fields_.data() + n_, n_}; }
  std::span<double> fields() { return fields_; }
  void set_site(std::size_t i, double a, double s) {
    fields_[i] = a;
    fields_[n_ + i] = s;
  }

  // The exact update with v, Θ frozen over the step (σ̄ with Ā = (A + A')/2, as the paper's law).
  core::LawStepInfo advance(double dt, std::span<const double> v) {
    bool any = false;
    for (std::size_t i = 0; i < n_; ++i) {
      double& a = fields_[i];
      double& s = fields_[n_ + i];
      const bool theta = sliding({v[i], a, s});
      any |= theta;
      const double detach = theta ? p_.kappa * v[i] * v[i] : 0.0, relax_rate = theta ? std::abs(v[i]) : 0.0;
      const double a_new = core::relax(a, 1.0, 1.0 + detach, dt);
      s = core::relax(s, p_.alpha * 0.5 * (a + a_new) * v[i], relax_rate, dt);
      a = a_new;
    }
    return {any};
  }
  // σ̄' ≈ c0 + c1 W with Θ and the rates frozen at the previous W.
  auto linearisation(double dt) const {
    return [this, dt](std::size_t i, double w, double& c0, double& c1) {
      const double a = fields_[i], s = fields_[n_ + i];
      const bool theta = w != 0.0 && sliding({w, a, s});
      const double lam = theta ? std::abs(w) : 0.0;
      const double a_new = core::relax(a, 1.0, 1.0 + (theta ? p_.kappa * w * w : 0.0), dt);
      c0 = s * std::exp(-lam * dt);
      c1 = p_.alpha * 0.5 * (a + a_new) * core::relax_weight(lam, dt);
    };
  }

  // Steady sliding: A_ss = 1/(1 + κv²), σ̄_ss = α A_ss sgn v, σ_ss = σ̄_ss + ηv.
  core::SteadyState steady_sliding(double v) const {
    const double area = 1.0 / (1.0 + p_.kappa * v * v), sb = p_.alpha * area * (v >= 0.0 ? 1.0 : -1.0);
    return {area, sb, sb + p_.eta * v};
  }
  // σ_ss(v) = σ on the strengthening branch (beyond the minimum of σ_ss, where dσ_ss/dv = η − 2ακv/(1 + κv²)² turns
  // positive for good), by bisection; NaN below the minimum.
  double steady_velocity(double sigma) const {
    auto slope = [&](double v) { return p_.eta - 2.0 * p_.alpha * p_.kappa * v / ((1.0 + p_.kappa * v * v) * (1.0 + p_.kappa * v * v)); };
    const double peak = 1.0 / std::sqrt(3.0 * p_.kappa);  // where 2ακv/(1 + κv²)² is largest
    double vm = 0.0;
    if (slope(peak) < 0.0) vm = bisect(slope, peak, 1e6);
    const double hi = std::max(vm, sigma / p_.eta) + 1.0;
    if (steady_sliding(vm).sigma > sigma) return std::numeric_limits<double>::quiet_NaN();
    return bisect([&](double v) { return steady_sliding(v).sigma - sigma; }, vm, hi);
  }

  bool sliding(core::SiteState s) const { return core::contact_stress(s.sigma_bar + p_.eta * s.v, s.area) > 1.0; }
  double load(core::SiteState s) const { return std::abs(s.sigma_bar + p_.eta * s.v); }
  core::SiteRate rate(core::SiteState s, bool theta) const {
    const double d = theta ? p_.kappa * s.v * s.v : 0.0, r = theta ? std::abs(s.v) : 0.0;
    return {1.0 - s.area - d * s.area, p_.alpha * s.area * s.v - r * s.sigma_bar};
  }
  core::SiteJacobian jacobian(core::SiteState s, bool theta) const {
    if (!theta) return {0.0, -1.0, p_.alpha * s.area, p_.alpha * s.v, 0.0};
    const double sg = s.v >= 0.0 ? 1.0 : -1.0;
    return {-2.0 * p_.kappa * s.v * s.area, -(1.0 + p_.kappa * s.v * s.v), p_.alpha * s.area - sg * s.sigma_bar,
            p_.alpha * s.v, -std::abs(s.v)};
  }

 private:
  // The root of f in [lo, hi] with f(lo) ≤ 0 ≤ f(hi), to the last bit.
  template <class F>
  static double bisect(F f, double lo, double hi) {
    for (int k = 0; k < 200 && lo < hi; ++k) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (f(mid) > 0.0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  }
  core::InterfaceParams p_;
  std::size_t n_;
  std::vector<double> fields_;  // [A | σ̄]
};

}  // namespace slipfront::testing
