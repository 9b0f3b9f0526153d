#pragma once
// Adaptive, linearly implicit time stepping of bulk + a deterministic interface law given by its rates
// (SmoothLaw, core/law.hpp: the continuum FrictionLaw, docs/model.md §1), for scenes where long
// quiet stretches (elastic loading, the slow front, healing) alternate with short fast ones (the
// transient front). Same method-of-lines ODE as the fixed-step schemes: the body's elastic operator and loading
// (core/body.hpp: the chain of core/bulk.hpp, the strip of core/strip.hpp) and the law's rates, per site i
//   u' = v                                                 (every dof of the body)
//   ρ v' = F_i/w_i + σ_d − σ̄_i − η v_i                     (the chain; the strip's: docs/numerics.md §8.5)
//   (A', σ̄') = law.rate({v_i, A_i, σ̄_i, a_i}, Θ_i)         (docs/model.md §1.1: A' = a − A − ΘκA|v|, σ̄' = αAv − Θσ̄|v|;
//                                                            a_i the resting area, 1 but under a normal load, §12.1)
// integrated as one stiff system (docs/performance.md):
//   - a 2-stage Rosenbrock method (Shampine–Reichelt "ode23s": order 2, L-stable, embedded order-3
//     error estimate, order-2 dense output) with the exact Jacobian (law.jacobian and the bulk's
//     stiffness). Each W = I − h d J solve eliminates (A, σ̄) site by site and leaves the body's system for u
//     (the chain: symmetric tridiagonal, Thomas, O(nodes); the strip: docs/numerics.md §8.5);
//   - error-controlled step sizes (PI controller), by default a max norm per field (ErrorNorm);
//   - Θ piecewise constant inside every step, switched by event location: the zeros of
//     g_i = law.load = |σ̄_i + η v_i| against A_i (|σ|/A = 1) are located on the dense output of each accepted
//     step (Illinois regula falsi to 1e-13 in time) and the step ends at the first one, where Θ_i flips
//     (with every other site that has crossed by then) — or, by default (group_fraction = 1, time.group_switchings),
//     at a later one when the sites flipped late leave a local error within the step's tolerance (docs/numerics.md
//     §8.7). A hysteresis band (switch_band, relative 1e-9) keeps a site that just flipped from flipping back at once.
// The state is where it belongs: u and v in the body's stage representation (their node values in the stepper core),
// A and σ̄ in the law (law.fields(), advanced in place); the work vectors hold stages [u | v | A | σ̄].
// The explicit scheme stays the reference; this one buys speed at a stated tolerance.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/body.hpp"
#include "core/bulk.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "core/stepper.hpp"
#include "core/strip.hpp"

namespace slipfront::core {

/// How the local error estimate is weighed, component j of field f (u, v, A or σ̄):
///   field: max_j |e_j| / (atol + rtol · max(|y_j|, max over the grid of |y_f|))   (default)
///   local: max_j |e_j| / (atol + rtol · |y_j|)
///   rms:   the same weights as local, root mean square over all unknowns (CVODE's norm)
/// `field` measures each error against the size of its field: a slip-rate error of 1e-4 ahead of
/// the front, where v ≈ 0, counts as much as one behind it (docs/performance.md §2).
enum class ErrorNorm { field, local, rms };

/// How a step that would cross a switching ends there:
///   retake:      the step is recomputed with the shortened size (one more Rosenbrock step)
///   interpolate: the step ends at the switching on its own dense output (order 2, no extra work)
enum class EventEnd { retake, interpolate };

/// Tolerances and limits of the adaptive integrator.
struct AdaptiveOptions {
  double rtol = TimeParams{}.rtol;      ///< relative tolerance of the local error per step (see ErrorNorm)
  double atol = TimeParams{}.atol;      ///< absolute tolerance (same units as the unknowns)
  double dt_max = TimeParams{}.dt_max;  ///< largest step
  double dt_initial = 1e-3;  ///< first trial step (shortened automatically if too large)
  double dt_min = 1e-12;     ///< a step below this is reported as a failure (NumericalError)
  ErrorNorm norm = ErrorNorm::field;
  EventEnd event_end = EventEnd::interpolate;
  /// 0: every step ends at the first switching it would cross (exact). > 0: it ends at the last
  /// switching within event_window (time) of the first, flipping all of them there: each switching
  /// is then late by up to event_window (an O(event_window) error the error estimate does not see).
  double event_window = 0.0;
  /// Switchings grouped under the error control (docs/numerics.md §8.7): a step that would end at its first
  /// switching ends at a later one when every site crossing in between, flipped late by δ_i, leaves a local error
  /// δ_i |Δ rate_i| (the jump of its A' and σ̄' at its switching) within group_fraction of the step's tolerance
  /// (atol + rtol · the field's scale, as in the error norm). 0: every switching ends a step (exact).
  double group_fraction = TimeParams{}.group_switchings;
  /// Hysteresis of the Θ switching: a stuck site starts sliding when |σ|/A crosses 1 + band, a
  /// sliding one sticks when it crosses 1 − band (each step ends there, so the band is all the
  /// delay there is: ~band/(d(|σ|/A)/dt), 1e-8 time units for fig1).
  double switch_band = 1e-9;
  /// The step-controlled integrator of the stochastic laws (core/leap.hpp): the leap condition's bound on
  /// the change of a site's relaxation rate per step, and the linearisation defect a step may leave.
  double leap_epsilon = TimeParams{}.leap_epsilon;
  double defect_tolerance = TimeParams{}.implicit_tolerance;
  void validate() const;     ///< throws ParamError("time.<key>", reason)
  /// The scene's time.rtol, time.atol and time.dt_max; every other option at its default.
  static AdaptiveOptions from(const TimeParams& t) {
    AdaptiveOptions o;
    o.rtol = t.rtol;
    o.atol = t.atol;
    o.dt_max = t.dt_max;
    o.leap_epsilon = t.leap_epsilon;
    o.defect_tolerance = t.implicit_tolerance;
    o.group_fraction = t.group_switchings;
    return o;
  }
};

/// Work counters (for the work-precision study).
struct AdaptiveStats {
  std::int64_t accepted = 0;      ///< accepted steps (== steps())
  std::int64_t rejected = 0;      ///< steps rejected by the error test
  std::int64_t event_steps = 0;   ///< accepted steps shortened to end at a located switching
  std::int64_t switchings = 0;    ///< Θ flips (site × time)
  std::int64_t rhs = 0;           ///< right-hand side evaluations
  std::int64_t solves = 0;        ///< W solves (each: node elimination + one Thomas solve)
  std::int64_t factorizations = 0;
};

/// Which unknown a dense-output call asks for.
enum class Field { slip, slip_rate, contact_area, sigma_bar };


namespace detail {
// Shampine & Reichelt, "The MATLAB ODE suite" (SIAM J. Sci. Comput. 18, 1997), ode23s:
//   W = I − h d J,  d = 1/(2 + √2),  e32 = 6 + √2
//   k1 = W⁻¹ (f(t, y) + h d f_t)
//   k2 = W⁻¹ (f(t + h/2, y + h k1/2) − k1) + k1
//   y' = y + h k2                                   (order 2, L-stable)
//   k3 = W⁻¹ (f(t + h, y') − e32 (k2 − f1) − 2 (k1 − f0) + h d f_t)
//   error ≈ h/6 (k1 − 2 k2 + k3)                    (order 3 estimate of the local error)
//   y(t + θh) ≈ y + h (θ(1 − θ) k1 + θ(θ − 2d) k2)/(1 − 2d)    (dense output, order 2)
inline constexpr double kGamma = 0.29289321881345247560;          ///< d = 1/(2 + √2) = 1 − 1/√2
inline constexpr double kE32 = 7.41421356237309504880;            ///< 6 + √2
inline constexpr double kDenseScale = 1.0 / (1.0 - 2.0 * kGamma);  ///< 1/(1 − 2d)
// PI step-size controller (Gustafsson), local error ∝ h³.
inline constexpr double kSafety = 0.9, kBeta1 = 0.7 / 3.0, kBeta2 = 0.4 / 3.0, kGrowMax = 5.0, kShrinkMin = 0.2;
}  // namespace detail

// On a body (core::AdaptiveBody, core/body.hpp; docs/numerics.md §8.8): the Rosenbrock logic, the events and the
// dense output are written once here; what differs per body is the body's. The stage vectors are [u | v | A | σ̄]
// with blocks of dofs, dofs, sites, sites: u and v over all the body's dofs in its stage representation (the
// chain's node values; the strip's mixed representation, docs/numerics.md §8.6), whose first sites() entries are
// the interface sites' node values; A and σ̄ on the sites. The law's part is here, per site: its rates, its
// Jacobian and the elimination of each site's A and σ̄ rows in the W solve (x_A = p_A + q_A x_v,
// x_σ = p_σ + q_σ x_v); the body's (stage_accelerations, stage_factor, stage_solve) is v' and the u system left
// for x_u, which it solves with the sites' q_σ and p_σ (the chain: one Thomas sweep; the strip:
// Strip::solve_stage_mixed, docs/numerics.md §8.5).
template <SmoothLaw Law, AdaptiveBody B = Bulk>
class AdaptiveSimulation : public StepperCore<Law, B> {
  using Core = StepperCore<Law, B>;

