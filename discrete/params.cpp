#include "discrete/params.hpp"

#include <cmath>

#include "continuum/params.hpp"

namespace slipfront::discrete {

void DiscreteParams::validate() const {
  using continuum::ParamError;
  if (contacts_per_site < 1)
    throw ParamError("discrete.contacts_per_site", "must be >= 1, got " + std::to_string(contacts_per_site));
  if (threshold != "delta" && threshold != "uniform" && threshold != "gaussian" && threshold != "weibull")
    throw ParamError("discrete.threshold",
                     "unknown distribution '" + threshold + "' (expected delta, uniform, gaussian or weibull)");
  if (!std::isfinite(width) || width < 0.0)
    throw ParamError("discrete.width", "must be >= 0, got " + std::to_string(width));
  if (threshold == "uniform" && width > 1.0 / std::sqrt(3.0))
    throw ParamError("discrete.width", "a uniform distribution with mean 1 and positive support needs w <= 1/sqrt(3)");
  if (renewal != "fresh" && renewal != "quenched")
    throw ParamError("discrete.renewal", "unknown renewal '" + renewal + "' (expected fresh or quenched)");
  if (representation != "count" && representation != "agent" &&
      representation != "naive")
    throw ParamError("discrete.representation",
                     "unknown representation '" + representation + "' (expected count, agent or naive)");
  if (bins < 1) throw ParamError("discrete.bins", "must be >= 1");
  if (threads < 1) throw ParamError("discrete.threads", "must be >= 1");
  if (threshold == "delta" && width != 0.0)
    throw ParamError("discrete.width", "a delta distribution has width 0 (choose uniform, gaussian or weibull)");
}

}  // namespace slipfront::discrete
