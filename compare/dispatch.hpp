#pragma once
// The integrator, chosen in one place (docs/numerics.md): time.integrator names a stepper class for
// every law, and with_integrator is the only switch on it.
#include <span>

#include "compare/scene.hpp"
#include "core/adaptive.hpp"
#include "core/implicit.hpp"
#include "core/law.hpp"
#include "core/stepper.hpp"

namespace slipfront::compare {

/// Tags of time.integrator: Tag::stepper<Law> is the stepper class for a law. The adaptive integrator
/// advances deterministic rate laws (core::SmoothLaw); a stochastic law runs on the explicit
/// scheme then (it has no rates to integrate), alongside on the same scene.
struct ExplicitTag {
  template <class Law>
  using stepper = core::ExplicitSimulation<Law>;
};
struct ImplicitTag {
  template <class Law>
  using stepper = core::ImplicitSimulation<Law>;
};
namespace detail {
template <class Law, bool Smooth = core::SmoothLaw<Law>>
struct AdaptiveStepper {
  using type = core::ExplicitSimulation<Law>;
};
template <class Law>
struct AdaptiveStepper<Law, true> {
  using type = core::AdaptiveSimulation<Law>;
};
}  // namespace detail
struct AdaptiveTag {
  template <class Law>
  using stepper = typename detail::AdaptiveStepper<Law>::type;
};

/// Calls f(Tag{}) for the scene's time.integrator.
template <class F>
decltype(auto) with_integrator(const Scene& s, F&& f) {
  switch (s.time.integrator) {
    case core::Integrator::implicit_trapezoidal: return f(ImplicitTag{});
    case core::Integrator::adaptive_rosenbrock: return f(AdaptiveTag{});
    case core::Integrator::central_difference: break;
  }
  return f(ExplicitTag{});
}

/// Steppers with dense output (the adaptive integrator): measurements and records at exact times.
template <class S>
concept DenseStepper = requires(const S& sim, double t, std::span<double> out) {
  sim.previous_time();
  sim.dense_state(t, core::Field::slip_rate, out);
};

}  // namespace slipfront::compare