 public:
  static constexpr const char* integrator_name = "adaptive";
  static constexpr bool error_control = false;  ///< set_error_control, substeps (implicit only)
  static constexpr double kGamma = detail::kGamma;
  static constexpr double kDenseScale = detail::kDenseScale;

  AdaptiveSimulation(B bulk, Law law, AdaptiveOptions opt)
      : Core(std::move(bulk), std::move(law), "AdaptiveSimulation"), opt_(opt), h_next_(opt.dt_initial),
        last_dt_(opt.dt_initial) {
    opt_.validate();
    const std::size_t m = 2 * this->n_ + 2 * this->sites_;
    for (auto* v : {&y_prev_, &ynew_, &f0_, &f1_, &f2_, &k1_, &k2_, &k3_, &k1_prev_, &k2_prev_, &state_}) v->assign(m, 0.0);
    for (auto* v : {&inv_a1_, &q_area_, &inv_s1_, &c_alpha_v_, &q_sigma_}) v->assign(this->sites_, 0.0);
    theta_.assign(this->sites_, 0);
    theta_prev_.assign(this->sites_, 0);
    this->bulk_.set_stage_tolerance(opt_.rtol);
  }

  double dt() const { return last_dt_; }  ///< size of the last accepted step (before any: dt_initial)
  /// Initial slip and slip rate of node i (with law().set_site for A, σ̄), before the first step: Θ is
  /// taken from the state at the first step.
  void set_initial(std::size_t i, double u, double v) {
    Core::set_initial(i, u, v);
    f0_valid_ = false;
    state_made_ = false;
  }
  /// Displacement and velocity of every dof (node values; made from the stage representation when asked).
  std::span<const double> displacement() const {
    sync_nodes();
    return this->u_;
  }
  std::span<const double> velocity() const {
    sync_nodes();
    return this->v_;
  }
  double drive_force() const {
    if (!state_made_) return Core::drive_force();
    return this->bulk_.stage_drive_force(this->t_, state_u());
  }

  // One accepted step, in named stages (docs/performance.md §2):
  //   1. trial    error-controlled Rosenbrock step from t (rejections shrink h), Θ frozen
  //   2. events   earliest crossing of a switching surface on the step's dense output
  //   3. shorten  the step ends at that switching (on the dense output, or recomputed)
  //   4. accept   advance t, keep the dense output, propose the next h (PI, from the trial's error);
  //               the law's optional extras over the step (advance_age: contact ages, docs/model.md §7)
  //   5. switch   flip Θ of every site that has crossed by the new t
  void step() {
    if (!started_) start();
    else if (!state_made_) make_state();
    double h = std::min(quantize(std::min(h_next_, opt_.dt_max)), opt_.dt_max);
    const double h_wanted = h;
    if (t_stop_ > this->t_ && h >= t_stop_ - this->t_) h = t_stop_ - this->t_;
    bool rejected = false;
    const double err = trial_step(h, rejected);       // 1.
    const double h_trial = h, frac = first_switching(h);  // 2.
    double h_dense = h_trial;  // the step of the dense-output polynomial of this step
    bool f_end_valid = true;
    if (frac < 1.0) {  // 3.
      ++stats_.event_steps;
      h *= frac;
      if (opt_.event_end == EventEnd::retake && frac > 0.0) {
        attempt(h);  // recompute the step to end at the switching (its error is smaller still)
        h_dense = h;
      } else {
        end_on_dense_output(frac, h_trial);  // order 2, like the step itself; no extra work
        f_end_valid = false;
      }
    }
    const bool at_stop = accept(h, h_dense, f_end_valid);  // 4.
    advance_law_extras();
    propose_next(at_stop && !rejected ? std::max(h_trial, h_wanted) : h_trial, err, rejected);
    flip_crossed();  // 5.
    if (this->energy_) energy_over_step();
  }

