#pragma once
// Parameters of the microcontact ensemble (docs/model.md §2), config section [discrete].
#include <cstdint>
#include <span>
#include <string>

#include "core/params.hpp"

namespace slipfront::discrete {

struct DiscreteParams {
  long contacts_per_site = 1000;         ///< N, contacts per site
  std::string threshold = "delta";       ///< delta | uniform | gaussian | weibull
  double width = 0.0;                    ///< relative width w of the threshold distribution (mean 1)
  std::string renewal = "fresh";         ///< fresh: new threshold at each detachment | quenched
  std::string representation = "count"; ///< count | agent | naive (agent visiting every contact every step: a baseline)
  bool noise = true;                     ///< false: every draw replaced by its expectation
  std::uint64_t seed = 1;                ///< random streams derive from (seed, site)
  int bins = 64;                         ///< count representation: quantile bins of g when w > 0
  bool contact_statistics = false;       ///< agent: store /discrete/contacts
  int threads = 1;                       ///< threads over sites (results do not depend on it)
  void validate() const;                 ///< throws core::ParamError("discrete.<key>", reason)
  /// The keys of the threshold law alone (threshold, width, renewal, bins), with validate()'s messages:
  /// what the mean-field law reads (discrete/mean_field_law.hpp; it has no N, seed or representation).
  void validate_threshold_law() const;
};

/// The domains of the [discrete] keys (see core::KeyDomain): validate() checks them, the
/// hostile-input test iterates them. discrete.width's row is the widest law's; each law's own limit
/// is max_width(threshold) (discrete/thresholds.hpp).
std::span<const core::KeyDomain> key_domains();

/// Largest accepted discrete.threads: more threads than this only adds overhead (sites are shared in
/// chunks of 64, so 1024 threads need 65536 sites to be busy) and each costs a stack.
inline constexpr int max_threads = 1024;

}  // namespace slipfront::discrete
