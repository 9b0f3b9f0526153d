#pragma once
// The continuum friction law of docs/model.md §1 as an interface law: InterfaceLaw and SmoothLaw of
// core/law.hpp. Its state is one vector [A_0..A_{n−1} | σ̄_0..σ̄_{n−1}] (fields()), advanced by
// the exact update (advance, fixed-step integrators) or by the adaptive integrator through rate() and
// jacobian(). Nothing here knows which stepper drives it.
//
// On request (track_ages) it also carries the contact age of docs/model.md §7 as the age mass
// M = A ā per site, a separate vector (not part of fields(): the adaptive integrator's state stays
// [A | σ̄]): dM/dt = A − Θκ|v| M, advanced exactly with frozen rates in advance() (as σ̄) and, under the
// adaptive integrator, by advance_age() after each accepted step from the step's dense output.
//
// With contact aging (interface.aging_b > 0, docs/model.md §11.4) it is the one-variable closure the paper
// suggests, A_0 aging logarithmically: per site the attached fraction φ (§1.1's A equation), a mean age θ with
// dθ/dt = 1 − θ Θκ|v| (the aging law of rate-and-state friction), and the area A = φ (1 + b ln(1 + θ/τ_a)); Θ
// and the σ̄ equation read A. Advanced by the same exact frozen-rate updates (fixed-step integrators only: the
// scene refuses the adaptive one, compare/scene.cpp). aging_b = 0 never enters this branch.
//
// Under a prescribed normal load (docs/model.md §12; set_normal_load, core::LawHooks::normal_load) the A equation
// relaxes towards the site's resting area a = (p/p_0)^m instead of 1: dA/dt = (a − A) − Θκ|v|A, through either
// channel. Re-attachment: A' = relax(A, a, r). Instantaneous: contacts of area a, A = a φ with φ §1.1's fraction
// (φ' = relax(φ, 1, r), the count law's arithmetic: the noise-off identity stays bit for bit), and a change of a scales
// A and σ̄ at once. A law never given a load is today's, bit for bit (a = 1 enters as 1 · w = w). The adaptive
// integrator advances [A | σ̄] by rate() with a = resting_area(i) (a profile is constant in time, so both channels
// have one A equation); it does not carry φ, so under the instantaneous channel a law it advanced is given no new
// load (the in-plane coupling is refused with it, compare/scene.cpp).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/exact_update.hpp"
#include "core/law.hpp"
#include "core/params.hpp"

namespace slipfront::continuum {

// core::LawHooks::steady_state: the closed form of docs/model.md §1.4 (core/steady_sliding.hpp).
class FrictionLaw : public core::OverloadedSteadyState<FrictionLaw> {
 public:
  // The hook's steady state is the non-aging closed form; aging scenes (interface.aging_b > 0) are refused where it is
  // used (homogeneous loading: the patch and sigma_ss at v_behind; compare/scene.cpp check_aging).
  static constexpr core::LawHooks hooks{
      .ages = true, .dense_ages = true, .contact_hazard = true, .checkpoints = true, .steady_state = true,
      .steady_front = true, .normal_load = true};
  FrictionLaw(const core::InterfaceParams& p, std::size_t sites)
      : p_(p), n_(sites), fields_(2 * sites, 0.0), aging_(p.ages_contacts()) {
    std::fill(fields_.begin(), fields_.begin() + static_cast<std::ptrdiff_t>(sites), 1.0);
    if (aging_) {
      attached_.assign(sites, 1.0);
      theta_.assign(sites, 0.0);
    }
  }

  // --- state ------------------------------------------------------------------------------------
  std::size_t size() const { return n_; }
  const core::InterfaceParams& params() const { return p_; }
  std::span<const double> contact_area() const { return {fields_.data(), n_}; }
  std::span<const double> sigma_bar() const { return {fields_.data() + n_, n_}; }
  std::span<double> fields() { return fields_; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("continuum law");
    ar(fields_, ages_, age_mass_, age_prev_, theta_step_, step_t0_);
    if (aging_) ar(attached_, theta_);  // docs/model.md §11.4 (absent without aging: today's format)
    if (scaled()) ar(attached_);        // docs/model.md §12.1: φ under an instantaneous load
  }