  // --- extras ------------------------------------------------------------------------------------
  /// No step will cross t (a scene's t_end, an output time): the step that would is shortened to
  /// end on it exactly. Inactive once reached.
  void set_stop_time(double t) { t_stop_ = t; }
  double previous_time() const { return t_prev_; }  ///< start of the last accepted step
  /// Dense output (order 2) of one field at t ∈ [previous_time(), time()], as node values.
  /// out: the first out.size() values of the field (the sites; u and v of up to all dofs).
  void dense_state(double t, Field f, std::span<double> out) const {
    if (static_cast<std::size_t>(f) < 2 && out.size() > this->sites_ && state_made_) {  // beyond the sites: the body's
      dense_nodes_.resize(this->n_);
      dense_state_raw(t, f, dense_nodes_);
      this->bulk_.from_stage(dense_nodes_, dense_nodes_);
      std::copy_n(dense_nodes_.begin(), std::min(out.size(), this->n_), out.begin());
      return;
    }
    dense_state_raw(t, f, out);
  }
  /// Dense output of one value (inline: the runner's tip restriction calls it per node).
  double dense_value(double t, Field f, std::size_t i) const {
    if (static_cast<std::size_t>(f) < 2 && i >= this->sites_ && state_made_) {  // beyond the sites: the body's
      // the dense output is linear in the stage representation: the node value of y_prev, k1 and k2, combined
      const B& b = this->bulk_;
      if (stats_.accepted == 0 || h_prev_ <= 0.0) return b.stage_value(current(static_cast<std::size_t>(f)), i);
      const std::size_t q = offset(static_cast<std::size_t>(f));
      const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
      const double b1 = th * (1.0 - th) * kDenseScale * h_prev_, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h_prev_;
      return b.stage_value(y_prev_.data() + q, i) + b1 * b.stage_value(k1_prev_.data() + q, i) +
             b2 * b.stage_value(k2_prev_.data() + q, i);
    }
    return dense_value_raw(t, f, i);
  }

 private:
  // The dense output in the stage representation.
  void dense_state_raw(double t, Field f, std::span<double> out) const {
    const std::size_t n = std::min(out.size(), block_size(static_cast<std::size_t>(f)));
    const std::size_t off = offset(static_cast<std::size_t>(f));
    if (stats_.accepted == 0 || h_prev_ <= 0.0) {
      const double* c = current(static_cast<std::size_t>(f));
      for (std::size_t i = 0; i < n; ++i) out[i] = c[i];
      return;
    }
    const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
    const double b1 = th * (1.0 - th) * kDenseScale * h_prev_, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h_prev_;
    for (std::size_t i = 0; i < n; ++i) out[i] = y_prev_[off + i] + b1 * k1_prev_[off + i] + b2 * k2_prev_[off + i];
  }
  double dense_value_raw(double t, Field f, std::size_t i) const {
    if (stats_.accepted == 0 || h_prev_ <= 0.0) return current(static_cast<std::size_t>(f))[i];
    const std::size_t j = offset(static_cast<std::size_t>(f)) + i;
    const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
    const double b1 = th * (1.0 - th) * kDenseScale * h_prev_, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h_prev_;
    return y_prev_[j] + b1 * k1_prev_[j] + b2 * k2_prev_[j];
  }

 public:
  /// Bound on |target − y_i(t)| over the whole last step, from the dense output's coefficients:
  /// y(θ) = y_prev + h (θ(1 − θ) k1 + θ(θ − 2d) k2)/(1 − 2d), with max |θ(1 − θ)| = 1/4 and
  /// max |θ(θ − 2d)| = 1 − 2d on [0, 1].
  double dense_deviation_bound(Field f, std::size_t i, double target) const {
    if (stats_.accepted == 0 || h_prev_ <= 0.0) return std::abs(target - current(static_cast<std::size_t>(f))[i]);
    const std::size_t j = offset(static_cast<std::size_t>(f)) + i;
    return std::abs(target - y_prev_[j]) + h_prev_ * (0.25 * kDenseScale * std::abs(k1_prev_[j]) + std::abs(k2_prev_[j]));
  }
  const AdaptiveStats& stats() const { return stats_; }
  const AdaptiveOptions& options() const { return opt_; }
  /// The checkpoint: the core's node values and the integrator's state; a body whose stage representation is not
  /// node values adds the stage state (the round trip is not bit for bit), one whose is makes it from the nodes.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag(this->bulk_.stage_archive_tag());
    sync_nodes();  // the node values the core writes are the state's
    this->serialize_core(ar);
    ar(t_prev_, h_next_, last_dt_, err_prev_, started_, f0_valid_, y_prev_, f0_, k1_prev_, k2_prev_, h_prev_, t_stop_,
       theta_, theta_prev_, stats_);
    if constexpr (!B::stage_is_nodes) {
      ar(state_, state_made_);
    } else {
      nodes_to_state();
    }
    nodes_stale_ = false;
    block_scale_valid_ = false;
  }
  /// A_i(t) and v_i(t) on the last step's dense output (area(t, i), slip_rate(t, i)).
  struct DenseSampler {
    const AdaptiveSimulation* sim;
    double area(double t, std::size_t i) const { return sim->dense_value(t, Field::contact_area, i); }
    double slip_rate(double t, std::size_t i) const { return sim->dense_value(t, Field::slip_rate, i); }
  };
  DenseSampler dense_sampler() const { return DenseSampler{this}; }

 private:
  // Optional hook of the law (docs/model.md §7, FrictionLaw::advance_age): quantities the law carries
  // beside its state [A | σ̄] are advanced over the accepted step from its dense output, with Θ as it
  // was during the step (before step 5 flips it). Laws that do not declare the hook
  // (core::LawHooks::dense_ages) compile without a trace of it.
  void advance_law_extras() {
    if constexpr (Law::hooks.dense_ages)
      this->law_.advance_age(t_prev_, this->t_, std::span<const std::uint8_t>(theta_), dense_sampler());
  }


