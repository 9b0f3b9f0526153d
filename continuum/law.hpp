#pragma once
// The interface-law contract (docs/model.md §1, §2): what every interface law provides and every
// stepper uses. The continuum FrictionLaw (continuum/friction_law.hpp) and the microcontact ensembles
// (discrete/: CountLaw, AgentLaw, NaiveAgentLaw) are implementations; the steppers (ExplicitSimulation,
// ImplicitSimulation, AdaptiveSimulation) are templates on the law, so no call is virtual.
//
//   InterfaceLaw   every law: the state per site (A, σ̄), its initial value, the exact or stochastic
//                  step with the slip rates frozen over it, and the linearisation an implicit step needs
//   SmoothLaw      a deterministic law written as rates: the adaptive integrator advances its state
//                  itself with the rates and their Jacobian (no stochastic step to freeze rates for)
#include <cmath>
#include <concepts>
#include <cstddef>
#include <span>

#include "continuum/exact_update.hpp"
#include "continuum/params.hpp"

namespace slipfront::continuum {

struct LawStepInfo {
  bool any_yield = false;  ///< some site had Θ = 1 (or an overloaded contact) at the start of the step
};

/// Every interface law.
///   size()                      number of sites
///   params()                    α, κ, η (η enters the contact-level stress |σ̄ + η v|/A and the bulk)
///   contact_area(), sigma_bar() A and σ̄ per site
///   set_site(i, A, σ̄)           initial state of site i
///   advance(dt, v)              A, σ̄: t → t + dt with the slip rates v frozen over the step (exact
///                               for the continuum law, the exact two-state chain for the ensembles)
///   linearise(dt, w, c0, c1)    σ̄_i(t + dt) ≈ c0_i + c1_i W_i: the stress the law's own update would
///                               give for a slip rate W_i frozen over the step, linear in W_i, with the
///                               yield state (Θ_i, or the overloaded fraction Y_i) and the relaxation
///                               rate frozen at the rates w_i of the previous step (linearise_stress)
template <class L>
concept InterfaceLaw = requires(L& law, const L& cl, std::size_t i, double a, double s, double dt,
                                std::span<const double> v, std::span<double> out) {
  { cl.size() } -> std::convertible_to<std::size_t>;
  { cl.params() } -> std::convertible_to<const InterfaceParams&>;
  { cl.contact_area() } -> std::convertible_to<std::span<const double>>;
  { cl.sigma_bar() } -> std::convertible_to<std::span<const double>>;
  law.set_site(i, a, s);
  { law.advance(dt, v) } -> std::same_as<LawStepInfo>;
  law.linearise(dt, v, out, out);
};

/// One site's state as the rates see it.
struct SiteState {
  double v, area, sigma_bar;
};
/// d/dt of (A, σ̄) at one site.
struct SiteRate {
  double area, sigma_bar;
};
/// ∂(dA/dt, dσ̄/dt)/∂(v, A, σ̄) at one site with the yield state fixed; ∂(dA/dt)/∂σ̄ = 0 by the
/// structure of the contract (the area relaxes whatever the stress, once the yield state is known),
/// which is what lets the adaptive integrator eliminate (v, A, σ̄) node by node.
struct SiteJacobian {
  double area_v, area_area;
  double sigma_v, sigma_area, sigma_sigma;
};

/// A deterministic law given by its rates (the continuum law; a test law with another detachment
/// rate): what the adaptive integrator needs besides InterfaceLaw.
///   fields()                    the state [A_0..A_{n−1} | σ̄_0..σ̄_{n−1}], contiguous and writable:
///                               the integrator advances it in place (no second copy anywhere)
///   sliding(st)                 the yield state Θ of a site (|σ̄ + η v|/A > 1)
///   load(st)                    |σ̄ + η v|: Θ flips where the load crosses the area A
///   rate(st, Θ), jacobian(st, Θ) the right-hand side and its Jacobian with Θ fixed
template <class L>
concept SmoothLaw = InterfaceLaw<L> && requires(L& law, const L& cl, SiteState st, bool sliding) {
  { law.fields() } -> std::same_as<std::span<double>>;
  { cl.sliding(st) } -> std::same_as<bool>;
  { cl.load(st) } -> std::convertible_to<double>;
  { cl.rate(st, sliding) } -> std::same_as<SiteRate>;
  { cl.jacobian(st, sliding) } -> std::same_as<SiteJacobian>;
};

/// Constants of linearise_stress that depend on the step only (computed once per step).
struct StressStepConstants {
  double alpha, kappa, dt;
  double e1, w1;  ///< e^{−Δt} and (1 − e^{−Δt}): A' of a site with no overloaded contact
  StressStepConstants(const InterfaceParams& p, double step)
      : alpha(p.alpha), kappa(p.kappa), dt(step), e1(std::exp(-step)), w1(relax_weight(1.0, step)) {}
};

/// The implicit integrator's view of the stress update of docs/model.md §1–§2 at one site, shared by
/// every law: with the overloaded fraction y (Θ for the continuum law) and the rate |w| of the previous
/// step frozen, A' = relax(A, 1, 1 + y κ |w|, Δt) and
///   σ̄' = σ̄ e^{−y|w|Δt} + α (A + A')/2 · W · (1 − e^{−y|w|Δt})/(y|w|)     = c0 + c1 W,
/// linear in the step's slip rate W (the source α Ā W is linear in W; y = 0: σ̄' = σ̄ + α Ā W Δt).
inline void linearise_stress(double area, double sigma_bar, double y, double w_prev, const StressStepConstants& k,
                             double& c0, double& c1) {
  if (y == 0.0) {
    c0 = sigma_bar;
    c1 = k.alpha * 0.5 * (area + (area * k.e1 + k.w1)) * k.dt;
    return;
  }
  const double speed = std::abs(w_prev), lam = y * speed;
  const double a_new = relax(area, 1.0, 1.0 + y * k.kappa * speed, k.dt);
  c0 = sigma_bar * std::exp(-lam * k.dt);
  c1 = k.alpha * 0.5 * (area + a_new) * relax_weight(lam, k.dt);
}

}  // namespace slipfront::continuum