  /// Set the state of one site (initial conditions).
  void set_site(std::size_t i, double area, double sigma_bar) {
    fields_[i] = area;
    fields_[n_ + i] = sigma_bar;
    if (ages_) age_mass_[i] = 0.0;  // every contact present at the start is new (age 0)
    if (aging_) {                   // new contacts: area 1 each, θ = 0 (docs/model.md §11.4)
      attached_[i] = area;
      theta_[i] = 0.0;
    }
    if (scaled()) attached_[i] = area / rest_[i];  // instantaneous load: contacts of area a_i (docs/model.md §12.1)
  }
  /// The resting area a_i = (p_i/p_0)^m of every site (docs/model.md §12.1). Under the instantaneous channel
  /// (interface.load_channel) A and σ̄ scale at once by a_new/a_old (each contact's stretch is unchanged, its area and
  /// stiffness scale); under re-attachment nothing moves at once, A relaxes towards a_new at unit rate.
  void set_normal_load(std::span<const double> factor) {
    if (factor.size() != n_) throw std::invalid_argument("FrictionLaw::set_normal_load: one factor per site");
    if (aging_) throw std::invalid_argument("FrictionLaw::set_normal_load: not with aging (docs/model.md §12)");
    if (p_.instantaneous_load()) {
      if (attached_.empty()) attached_.assign(fields_.begin(), fields_.begin() + static_cast<std::ptrdiff_t>(n_));
      for (std::size_t i = 0; i < n_; ++i) {
        fields_[n_ + i] *= factor[i] / resting_area(i);
        fields_[i] = factor[i] * attached_[i];
      }
    }
    rest_.assign(factor.begin(), factor.end());
  }
  /// The resting area a_i of site i (1 without a normal load).
  double resting_area(std::size_t i) const { return rest_.empty() ? 1.0 : rest_[i]; }

  /// Aging (docs/model.md §11.4): the attached fraction φ and the mean-age state θ per site (empty without aging).
  std::span<const double> attached_fraction() const { return attached_; }
  std::span<const double> aging_state() const { return theta_; }

  // --- the exact step (explicit and implicit integrators) ---------------------------------------
  /// docs/model.md §1 over [t, t+dt], v frozen; Θ evaluated from the start-of-step state:
  ///   Θ = θ(|σ̄ + η v|/A − 1),  r = 1 + Θκ|v|,  A' = A e^{−r dt} + a (1 − e^{−r dt})/r  (a: the resting area,
  ///   1 without a normal load, docs/model.md §12),
  ///   σ̄' = exact solution of dσ̄/dt = α Ā v − Θ|v| σ̄ with Ā = (A + A')/2.
  core::LawStepInfo advance(double dt, std::span<const double> v) {
    bool any = false;
    const double alpha = p_.alpha, kappa = p_.kappa, eta = p_.eta;
    // A stuck site (Θ = 0) relaxes A at rate 1 and σ̄ at rate 0: relax() with these rates is
    // a e^{−dt} + (1 − e^{−dt}) and σ̄ + source·dt, computed once per dt (bit for bit the same values).
    if (dt != cached_dt_) {
      cached_dt_ = dt;
      stuck_exp_ = std::exp(-dt);
      stuck_weight_ = core::relax_weight(1.0, dt);
    }
    if (aging_) return advance_aging(dt, v);
    if (scaled()) return advance_scaled(dt, v);
    double* area = fields_.data();
    double* sigma_bar = area + n_;
    for (std::size_t i = 0; i < n_; ++i) {
      const double vi = v[i], a = area[i], sb = sigma_bar[i];
      const bool theta = core::slides(sb, vi, a, eta);
      const double rest = resting_area(i);
      any |= theta;
      if (!theta) {
        const double a_new = a * stuck_exp_ + rest * stuck_weight_;
        sigma_bar[i] = sb + alpha * 0.5 * (a + a_new) * vi * dt;
        area[i] = a_new;
        if (ages_) age_mass_[i] += 0.5 * (a + a_new) * dt;  // docs/model.md §7, Θ = 0: dM/dt = A
        continue;
      }
      const double speed = std::abs(vi);
      const double a_new = core::relax(a, rest, 1.0 + kappa * speed, dt);
      sigma_bar[i] = core::relax(sb, alpha * 0.5 * (a + a_new) * vi, speed, dt);
      area[i] = a_new;
      // docs/model.md §7: dM/dt = Ā − κ|v| M, exact with Ā = (A + A')/2 and the rate frozen (as σ̄)
      if (ages_) age_mass_[i] = core::relax(age_mass_[i], 0.5 * (a + a_new), kappa * speed, dt);
    }
    return {any};
  }

