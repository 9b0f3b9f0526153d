#include "discrete/params.hpp"

#include <cmath>
#include <cstdint>

#include "discrete/thresholds.hpp"

namespace slipfront::discrete {

namespace {
using core::KeyDomain;
using K = core::KeyKind;
const KeyDomain discrete_domains[] = {
    {"discrete.contacts_per_site", K::integer, 1.0, 1e15, false, false, false, "",
     "(counts are whole numbers held in doubles: exact up to 2^53)"},
    {"discrete.threshold", K::choice, 0, 0, false, false, false, "delta|uniform|gaussian|weibull"},
    {"discrete.width", K::number, 0.0, 10.0, false, false, false, "",
     "(the limit of each law: delta 0, uniform 1/sqrt(3), gaussian 0.99, weibull 10)"},
    {"discrete.renewal", K::choice, 0, 0, false, false, false, "fresh|quenched"},
    {"discrete.representation", K::choice, 0, 0, false, false, false, "count|agent|naive"},
    {"discrete.noise", K::boolean},
    {"discrete.seed", K::integer, 0.0, 9223372036854775807.0, false, false, false, "", "(0 ... 2^63 - 1)"},
    {"discrete.bins", K::integer, 1.0, 1e6, false, false, false, "",
     "(quantile bins of the threshold law; memory and time grow with them: see limits)"},
    {"discrete.contact_statistics", K::boolean},
    {"discrete.threads", K::integer, 1.0, static_cast<double>(max_threads), false, false, false, "",
     "(threads over sites, in chunks of 64 sites)"},
};

// One bin holds every threshold at the law's conditional mean over [0, 1] of the quantiles, the mean 1
// (docs/discrete.md, "Bins"): with w > 0 that is the delta law bit for bit, while the run is labelled with the
// width. B >= 2 keeps the CDF within 1/B of g's.
void check_bins(const DiscreteParams& d) {
  if (d.bins == 1 && d.threshold != "delta" && d.width > 0.0)
    throw core::ParamError("discrete.bins",
                           "1 bin represents every threshold by the mean 1: the delta law, whatever discrete.width (" +
                               core::format_number(d.width) + "); use bins >= 2 (the count law's CDF is then within 1/bins "
                               "of the " + d.threshold + " law's), or threshold = \"delta\"");
}

bool one_of(const std::string& value, const char* choices) {
  std::string_view c(choices);
  for (std::size_t start = 0;;) {
    const auto bar = c.find('|', start);
    if (c.substr(start, bar == std::string_view::npos ? bar : bar - start) == value) return true;
    if (bar == std::string_view::npos) return false;
    start = bar + 1;
  }
}
}  // namespace

std::span<const KeyDomain> key_domains() { return discrete_domains; }

void DiscreteParams::validate() const {
  using core::ParamError;
  auto domain = [](const char* key) { return *core::find_key_domain(key_domains(), key); };
  core::check_in_domain(domain("discrete.contacts_per_site"), static_cast<double>(contacts_per_site));
  if (!one_of(threshold, domain("discrete.threshold").choices))
    throw ParamError("discrete.threshold",
                     "unknown distribution '" + threshold + "' (expected delta, uniform, gaussian or weibull)");
  core::check_in_domain(domain("discrete.width"), width);
  if (threshold == "delta" && width != 0.0)
    throw ParamError("discrete.width", "a delta distribution has width 0 (choose uniform, gaussian or weibull)");
  // the law itself: its domain, the convergence of its construction, its mean and sd (throws with the reason)
  if (threshold != "delta" && width > 0.0) (void)ThresholdDistribution(threshold, width);
  if (!one_of(renewal, domain("discrete.renewal").choices))
    throw ParamError("discrete.renewal", "unknown renewal '" + renewal + "' (expected fresh or quenched)");
  if (!one_of(representation, domain("discrete.representation").choices))
    throw ParamError("discrete.representation",
                     "unknown representation '" + representation + "' (expected count, agent or naive)");
  if (seed > static_cast<std::uint64_t>(INT64_MAX))  // (as a double 2^63 - 1 and 2^63 are the same number)
    throw ParamError("discrete.seed", "must be <= 2^63 - 1 = 9223372036854775807 (a TOML integer), got " + std::to_string(seed));
  core::check_in_domain(domain("discrete.bins"), bins);
  check_bins(*this);
  core::check_in_domain(domain("discrete.threads"), threads);
}

void DiscreteParams::validate_threshold_law() const {
  using core::ParamError;
  auto domain = [](const char* key) { return *core::find_key_domain(key_domains(), key); };
  if (!one_of(threshold, domain("discrete.threshold").choices))
    throw ParamError("discrete.threshold",
                     "unknown distribution '" + threshold + "' (expected delta, uniform, gaussian or weibull)");
  core::check_in_domain(domain("discrete.width"), width);
  if (threshold == "delta" && width != 0.0)
    throw ParamError("discrete.width", "a delta distribution has width 0 (choose uniform, gaussian or weibull)");
  if (threshold != "delta" && width > 0.0) (void)ThresholdDistribution(threshold, width);
  if (!one_of(renewal, domain("discrete.renewal").choices))
    throw ParamError("discrete.renewal", "unknown renewal '" + renewal + "' (expected fresh or quenched)");
  core::check_in_domain(domain("discrete.bins"), bins);
  check_bins(*this);
}

}  // namespace slipfront::discrete
