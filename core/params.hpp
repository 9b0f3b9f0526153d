#pragma once
// Plain parameter structs of the continuum model (docs/model.md §1, §4).
// Each has validate(): it throws ParamError naming the config key and the reason.
// Filling them from TOML is the job of apps/config; nothing here knows about files.
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace slipfront::core {

/// A number as people write it (%g: 1e-07, 0.5, 300) with `digits` significant digits: 10 in error
/// messages (enough to tell values apart), fewer in summaries.
std::string format_number(double x, int digits = 10);

/// A parameter value that is out of range. `key` is the dotted config key ("bulk.rho").
struct ParamError : std::runtime_error {
  std::string key;
  std::string reason;
  ParamError(std::string k, std::string r)
      : std::runtime_error(k + ": " + r), key(std::move(k)), reason(std::move(r)) {}
};

// ---------------------------------------------------------------------------------------------
// Key domains: the accepted values of every configuration key, one row per key. This table (with
// discrete::key_domains() and compare::limit_key_domains()) is the single source of truth: the
// validate() functions check values against it, docs/cli.md mirrors it, and the hostile-input test
// (tests/test_hostile.cpp) iterates it and fails for a schema key without a row. Rules between keys
// (L ≥ dx, switch times increasing, the width of each threshold law, ...) stay in validate().

enum class KeyKind {
  number,       ///< a finite double in [lo, hi] (open ends where lo_open / hi_open)
  integer,      ///< a whole number in [lo, hi]
  boolean,      ///< true or false
  choice,       ///< one of `choices` ("a|b|c")
  text,         ///< any string (rules, if any, in validate())
  number_list,  ///< an array of numbers, each in [lo, hi]
  text_list,    ///< an array of strings, each one of `choices`
};

struct KeyDomain {
  const char* key;             ///< dotted key: "bulk.rho" (top-level keys: "models")
  KeyKind kind;
  double lo = 0.0, hi = 0.0;   ///< numbers, integers, list elements
  bool lo_open = false, hi_open = false;
  bool zero_ok = false;        ///< 0 is accepted too, outside [lo, hi] (a switch: "0: none")
  const char* choices = "";    ///< choice, text_list: "a|b|c"
  const char* why = "";        ///< the basis of the bounds, appended to messages: "(0: use time.cfl)"
  bool contains(double x) const;                 ///< x in the domain (numbers, integers, list elements)
  std::string describe() const;                  ///< "in (0, 1]", ">= 0", "0 or in [1e-12, 1e+12]", "one of a, b"
};

/// Upper bound of the physical parameters of the dimensionless model (the paper's are O(1)–O(10^2)):
/// products of a few of them stay far from overflow, and larger values are outside its scaling.
inline constexpr double parameter_cap = 1e12;

/// The continuum and scene keys (everything but [discrete] and [limits]).
std::span<const KeyDomain> key_domains();
/// The row of `key` in `table` (nullptr if absent).
const KeyDomain* find_key_domain(std::span<const KeyDomain> table, std::string_view key);
/// Throws ParamError(d.key, "must be ..., got <value>") unless d.contains(value).
void check_in_domain(const KeyDomain& d, double value);
/// The same for a key of key_domains().
void check_in_domain(const char* key, double value);

/// Interface law parameters: docs/model.md §1 friction law.
struct InterfaceParams {
  double alpha = 1.05;  ///< interfacial stiffness (≥ 1 for a self-consistent sliding branch)
  double kappa = 8.0;   ///< area-decay factor
  double eta = 0.1;     ///< viscous strengthening
  /// Contact aging (docs/model.md §11): a contact of age a has area 1 + aging_b ln(1 + a/aging_tau).
  /// aging_b = 0 (the default) is the paper's law and today's ensemble bit for bit.
  double aging_b = 0.0;
  double aging_tau = 1.0;
  bool ages_contacts() const { return aging_b != 0.0; }
  /// Area of a contact of age a (docs/model.md §11): 1 + b ln(1 + a/τ_a).
  double aged_area(double age) const { return 1.0 + aging_b * std::log1p(age / aging_tau); }
  /// Normal load (docs/model.md §12): a prescribed profile p(x)/p_0, the table (load_x, load_p) interpolated
  /// linearly and constant beyond its ends; the resting area of a site follows it as (p/p_0)^load_exponent, through
  /// re-attachment (load_channel = "reattachment": the A equation relaxes towards it at unit rate) or at once
  /// ("instantaneous": the existing contacts' areas scale with it). No table (the default) is today's model.
  std::vector<double> load_x = {}, load_p = {};
  double load_exponent = 1.0;
  std::string load_channel = "reattachment";
  /// The in-plane strip's own normal load (docs/model.md §12.5): "sigma_yy" feeds p(x, t)/p_0 = −σ_yy(x, 0, t)/p_0
  /// (p_0 = bulk.normal_load) to the law's normal-load hook every step; "none" (the default) is today's model.
  std::string load_coupling = "none";
  /// The regularisation of the coupled instantaneous channel (docs/model.md §12.7, Prakash–Clifton): the law sees
  /// p_eff, ṗ_eff = −((|v| + v*)/L)(p_eff − p), L = load_relaxation_length, v* = load_relaxation_speed; L = 0 (the
  /// default): off, p_eff = p (today's channel bit for bit).
  double load_relaxation_length = 0.0;
  double load_relaxation_speed = 0.0;
  bool relaxes_load() const { return load_relaxation_length != 0.0; }
  bool has_load_profile() const { return !load_p.empty(); }
  bool couples_load() const { return load_coupling == "sigma_yy"; }
  /// A normal load of either kind: the profile or the coupling (load_exponent and load_channel are used).
  bool has_normal_load() const { return has_load_profile() || couples_load(); }
  bool instantaneous_load() const { return load_channel == "instantaneous"; }
  /// p(x)/p_0 from the table (linear interpolation; constant beyond its ends); 1 without a table.
  double load_at(double x) const;
  /// The resting area (p(x)/p_0)^m of docs/model.md §12.1 (exactly 1 without a table or at m = 0).
  double resting_area_at(double x) const;
  void validate() const;
};

/// The elastic body a bulk scene runs (docs/model.md §1.2, §9): decided once, by BulkParams::body(), and
/// mapped to its class once, by core::with_body (core/bodies.hpp). Everything that differs between bodies
/// (sites, rows, the stable step, the initial lift, the snapshot fields) is the body class's, not a test of
/// bulk.height. (0D scenes: the spring block is the chain's one-node case; an imposed rate has no body.)
enum class BodyKind {
  chain,    ///< the 1D chain, core::Bulk (bulk.height absent)
  strip,    ///< the antiplane strip of height H, core::Strip (bulk.height given; bulk.body absent or "antiplane")
  inplane,  ///< the in-plane (plane-strain) strip of height H, core::InPlane (bulk.body = "inplane", docs/model.md §10)
};

/// Elastic bulk: ρ u_tt = μ u_xx + f − σ̄ − η u_t on [0, L].
struct BulkParams {
  BulkParams() = default;
  /// The chain's parameters and a height (0: the chain; > 0: the antiplane strip), the in-plane keys at their
  /// defaults (a constructor, so that {ρ, μ, L, H} leaves the later members to their defaults without a warning).
  BulkParams(double rho_, double mu_, double length_, double height_ = 0.0)
      : rho(rho_), mu(mu_), length(length_), height(height_) {}
  double rho = 0.01;     ///< inertia
  double mu = 300.0;     ///< shear stiffness (unused in 0D scenes)
  double length = 300.0; ///< L (unused in 0D scenes)
  double height = 0.0;   ///< H of the strip (docs/model.md §9, §10); 0: the 1D chain (key absent)
  /// bulk.body: "antiplane" (§9) or "inplane" (§10) with a height; "" (key absent): antiplane.
  std::string body_name;
  double poisson = 1.0 / 3.0;  ///< ν of the in-plane strip (bulk.poisson, docs/model.md §10.1)
  double normal_load = 0.0;    ///< p ≥ 0 on the in-plane strip's top face, σ_yy(x, H) = −p (bulk.normal_load)
  /// The body these parameters give: the one place bulk.height and bulk.body decide it.
  BodyKind body() const {
    return height == 0.0 ? BodyKind::chain : body_name == "inplane" ? BodyKind::inplane : BodyKind::strip;
  }
  void validate(bool one_dimensional) const;
};

enum class Loading {
  edge,          ///< 1D, spring K pulled at v_d attached at x = 0 (paper Fig. 1)
  homogeneous,   ///< 1D, uniform σ_d, nucleation patch at x = 0
  imposed_rate,  ///< 0D, imposed slip rate v(t) (piecewise constant), or a sweep over v
  spring_block,  ///< 0D, block of mass ρ pulled through a spring K at v_d
};
const char* to_string(Loading l);
Loading loading_from_string(const std::string& s);  // throws ParamError("drive.loading", ...)
bool is_one_dimensional(Loading l);

/// The time integrator of a bulk scene (config key time.integrator), chosen in one place:
/// compare::with_integrator (compare/dispatch.hpp) maps it to the stepper class.
enum class Integrator {
  central_difference,    ///< "explicit": the reference central-difference scheme, steps of cfl × the stability limit
  implicit_trapezoidal,  ///< "implicit": fixed step time.dt chosen by accuracy, both models (core/implicit.hpp)
  adaptive_rosenbrock,   ///< "adaptive": L-stable Rosenbrock with error control (core/adaptive.hpp)
};
const char* to_string(Integrator i);
Integrator integrator_from_string(const std::string& s);  // throws ParamError("time.integrator", ...)

/// Drive. Which fields matter depends on `loading`.
struct DriveParams {
  Loading loading = Loading::edge;
  double K = 2.5;                    ///< edge / spring_block: spring stiffness
  double v_d = 0.3;                  ///< edge / spring_block: driver velocity
  double sigma_d = 0.5;              ///< homogeneous: applied stress
  double nucleation_length = 150.0;  ///< homogeneous, start = nucleation: patch 0 ≤ x < ℓ_n put in steady sliding
  /// homogeneous: how a front is started (docs/model.md §6): "nucleation" (the patch above) or
  /// "steady_front" (the solved traveling wave at σ_d, its tip at front_x, the rear edge x = 0 carrying
  /// the front's far-field traction μ v_b / c so that the interface behind slides steadily to it).
  std::string start = "nucleation";
  double front_x = 200.0;            ///< start = steady_front: tip position at t = 0
  /// start = steady_front: a slip-rate kick kick_dv added at t = 0 over the kick_length behind the tip
  /// (the stability test of the branch, docs/model.md §6); 0: none.
  double kick_dv = 0.0;
  double kick_length = 20.0;
  /// Force on node 0 besides the drive spring: the rear traction of a steady-front start (set by the
  /// runner from the solved front; not a configuration key).
  double rear_traction = 0.0;
  /// imposed_rate: slip rates v_k applied from times v_times_k (v_times[0] == 0); one value = constant.
  std::vector<double> v{1.0};
  std::vector<double> v_times{0.0};
  /// imposed_rate sweep (friction law): if sweep_points > 0, run one 0D site per v on a log grid.
  double v_min = 1e-3, v_max = 1e2;
  int sweep_points = 0;
  void validate() const;
};

struct GridParams {
  double dx = 0.5;
  double dy = 0.0;  ///< the strip's row spacing (docs/model.md §9); 0: dx (key absent)
  double row_spacing() const { return dy > 0.0 ? dy : dx; }  ///< the strip's dy
  void validate(const BulkParams& bulk, bool one_dimensional) const;
};

struct TimeParams {
  double t_end = 100.0;
  double dt = 0.0;   ///< fixed step if > 0
  double cfl = 0.5;  ///< otherwise dt = cfl · explicit stability limit (1D, spring block)
  /// imposed_rate: each sweep point runs t_end + slip_end/|v| with `steps` steps (exact updates).
  double slip_end = 50.0;
  int steps = 4000;
  /// Bulk scenes: see Integrator (adaptive: the continuum law on the Rosenbrock integrator, the discrete
  /// and mean-field laws on the step-controlled implicit one, core/leap.hpp).
  Integrator integrator = Integrator::central_difference;
  double rtol = 1e-2;    ///< adaptive: relative tolerance of the local error per step
  double atol = 1e-5;    ///< adaptive: absolute tolerance
  double dt_max = 1.0;   ///< adaptive: largest step
  /// adaptive, the discrete and mean-field laws (core/leap.hpp, docs/numerics.md §9): the leap condition's
  /// bound on the change of a site's relaxation rate 1 + κ|v| over one step, relative to the rate.
  double leap_epsilon = 0.2;
  /// adaptive, the continuum law (core/adaptive.hpp, docs/numerics.md §8.7): 0 ends a step at every switching
  /// (exact); f in (0, 1] groups the switchings of a step whose late flips leave a local error within f of the
  /// step's tolerance. 1 by default (issue 22): at matched error fig1 takes 0.7x the time (bench_work_precision).
  double group_switchings = 1.0;
  /// implicit: error control around switchings (core/implicit.hpp, docs/numerics.md §7): a step
  /// whose linearisation defect exceeds implicit_tolerance (stress units) is halved, at most
  /// implicit_max_halvings times; 0 turns it off.
  double implicit_tolerance = 1e-3;
  int implicit_max_halvings = 10;
  /// implicit: refuse a step that does not resolve the drive spring or the contact turnover
  /// (core::implicit_resolution); false runs it anyway, at the user's risk.
  bool implicit_resolution_check = true;
  /// edge loading: end the run at the arrest of the transient front (t_arrest of docs/model.md §3) of every
  /// model instead of at t_end, for studies that need the events up to it (docs/cli.md, `time.stop_at_arrest`).
  bool stop_at_arrest = false;
  void validate(Loading l) const;
};

/// Measurement definitions, docs/model.md §3.
struct MeasureParams {
  double A_tip = 0.5;          ///< front tip: largest x with A < A_tip
  double A_tip_alt = 0.9;      ///< reported too
  double v_event = 0.5;        ///< instability time: first max v > v_event
  double sample_dt = 0.01;     ///< cadence at which the tip is tracked
  double average_from = 0.5;   ///< friction law: average σ over the last (1 − average_from) of the run
  int batches = 20;            ///< friction law: batch means for the standard error
  double arrest_fraction = 0.2;  ///< arrest / end of a slip event: max v falls below arrest_fraction · v_event
  /// Homogeneous loading: v_behind is measured when the tip first passes behind_tip_fraction · L, as the
  /// mean slip rate over the nodes in [x_tip − behind_far, x_tip − behind_near] (docs/model.md §3).
  double behind_tip_fraction = 0.75;
  double behind_near = 100.0;
  double behind_far = 150.0;
  /// Homogeneous loading, the settled front speed (docs/model.md §3): windows of settle_window length units of
  /// travel, a relative band of settle_band, the last settle_end_zone length units before the far end left out.
  double settle_window = 150.0;
  double settle_band = 2e-3;
  double settle_end_zone = 50.0;
  /// Contact statistics by region (docs/model.md §7.2): half-width of the tip band around the
  /// A_tip_alt front (length units).
  double tip_band = 5.0;
  void validate() const;
};

/// What the scene asks to store (docs/model.md §5: nothing nobody asked for).
struct OutputParams {
  double series_dt = 0.05;    ///< cadence of /series (0: every step)
  double snapshot_dt = 1.0;   ///< cadence of /snapshots (0: none)
  bool energy = false;        ///< store the energy budget series
  bool ages = false;          ///< carry and store the mean contact age ā (docs/model.md §7): snapshots/age, 0D series/age
  bool sequence = false;      ///< edge loading: store the sequence of slip events (/<model>/sequence, docs/model.md §3.2)
  double compare_dt = 1.0;    ///< cadence of the online field comparison of alongside runs (0: none)
  /// Cadence of the contact snapshots (ages and thresholds of the attached contacts, agent with
  /// discrete.contact_statistics; the continuum's predicted ages): < 0 means snapshot_dt, 0 none.
  double contact_snapshot_dt = -1.0;
  /// gzip level of the field datasets (snapshots, the strip's bulk, the fronts' bulk profiles), with the
  /// byte shuffle, in chunks of whole rows; 0: none, contiguous (the default, docs/output.md "Layout of
  /// the fields": compression cost more than the run and saved 40%).
  int deflate = 0;
  /// The contact-snapshot cadence in effect (−1: none).
  double contact_every() const {
    const double c = contact_snapshot_dt < 0 ? snapshot_dt : contact_snapshot_dt;
    return c > 0 ? c : -1.0;
  }
  void validate() const;
};

}  // namespace slipfront::core
