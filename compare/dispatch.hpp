#pragma once
// The integrator and the body, chosen in one place (docs/numerics.md, docs/model.md §9): time.integrator
// names a stepper class for every law, the scene's body kind (core::BulkParams::body(), mapped to its class
// by core::with_body, core/bodies.hpp) the body it steps, and with_integrator is the only switch on either.
#include <span>
#include <type_traits>

#include "compare/scene.hpp"
#include "core/adaptive.hpp"
#include "core/bodies.hpp"
#include "core/bulk.hpp"
#include "core/implicit.hpp"
#include "core/leap.hpp"
#include "core/law.hpp"
#include "core/stepper.hpp"
#include "core/strip.hpp"

namespace slipfront::compare {

/// Tags of time.integrator on a body: Tag::stepper<Law> is the stepper class for a law. time.integrator =
/// adaptive advances deterministic rate laws (core::SmoothLaw: the continuum law) on the Rosenbrock integrator
/// and every other law (the discrete ensembles, the mean-field law) on the step-controlled implicit one
/// (core/leap.hpp), on either body (the chain, the strip), alongside on the same scene.
template <core::Body B>
struct ExplicitTag {
  using body = B;
  template <class Law>
  using stepper = core::ExplicitSimulation<Law, B>;
};
template <core::Body B>
struct ImplicitTag {
  using body = B;
  template <class Law>
  using stepper = core::ImplicitSimulation<Law, B>;
};
namespace detail {
template <class Law, class B, bool Smooth = core::SmoothLaw<Law>>
struct AdaptiveStepper {
  using type = core::LeapSimulation<Law, B>;
};
template <class Law, class B>
struct AdaptiveStepper<Law, B, true> {
  using type = core::AdaptiveSimulation<Law, B>;
};
template <class Tag>
struct IsAdaptive : std::false_type {};
}  // namespace detail
template <core::Body B>
struct AdaptiveTag {
  using body = B;
  template <class Law>
  using stepper = typename detail::AdaptiveStepper<Law, B>::type;
};
namespace detail {
template <class B>
struct IsAdaptive<AdaptiveTag<B>> : std::true_type {};
}  // namespace detail
template <class Tag>
inline constexpr bool is_adaptive = detail::IsAdaptive<Tag>::value;

/// Calls f(Tag{}) for the scene's time.integrator on the body B.
template <core::Body B, class F>
decltype(auto) with_integrator_on(const Scene& s, F&& f) {
  switch (s.time.integrator) {
    case core::Integrator::implicit_trapezoidal: return f(ImplicitTag<B>{});
    case core::Integrator::adaptive_rosenbrock:
      // every body of core::with_body has the adaptive integrator's members; a test body may not
      if constexpr (core::AdaptiveBody<B>) return f(AdaptiveTag<B>{});
      else throw core::ParamError("time.integrator", "the adaptive integrator needs the body's stage solve (core::AdaptiveBody)");
    case core::Integrator::central_difference: break;
  }
  return f(ExplicitTag<B>{});
}

/// Calls f(Tag{}) for the scene's time.integrator on the scene's body (core::with_body).
template <class F>
decltype(auto) with_integrator(const Scene& s, F&& f) {
  return core::with_body(s.bulk.body(), [&]<class B>(std::type_identity<B>) -> decltype(auto) {
    return with_integrator_on<B>(s, f);
  });
}

/// The body of a scene with the drive `drive` (Scene::validate has checked the keys).
template <core::RunBody B>
B make_body(const Scene& s, const core::DriveParams& drive) {
  return B(s.bulk, drive, s.interface, s.grid);
}

/// The grid of the scene's body, without building it: its sites are the law's (compare/runner.hpp).
inline core::BodyShape body_shape(const Scene& s) {
  return core::with_body(s.bulk.body(), [&]<class B>(std::type_identity<B>) {
    return B::shape(s.bulk, s.drive, s.grid);
  });
}

/// Steppers with dense output (the adaptive integrators): measurements and records at exact times.
template <class S>
concept DenseStepper = requires(const S& sim, double t, std::span<double> out) {
  sim.previous_time();
  sim.dense_state(t, core::Field::slip_rate, out);
};

/// Steppers whose law advances in steps with the slip rates frozen, one law step per stepper step (the
/// explicit, the implicit and the step-controlled integrators; not the Rosenbrock one): what a contact
/// prediction integrated along the law's fields step by step needs (compare/dynamic_run.hpp).
template <class S>
concept FrozenRateSteps = !DenseStepper<S> || requires { requires S::frozen_rate_steps; };

}  // namespace slipfront::compare
