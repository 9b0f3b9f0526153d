#pragma once
// Steady sliding with every contact overloaded (docs/model.md §1.4): the rate law of §1.1 with Θ = 1 and the
// detachment rate κ|v| at rest, A_ss = 1/(1 + κ|v|), σ̄_ss = α A_ss sgn v, σ_ss = σ̄_ss + ηv. It is the continuum
// law's steady state (continuum::steady_sliding) and the ensembles' mean-field steady state while every threshold
// lies below the steady contact stress |σ_ss|/A_ss (docs/model.md §2.2: always at w = 0). A law gives its own steady
// state through core::LawHooks::steady_state; these laws give this one.
#include <cmath>
#include <limits>

#include "core/params.hpp"

namespace slipfront::core {

struct SteadyState {
  double area, sigma_bar, sigma;
};

/// A_ss, σ̄_ss, σ_ss at slip rate v.
inline SteadyState overloaded_steady_sliding(const InterfaceParams& p, double v) {
  const double s = std::abs(v);
  const double area = 1.0 / (1.0 + p.kappa * s);
  const double sb = p.alpha * area * (v >= 0 ? 1.0 : -1.0);
  return {area, sb, sb + p.eta * v};
}

/// The slip rate on the strengthening branch (v > v_m) with σ_ss(v) = σ, NaN where there is none (σ below the
/// minimum σ_c^d): σ_ss(v) = α/(1+κv) + ηv = σ ⇔ ηκ v² + (η − σ κ) v + (α − σ) = 0, the larger root.
inline double overloaded_steady_velocity(const InterfaceParams& p, double sigma) {
  const double a = p.eta * p.kappa, b = p.eta - sigma * p.kappa, c = p.alpha - sigma;
  if (a == 0.0) return b != 0.0 && -c / b > 0.0 ? -c / b : std::numeric_limits<double>::quiet_NaN();
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (-b + std::sqrt(disc)) / (2.0 * a);
}

/// The steady_state hook (core::LawHooks) of a law whose steady sliding is this closed form, at its params(): a law
/// derives from OverloadedSteadyState<itself> and declares the hook.
template <class Law>
struct OverloadedSteadyState {
  SteadyState steady_sliding(double v) const { return overloaded_steady_sliding(law().params(), v); }
  double steady_velocity(double sigma) const { return overloaded_steady_velocity(law().params(), sigma); }

 private:
  const Law& law() const { return static_cast<const Law&>(*this); }
};

}  // namespace slipfront::core