  // Block f of the stage vectors [u | v | A | σ̄]: where it starts and its length.
  std::size_t offset(std::size_t f) const {
    return f < 2 ? f * this->n_ : 2 * this->n_ + (f - 2) * this->sites_;
  }
  std::size_t block_size(std::size_t f) const { return f < 2 ? this->n_ : this->sites_; }
  // The current state, block f of [u | v | A | σ̄] (u, v: the stage state once made, the core's node values before).
  const double* current(std::size_t f) const {
    if (f < 2) return state_made_ ? state_.data() + f * this->n_ : (f == 0 ? this->u_.data() : this->v_.data());
    return fields_ptr() + (f - 2) * this->sites_;
  }
  double* current(std::size_t f) { return const_cast<double*>(std::as_const(*this).current(f)); }
  const double* fields_ptr() const { return const_cast<Law&>(this->law_).fields().data(); }

  // Θ from the initial state (docs/model.md §1: Θ = 1 iff |σ|/A > 1); then the overload is below
  // the band at every site, the invariant that every step starts from.
  void start() {
    make_state();
    const double* a = current(2);
    const double* s = current(3);
    for (std::size_t i = 0; i < this->sites_; ++i)
      theta_[i] = this->law_.sliding({this->v_[i], a[i], s[i]}) ? 1 : 0;
    theta_prev_ = theta_;
    f0_valid_ = false;
    started_ = true;
    if (this->energy_) {
      EnergyBudget& e = *this->energy_;
      e.time = this->t_;
      e.kinetic = this->kinetic_energy(this->v_);
      e.elastic = this->bulk_.elastic_energy(this->u_);
      e.spring = this->bulk_.spring_energy(this->t_, std::span<const double>(this->u_));
      e.mechanical0 = e.mechanical();
    }
  }

  // The resting area site i's A relaxes towards (docs/model.md §12.1: a prescribed normal load's (p/p_0)^m, constant in
  // time; 1 without one), for the law's rates.
  double resting(std::size_t i) const {
    if constexpr (Law::hooks.normal_load) return this->law_.resting_area(i);
    else return 1.0;
  }

  // e_i > 0 means site i has crossed its switching surface: Θ = 0 and |σ| > A (1 + band), or Θ = 1 and
  // |σ| < A (1 − band).
  double switch_function(std::size_t i, SiteState st) const {
    const double s = this->law_.load(st), b = opt_.switch_band * st.area;
    return theta_[i] ? (st.area - b) - s : s - (st.area + b);
  }


  // The right-hand side at (t; u, v, A, σ̄), Θ frozen: u' = v, v' the body's (its forces, loading and the interface
  // traction σ̄ + η v on the sites), (A', σ̄') the law's rates on the sites.
  void rhs(double t, const double* u, const double* v, const double* a, const double* s, std::vector<double>& f) {
    ++stats_.rhs;
    const std::size_t n = this->n_, m = this->sites_;
    double* fu = f.data();
    double* fv = fu + n;
    double* fa = fv + n;
    double* fs = fa + m;
    this->bulk_.stage_accelerations(t, std::span<const double>(u, n), v, s, this->law_.params().eta,
                                    std::span<double>(fv, n));
    std::copy_n(v, n, fu);
    const std::uint8_t* th = theta_.data();
    for (std::size_t i = 0; i < m; ++i) {
      const SiteRate r = this->law_.rate({v[i], a[i], s[i], resting(i)}, th[i] != 0);
      fa[i] = r.area;
      fs[i] = r.sigma_bar;
    }
  }
  void rhs_current(double t, std::vector<double>& f) { rhs(t, current(0), current(1), current(2), current(3), f); }
  void rhs_stage(double t, const std::vector<double>& y, std::vector<double>& f) {
    rhs(t, y.data() + offset(0), y.data() + offset(1), y.data() + offset(2), y.data() + offset(3), f);
  }

  // W = I − c J(y) at the current state. Per site, the rows of A and σ̄ give x_A = p_A + q_A x_v,
  // x_σ = p_σ + q_σ x_v (eliminate_site, the law's Jacobian); the u row x_v = (x_u − b_u)/c; the v rows then
  // leave a system for x_u that the body factors with each site's q_σ (stage_factor).
  void factor(double c) {
    ++stats_.factorizations;
    const double* v = current(1);
    const double* a = current(2);
    const double* s = current(3);
    this->bulk_.stage_factor(c, this->law_.params().eta,
                             [&](std::size_t i) { return eliminate_site(i, c, v[i], a[i], s[i]); });
  }
  // Site i's rows of A and σ̄ in W = I − c J (both bodies): x_A = p_A + q_A x_v, x_σ = p_σ + q_σ x_v. Stores the
  // elimination coefficients and returns q_σ.
  double eliminate_site(std::size_t i, double c, double v, double a, double s) {
    const SiteJacobian j = this->law_.jacobian({v, a, s}, theta_[i] != 0);
    const double ia1 = 1.0 / (1.0 - c * j.area_area);
    const double qa = c * j.area_v * ia1;
    const double is1 = 1.0 / (1.0 - c * j.sigma_sigma);
    const double cav = c * j.sigma_area;
    const double qs = (cav * qa + c * j.sigma_v) * is1;
    inv_a1_[i] = ia1;
    q_area_[i] = qa;
    inv_s1_[i] = is1;
    c_alpha_v_[i] = cav;
    q_sigma_[i] = qs;
    return qs;
  }

