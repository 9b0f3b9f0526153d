#include "compare/initial.hpp"

#include <algorithm>
#include <cmath>

#include "compare/estimate.hpp"

namespace slipfront::compare {

double dynamic_time_step(const Scene& s) {
  // the explicit limit of the scene's body (the chain's or the strip's): compare::explicit_stable_dt
  const double dt = s.time.dt > 0 ? s.time.dt : s.time.cfl * explicit_stable_dt(s);
  const double n = std::max(1.0, std::ceil(s.time.t_end / dt - 1e-9));
  return s.time.t_end / n;
}

std::int64_t fixed_step_count(const Scene& s) {
  const double n = std::round(s.time.t_end / dynamic_time_step(s));
  if (!(n < 9.0e18))
    throw core::ParamError("time.t_end", "gives " + core::format_number(n) +
                                             " time steps, more than a 64-bit count holds (time.t_end / time.dt)");
  return static_cast<std::int64_t>(n);
}

continuum::StripFrontOptions strip_start_options(const Scene& s) {
  continuum::StripFrontOptions o;
  o.rows = static_cast<int>(std::llround(s.bulk.height / s.grid.row_spacing()));
  o.row_spacing = s.bulk.height;  // ≥ H/M: uniform rows, the strip's own
  o.tip_spacing = std::min(o.tip_spacing, 0.1 * s.grid.dx);
  return o;
}

FrontStartCost front_start_cost(const Scene& s) {
  FrontStartCost c;
  const core::BodyKind body = s.bulk.body();
  if (s.drive.loading != core::Loading::homogeneous || s.drive.start != "steady_front" || body == core::BodyKind::chain)
    return c;
  const continuum::StripFrontOptions o = strip_start_options(s);
  // antiplane: measured 32 and 39 stop polls over 7 and 8 solves (H = 17, 34); in-plane: 23 over 5 solves (H = 8,
  // 8 rows; docs/fronts.md §11.10)
  constexpr double iterations_per_solve = 5.0;
  c.rows = o.rows;
  c.intervals = o.intervals;
  c.solves = 1;
  for (double h = std::min(s.bulk.height, o.thin_height); h < s.bulk.height; h *= o.height_factor) ++c.solves;
  // the in-plane block carries u_x and u_y: (4M + 4)² against the antiplane (2M + 4)² (docs/fronts.md §11.5)
  const auto per = continuum::strip_solve_cost(o.rows, o.intervals, body == core::BodyKind::inplane ? 2 : 1);
  c.seconds = iterations_per_solve * c.solves * per.iteration_seconds;
  c.memory_bytes = per.memory_bytes;
  return c;
}

std::optional<FrontStart> front_start(const Scene& s, const std::function<bool()>& stop) {
  if (s.drive.loading != core::Loading::homogeneous || s.drive.start != "steady_front") return std::nullopt;
  auto refuse = [&](continuum::FrontStatus status, const std::string& reason) {
    const core::BodyKind body = s.bulk.body();
    const char* where = body == core::BodyKind::strip     ? " in the strip"
                        : body == core::BodyKind::inplane ? " in the in-plane strip"
                                                          : "";
    return core::ParamError("drive.sigma_d", "no steady front" + std::string(where) +
                                                 " at sigma_d = " + core::format_number(s.drive.sigma_d) +
                                                 " to start from (" + continuum::to_string(status) + ": " + reason + ")");
  };
  FrontStart out;
  if (s.bulk.body() != core::BodyKind::chain) {  // either strip: solve_strip_front solves the in-plane front on inplane
    continuum::StripFrontOptions o = strip_start_options(s);
    o.stop = stop;
    auto front = continuum::solve_strip_front(s.interface, s.bulk, s.drive.sigma_d, o);
    if (front.status == continuum::FrontStatus::stopped) {
      out.stopped = true;
      return out;
    }
    if (front.status != continuum::FrontStatus::converged) throw refuse(front.status, front.reason);
    out.c = front.c;
    out.v_tip = front.v_tip;
    out.v_behind = front.v_behind;
    out.far_field_strain = -front.v_behind / front.c;
    out.strip = std::move(front);
    return out;
  }
  auto front = continuum::solve_steady_front(s.interface, s.bulk, s.drive.sigma_d);
  if (front.status != continuum::FrontStatus::converged) throw refuse(front.status, front.reason);
  out.c = front.c;
  out.v_tip = front.v_tip;
  out.v_behind = front.v_behind;
  out.far_field_strain = front.far_field_strain;
  out.chain = std::move(front);
  return out;
}

}  // namespace slipfront::compare