  /// The implicit step's linearisation (law.hpp), one site at a time: y = Θ of the site at the
  /// previous step's rate.
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(p_, dt)](std::size_t i, double wp, double& c0, double& c1) {
      const double a = fields_[i], sb = fields_[n_ + i];
      const double y = wp != 0.0 && core::slides(sb, wp, a, p_.eta) ? 1.0 : 0.0;
      core::linearise_stress(a, sb, y, wp, k, c0, c1, resting_area(i));
    };
  }

  // --- contact age, docs/model.md §7 -----------------------------------------------------------
  /// Carry the age mass M = A ā (default off: advance() then costs nothing more). Every site starts
  /// at M = 0 (its contacts are new), as set_site() does.
  void track_ages(bool on) {
    ages_ = on;
    age_mass_.assign(on ? n_ : 0, 0.0);
    age_prev_.clear();
    theta_step_.clear();
  }
  bool tracks_ages() const { return ages_; }
  /// M per site (empty unless tracks_ages()).
  std::span<const double> age_mass() const { return age_mass_; }
  /// Mean age of the attached contacts ā = M/A per site (NaN where A = 0); needs tracks_ages().
  void mean_age(std::span<double> out) const {
    for (std::size_t i = 0; i < n_; ++i) {
      const double att = aging_ ? attached_[i] : fields_[i];  // aging: M = φ ā (docs/model.md §11.4)
      out[i] = att > 0.0 ? age_mass_[i] / att : std::numeric_limits<double>::quiet_NaN();
    }
  }
  /// Initial mean age of site i (after set_site): M = A ā (aging: φ ā).
  void set_site_age(std::size_t i, double mean_age) { age_mass_[i] = (aging_ ? attached_[i] : fields_[i]) * mean_age; }

  /// The adaptive integrator's hook (core/adaptive.hpp calls it after each accepted step
  /// [t0, t1], before Θ flips): M over the step with Θ_i = theta[i] fixed, from the step's dense output
  /// at.area(t, i), at.slip_rate(t, i) (integrate_age_mass: second order). Keeps M(t0) and Θ for
  /// age_mass_at().
  template <class Sample>
  void advance_age(double t0, double t1, std::span<const std::uint8_t> theta, const Sample& at) {
    if (!ages_) return;
    age_prev_.swap(age_mass_);
    age_mass_.resize(n_);
    theta_step_.assign(theta.begin(), theta.end());
    step_t0_ = t0;
    for (std::size_t i = 0; i < n_; ++i)
      age_mass_[i] = core::integrate_age_mass(
          age_prev_[i], t0, t1, theta[i] != 0, p_.kappa, [&](double t) { return at.area(t, i); },
          [&](double t) { return at.slip_rate(t, i); });
  }
  /// M_i at t inside the last adaptive step (the same integration, stopped at t): for records at
  /// exact times on the dense output. Before any adaptive step, the current M_i.
  template <class Sample>
  double age_mass_at(std::size_t i, double t, const Sample& at) const {
    if (age_prev_.empty()) return age_mass_[i];
    return core::integrate_age_mass(
        age_prev_[i], step_t0_, t, theta_step_[i] != 0, p_.kappa, [&](double s) { return at.area(s, i); },
        [&](double s) { return at.slip_rate(s, i); });
  }

  // --- the rates (adaptive integrator), docs/model.md §1 ----------------------------------------
  /// Θ = θ(|σ̄ + η v|/A − 1).
  bool sliding(core::SiteState s) const { return core::slides(s.sigma_bar, s.v, s.area, p_.eta); }
  /// The hazard Θκ|v| of an attached contact at the state s (docs/model.md §7.2: what the contact
  /// prediction integrates along this law's fields).
  double detachment_hazard(core::SiteState s) const { return sliding(s) ? p_.kappa * std::abs(s.v) : 0.0; }
  /// |σ̄ + η v|: Θ flips where the load crosses A (|σ|/A = 1).
  double load(core::SiteState s) const { return std::abs(s.sigma_bar + p_.eta * s.v); }
  /// dA/dt = a − A − Θ κ A |v|,  dσ̄/dt = α A v − Θ σ̄ |v|, a = s.rest the site's resting area (docs/model.md §12.1; 1
  /// without a normal load, today's bits: `1.0 - A`). Under a profile that does not change in time both channels have
  /// this A equation (instantaneous: A = a φ, a fixed), the right-hand side the exact step of advance() integrates.
  core::SiteRate rate(core::SiteState s, bool theta) const {
    const double speed = theta ? std::abs(s.v) : 0.0;
    return {s.rest - s.area - p_.kappa * s.area * speed, p_.alpha * s.area * s.v - s.sigma_bar * speed};
  }
  /// Jacobian of rate() with Θ fixed (sgn v at v = 0 taken as +1); the resting area is a constant of the step.
  core::SiteJacobian jacobian(core::SiteState s, bool theta) const {
    if (!theta) return {0.0, -1.0, p_.alpha * s.area, p_.alpha * s.v, 0.0};
    const double sg = s.v >= 0.0 ? 1.0 : -1.0, speed = std::abs(s.v);
    return {-p_.kappa * s.area * sg, -(1.0 + p_.kappa * speed), p_.alpha * s.area - s.sigma_bar * sg, p_.alpha * s.v,
            -speed};
  }

 private:
  /// An instantaneous normal load: A = a φ (docs/model.md §12.1); φ holds the attached fraction (attached_).
  bool scaled() const { return !aging_ && !rest_.empty() && p_.instantaneous_load(); }
  /// advance() under an instantaneous load: φ' = relax(φ, 1, 1 + Θκ|v|) (the stuck factors cached by advance()),
  /// A' = a φ', σ̄' as advance(); the count law's noise-off arithmetic, operation for operation.
  core::LawStepInfo advance_scaled(double dt, std::span<const double> v) {
    bool any = false;
    double* area = fields_.data();
    double* sigma_bar = area + n_;
    for (std::size_t i = 0; i < n_; ++i) {
      const double vi = v[i], a = area[i], sb = sigma_bar[i], phi = attached_[i];
      const bool theta = core::slides(sb, vi, a, p_.eta);
      any |= theta;
      const double speed = std::abs(vi);
      attached_[i] = theta ? core::relax(phi, 1.0, 1.0 + p_.kappa * speed, dt) : phi * stuck_exp_ + stuck_weight_;
      const double a_new = rest_[i] * attached_[i];
      const double source = p_.alpha * 0.5 * (a + a_new) * vi;
      sigma_bar[i] = theta ? core::relax(sb, source, speed, dt) : sb + source * dt;
      area[i] = a_new;
      if (ages_) age_mass_[i] = core::relax(age_mass_[i], 0.5 * (phi + attached_[i]), theta ? p_.kappa * speed : 0.0, dt);
    }
    return {any};
  }

  /// The closure of docs/model.md §11.4 over [t, t+dt], v frozen, Θ from the start-of-step state (as advance):
  ///   h = Θκ|v|,  φ' = relax(φ, 1, 1 + h),  θ' = relax(θ, 1, h),  A' = φ' (1 + b ln(1 + θ'/τ_a)),
  ///   σ̄' = relax(σ̄, α Ā v, Θ|v|) with Ā = (A + A')/2; the age mass (output.ages) with source φ.
  core::LawStepInfo advance_aging(double dt, std::span<const double> v) {
    bool any = false;
    double* area = fields_.data();
    double* sigma_bar = area + n_;
    for (std::size_t i = 0; i < n_; ++i) {
      const double vi = v[i], a = area[i], sb = sigma_bar[i];
      const bool theta = core::slides(sb, vi, a, p_.eta);
      any |= theta;
      const double speed = theta ? std::abs(vi) : 0.0, hazard = p_.kappa * speed, phi = attached_[i];
      if (theta) {
        attached_[i] = core::relax(phi, 1.0, 1.0 + hazard, dt);
        theta_[i] = core::relax(theta_[i], 1.0, hazard, dt);
      } else {  // relax() at the stuck rates, bit for bit (the factors cached by advance())
        attached_[i] = phi * stuck_exp_ + stuck_weight_;
        theta_[i] += dt;
      }
      const double a_new = attached_[i] * p_.aged_area(theta_[i]);
      const double source = p_.alpha * 0.5 * (a + a_new) * vi;
      sigma_bar[i] = theta ? core::relax(sb, source, speed, dt) : sb + source * dt;
      area[i] = a_new;
      if (ages_) age_mass_[i] = core::relax(age_mass_[i], 0.5 * (phi + attached_[i]), hazard, dt);
    }
    return {any};
  }

  core::InterfaceParams p_;
  std::size_t n_;
  std::vector<double> fields_;  ///< [A | σ̄]
  bool aging_ = false;
  std::vector<double> attached_, theta_;  ///< aging: φ and θ per site (docs/model.md §11.4)
  std::vector<double> rest_;  ///< the resting area (p/p_0)^m per site (docs/model.md §12); empty: 1 everywhere
  double cached_dt_ = -1.0, stuck_exp_ = 1.0, stuck_weight_ = 0.0;
  bool ages_ = false;
  std::vector<double> age_mass_, age_prev_;  ///< M at the end (and start) of the last step
  std::vector<std::uint8_t> theta_step_;     ///< Θ of the last adaptive step
  double step_t0_ = 0.0;
};