  // out = W⁻¹ (b − sub + h d ∂f/∂t) (+ sub when add_back); out may be b. The sites' entries of every block are formed
  // and completed here (A and σ̄ by the site elimination, around the body's solve); the body's stage_solve takes
  // the rest of u and v from `in` (the strip fuses that arithmetic into its sweeps) and hdT over its loaded dofs.
  void solve(std::vector<double>& out, const std::vector<double>& b, const std::vector<double>* sub, bool add_back,
             double hdT, const double* guess_u = nullptr, const double* guess_sub_u = nullptr, double guess_scale = 1.0) {
    ++stats_.solves;
    const std::size_t n = this->n_, m = this->sites_;
    B& body = this->bulk_;
    const double* sb = sub != nullptr ? sub->data() : nullptr;
    for (const std::size_t o : {std::size_t{0}, n, 2 * n, 2 * n + m})
      for (std::size_t i = 0; i < m; ++i) out[o + i] = sb != nullptr ? b[o + i] - sb[o + i] : b[o + i];
    if (body.has_drive_spring()) out[n] += hdT;  // the spring pulls site 0
    double* xu = out.data();
    double* xv = xu + n;
    double* xa = xv + n;
    double* xs = xa + m;
    BulkStage in{b.data(), b.data() + n};
    if (sb != nullptr) {
      in.sub_u = sb;
      in.sub_v = sb + n;
    }
    if (add_back) {
      in.add_u = sb;
      in.add_v = sb + n;
    }
    in.hdT = hdT;
    in.guess_u = guess_u;
    in.guess_sub_u = guess_sub_u;
    in.guess_scale = guess_scale;
    const auto p_sigma = [&](std::size_t i) {
      const double pa = xa[i] * inv_a1_[i];
      const double ps = (xs[i] + c_alpha_v_[i] * pa) * inv_s1_[i];
      xa[i] = pa;
      xs[i] = ps;
      return ps;
    };
    const auto back = [&](std::size_t i, double vi) {
      xa[i] += q_area_[i] * vi;
      xs[i] += q_sigma_[i] * vi;
    };
    body.stage_solve(in, p_sigma, back, xu, xv);
    if (add_back)
      for (const std::size_t o : {std::size_t{0}, n, 2 * n, 2 * n + m})
        for (std::size_t i = 0; i < m; ++i) out[o + i] += sb[o + i];
  }

  // y_out = current + scale · k over all four blocks.
  void stage(double scale, const std::vector<double>& k, std::vector<double>& out) const {
    for (std::size_t f = 0; f < 4; ++f) {
      const double* y = current(f);
      const std::size_t o = offset(f), n = block_size(f);
      for (std::size_t i = 0; i < n; ++i) out[o + i] = y[i] + scale * k[o + i];
    }
  }

  // One Rosenbrock step of size h from the current state; fills ynew_, k1_, k2_, k3_; returns the
  // error norm.
  double attempt(double h) {
    const std::size_t m = k1_.size();
    const B& b = this->bulk_;
    if (!f0_valid_) {
      rhs_current(this->t_, f0_);
      f0_valid_ = true;
    }
    factor(kGamma * h);
    // h d ∂f/∂t: only the drive spring depends on t explicitly, K v_d/(ρ w_0) in the v row of site 0 (the body
    // spreads it over the dofs it loads: the strip's edge column).
    const double hdT =
        b.has_drive_spring() ? kGamma * h * b.spring_K() * b.driver_velocity() / (b.rho() * b.interface_weight(0)) : 0.0;
    // A body whose stage solve iterates starts from a guess of its x_u: k1 and k2 − k1 of the last accepted step,
    // k3 ≈ 2 k2 − k1 of this one (the local error h/6 (k1 − 2 k2 + k3) is within the tolerance).
    const bool guess = stats_.accepted > 0;
    solve(k1_, f0_, nullptr, false, hdT, guess ? k1_prev_.data() : nullptr);  // k1 = W⁻¹ (f0 + h d ∂f/∂t)
    stage(0.5 * h, k1_, ynew_);
    rhs_stage(this->t_ + 0.5 * h, ynew_, f1_);
    solve(k2_, f1_, &k1_, true, 0.0, guess ? k2_prev_.data() : nullptr, k1_prev_.data());  // k2 = W⁻¹ (f1 − k1) + k1
    stage(h, k2_, ynew_);
    rhs_stage(this->t_ + h, ynew_, f2_);
    for (std::size_t j = 0; j < m; ++j)
      k3_[j] = f2_[j] - detail::kE32 * (k2_[j] - f1_[j]) - 2.0 * (k1_[j] - f0_[j]);
    solve(k3_, k3_, nullptr, false, hdT, k2_.data(), k1_.data(), 2.0);  // k3 = W⁻¹ (f2 − e32 (k2 − f1) − 2 (k1 − f0) + h d ∂f/∂t)
    return error_norm(h);
  }

