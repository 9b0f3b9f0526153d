#include "compare/scene.hpp"

#include "continuum/bulk.hpp"
#include "continuum/implicit.hpp"

namespace slipfront::compare {

void Scene::validate() const {
  using continuum::ParamError;
  if (models.empty()) throw ParamError("models", "must list at least one model");
  for (const auto& m : models)
    if (m != "continuum" && m != "discrete")
      throw ParamError("models", "unknown model '" + m + "' (expected continuum or discrete)");
  const bool one_d = continuum::is_one_dimensional(drive.loading);
  interface.validate();
  bulk.validate(one_d);
  drive.validate();
  grid.validate(bulk, one_d);
  time.validate(drive.loading);
  measure.validate();
  output.validate();
  for (const auto& m : models)
    if (m == "discrete") discrete.validate();
  if (drive.loading == continuum::Loading::imposed_rate && drive.sweep_points == 0 && drive.v_times.back() >= time.t_end)
    throw ParamError("drive.switch_times", "every switch time must be before time.t_end (" +
                                              continuum::format_number(time.t_end) + "), got " +
                                              continuum::format_number(drive.v_times.back()));
  if (drive.loading != continuum::Loading::imposed_rate && time.integrator == continuum::Integrator::implicit_trapezoidal &&
      time.implicit_resolution_check) {
    const continuum::Bulk b(bulk, drive, interface, grid.dx);
    const auto r = continuum::implicit_resolution(b, interface, measure.v_event, time.dt);
    using R = continuum::ImplicitResolution;
    if (r.drive > R::drive_bound)
      throw ParamError("time.dt", "too large for the implicit integrator: dt sqrt(K/(rho w_0)) = " + continuum::format_number(r.drive, 4) +
                                      " > " + continuum::format_number(R::drive_bound) +
                                      " (the drive spring's oscillation of the edge node is neither resolved nor damped); use time.dt <= " +
                                      continuum::format_number(time.dt * R::drive_bound / r.drive, 4) +
                                      ", the explicit or adaptive integrator, or time.implicit_resolution_check = false");
    if (r.detach > R::detach_bound)
      throw ParamError("time.dt", "too large for the implicit integrator: dt (1 + kappa v_event) = " + continuum::format_number(r.detach, 4) +
                                      " > " + continuum::format_number(R::detach_bound) +
                                      " (the contact turnover at the event slip rate is not resolved: spurious or missed events); use time.dt <= " +
                                      continuum::format_number(time.dt * R::detach_bound / r.detach, 4) +
                                      ", the explicit or adaptive integrator, or time.implicit_resolution_check = false");
  }
  if (drive.loading != continuum::Loading::imposed_rate && time.dt > 0 && time.integrator != continuum::Integrator::implicit_trapezoidal) {
    const continuum::Bulk b(bulk, drive, interface, grid.dx);
    if (time.dt > b.stable_dt())
      throw ParamError("time.dt", "exceeds the explicit stability limit " + continuum::format_number(b.stable_dt()) +
                                      " of this grid (use time.cfl <= 1, a smaller dt, or time.integrator = \"implicit\")");
  }
}

}  // namespace slipfront::compare
