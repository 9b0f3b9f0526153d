#pragma once
// The prescribed normal load's rule shared by the ensembles and the mean field (docs/model.md §12.2).
#include <span>
#include <string>
#include <vector>

#include "core/params.hpp"

namespace slipfront::discrete {

/// Under re-attachment a site's N contacts are its capacity at p_0: every resting area a_i = (p_i/p_0)^m must be at
/// most 1 (ParamError naming interface.load_p otherwise). The instantaneous channel takes any.
inline void check_resting_capacity(std::span<const double> factor, bool instantaneous) {
  if (instantaneous) return;
  for (std::size_t i = 0; i < factor.size(); ++i)
    if (!(factor[i] <= 1.0))
      throw core::ParamError("interface.load_p",
                             "a load above p_0 (resting area " + core::format_number(factor[i]) + " > 1 at site " +
                                 std::to_string(i) + ") under load_channel = \"reattachment\": a site's N contacts are "
                                 "its capacity at p_0, so p/p_0 <= 1 (or use the instantaneous channel)");
}

/// A law's set_normal_load (docs/model.md §12.2): the capacity check, then under the instantaneous channel σ̄ scaled by
/// a_new/a_old (`rest` empty: a_old = 1), then the new areas and the channel flags. The caller recomputes its A.
inline void install_resting_areas(std::span<const double> factor, const core::InterfaceParams& ip,
                                  std::vector<double>& rest, std::span<double> sigma_bar, bool& reattach, bool& scaled) {
  const bool at_once = ip.instantaneous_load();
  check_resting_capacity(factor, at_once);
  if (at_once)
    for (std::size_t i = 0; i < factor.size(); ++i) sigma_bar[i] *= factor[i] / (rest.empty() ? 1.0 : rest[i]);
  rest.assign(factor.begin(), factor.end());
  reattach = !at_once;
  scaled = at_once;
}

}  // namespace slipfront::discrete