  // Weighted norm of the local error estimate h/6 (k1 − 2 k2 + k3), see ErrorNorm.
  double error_norm(double h) const {
    if (opt_.norm == ErrorNorm::field) return error_norm_field(h);
    if constexpr (B::stage_is_nodes) {
      return error_norm_weighted(h, ynew_, k1_, k2_, k3_, [this](std::size_t f) { return current(f); });
    } else {
      return error_norm_nodes(h);
    }
  }
  // ErrorNorm::field: each block against its own scale; u and v as the body measures them in its stage
  // representation (the strip: by bounds never below the node values', docs/numerics.md §8.6), A and σ̄ here.
  double error_norm_field(double h) const {
    const B& b = this->bulk_;
    if (!block_scale_valid_) {  // the state's scale beyond its sites: once per step
      for (std::size_t f = 0; f < 2; ++f) block_scale_[f] = b.stage_scale(current(f));
      block_scale_valid_ = true;
    }
    double norm = 0.0, probe = 0.0;  // probe: a NaN or infinity anywhere (std::max would drop a NaN)
    for (std::size_t f = 0; f < 4; ++f) {
      const std::size_t o = offset(f);
      StageError e;
      if (f < 2) {
        e = b.stage_error(current(f), ynew_.data() + o, k1_.data() + o, k2_.data() + o, k3_.data() + o);
        e.scale = std::max(e.scale, block_scale_[f]);
      } else {
        e = site_error(current(f), o);
      }
      probe += e.probe;
      norm = std::max(norm, h / 6.0 * e.emax / (opt_.atol + opt_.rtol * e.scale));
    }
    if (!std::isfinite(probe)) return std::numeric_limits<double>::infinity();
    return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
  }
  // The field norm's parts of a sites' block (A or σ̄) starting at o in the stage vectors.
  StageError site_error(const double* y, std::size_t o) const {
    StageError r;
    const double *yn = ynew_.data() + o, *k1 = k1_.data() + o, *k2 = k2_.data() + o, *k3 = k3_.data() + o;
    for (std::size_t j = 0; j < this->sites_; ++j) {
      r.scale = std::max(r.scale, std::max(std::abs(y[j]), std::abs(yn[j])));
      const double e = std::abs(k1[j] - 2.0 * k2[j] + k3[j]);
      r.emax = std::max(r.emax, e);
      r.probe += e + yn[j];
    }
    return r;
  }
  // ErrorNorm::local or rms on a body whose stage representation is not node values: on node values (three
  // transforms of u and v each; correct, not fast: no scene uses them).
  double error_norm_nodes(double h) const {
    nodes_.resize(6);
    const std::size_t n = this->n_;
    const B& b = this->bulk_;
    for (auto& v : nodes_) v.resize(ynew_.size());
    const std::vector<double>* src[4] = {&ynew_, &k1_, &k2_, &k3_};
    for (std::size_t q = 0; q < 4; ++q) {
      nodes_[q] = *src[q];
      b.from_stage(std::span<const double>(nodes_[q]).first(n), std::span<double>(nodes_[q]).first(n));
      b.from_stage(std::span<const double>(nodes_[q]).subspan(n, n), std::span<double>(nodes_[q]).subspan(n, n));
    }
    nodes_[4].resize(n);
    nodes_[5].resize(n);
    b.from_stage(state_u(), nodes_[4]);
    b.from_stage(state_v(), nodes_[5]);
    return error_norm_weighted(h, nodes_[0], nodes_[1], nodes_[2], nodes_[3], [this](std::size_t f) {
      return f == 0 ? nodes_[4].data() : f == 1 ? nodes_[5].data() : current(f);
    });
  }
  // ErrorNorm::local or rms on node values: each unknown against its own value.
  template <class Current>
  double error_norm_weighted(double h, const std::vector<double>& ynew, const std::vector<double>& k1v,
                             const std::vector<double>& k2v, const std::vector<double>& k3v, Current&& cur) const {
    const double rtol = opt_.rtol, atol = opt_.atol, h6 = h / 6.0;
    double norm = 0.0, probe = 0.0;  // probe: a NaN or infinity anywhere (std::max would drop a NaN)
    for (std::size_t j = 0; j < ynew.size(); ++j) probe += ynew[j] + k3v[j];
    if (!std::isfinite(probe)) return std::numeric_limits<double>::infinity();
    const double *yn = ynew.data(), *k1 = k1v.data(), *k2 = k2v.data(), *k3 = k3v.data();
    for (std::size_t f = 0; f < 4; ++f) {
      const std::size_t j0 = offset(f), j1 = j0 + block_size(f);
      const double* y = cur(f);  // y[j − j0], j in [j0, j1)
      for (std::size_t j = j0; j < j1; ++j) {
        const double e = std::abs(h6 * (k1[j] - 2.0 * k2[j] + k3[j])) /
                         (atol + rtol * std::max(std::abs(y[j - j0]), std::abs(yn[j])));
        if (opt_.norm == ErrorNorm::local) norm = std::max(norm, e);
        else norm += e * e;
      }
    }
    if (opt_.norm == ErrorNorm::rms) norm = std::sqrt(norm / static_cast<double>(ynew.size()));
    return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
  }

  // θ ∈ (0, 1] at which e_i first exceeds 0 on the dense output of the trial step (k1_, k2_, h) from
  // the current state (where e_i < 0) to ynew_ (where e_i > 0): Illinois regula falsi, upper end of
  // the bracket.
  double event_fraction(std::size_t i, double h) const {
    const std::size_t iv = offset(1) + i, ia = offset(2) + i, is = offset(3) + i;
    const double yv = current(1)[i], ya = current(2)[i], ys = current(3)[i];
    auto e = [&](double th) {
      const double b1 = th * (1.0 - th) * kDenseScale * h, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h;
      return switch_function(i, {yv + b1 * k1_[iv] + b2 * k2_[iv], ya + b1 * k1_[ia] + b2 * k2_[ia],
                                 ys + b1 * k1_[is] + b2 * k2_[is]});
    };
    double lo = 0.0, hi = 1.0, elo = e(0.0), ehi = e(1.0);
    if (!(elo < 0.0)) return 0.0;  // not expected (e_i < 0 at every step start): switch at once
    const double tol = 1e-13 * std::max(1.0, std::abs(this->t_)) / h;
    // Illinois regula falsi; a bisection whenever the bracket fails to halve over two iterations.
    int side = 0;
    double width = hi - lo;
    for (int it = 0; it < 200 && hi - lo > tol; ++it) {
      double th = (lo * ehi - hi * elo) / (ehi - elo);
      if (it % 2 == 1) {
        if (hi - lo > 0.5 * width) th = 0.5 * (lo + hi);
        width = hi - lo;
      }
      if (!(th > lo && th < hi)) th = 0.5 * (lo + hi);
      const double et = e(th);
      if (et > 0.0) {
        hi = th;
        ehi = et;
        if (side == 1) elo *= 0.5;
        side = 1;
      } else {
        lo = th;
        elo = et;
        if (side == -1) ehi *= 0.5;
        side = -1;
      }
    }
    return hi;
  }

  // At a step end: flip Θ of every site whose |σ|/A has crossed 1 (e_i > −band·A/2; after the flip
  // e_i < −band·A, the invariant of every step start). Only A' and σ̄' of a flipped site change.
  bool flip_crossed() {
    bool any = false;
    const std::size_t n = this->sites_, oa = offset(2), os = offset(3);
    const double* v = current(1);
    const double* a = current(2);
    const double* s = current(3);
    for (std::size_t i = 0; i < n; ++i) {
      const SiteState st{v[i], a[i], s[i], resting(i)};
      if (switch_function(i, st) > -0.5 * opt_.switch_band * st.area) {
        theta_[i] = static_cast<std::uint8_t>(1 - theta_[i]);
        ++stats_.switchings;
        if (f0_valid_) {
          const SiteRate r = this->law_.rate(st, theta_[i] != 0);
          f0_[oa + i] = r.area;
          f0_[os + i] = r.sigma_bar;
        }
        any = true;
      }
    }
    return any;
  }

