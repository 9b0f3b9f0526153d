#pragma once
// How a bulk scene starts (docs/model.md §1 loadings, §6 steady-front start): the time step of a
// fixed-step scene, the solved steady front a scene may start from, the stepper built for the scene, and
// the initial state of its sites.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>
#include <functional>
#include <limits>
#include <type_traits>
#include <optional>

#include "compare/dispatch.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/steady_front.hpp"
#include "continuum/strip_front.hpp"
#include "core/adaptive.hpp"
#include "core/bulk.hpp"

namespace slipfront::compare {

/// The time step a fixed-step scene will use: time.dt, or time.cfl × the explicit limit, shortened so
/// that t_end is a whole number of steps.
double dynamic_time_step(const Scene& s);
/// The number of fixed steps to t_end (dynamic_time_step); throws core::ParamError naming
/// time.t_end when it would not fit a 64-bit count (the run could not even start).
std::int64_t fixed_step_count(const Scene& s);

/// The solved front a steady-front start begins from: the chain's (continuum::SteadyFront) or, on the strip
/// (bulk.height > 0), the strip's (continuum::StripFront, solved on the scene's own rows: docs/fronts.md §10.15; on the
/// in-plane strip the in-plane front, its bulk.body() inplane: docs/fronts.md §11.10).
struct FrontStart {
  std::optional<continuum::SteadyFront> chain;
  std::optional<continuum::StripFront> strip;
  double c = 0.0, v_tip = 0.0, v_behind = 0.0;
  double far_field_strain = 0.0;  ///< u_x far behind (−v_b/c), the same in every row of the strip
  /// The solve was stopped on request (front_start's `stop`): no front (chain and strip empty); the run
  /// starts from the nucleation state and ends interrupted before its first step.
  bool stopped = false;
};

/// Homogeneous loading with drive.start = "steady_front": the steady front at σ_d (docs/model.md §6),
/// solved by continuum::solve_steady_front on the chain and by continuum::solve_strip_front on either strip (the
/// in-plane solver on bulk.body = "inplane"; strip_start_options); nothing otherwise. Throws core::ParamError naming
/// drive.sigma_d when there is no front there. `stop` is polled before every Newton iteration of the strip's solve (and every height of its
/// cold start): true returns a FrontStart with `stopped` within one iteration. Its cost: front_start_cost.
std::optional<FrontStart> front_start(const Scene& s, const std::function<bool()>& stop = {});

/// front_start for a run of `Law`: a law that does not declare its steady front the continuum's
/// (core::LawHooks::steady_front) is refused, naming drive.start, before the front is solved.
template <class Law>
std::optional<FrontStart> front_start_for(const Scene& s, const std::function<bool()>& stop = {}) {
  if constexpr (!Law::hooks.steady_front)
    if (s.drive.loading == core::Loading::homogeneous && s.drive.start == "steady_front")
      throw core::ParamError("drive.start", "this model's law has no steady front to start from "
                                            "(core::LawHooks::steady_front: the continuum's solved front is not its own); "
                                            "use drive.start = \"nucleation\"");
  return front_start(s, stop);
}

/// What front_start costs on the strip (docs/fronts.md §10.15, §11.10; compare::estimate counts it once per model):
/// the 1D front, then the cold start's solves at H_0 = 0.5, 1, 2, … H on the scene's rows and the solver's 600
/// intervals, each ~5 Newton iterations at continuum::strip_solve_cost (two components on the in-plane strip). Zero
/// for the chain (~0.05 s) and for a scene without a steady-front start.
struct FrontStartCost {
  double seconds = 0.0;     ///< CPU seconds (strip_solve_cost's calibration)
  double memory_bytes = 0.0;///< the solver's Jacobian and LU factors while it runs
  int solves = 0, rows = 0, intervals = 0;
};
FrontStartCost front_start_cost(const Scene& s);

/// The strip front's settings for a strip scene's start: the scene's rows (uniform, H/grid.dy intervals, so
/// u and v are set row by row with no interpolation in y), a tip spacing of dx/10 (at most the solver's 0.05).
continuum::StripFrontOptions strip_start_options(const Scene& s);

/// The stepper of a scene for `law` (asked first to carry what the scene records: the mean contact age
/// of output.ages, for laws with core::LawHooks::ages); a steady-front start puts the front's far-field
/// traction μ v_b/c on the rear edge (the strain u_x = −v_b/c it has far behind), so the interface
/// behind slides steadily up to x = 0.
template <class Stepper, class Law>
Stepper make_stepper(const Scene& s, Law law, const std::optional<FrontStart>& front) {
  if constexpr (Law::hooks.ages) law.track_ages(s.output.ages);  // before any set_site: ages start at 0
  core::DriveParams drive = s.drive;
  if (front) drive.rear_traction = -s.bulk.mu * front->far_field_strain;
  auto bulk = make_body<typename Stepper::body_type>(s, drive);
  if constexpr (DenseStepper<Stepper>) {
    Stepper sim(std::move(bulk), std::move(law), core::AdaptiveOptions::from(s.time));
    sim.set_stop_time(s.time.t_end);
    return sim;
  } else {
    Stepper sim(std::move(bulk), std::move(law), dynamic_time_step(s));
    if constexpr (Stepper::error_control)
      sim.set_error_control(s.time.implicit_tolerance, s.time.implicit_max_halvings);
    return sim;
  }
}

/// The resting area (p(x_i)/p_0)^m of every interface site x_i (docs/model.md §12.1).
inline std::vector<double> resting_areas(const core::InterfaceParams& ip, std::span<const double> x) {
  std::vector<double> a(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) a[i] = ip.resting_area_at(x[i]);
  return a;
}

/// Give the law the scene's normal-load profile and start every site at rest under it (set_initial_conditions).
template <class Stepper>
void apply_normal_load(const Scene& s, Stepper& sim) {
  if (!s.interface.has_load_profile()) return;
  const auto& x = sim.bulk().x();
  const auto rest = resting_areas(s.interface, std::span<const double>(x.data(), x.size()));
  if (std::all_of(rest.begin(), rest.end(), [](double a) { return a == 1.0; })) return;
  using Law = std::remove_cvref_t<decltype(sim.law())>;
  if constexpr (Law::hooks.normal_load) {
    sim.law().set_normal_load(rest);
    for (std::size_t i = 0; i < rest.size(); ++i) sim.law().set_site(i, rest[i], 0.0);
  } else {
    throw core::ParamError("interface.load_p", "this model's law takes no normal load (core::LawHooks::normal_load)");
  }
}

/// docs/model.md §1 initial state: at rest and stuck (edge loading, spring block: u = v = 0, A = 1,
/// σ̄ = 0), or, under homogeneous loading, the stuck state A = 1, σ̄ = σ_d, u = σ_d/α with a nucleation
/// patch 0 ≤ x < ℓ_n in steady sliding at σ_d on the strengthening branch — or the solved steady front
/// with its tip at drive.front_x (docs/model.md §6), plus the slip-rate kick drive.kick_dv behind it (on
/// the strip: u and v of every row from the strip's front, the kick on the interface row only; on the in-plane strip
/// u_x, u_y and both velocities of every row from the in-plane front, docs/fronts.md §11.10).
/// The interface's state is lifted into the body by the body (core::RunBody::lift): on the strip
/// (docs/model.md §9.4) every row above the interface carries the uniform shear σ_d, u(x, y) = u(x, 0) + σ_d y/μ',
/// moving with the interface's slip rate (the chain has one row, y = 0).
///
/// A normal-load profile (docs/model.md §12, edge loading only) gives the law each site's resting area
/// a_i = (p(x_i)/p_0)^m, and every site starts at rest under its load: A = a_i, σ̄ = 0. When every a_i is 1 (no
/// profile, m = 0, or p = p_0 everywhere) the law is not told: today's run, bit for bit.
template <class Stepper>
void set_initial_conditions(const Scene& s, Stepper& sim, const std::optional<FrontStart>& front) {
  apply_normal_load(s, sim);
  if (s.drive.loading != core::Loading::homogeneous) return;
  const auto& x = sim.bulk().x();
  if (front && front->strip) {
    const auto& body = sim.bulk();
    const std::size_t n = x.size(), rows = body.rows();
    if (static_cast<std::size_t>(front->strip->rows()) + 1 != rows)
      throw core::ParamError("grid.dy", "the strip front has " + std::to_string(front->strip->rows() + 1) +
                                            " rows, the strip " + std::to_string(rows));
    std::vector<double> xi(n);
    for (std::size_t i = 0; i < n; ++i) xi[i] = x[i] - s.drive.front_x;
    // the in-plane strip's front (docs/fronts.md §11.10) also sets u_y and its velocity, component 1 of every node
    const bool inplane = body.shape().components == 2 && front->strip->bulk.body() == core::BodyKind::inplane;
    const auto fp = inplane ? continuum::sample_inplane_front(*front->strip, xi)
                            : continuum::InPlaneFrontSample{continuum::sample_strip_front(*front->strip, xi), {}, {}};
    const auto& f = fp.x;
    for (std::size_t i = 0; i < n; ++i) {
      const bool kicked = x[i] <= s.drive.front_x && x[i] >= s.drive.front_x - s.drive.kick_length;
      sim.law().set_site(i, f.interface.area[i], f.interface.sigma_bar[i]);
      for (std::size_t j = 0; j < rows; ++j) {
        sim.set_initial(body.dof(i, j, 0), f.u[i * rows + j],
                        f.velocity[i * rows + j] + (kicked && j == 0 ? s.drive.kick_dv : 0.0));
        if (inplane) sim.set_initial(body.dof(i, j, 1), fp.uy[i * rows + j], fp.uy_velocity[i * rows + j]);
      }
    }
    return;
  }
  if (front && front->chain) {
    const auto f = continuum::sample_steady_front(*front->chain, x, s.drive.front_x);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const bool kicked = x[i] <= s.drive.front_x && x[i] >= s.drive.front_x - s.drive.kick_length;
      sim.law().set_site(i, f.area[i], f.sigma_bar[i]);
      sim.set_initial(i, f.slip[i], f.slip_rate[i] + (kicked ? s.drive.kick_dv : 0.0));
    }
    return;
  }
  const auto& ip = s.interface;
  const double sd = s.drive.sigma_d;
  // the patch slides steadily at σ_d in the law's own steady state (core::LawHooks::steady_state)
  const auto& law = sim.law();
  double vs = std::numeric_limits<double>::quiet_NaN();
  if constexpr (std::remove_cvref_t<decltype(law)>::hooks.steady_state) vs = law.steady_velocity(sd);
  else if (s.drive.nucleation_length > 0.0)
    throw core::ParamError("drive.nucleation_length", "this model's law has no steady state to start a nucleation patch "
                                                      "from (core::LawHooks::steady_state); set it to 0");
  const auto set = [&sim](std::size_t k, double u, double v) { sim.set_initial(k, u, v); };
  for (std::size_t i = 0; i < x.size(); ++i) {
    const bool patch = std::isfinite(vs) && x[i] < s.drive.nucleation_length;
    if (patch) {
      core::SteadyState ss{};
      if constexpr (std::remove_cvref_t<decltype(law)>::hooks.steady_state) ss = law.steady_sliding(vs);
      sim.law().set_site(i, ss.area, ss.sigma_bar);
    } else {
      sim.law().set_site(i, 1.0, sd);
    }
    sim.bulk().lift(i, sd / ip.alpha, patch ? vs : 0.0, sd, set);  // the strip: u + σ_d y/μ' in row y
  }
}

}  // namespace slipfront::compare
