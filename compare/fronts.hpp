#pragma once
// The steady fronts of a homogeneous scene (docs/model.md §6) as a result to store and plot: the branch
// c(σ_d) by continuation to its end, a few solved profiles along it, and optionally the minimal-speed
// scaling study (continuum/steady_front.hpp does the numerics). `slipfront fronts` writes it to
// fronts.h5 (apps/h5out, docs/output.md). Nothing here reads or writes files.
#include <map>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "continuum/steady_front.hpp"

namespace slipfront::compare {

struct FrontProfile {
  double sigma_d = 0.0, c = 0.0, v_tip = 0.0, v_behind = 0.0;
  bool limiting = false;  ///< the limiting front at the end of the branch
  Columns fields;         ///< xi, A, sigma_bar, v, u on the solver's mesh (tip at xi = 0)
};

struct FrontsResult {
  Columns branch;                              ///< one entry per continuation point (see docs/output.md)
  std::map<std::string, double> scalars;       ///< c_min, sigma_d_at_c_min, sigma_c_d, scale, ...
  std::map<std::string, std::string> labels;   ///< end, reason
  std::vector<FrontProfile> profiles;
  /// The minimal-speed scaling study (empty unless asked for): one entry per point, and per fit.
  Columns scaling_points;                      ///< value, c_min, sigma_d_at_c_min, scale, parameter_index
  std::vector<std::string> scaling_parameters; ///< names indexed by parameter_index
  Columns scaling_fits;                        ///< prefactor, spread, rms_relative, points, parameter_index (-1: all)
  double wall_seconds = 0.0;
};

/// The branch of the scene's interface and bulk parameters (the scene's σ_d only chooses one of the
/// profiles), with `scaling` the minimal-speed scaling study too. Throws core::ParamError when the
/// scene is not under homogeneous loading.
FrontsResult compute_fronts(const Scene& s, bool scaling);

/// c of the solved steady front at σ_d (NaN where there is none).
double solved_front_speed(const Scene& s, double sigma_d);

}  // namespace slipfront::compare