static_assert(core::SmoothLaw<FrictionLaw>);

// Closed forms of docs/model.md §1 (tests and the comparison layer check against these).
using core::SteadyState;
/// A_ss = 1/(1 + κ|v|), σ̄_ss = α A_ss sgn v, σ_ss = σ̄_ss + ηv (core/steady_sliding.hpp); with aging (docs/model.md
/// §11.4) the closure's: φ_ss = 1/(1 + κv), θ_ss = 1/(κv), A_ss = φ_ss (1 + b ln(1 + θ_ss/τ_a)).
inline SteadyState steady_sliding(const core::InterfaceParams& p, double v) {
  if (!p.ages_contacts()) return core::overloaded_steady_sliding(p, v);
  const double s = std::abs(v);
  double area = 1.0 / (1.0 + p.kappa * s);
  if (p.kappa * s > 0.0) area *= p.aged_area(1.0 / (p.kappa * s));
  const double sb = p.alpha * area * (v >= 0 ? 1.0 : -1.0);
  return {area, sb, sb + p.eta * v};
}
/// Velocity of the minimum of σ_ss(v): v_m = (sqrt(ακ/η) − 1)/κ.
inline double steady_minimum_velocity(const core::InterfaceParams& p) {
  return (std::sqrt(p.alpha * p.kappa / p.eta) - 1.0) / p.kappa;
}
/// σ_c^d = 2 sqrt(αη/κ) − η/κ.
inline double steady_minimum_stress(const core::InterfaceParams& p) {
  return 2.0 * std::sqrt(p.alpha * p.eta / p.kappa) - p.eta / p.kappa;
}
/// Slip rate on the strengthening branch (v > v_m) with σ_ss(v) = σ_d; NaN if σ_d < σ_c^d.
double strengthening_branch_velocity(const core::InterfaceParams& p, double sigma_d);

}  // namespace slipfront::continuum
