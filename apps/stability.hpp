#pragma once
// `slipfront stability CONFIG --v0 V` (docs/cli.md; issue 40 item 5): the growth rates of homogeneous sliding at v0 on
// the in-plane strip under the normal-load coupling (docs/model.md §12.6, §12.7), from the project's linearisation
// (continuum::leading_growth_rate, continuum/inplane_stability.hpp) with the scene's parameters. Over a kH grid it
// computes the least-damped resolved mode and the fastest mode of all for four channels: the uncoupled strip, the
// re-attachment channel, the instantaneous one and the regularised instantaneous one (the scene's L, or
// --relaxation-length); at each channel's fastest kH, the fastest mode again on 2 and 4 times the rows (whether it
// converges: docs/output.md "stability.h5"). Writes DIR/growth_rates.csv (scripts/plot.py draws it) and
// DIR/stability.h5 (/meta, /config, /stability), each through a temporary file renamed when complete.
#include <complex>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "continuum/inplane_stability.hpp"

namespace CLI {
class App;
}

namespace slipfront::app {

struct StabilityOptions {
  std::filesystem::path config;
  std::vector<std::string> overrides;  ///< --set, as for run
  std::filesystem::path out;           ///< empty: out/<scene name>
  double v0 = 0.0;                     ///< --v0: the sliding rate (required; v0 > v_m)
  std::vector<double> kh;              ///< --kh: the kH values; empty: the log grid kh_min .. kh_max
  double kh_min = 0.1, kh_max = 8.0;
  int points = 41;
  int rows = 0;                        ///< --rows: elements over the height; 0: the scene's rows, round(H/dy)
  double relaxation_length = 0.03;     ///< L of the regularised channel when the scene has none (docs/model.md §12.7)
  bool force = false;
  bool quiet = false;
  std::string command_line;
};

/// One channel's growth rates over the kH grid (docs/output.md, /stability/<group>).
struct StabilityChannel {
  std::string group;   ///< uncoupled, reattachment, instantaneous, regularised
  std::string label;   ///< growth_rates.csv's channel: the group, "instantaneous L=<L>" for the regularised one
  bool scene = false;  ///< the scene's own channel
  continuum::InPlaneStabilityParams params;
  std::vector<std::complex<double>> resolved, fastest;  ///< per kH: leading_growth_rate below max_frequency; of all
  std::vector<double> roundoff;  ///< per kH: 1e-8 of the largest |s| (the eigensolver's round-off)
  double check_kh = 0.0;         ///< the kH of the largest Re s of the fastest modes
  std::vector<int> check_rows;   ///< rows, 2 rows, 4 rows
  std::vector<std::complex<double>> check_fastest;  ///< the fastest mode at check_kh on each
  bool converged = false;        ///< stability_converged of check_fastest
};

struct StabilityResult {
  continuum::InPlaneStabilityParams params;  ///< the scene's (its channel, its rows)
  std::vector<double> kh;
  double max_frequency = 0.0;  ///< 4 c_p/H: the resolved modes have |Im s| ≤ it
  std::vector<StabilityChannel> channels;
  compare::RunStatus status = compare::RunStatus::complete;
  std::string message;
};

/// The linearisation's parameters of a scene (docs/model.md §12.6): μ' = μ(1 − ν)/(2H), λ' = 2μ'ν/(1 − 2ν), ρ' = ρ/H,
/// the law, p_0 = bulk.normal_load, m, the scene's channel and regularisation, `rows` elements (0: round(H/dy)).
/// Throws ConfigError(file, key, reason) for a scene that is not an in-plane strip (bulk.body) or has no coupling
/// (interface.load_coupling).
continuum::InPlaneStabilityParams stability_params_of(const compare::Scene& scene, const std::string& file, double v0,
                                                      int rows);

/// The kH values of the options: --kh, else points values geometrically spaced from kh_min to kh_max.
std::vector<double> stability_kh(const StabilityOptions& opts);

/// Whether the fastest mode on rows, 2 rows, 4 rows (s1, s2, s4) has converged: its rate and its frequency each move
/// by at most 5 % (plus 1e-3, and 1e-3 c_p/H for the frequency) from 2 to 4 times the rows, and less than from 1 to 2.
bool stability_converged(const std::vector<std::complex<double>>& s, double frequency_scale);

/// The channels' rates over the kH grid (`stop` polled between kH values: the result is then interrupted).
StabilityResult compute_stability(const continuum::InPlaneStabilityParams& scene_params, double regularised_length,
                                  const std::vector<double>& kh, const std::function<bool()>& stop);

/// growth_rates.csv: channel,kH,kind,re_s,im_s; kinds theory_resolved and theory_max, 17 significant digits.
std::string growth_rates_csv(const StabilityResult& r);

/// `slipfront stability`: returns the exit code (0, 1 failed, 2 usage, 130 interrupted).
int stability_command(const StabilityOptions& opts, std::ostream& out, std::ostream& err);

/// The verb and its options on `app`.
CLI::App* add_stability_verb(CLI::App& app, StabilityOptions& opts);

}  // namespace slipfront::app
