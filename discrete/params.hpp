#pragma once
// Parameters of the microcontact ensemble (docs/model.md §2), config section [discrete].
#include <cstdint>
#include <string>

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
  void validate() const;                 ///< throws continuum::ParamError("discrete.<key>", reason)
};

}  // namespace slipfront::discrete
