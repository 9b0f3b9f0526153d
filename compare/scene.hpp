#pragma once
// A scene: everything one run needs, as plain structs (docs/model.md §4, §5). Filled from TOML by apps/.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/params.hpp"
#include "discrete/params.hpp"

namespace slipfront::compare {

/// What a run may cost, config section [limits] (docs/cli.md; the estimate: compare/estimate.hpp,
/// docs/robustness.md). A scene whose estimate exceeds a limit is refused before any work, with
/// the key to raise named in the message.
struct LimitParams {
  double max_steps = 1e10;      ///< time steps of any model (sweeps: all points together)
  double max_memory_gib = 16.0; ///< peak memory of the run, writing the results included
  double max_hours = 24.0;      ///< run time
  /// Bulk scenes run with `--checkpoint-every T`: the data every checkpoint of the run writes together
  /// (compare::estimate_checkpoints: writes x size), in GiB.
  double max_checkpoint_gib = 100.0;
  /// 1D scenes: nodes per elastic length sqrt(μ/α) (the process zone of the fronts); below it the
  /// event times and front speeds are wrong by more than ~3% (docs/robustness.md §4). 0: no check (and, on
  /// the strip, no row rule either: strip_max_row_spacing).
  double min_nodes_per_elastic_length = 2.0;
  void validate() const;
};

/// The domains of the [limits] keys (core::KeyDomain).
std::span<const core::KeyDomain> limit_key_domains();

/// Snapshots of the strip's body (docs/model.md §9, docs/output.md `/<model>/bulk/`): the displacement u and
/// the two shear stresses on a decimated grid, keys output.bulk_dt and output.bulk_stride. Used on the strip
/// only (bulk.height); a chain's configuration that gives them is noted and they are ignored.
struct BulkOutputParams {
  double dt = 0.0;  ///< cadence (0: none, the default)
  int stride = 4;   ///< keep every stride-th node in x and in y, and always the last column and the top row
  void validate() const;
};

/// The domains of output.bulk_dt and output.bulk_stride (core::KeyDomain).
std::span<const core::KeyDomain> bulk_output_key_domains();

/// The indices 0, stride, 2 stride, ... below n, and n − 1 (the last node is always kept); n ≥ 1,
/// stride ≥ 1. The decimation of the bulk snapshots in x (n = sites) and y (n = rows: row 0 is the
/// interface, row n − 1 the top).
std::vector<std::size_t> kept_indices(std::size_t n, std::size_t stride);

/// Every key domain of the schema: core::key_domains(), discrete::key_domains(),
/// bulk_output_key_domains(), limit_key_domains(), in that order.
std::vector<core::KeyDomain> all_key_domains();
/// The row of a dotted key in all_key_domains() (nullptr if none).
const core::KeyDomain* find_key_domain(std::string_view key);

struct Scene {
  std::string name;         ///< scene name (default output directory out/<name>)
  std::string description;
  std::vector<std::string> models{"continuum"};  ///< which models to run
  core::InterfaceParams interface;
  core::BulkParams bulk;
  core::DriveParams drive;
  core::GridParams grid;
  core::TimeParams time;
  core::MeasureParams measure;
  core::OutputParams output;
  BulkOutputParams bulk_output;  ///< output.bulk_dt, output.bulk_stride (the strip)
  discrete::DiscreteParams discrete;
  LimitParams limits;
  /// Whether `model` ("continuum", "discrete") is one of the models to run.
  bool lists(std::string_view model) const;
  /// Validate everything (throws core::ParamError naming the key): every value in its domain,
  /// the rules between keys, then the cost estimate against the limits and the grid's resolution
  /// (compare::estimate, compare::check_limits).
  void validate() const;
};

/// The strip's "too few rows" rule (docs/numerics.md §8.2): the largest row spacing dy that keeps fig1's
/// events (t*, t^, c_slow, c_transient, x_arrest) within ~1% of the converged strip's. Measured: the worst
/// event's error is ≈ 0.3 (dy/ℓ_e)² (H/ℓ_e), ℓ_e = sqrt(μ/α), for 0.3 ≤ H/ℓ_e ≤ 4; the rule keeps that
/// product ≤ 1/30:  dy ≤ ℓ_e sqrt(ℓ_e / (30 H)) = sqrt(ℓ_e ℓ_R / 30), ℓ_R = μ/(αH) = μ'/α the length of the
/// interface's Robin condition. One row interval (dy = H) passes for H ≤ ℓ_e / 30^{1/3} = 0.32 ℓ_e.
inline constexpr double strip_row_rule_bound = 1.0 / 30.0;
double strip_max_row_spacing(double mu, double alpha, double height);

/// Slip-rate grid of an imposed-rate sweep (log spaced, docs/model.md §4 friction_law).
std::vector<double> sweep_rates(const core::DriveParams& d);

/// Whether the scene's two models run in lockstep in one process (compare/alongside.hpp): both listed,
/// on a bulk scene, with a common fixed step (not the adaptive integrator). Then their states are held
/// at once (the estimate) and their fields compared as they go.
bool runs_in_lockstep(const Scene& s);

/// The discrete model's reference (docs/model.md §2.2): mean_field, the ensemble's own N → ∞ limit at its w, when the
/// scene lists it, else the continuum. Its fields are compared with the discrete model's, its contact statistics
/// predicted (compare/alongside.hpp).
const char* discrete_reference(const Scene& s);

}  // namespace slipfront::compare