  // Stage 1: attempt steps from the current state until the error test passes; h is the accepted
  // trial size.
  double trial_step(double& h, bool& rejected) {
    for (;;) {
      if (h < opt_.dt_min) {
        std::size_t bad = 0;
        for (std::size_t j = 0; j < ynew_.size(); ++j)
          if (!std::isfinite(ynew_[j])) {
            bad = j < 2 * this->n_ ? j % this->n_ : (j - 2 * this->n_) % this->sites_;
            break;
          }
        throw NumericalError(stats_.accepted, this->t_, bad, "adaptive step below dt_min (" + format_number(h) + ")");
      }
      const double err = attempt(h);
      if (err <= 1.0) return err;
      ++stats_.rejected;
      rejected = true;
      h = quantize(h * (std::isfinite(err) ? std::clamp(detail::kSafety * std::pow(err, -1.0 / 3.0), 0.1, 0.5) : 0.25));
    }
  }
  // A body may restrict the step sizes to a grid (B::quantized_step(h), near h; the in-plane strip, so that its stage
  // matrices repeat and their factors are reused, docs/numerics.md §8.9); the others take h as proposed.
  static double quantize(double h) {
    if constexpr (requires { B::quantized_step(h); }) return B::quantized_step(h);
    else return h;
  }

  // Stage 2: fraction θ ∈ [0, 1) of the trial step at which the first site crosses its switching
  // surface (2 if none does); with event_window > 0, the last crossing within the window instead.
  double first_switching(double h) {
    const std::size_t n = this->sites_;
    const double* v = ynew_.data() + offset(1);
    const double* a = ynew_.data() + offset(2);
    const double* s = ynew_.data() + offset(3);
    crossings_.clear();
    groups_.clear();
    group_scales_valid_ = false;
    for (std::size_t i = 0; i < n; ++i)
      if (switch_function(i, {v[i], a[i], s[i]}) > 0.0) {
        const double th = event_fraction(i, h);
        crossings_.push_back(th);
        if (opt_.group_fraction > 0.0) groups_.emplace_back(th, group_allowance(i, th, h));
      }
    if (crossings_.empty()) return 2.0;
    double frac = *std::min_element(crossings_.begin(), crossings_.end());
    if (opt_.event_window > 0.0) {
      const double limit = frac + opt_.event_window / h;
      for (double c : crossings_)
        if (c <= limit) frac = std::max(frac, c);
    } else if (opt_.group_fraction > 0.0 && groups_.size() > 1) {
      // The latest θ_c such that every crossing θ_i ≤ θ_c is within its allowance: θ_c ≤ min_{i ≤ c} (θ_i + a_i).
      std::sort(groups_.begin(), groups_.end());
      double limit = groups_[0].first + groups_[0].second;
      for (const auto& [th, allow] : groups_) {
        if (th > limit) break;
        frac = th;
        limit = std::min(limit, th + allow);
      }
    }
    return frac;
  }
  // How late (as a fraction of h) site i, crossing at θ, may flip: group_fraction (atol + rtol · scale_f)/|Δ rate_f|
  // for f = A, σ̄, the jump of the site's rates at its switching (both Θ at the crossing's dense state), the scales
  // the field norm's (the largest |A|, |σ̄| over the sites, of the step's start and of the trial's end).
  double group_allowance(std::size_t i, double th, double h) {
    if (!group_scales_valid_) {
      const std::size_t m = this->sites_;
      double sa = 0.0, ss = 0.0;
      const double *a0 = current(2), *s0 = current(3), *a1 = ynew_.data() + offset(2), *s1 = ynew_.data() + offset(3);
      for (std::size_t k = 0; k < m; ++k) {
        sa = std::max({sa, std::abs(a0[k]), std::abs(a1[k])});
        ss = std::max({ss, std::abs(s0[k]), std::abs(s1[k])});
      }
      group_tol_[0] = opt_.atol + opt_.rtol * sa;
      group_tol_[1] = opt_.atol + opt_.rtol * ss;
      group_scales_valid_ = true;
    }
    const std::size_t iv = offset(1) + i, ia = offset(2) + i, is = offset(3) + i;
    const double b1 = th * (1.0 - th) * kDenseScale * h, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h;
    const SiteState st{current(1)[i] + b1 * k1_[iv] + b2 * k2_[iv], current(2)[i] + b1 * k1_[ia] + b2 * k2_[ia],
                       current(3)[i] + b1 * k1_[is] + b2 * k2_[is], resting(i)};
    const SiteRate now = this->law_.rate(st, theta_[i] != 0), flipped = this->law_.rate(st, theta_[i] == 0);
    const double ja = std::abs(flipped.area - now.area), js = std::abs(flipped.sigma_bar - now.sigma_bar);
    double allow = std::numeric_limits<double>::infinity();
    if (ja > 0.0) allow = std::min(allow, group_tol_[0] / ja);
    if (js > 0.0) allow = std::min(allow, group_tol_[1] / js);
    return opt_.group_fraction * allow / h;
  }

