#pragma once
// Exact updates of linear relaxation equations with rates frozen over a step.
// Shared by the continuum law and the discrete ensemble so that, with noise off and w = 0,
// both perform the same arithmetic (docs/model.md §2, hierarchy item 1).
#include <cmath>
#include <limits>

namespace slipfront::core {

/// (1 − e^{−r dt}) / r, accurate for small r dt and equal to dt at r = 0.
inline double relax_weight(double rate, double dt) {
  const double x = rate * dt;
  return x > 1e-300 ? -std::expm1(-x) / rate : dt;
}

/// Exact solution at t + dt of  dy/dt = source − rate·y  with constant source and rate ≥ 0.
inline double relax(double y, double source, double rate, double dt) {
  return y * std::exp(-rate * dt) + source * relax_weight(rate, dt);
}

/// Contact-level stress |σ|/A of docs/model.md §1 (+∞ on a site with no contact area).
inline double contact_stress(double sigma, double area) {
  return area > 0.0 ? std::abs(sigma) / area : std::numeric_limits<double>::infinity();
}

/// Θ of docs/model.md §1: a site of the continuum law slides when its contact-level stress
/// |σ̄ + η v|/A exceeds 1 (the law's exact step, its linearisation and rates, and the contact
/// prediction from the continuum's fields all decide it here).
inline bool slides(double sigma_bar, double v, double area, double eta) {
  return contact_stress(sigma_bar + eta * v, area) > 1.0;
}

/// Two-state Markov chain (attached ⇄ detached) with constant attach rate a and detach rate d,
/// docs/model.md §2: r = a + d, P(att→att) = (a + d e^{−r dt})/r, P(det→att) = a (1 − e^{−r dt})/r.
struct TwoStateTransition {
  double stay_attached;   ///< P(att → att)
  double become_attached; ///< P(det → att)
};
inline TwoStateTransition two_state_transition(double attach, double detach, double dt) {
  const double r = attach + detach;
  const double w = relax_weight(r, dt);  // (1 − e^{−r dt})/r
  return {1.0 - detach * w, attach * w};
}

}  // namespace slipfront::core
