// scratch driver until the CLI lands
#include <cstdio>
#include "compare/runner.hpp"
using namespace slipfront;
int main(int argc, char** argv) {
  compare::Scene s;
  s.name = "fig1";
  s.time.t_end = argc > 1 ? std::atof(argv[1]) : 140.0;
  s.grid.dx = argc > 2 ? std::atof(argv[2]) : 0.5;
  s.time.cfl = argc > 3 ? std::atof(argv[3]) : 0.5;
  s.output.series_dt = 0.5;
  s.validate();
  auto r = compare::run_scene(s, {});
  auto& m = r[0];
  auto& S = m.series;
  for (size_t i = 0; i < S["t"].size(); i += 4)
    std::printf("t=%7.2f F=%8.4f tip=%8.3f tip9=%8.3f maxv=%9.4g\n", S["t"][i], S["drive_force"][i], S["tip_x"][i], S["tip_x_alt"][i], S["max_v"][i]);
  auto& e = m.events;
  std::printf("status=%s dt=%g wall=%g\nt*=%g t^=%g c_slow=%g c_tr=%g peak=%g x_arr=%g t_arr=%g\n", m.status.c_str(), m.scalars["dt"], m.wall_seconds,
              e.t_star, e.t_hat, e.c_slow, e.c_transient, e.c_transient_peak, e.x_arrest, e.t_arrest); std::printf("alt: c_slow=%g c_tr=%g x_arr=%g\n", m.events_alt.c_slow, m.events_alt.c_transient, m.events_alt.x_arrest);
}
