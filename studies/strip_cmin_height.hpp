#pragma once
// c_min(H) of the antiplane strip at a fixed strip material (issue 20 items 1, 2; docs/fronts.md §10.11–§10.13):
// the limiting front at σ_c^d continued in H (continuum::continue_strip_height), at every target H optionally the
// branch c(σ_d) from σ_d = 0.8 to its end (started from a second path at σ_d = 0.8), the 1D c_min of the same
// column stiffness μ = μ'H, and the paper's lengths ℓ = μ', ℓ_κ = μ'κ/(ηα), s = μ'/η. The computation of the
// study kind "strip_cmin_height" (docs/studies.md) and of bench/strip_cmin_height (its command line). No files:
// strip_cmin_csv gives the table's text.
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "continuum/strip_front.hpp"
#include "core/params.hpp"

namespace slipfront::compare {
struct Scene;
struct StudySpec;
}  // namespace slipfront::compare

namespace slipfront::studies {
using namespace compare;  // the run layer's vocabulary: Scene, StudySpec, ModelResult, ...

struct StudyReport;
struct StudyWork;
struct StudyOutcome;

struct StripCminHeightOptions {
  core::InterfaceParams law{1.05, 8.0, 0.1};
  double mu_strip = 300.0;    ///< μ' = μ/H, held along the path (in-plane: the shear modulus μ' = μ(1 − ν)/(2H))
  double rho_strip = 1e-9;    ///< ρ' = ρ/H (1e-9: the quasi-static material of docs/fronts.md §10.12)
  /// The body (docs/fronts.md §11.8): the antiplane strip (core::BodyKind::strip) or the in-plane strip
  /// (core::BodyKind::inplane, with ν and the top's normal load p; its column stiffness is E' = 2μ'/(1 − ν) per height).
  core::BodyKind body = core::BodyKind::strip;
  double poisson = 1.0 / 3.0, normal_load = 0.0;
  double hmin = 1.0, hmax = 1e6;
  double per_decade = 2.0;    ///< target heights per decade: round(per_decade · log10(hmax/hmin)) + 1 of them
  int rows = 16, intervals = 400;               ///< the limiting path's mesh
  bool branches = true;                         ///< also the branch c(σ_d) at every target H
  int branch_rows = 8, branch_intervals = 300;  ///< the branches' mesh
  double tolerance = 1e-11;   ///< Newton tolerance of every solve
  double max_factor = 2.0;    ///< largest step H_{n+1}/H_n of the paths
  /// The limiting path's meshes chosen per target height by a tolerance on c_min (docs/fronts.md §10.20): with
  /// choose_meshes the rows from first_rows (and the intervals from `intervals`) are doubled at each height until
  /// c_min's estimate is below 0.9 rtol·c_min, within budget_seconds; otherwise `rows`, `intervals` as given (the
  /// bench; the study with paths.rows). rtol > 0 judges every height either way (StripCminRow::rtol_met); 0: not judged.
  double rtol = 0.0;
  bool choose_meshes = false;
  int first_rows = 8;
  int max_rows = 64, max_intervals = 2400;     ///< the largest meshes of the choice (and strip_max_iteration_seconds)
  /// CPU seconds of the reference machine (continuum::strip_solve_cost) the whole path may be predicted at: a
  /// refinement predicted above it is not made and its height is NOT met (budget).
  double budget_seconds = 600.0;
  std::function<bool()> stop;                       ///< polled before every solve (empty: never)
  std::function<void(const std::string&)> log;      ///< progress lines, without the newline (empty: none)
};

/// The study's defaults (a [paths] without `rows`, or none): the meshes chosen by rtol = 1e-3 from 8 rows.
StripCminHeightOptions strip_cmin_study_defaults();

/// The column stiffness per unit height, the 1D μ/H of the body (μ' antiplane, E' = 2μ'/(1 − ν) in-plane): the paper's
/// lengths ℓ = μ/H, ℓ_κ = ℓκ/(ηα) and speed s = ℓ/η, and the 1D c_min of μ = (μ/H)·H compared with.
double strip_cmin_column_modulus(const StripCminHeightOptions& o);
/// The scene's bulk of o's body and material at height H (μ, ρ integrated over the height, docs/model.md §9.1, §10.2).
core::BulkParams strip_cmin_bulk(const StripCminHeightOptions& o, double H);

/// The target heights: hmin · (hmax/hmin)^(k/n), k = 0..n, n = round(per_decade · log10(hmax/hmin)).
std::vector<double> strip_cmin_heights(const StripCminHeightOptions& o);

/// The options of the limiting path (continue_strip_height) for `o`: its heights, rows, intervals, 12 Newton
/// iterations, tolerance, max_factor.
continuum::StripHeightOptions strip_cmin_path_options(const StripCminHeightOptions& o);

/// One row of the table: one target height the limiting path reached.
struct StripCminRow {
  double H = 0, H_over_l = 0, H_over_l_kappa = 0;
  double c_min = 0, c_min_over_s = 0, c_min_over_cs = 0;
  double c_min_1d = 0, ratio_to_1d = 0;
  /// Estimated errors (docs/fronts.md §10.20): c_min's from the front re-solved on every other row (rows) plus its
  /// ξ part, c_min_1d's the 1D solver's own, ratio_to_1d's both relative errors summed; NaN with `note`.
  double c_min_error = 0, c_min_1d_error = 0, ratio_to_1d_error = 0;
  std::string note;                 ///< why a number of this row is NaN ("" when none is)
  /// With rtol > 0: 1 when c_min_error < rtol·c_min, else 0 with `verdict` (NaN when not judged, rtol = 0).
  double rtol_met = 0;
  std::string verdict;              ///< why not met ("NOT met (budget|limit|no convergence|no estimate): ..."), "" else
  double local_exponent = 0;        ///< d ln c_min/d ln H to the next height (NaN at the last)
  double branch_c_min = 0, branch_sigma_d_at_c_min = 0;  ///< NaN without branches
  int branch_c_min_at_end = 0, branch_points = 0, branch_folds = 0;
  std::string branch_end = "none";
  double branch_seconds = 0;        ///< wall time of the branch (0 without): the table's only timing column
  int rows = 0, intervals = 0;
  double domain_length = 0, tip_zone = 0;
};

/// The limiting path of `o` (log: the material line, the path's summary and one line per step).
continuum::StripHeightPath strip_cmin_limiting_path(const StripCminHeightOptions& o);

/// How the mesh of one target height was chosen (o.choose_meshes): the estimate of the front kept, and why the
/// choice stopped short of rtol ("" when it did not).
struct StripCminMesh {
  continuum::StripSpeedError error;
  std::string limited;              ///< "", "budget", "limit", "no convergence", "no estimate", "stopped"
  std::string how;                  ///< the meshes tried: "rows 8 -> 16, intervals 400 (budget: ...)"
};

/// The limiting path with the meshes chosen per target height (o.choose_meshes, docs/fronts.md §10.20): from
/// o.first_rows rows and o.intervals, the path continued to each height on the meshes of the last, where the front
/// is re-solved with the rows (and, when its ξ part is ≥ 0.1 rtol·c, the intervals) doubled until its estimate is
/// below 0.9 rtol·c. `meshes`: one per front. `predicted_seconds`: the cost model's prediction of the whole.
continuum::StripHeightPath strip_cmin_chosen_path(const StripCminHeightOptions& o, std::vector<StripCminMesh>& meshes,
                                                  double& predicted_seconds);

/// The table's rows from a limiting path of `o` (with o.branches, each target H's branch; log: one line each).
/// With `meshes` (strip_cmin_chosen_path's) their estimates are used instead of estimating each front again.
std::vector<StripCminRow> strip_cmin_rows(const StripCminHeightOptions& o, const continuum::StripHeightPath& path,
                                          const std::vector<StripCminMesh>* meshes = nullptr);

struct StripCminHeight {
  continuum::StripHeightPath path;
  std::vector<StripCminRow> rows;
  std::vector<StripCminMesh> meshes;  ///< with o.choose_meshes: one per front
  double predicted_seconds = 0.0;     ///< with o.choose_meshes: the cost model's CPU seconds of the path (NaN without)
};

/// Both: the limiting path (its meshes chosen when o.choose_meshes), then the rows.
StripCminHeight strip_cmin_height(const StripCminHeightOptions& o);

/// The table as CSV text (header line, one line per row; the columns of docs/fronts.md §10.12).
std::string strip_cmin_csv(const std::vector<StripCminRow>& rows);

// ---------------------------------------------------------------------------------------------------
// The study kind "strip_cmin_height" (docs/studies.md): no scene runs; the law and the strip material of the
// study's base scene, the path's settings in the study file's [paths].

/// The domains of the [paths] keys ("paths.hmin", ...), as core::KeyDomain rows: rows and intervals bounded as
/// `slipfront fronts --rows/--intervals`.
std::span<const core::KeyDomain> strip_cmin_path_domains();

/// The rules between [paths] keys (each key's own domain checked already): hmax > hmin, and between 2 and
/// strip_cmin_max_heights target heights. Throws core::ParamError naming the key.
inline constexpr int strip_cmin_max_heights = 1000;
void check_strip_cmin_paths(const StripCminHeightOptions& o);

/// The study's [paths] with the base scene's law, body and strip material: μ' = bulk.mu/bulk.height, ρ' =
/// bulk.rho/bulk.height (docs/model.md §9.1); on an in-plane scene μ' = bulk.mu (1 − ν)/(2 bulk.height) with ν, p
/// (§10.2). Throws core::ParamError (key "scene") unless the scene is a strip of either body.
StripCminHeightOptions strip_cmin_study_options(const StudySpec& spec, const Scene& base);
/// The same, as the kind's check before any work (studies::StudyCheck).
void check_strip_cmin_study(const StudySpec& spec, const Scene& base);

/// The kind's computation (studies::StudyComputation): the table `strip_cmin_height` (the CSV's numeric columns),
/// scalars (the material, ℓ, ℓ_κ, s, c_s, heights targeted and reached), notes, and the file
/// strip_cmin_height.csv. Interrupted when work.stop ends it, failed when the path stops short otherwise.
StudyOutcome strip_cmin_height_study(StudyReport& rep, const StudySpec& spec, const Scene& base, const StudyWork& work);

}  // namespace slipfront::studies
