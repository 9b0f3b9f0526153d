#pragma once
// What a scene will cost, estimated from the whole configuration before any work (issue 10): time
// steps, peak memory and run time per model, and the checks of the estimate against [limits] and of
// the grid against the fronts' process zone. Scene::validate() runs both, so every accepted run is
// within its limits; `slipfront check` prints the estimate. Basis and measured accuracy:
// docs/robustness.md §3–§4.
#include <string>
#include <utility>
#include <vector>

#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "compare/study_plan.hpp"

namespace slipfront::compare {

struct ModelEstimate {
  std::string model;        ///< continuum | discrete
  std::string integrator;   ///< explicit | implicit | adaptive | leap | exact (imposed slip rate: the law alone)
  double dt = 0.0;          ///< fixed step (0: adaptive, or a sweep with one step per point)
  double steps = 0.0;       ///< time steps (a sweep: all points together)
  double work_steps = 0.0;  ///< the steps the cost is counted on: `steps`, or the implicit integrator's solves with
                            ///< its error control's halvings (time.implicit_tolerance; an estimate)
  std::string steps_basis;  ///< how `steps` was obtained
  double site_steps = 0.0;  ///< work_steps × sites
  double node_steps = 0.0;  ///< the strip: work_steps × bulk nodes (its bulk's cost; 0 on the chain)
  double ns_per_site_step = 0.0;  ///< the calibrated cost used
  double seconds = 0.0;     ///< run time
  double state_bytes = 0.0; ///< integrator and interface-law state
  double record_bytes = 0.0;///< series, snapshots, tip samples, contact statistics: kept until the end
};

struct Estimate {
  double sites = 1.0;                ///< interface sites of the grid (0D: 1)
  double rows = 1.0;                 ///< rows of the body: the strip's height / grid.dy + 1 (chain, 0D: 1)
  double bulk_nodes = 1.0;           ///< sites × rows × components: the body's degrees of freedom
  std::vector<ModelEstimate> models; ///< in the order of Scene::models
  double steps = 0.0;                ///< largest over the models
  double memory_bytes = 0.0;         ///< peak resident memory, writing the results included
  double output_bytes = 0.0;         ///< data written to results.h5 (before compression)
  double seconds = 0.0;              ///< run time of every model (setup and writing excluded)
  /// What the peak consists of, largest first ("snapshots (continuum)", bytes).
  std::vector<std::pair<std::string, double>> memory_items;
  /// A steady-front start on the strip (drive.start = "steady_front"; compare::front_start_cost): the front is
  /// solved by every model's run before its first step. Included in `seconds` and in `memory_bytes`.
  double start_seconds = 0.0;
  double start_bytes = 0.0;               ///< the solver's memory while it runs (0: no such start)
  std::string start_basis;                ///< how it was estimated ("" when there is none)
  double elastic_length = 0.0;            ///< 1D: sqrt(μ/α)
  double nodes_per_elastic_length = 0.0;  ///< 1D: sqrt(μ/α)/dx
  std::vector<std::string> notes;         ///< warnings that do not refuse the run
};

/// The estimate of a scene whose parameters are each valid (Scene::validate() calls it after the
/// domain checks). Never allocates anything of the scene's size.
Estimate estimate(const Scene& s);

/// Throws core::ParamError when the estimate exceeds a limit (key "limits.<key>", the reason
/// naming the estimate and what drives it) or the grid does not resolve the elastic length
/// (key "grid.dx", naming limits.min_nodes_per_elastic_length).
void check_limits(const Scene& s, const Estimate& e);

/// The estimate as lines of text ("steps: ...", "memory: ...", "run time: ...", notes), for
/// `slipfront check` (as TOML comments) and `slipfront run`.
std::vector<std::string> describe(const Estimate& e);

/// What `slipfront run --checkpoint-every T` adds to a bulk scene's cost (docs/cli.md, "Checkpoints"):
/// checkpoints are due at the first step at or after each multiple of T, once per run loop (models in
/// lockstep share one loop, models run one after the other have one each) and at most once a step;
/// each holds every model's state and the records so far, so the last is the largest and on average a
/// checkpoint holds the state and half the records. Writing one costs a fixed part (create, sync,
/// rename) and a part per byte (archive, checksum, write); while it is written the run holds two
/// copies of it (the archive and the file's bytes).
struct CheckpointEstimate {
  double every = 0.0;          ///< T
  double writes = 0.0;         ///< checkpoints written
  double largest_bytes = 0.0;  ///< the last one
  double bytes = 0.0;          ///< all of them together
  double seconds = 0.0;        ///< writing them
  double memory_bytes = 0.0;   ///< peak memory of the run with a checkpoint being written
};

/// The checkpoints of `s` at cadence `every` > 0, given the scene's estimate `e`.
CheckpointEstimate estimate_checkpoints(const Scene& s, const Estimate& e, double every);

/// Throws core::ParamError (key "--checkpoint-every", the reason naming the limit to raise) when the
/// checkpoints exceed limits.max_checkpoint_gib, or with them the run exceeds limits.max_hours or
/// limits.max_memory_gib.
void check_checkpoint_limits(const Scene& s, const Estimate& e, const CheckpointEstimate& c);

/// "checkpoints: N of up to X, Y in all, ~Z".
std::string describe(const CheckpointEstimate& c);

/// The explicit scheme's stability limit of the scene's body, 2/ω_max with the Gershgorin bound of its
/// stable_dt() (core::RunBody::stable_time_step: core/bulk.hpp, core/strip.hpp), computed without building the grid.
double explicit_stable_dt(const Scene& s);

/// Calibrated costs in nanoseconds on the reference machine (docs/robustness.md §3). "Active" site-steps
/// are those of sites away from the stuck state (contacts detached or overloaded): a fraction of the
/// site-steps that depends on the loading (active_fraction()).
struct StepCosts {
  double explicit_bulk;   ///< per site-step: bulk + continuum law, explicit central differences
  double implicit_bulk;   ///< per site-step: bulk + continuum law, implicit trapezoidal
  double adaptive_bulk;   ///< per site-step: bulk + continuum law, one adaptive Rosenbrock step
  double leap_bulk;       ///< per site-step: the leap integrator's implicit trial solves and tests (law apart)
  double count_idle;      ///< count representation, per site-step of a stuck site (noise on)
  double count_active;    ///< count representation, per active site-step (binomial draws; noise on)
  double count_bin;       ///< count representation, per threshold bin of an active site-step (noise on, w > 0)
  double count_mean;      ///< count representation with noise off, per site-step (every site, every step)
  double count_mean_bin;  ///< the same, per threshold bin
  double agent_site;      ///< agent representation, per site-step
  double agent_event;     ///< agent representation, per contact state change
  double naive_contact;   ///< naive agent loop, per contact of a site-step
  double aging_closure;   ///< contact aging (docs/model.md §11.4): the continuum closure's extra per site-step
  double aging_cohort;    ///< contact aging (§11.3): the age-structured mean field, per age cohort of a site-step
  double aging_contact;   ///< contact aging (§11.2): the agent's area sum, per contact of a site-step
  double law_step;        ///< imposed slip rate: one exact step of the continuum law with its measurements
  double step;            ///< bulk scenes: per step, whatever the grid (measurements, records, lockstep)
  double strip_explicit;  ///< the strip (docs/model.md §9): per node-step of its bulk, explicit kick and drift
  double strip_implicit;  ///< the strip: per node-step of its bulk, the implicit step's preconditioned CG solve
  double strip_adaptive;  ///< the strip: per node-step of its bulk, the adaptive step (rhs, four direct solves)
  double strip_leap;      ///< the strip: per node-step of its bulk, the leap step's trial solves (CG at large steps)
  double inplane_explicit;  ///< the in-plane strip (docs/model.md §10): per dof-step (two per node), explicit Q1 kick
  double inplane_implicit;  ///< the in-plane strip: per dof-step, the implicit step's preconditioned CG solve
  double inplane_adaptive;  ///< the in-plane strip: per dof-step, the adaptive step (rhs, three direct stage solves,
                            ///< the capacitance factors of each new step size, docs/numerics.md §8.9)
  double checkpoint;      ///< one checkpoint: create, sync and rename the file
  double checkpoint_byte; ///< per byte of a checkpoint: archive the state, checksum and write it
};
const StepCosts& step_costs();

/// What a study costs in its own process (issue 18), from the study file and one sample run per group
/// (compare::sample_runs), before any run is expanded or any directory created: its runs, their
/// directories, and the memory of the plan (per run: its overrides, scene, resolved TOML, bookkeeping)
/// and of the results kept in memory for the analysis (per run: series, tables and x, not the fields).
/// Each run's own cost is the scene estimate above, checked against the scene's [limits].
struct StudyEstimate {
  double runs = 0.0;           ///< points x seeds (compare::count_runs)
  double directories = 0.0;    ///< runs/<id>/ for every run, plus runs/ and the study directory
  double plan_bytes = 0.0;     ///< the plan
  double results_bytes = 0.0;  ///< the results kept for the analysis
  double memory_bytes = 0.0;   ///< the program, the plan and the results
};

/// The estimate of a study. `samples` are compare::sample_runs(spec) with their scenes and the
/// lengths of their resolved TOML (every sample stands for the runs of its group).
StudyEstimate estimate_study(const StudySpec& spec, const std::vector<StudyRun>& samples,
                             const std::vector<Scene>& sample_scenes, const std::vector<std::size_t>& resolved_bytes);

/// Throws core::ParamError("limits.max_runs" or "limits.max_memory_gib", reason naming the estimate and
/// what drives it) when the study's estimate exceeds the study's [limits].
void check_study_limits(const StudySpec& spec, const StudyEstimate& e);

/// The study's memory estimate in a few words ("~33 MiB in memory: plan 1.2 MiB, results kept 0.5 MiB"),
/// for the start line of `slipfront study`.
std::string describe(const StudyEstimate& e);

/// The fraction of site-steps that are active (see StepCosts), by loading: edge 0.1 (the fronts creep
/// from the loaded edge; fitted on fig1), homogeneous 0.6 (the front sweeps the system; fitted on
/// homogeneous_front), one site (spring block, imposed slip rate) 1.
double active_fraction(core::Loading loading);



}  // namespace slipfront::compare
