#include "compare/runner.hpp"

#include <stdexcept>

#include "discrete/count_law.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/naive_law.hpp"

namespace slipfront::compare {

double dynamic_time_step(const Scene& s) {
  const continuum::Bulk bulk(s.bulk, s.drive, s.interface, s.grid.dx);
  const double dt = s.time.dt > 0 ? s.time.dt : s.time.cfl * bulk.stable_dt();
  const double n = std::max(1.0, std::ceil(s.time.t_end / dt - 1e-9));
  return s.time.t_end / n;
}

std::vector<double> sweep_rates(const continuum::DriveParams& d) {
  std::vector<double> v(static_cast<std::size_t>(d.sweep_points));
  const double a = std::log(d.v_min), b = std::log(d.v_max);
  for (std::size_t k = 0; k < v.size(); ++k)
    v[k] = std::exp(a + (b - a) * static_cast<double>(k) / static_cast<double>(v.size() - 1));
  return v;
}

std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl) {
  std::vector<ModelResult> out;
  for (const auto& m : s.models) {
    if (m == "continuum") {
      auto make = [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); };
      out.push_back(run_model<continuum::FrictionLaw>(s, make, m, ctl));
    } else if (m == "discrete") {
      // MODEL §2: the microcontact ensemble on the same bulk, grid and time step.
      const auto& d = s.discrete;
      d.validate();
      if (d.representation == "count") {
        auto make = [&](std::size_t n) { return discrete::CountLaw(s.interface, d, n); };
        out.push_back(run_model<discrete::CountLaw>(s, make, m, ctl));
      }
      // agent and naive representations:
      else if (d.representation == "agent") {
        auto make = [&](std::size_t n) { return discrete::AgentLaw(s.interface, d, n); };
        out.push_back(run_model<discrete::AgentLaw>(s, make, m, ctl));
      } else if (d.representation == "naive") {
        auto make = [&](std::size_t n) { return discrete::NaiveAgentLaw(s.interface, d, n); };
        out.push_back(run_model<discrete::NaiveAgentLaw>(s, make, m, ctl));
      } else {
        throw continuum::ParamError("discrete.representation", "'" + d.representation + "' not built yet");
      }
      auto& r = out.back();
      r.labels["representation"] = d.representation;
      r.labels["threshold"] = d.threshold;
      r.labels["renewal"] = d.renewal;
      r.labels["noise"] = d.noise ? "true" : "false";
      r.labels["seed"] = std::to_string(d.seed);
      r.scalars["contacts_per_site"] = static_cast<double>(d.contacts_per_site);
      r.scalars["width"] = d.width;
      if (d.representation == "count") r.scalars["bins"] = d.width > 0.0 ? d.bins : 1.0;
    } else {
      throw std::invalid_argument("unknown model '" + m + "'");
    }
    if (out.back().status != "complete") break;
  }
  return out;
}

}  // namespace slipfront::compare
