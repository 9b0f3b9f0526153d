#include "compare/runner.hpp"

#include <optional>
#include <stdexcept>

#include "compare/laws.hpp"
#include "core/interrupt.hpp"

namespace slipfront::compare {

double dynamic_time_step(const Scene& s) {
  const core::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const double dt = s.time.dt > 0 ? s.time.dt : s.time.cfl * bulk.stable_dt();
  const double n = std::max(1.0, std::ceil(s.time.t_end / dt - 1e-9));
  return s.time.t_end / n;
}

std::optional<continuum::SteadyFront> front_start(const Scene& s) {
  if (s.drive.loading != core::Loading::homogeneous || s.drive.start != "steady_front") return std::nullopt;
  auto front = continuum::solve_steady_front(s.interface, s.bulk, s.drive.sigma_d);
  if (front.status != continuum::FrontStatus::converged)
    throw core::ParamError("drive.sigma_d", "no steady front at sigma_d = " + core::format_number(s.drive.sigma_d) +
                                                     " to start from (" + continuum::to_string(front.status) + ": " +
                                                     front.reason + ")");
  return front;
}

std::int64_t fixed_step_count(const Scene& s) {
  const double n = std::round(s.time.t_end / dynamic_time_step(s));
  if (!(n < 9.0e18))
    throw core::ParamError("time.t_end", "gives " + core::format_number(n) +
                                                  " time steps, more than a 64-bit count holds (time.t_end / time.dt)");
  return static_cast<std::int64_t>(n);
}

std::vector<double> sweep_rates(const core::DriveParams& d) {
  std::vector<double> v(static_cast<std::size_t>(d.sweep_points));
  const double a = std::log(d.v_min), b = std::log(d.v_max);
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = std::exp(a + (b - a) * static_cast<double>(k) / static_cast<double>(v.size() - 1));
  return v;
}

std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl) {
  // Models one after the other. A checkpoint holds the models finished so far and the one running.
  std::vector<ModelResult> out;
  std::optional<core::Archive> resume;
  if (!ctl.restart.empty()) {
    resume = core::Archive::reader(ctl.restart);
    resume->tag("sequential");
    (*resume)(out);
  }
  const CheckpointHeader header = [&](core::Archive& ar) {
    ar.tag("sequential");
    auto done = out;
    ar(done);
  };
  for (std::size_t k = out.size(); k < s.models.size(); ++k) {
    const std::string& m = s.models[k];
    core::Archive* from = resume && !resume->at_end() ? &*resume : nullptr;
    try {
      if (m == "continuum") {
        auto make = [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); };
        out.push_back(run_model<continuum::FrictionLaw>(s, make, m, ctl, header, from));
      } else if (m == "discrete") {
        // docs/model.md §2: the microcontact ensemble on the same bulk, grid and time step.
        out.push_back(with_discrete_law(s, [&](auto make) {
          using Law = decltype(make(std::size_t{1}));
          return run_model<Law>(s, make, m, ctl, header, from);
        }));
        label_discrete(s, out.back());
      } else {
        throw std::invalid_argument("unknown model '" + m + "'");
      }
    } catch (const core::ArchiveError&) {
      throw;  // a checkpoint that does not fit this scene: the caller reports it
    } catch (const core::Interrupted& e) {  // a stop request during the set-up of its law
      ModelResult stopped;
      stopped.model = m;
      stopped.status = RunStatus::interrupted;
      stopped.message = e.what();
      out.push_back(std::move(stopped));
    } catch (const std::exception& e) {  // keep what the earlier models produced
      ModelResult failed;
      failed.model = m;
      failed.status = RunStatus::failed;
      failed.message = e.what();
      out.push_back(std::move(failed));
    }
    if (out.back().status != RunStatus::complete) break;
  }
  return out;
}

}  // namespace slipfront::compare