  // Stage 3 (interpolate): the end state is the dense output of the trial step at θ = frac.
  void end_on_dense_output(double frac, double h) {
    const double b1 = frac * (1.0 - frac) * kDenseScale * h, b2 = frac * (frac - 2.0 * kGamma) * kDenseScale * h;
    for (std::size_t f = 0; f < 4; ++f) {
      const double* y = current(f);
      const std::size_t o = offset(f), n = block_size(f);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = o + i;
        ynew_[j] = y[i] + b1 * k1_[j] + b2 * k2_[j];
      }
    }
  }

  // Stage 4: the step [t, t + h] is taken; h_dense is the step of its dense-output polynomial. The stage vectors
  // rotate (y_prev ← the state, the state ← ynew: no copy of u and v); the law's A and σ̄, which live in the law, are
  // copied. Returns whether the step ended on the stop time.
  bool accept(double h, double h_dense, bool f_end_valid) {
    const std::size_t oa = offset(2), m2 = 2 * this->sites_;
    double* fields = const_cast<double*>(fields_ptr());
    std::copy_n(fields, m2, state_.data() + oa);
    std::swap(y_prev_, state_);
    std::swap(state_, ynew_);
    std::copy_n(state_.data() + oa, m2, fields);
    double vmax = 0.0;
    const std::size_t ov = offset(1);
    const double* vc = current(1);
    for (std::size_t i = 0; i < this->sites_; ++i) vmax = std::max({vmax, std::abs(y_prev_[ov + i]), std::abs(vc[i])});
    // the sites' node values at once, the rest when asked (sync_nodes)
    std::copy_n(state_u().data(), this->sites_, this->u_.data());
    std::copy_n(state_v().data(), this->sites_, this->v_.data());
    nodes_stale_ = this->n_ > this->sites_;
    block_scale_valid_ = false;
    std::swap(f0_, f2_);  // FSAL: f at the new state, unless the step ended on the dense output
    std::swap(k1_prev_, k1_);
    std::swap(k2_prev_, k2_);
    f0_valid_ = f_end_valid;
    t_prev_ = this->t_;
    const bool at_stop =
        t_stop_ > this->t_ && std::abs(this->t_ + h - t_stop_) <= 1e-13 * std::max(1.0, std::abs(t_stop_));
    this->t_ = at_stop ? t_stop_ : this->t_ + h;
    h_prev_ = h_dense;
    last_dt_ = h;
    this->steps_ = ++stats_.accepted;
    theta_prev_ = theta_;
    this->yielded_ = std::find(theta_.begin(), theta_.end(), std::uint8_t{1}) != theta_.end();
    this->max_v_ = vmax;
    return at_stop;
  }

  // PI controller on the trial step's error. h is the trial size (an event shortening the step does
  // not shrink the next one; neither does the stop time); after a rejection the step does not grow.
  void propose_next(double h, double err, bool rejected) {
    const double e = std::max(err, 1e-10);
    const double grow = std::clamp(detail::kSafety * std::pow(e, -detail::kBeta1) * std::pow(err_prev_, detail::kBeta2),
                                   detail::kShrinkMin, rejected ? 1.0 : detail::kGrowMax);
    err_prev_ = e;
    h_next_ = std::min(h * grow, opt_.dt_max);
  }

  // Energy budget over the accepted step [t_prev, t] (docs/performance.md §2): the mechanical energy at t from the
  // state, the work and dissipation by Simpson's rule on the step's dense output (its start, middle and end), so the
  // residual is the integration error of the step (O(rtol)): kinetic, elastic, the uniform stress's power and the
  // drive's over all dofs (node values), the viscous and interfacial power on the interface sites.
  void energy_over_step() {
    EnergyBudget& e = *this->energy_;
    const std::size_t n = this->n_, m = this->sites_;
    const B& b = this->bulk_;
    const double eta = this->law_.params().eta, t0 = t_prev_, t1 = this->t_;
    en_v_.resize(n);
    en_u_.resize(n);
    en_s_.resize(m);
    double visc[3], inter[3], drive[3];
    const double ts[3] = {t0, 0.5 * (t0 + t1), t1};
    for (int q = 0; q < 3; ++q) {
      dense_state(ts[q], Field::slip_rate, en_v_);
      dense_state(ts[q], Field::slip, en_u_);
      dense_state(ts[q], Field::sigma_bar, en_s_);
      double pv = 0.0, pi = 0.0;
      for (std::size_t i = 0; i < m; ++i) {
        const double w = b.interface_weight(i), vi = en_v_[i];
        pv += w * eta * vi * vi;
        pi += w * en_s_[i] * vi;
      }
      visc[q] = pv;
      inter[q] = pi;
      drive[q] = b.uniform_power(en_v_) + b.driver_velocity() * b.drive_force(ts[q], en_u_) +
                 b.rear_traction() * b.edge_slip(en_v_);
    }
    const double h6 = (t1 - t0) / 6.0;
    e.viscous += h6 * (visc[0] + 4.0 * visc[1] + visc[2]);
    e.interfacial += h6 * (inter[0] + 4.0 * inter[1] + inter[2]);
    e.drive_work += h6 * (drive[0] + 4.0 * drive[1] + drive[2]);
    e.time = t1;
    e.kinetic = this->kinetic_energy(velocity());
    e.elastic = b.elastic_energy(displacement());
    e.spring = b.spring_energy(t1, displacement());
  }

  AdaptiveOptions opt_;
  double t_prev_ = 0.0, h_next_, last_dt_, err_prev_ = 1.0;
  bool started_ = false, f0_valid_ = false;
  std::vector<double> y_prev_, ynew_, f0_, f1_, f2_, k1_, k2_, k3_;  // stages [u | v | A | σ̄]
  std::vector<double> k1_prev_, k2_prev_;  // dense output of the last accepted step
  double h_prev_ = 0.0, t_stop_ = -1.0;
  std::vector<std::uint8_t> theta_, theta_prev_;
  std::vector<double> crossings_;
  std::vector<std::pair<double, double>> groups_;  // (θ_i, allowance_i) of the crossings, for group_fraction
  double group_tol_[2] = {0.0, 0.0};               // the tolerances of A and σ̄ of the current trial
  bool group_scales_valid_ = false;
  // The W solve's elimination of each site's A and σ̄ rows (eliminate_site); the body keeps its own factors.
  std::vector<double> inv_a1_, q_area_, inv_s1_, c_alpha_v_, q_sigma_;
  std::vector<double> en_v_, en_s_, en_u_;  // energy budget work arrays
  // The state's u and v in the body's stage representation: the first 2 dofs() of state_ (its tail is the rotation's
  // room for A, σ̄: accept). The core's u_, v_ hold the sites' node values at every step end and the rest when asked
  // (sync_nodes); state_made_: state_ was made from them (make_state) since the last set_initial.
  std::vector<double> state_;
  std::span<const double> state_u() const { return std::span<const double>(state_).first(this->n_); }
  std::span<const double> state_v() const { return std::span<const double>(state_).subspan(this->n_, this->n_); }
  bool state_made_ = false;
  mutable bool nodes_stale_ = false;
  mutable std::vector<double> dense_nodes_;
  mutable double block_scale_[2] = {0.0, 0.0};  // error_norm_field: the state's scale of u and v beyond the sites
  mutable bool block_scale_valid_ = false;
  mutable std::vector<std::vector<double>> nodes_;
  AdaptiveStats stats_;

  // The stage state from the node values (at the start, and after set_initial).
  void make_state() {
    nodes_to_state();
    f0_valid_ = false;
  }
  void nodes_to_state() {
    const B& b = this->bulk_;
    b.to_stage(this->u_, std::span<double>(state_).first(this->n_));
    b.to_stage(this->v_, std::span<double>(state_).subspan(this->n_, this->n_));
    state_made_ = true;
    nodes_stale_ = false;
    block_scale_valid_ = false;
  }
  // The node values of the whole body from the stage state, when they are behind it.
  void sync_nodes() const {
    if (!nodes_stale_ || !state_made_) return;
    auto* self = const_cast<AdaptiveSimulation*>(this);
    this->bulk_.from_stage(state_u(), self->u_);
    this->bulk_.from_stage(state_v(), self->v_);
    nodes_stale_ = false;
  }
};

}  // namespace slipfront::core
