#include "core/adaptive.hpp"

#include <string>

namespace slipfront::core {

void AdaptiveOptions::validate() const {
  auto bad = [](const char* key, const std::string& why) { throw ParamError(std::string("time.") + key, why); };
  if (!(rtol > 0.0 && rtol < 1.0)) bad("rtol", "must be in (0, 1), got " + format_number(rtol));
  if (!(atol > 0.0)) bad("atol", "must be > 0, got " + format_number(atol));
  if (!(dt_max > 0.0)) bad("dt_max", "must be > 0, got " + format_number(dt_max));
  if (!(dt_initial > 0.0)) bad("dt_initial", "must be > 0, got " + format_number(dt_initial));
  if (!(dt_min > 0.0 && dt_min <= dt_initial)) bad("dt_min", "must be in (0, dt_initial], got " + format_number(dt_min));
  if (!(switch_band >= 0.0 && switch_band < 1e-3)) bad("switch_band", "must be in [0, 1e-3), got " + format_number(switch_band));
  if (!(event_window >= 0.0)) bad("event_window", "must be >= 0, got " + format_number(event_window));
  if (!(group_fraction >= 0.0 && group_fraction <= 1.0))
    bad("group_switchings", "must be in [0, 1], got " + format_number(group_fraction));
}

}  // namespace slipfront::core
