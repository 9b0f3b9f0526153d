#pragma once
// Adaptive, linearly implicit time stepping of bulk + a deterministic interface law given by its rates
// (SmoothLaw, core/law.hpp: the continuum FrictionLaw, docs/model.md §1), for scenes where long
// quiet stretches (elastic loading, the slow front, healing) alternate with short fast ones (the
// transient front). Same method-of-lines ODE as the fixed-step schemes: the bulk operator of
// core/bulk.hpp (grid, lumped masses, half cells, edge spring, free ends) and the law's rates, per
// node
//   u' = v
//   ρ v' = F_i/w_i + σ_d − σ̄_i − η v_i                     (Bulk::forces_per_length)
//   (A', σ̄') = law.rate({v_i, A_i, σ̄_i}, Θ_i)              (docs/model.md §1.1: A' = 1 − A − ΘκA|v|, σ̄' = αAv − Θσ̄|v|)
// integrated as one stiff system (docs/performance.md):
//   - a 2-stage Rosenbrock method (Shampine–Reichelt "ode23s": order 2, L-stable, embedded order-3
//     error estimate, order-2 dense output) with the exact Jacobian (law.jacobian and the bulk's
//     stiffness). The Jacobian is block tridiagonal; each W = I − h d J solve eliminates (v, A, σ̄)
//     node by node and leaves a symmetric tridiagonal system for u (Thomas): O(nodes) per solve;
//   - error-controlled step sizes (PI controller), by default a max norm per field (ErrorNorm);
//   - Θ piecewise constant inside every step, switched by event location: the zeros of
//     g_i = law.load = |σ̄_i + η v_i| against A_i (|σ|/A = 1) are located on the dense output of each accepted
//     step (Illinois regula falsi to 1e-13 in time) and the step ends at the first one, where Θ_i flips
//     (with every other site that has crossed by then) — or, by default (group_fraction = 1, time.group_switchings),
//     at a later one when the sites flipped late leave a local error within the step's tolerance (docs/numerics.md
//     §8.7). A hysteresis band (switch_band, relative 1e-9) keeps a site that just flipped from flipping back at once.
// The state is where it belongs: u and v in the stepper core, A and σ̄ in the law (law.fields(),
// advanced in place); the work vectors hold stages [u | v | A | σ̄] (4 blocks of n).
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

// On a body (core/body.hpp): the 1D chain (core::Bulk, every node a site, the u system tridiagonal and solved by
// Thomas, as above) or the antiplane strip (core::Strip, docs/model.md §9): u and v over all its dofs, A and σ̄
// on the interface sites; the W solve eliminates (v, A, σ̄) the same way and leaves the strip's step matrix
// M/c + c(S + K b bᵀ) + E diag(wx (η + q_σ)) Eᵀ for u, solved by Strip::solve_system (docs/numerics.md §8.5).
// The stage vectors are [u | v | A | σ̄] with blocks of dofs, dofs, sites, sites (on the chain: four of n).
template <SmoothLaw Law, Body B = Bulk>
class AdaptiveSimulation : public StepperCore<Law, B> {
  using Core = StepperCore<Law, B>;
  static constexpr bool kChain = std::is_same_v<B, Bulk>;

 public:
  static constexpr const char* integrator_name = "adaptive";
  static constexpr bool error_control = false;  ///< set_error_control, substeps (implicit only)
  static constexpr double kGamma = detail::kGamma;
  static constexpr double kDenseScale = detail::kDenseScale;
  /// The strip's stage solves: relative residual of the interface iterations per unit rtol.
  static constexpr double kStageSolveTolerance = 1e-4;

  AdaptiveSimulation(B bulk, Law law, AdaptiveOptions opt)
      : Core(std::move(bulk), std::move(law), "AdaptiveSimulation"), opt_(opt), h_next_(opt.dt_initial),
        last_dt_(opt.dt_initial) {
    opt_.validate();
    const std::size_t m = 2 * this->n_ + 2 * this->sites_;
    for (auto* v : {&y_prev_, &ynew_, &f0_, &f1_, &f2_, &k1_, &k2_, &k3_, &k1_prev_, &k2_prev_}) v->assign(m, 0.0);
    for (auto* v : {&tmp_, &inv_a1_, &q_area_, &inv_s1_, &c_alpha_v_, &q_sigma_, &d_coef_, &thomas_c_, &thomas_inv_})
      v->assign(this->n_, 0.0);
    theta_.assign(this->sites_, 0);
    theta_prev_.assign(this->sites_, 0);
    if constexpr (!kChain) {
      const B& b = this->bulk_;
      // The interface row's node masses (the rows above: Strip::solve_stage_mixed forms their right-hand side).
      mass_.resize(this->sites_);
      for (std::size_t i = 0; i < this->sites_; ++i) mass_[i] = b.node_mass(i, 0);
      urhs_.assign(this->sites_, 0.0);
      ystate_.assign(2 * this->n_ + 2 * this->sites_, 0.0);
      // The stage solves' interface iterations stop at a relative residual of 1e-4 rtol (docs/numerics.md §8.5):
      // the stage error they leave is far below what the step's error control admits.
      if constexpr (requires(B& mb) { mb.set_interface_tolerance(1e-3); })
        this->bulk_.set_interface_tolerance(std::clamp(kStageSolveTolerance * opt_.rtol, 1e-13, 1e-3));
    }
  }

  double dt() const { return last_dt_; }  ///< size of the last accepted step (before any: dt_initial)
  /// Initial slip and slip rate of node i (with law().set_site for A, σ̄), before the first step: Θ is
  /// taken from the state at the first step.
  void set_initial(std::size_t i, double u, double v) {
    Core::set_initial(i, u, v);
    f0_valid_ = false;
    mixed_valid_ = false;
  }
  /// Displacement and velocity of every dof (node values; on the strip made from the mixed state when asked).
  std::span<const double> displacement() const {
    sync_bulk();
    return this->u_;
  }
  std::span<const double> velocity() const {
    sync_bulk();
    return this->v_;
  }
  double drive_force() const {
    if constexpr (kChain) return Core::drive_force();
    else if (!mixed_valid_) return Core::drive_force();
    else return this->bulk_.drive_force_at(this->t_, this->bulk_.mixed_edge_slip(mixed_u()));
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
    else if constexpr (!kChain) if (!mixed_valid_) make_mixed();
    double h = std::min(h_next_, opt_.dt_max);
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
  /// Dense output (order 2) of one field at t ∈ [previous_time(), time()], all nodes.
  /// out: the first out.size() values of the field (the sites; on the strip u and v of up to all dofs).
  void dense_state(double t, Field f, std::span<double> out) const {
    if constexpr (!kChain) {
      if (static_cast<std::size_t>(f) < 2 && out.size() > this->sites_ && mixed_valid_) {  // node values of the bulk
        dense_mixed_.resize(this->n_);
        dense_state_raw(t, f, dense_mixed_);
        this->bulk_.from_mixed(dense_mixed_, dense_mixed_);
        std::copy_n(dense_mixed_.begin(), std::min(out.size(), this->n_), out.begin());
        return;
      }
    }
    dense_state_raw(t, f, out);
  }
  /// Dense output of one value (inline: the runner's tip restriction calls it per node).
  double dense_value(double t, Field f, std::size_t i) const {
    if constexpr (!kChain) {
      if (static_cast<std::size_t>(f) < 2 && i >= this->sites_ && mixed_valid_) {  // a bulk node: from its row's modes
        // the dense output is linear in the modes: the row's node value of y_prev, k1 and k2, combined
        const std::size_t m = this->sites_, j0 = (i / m) * m, col = i - j0;
        const B& b = this->bulk_;
        if (stats_.accepted == 0 || h_prev_ <= 0.0) return b.mode_row_value(current(static_cast<std::size_t>(f)) + j0, col);
        const std::size_t q = offset(static_cast<std::size_t>(f)) + j0;
        const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
        const double b1 = th * (1.0 - th) * kDenseScale * h_prev_, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h_prev_;
        return b.mode_row_value(y_prev_.data() + q, col) + b1 * b.mode_row_value(k1_prev_.data() + q, col) +
               b2 * b.mode_row_value(k2_prev_.data() + q, col);
      }
    }
    return dense_value_raw(t, f, i);
  }

 private:
  // The dense output in the stepper's own representation (on the strip: mixed, Strip::to_mixed).
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
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag(kChain ? "adaptive" : "adaptive_strip_mixed");
    sync_bulk();  // the node values the core writes are the state's
    this->serialize_core(ar);
    ar(t_prev_, h_next_, last_dt_, err_prev_, started_, f0_valid_, y_prev_, f0_, k1_prev_, k2_prev_, h_prev_, t_stop_,
       theta_, theta_prev_, stats_);
    if constexpr (!kChain) {
      ar(ystate_, mixed_valid_);
      bulk_stale_ = false;
      bulk_scale_valid_ = false;
    }
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
  // The current state, block f of [u | v | A | σ̄].
  const double* current(std::size_t f) const {
    if constexpr (kChain) {
      if (f == 0) return this->u_.data();
      if (f == 1) return this->v_.data();
    } else {
      if (f < 2) return ystate_.data() + f * this->n_;
    }
    return fields_ptr() + (f - 2) * this->sites_;
  }
  double* current(std::size_t f) { return const_cast<double*>(std::as_const(*this).current(f)); }
  const double* fields_ptr() const { return const_cast<Law&>(this->law_).fields().data(); }

  // Θ from the initial state (docs/model.md §1: Θ = 1 iff |σ|/A > 1); then the overload is below
  // the band at every site, the invariant that every step starts from.
  void start() {
    if constexpr (!kChain) make_mixed();
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

  // e_i > 0 means site i has crossed its switching surface: Θ = 0 and |σ| > A (1 + band), or Θ = 1 and
  // |σ| < A (1 − band).
  double switch_function(std::size_t i, SiteState st) const {
    const double s = this->law_.load(st), b = opt_.switch_band * st.area;
    return theta_[i] ? (st.area - b) - s : s - (st.area + b);
  }

  // The right-hand side at (t; u, v, A, σ̄), Θ frozen (see the header).
  void rhs(double t, const double* u, const double* v, const double* a, const double* s, std::vector<double>& f) {
    ++stats_.rhs;
    if constexpr (kChain) rhs_chain(t, u, v, a, s, f);
    else rhs_body(t, u, v, a, s, f);
  }
  void rhs_chain(double t, const double* u, const double* v, const double* a, const double* s, std::vector<double>& f) {
    const std::size_t n = this->n_;
    const Bulk& b = this->bulk_;
    double* fu = f.data();
    double* fv = fu + n;
    double* fa = fv + n;
    double* fs = fa + n;
    const double inv_rho = 1.0 / b.rho(), sd = b.uniform_stress(), eta = this->law_.params().eta;
    b.forces_per_length(std::span<const double>(u, n), b.drive_force(t, u[0]),
                        [&](std::size_t i, double force) { fv[i] = (force + sd - s[i] - eta * v[i]) * inv_rho; });
    const std::uint8_t* th = theta_.data();
    for (std::size_t i = 0; i < n; ++i) {
      const SiteRate r = this->law_.rate({v[i], a[i], s[i]}, th[i] != 0);
      fu[i] = v[i];
      fa[i] = r.area;
      fs[i] = r.sigma_bar;
    }
  }
  // The strip: u' = v, M v' = −S u + F(t) b + top wx σ_d − E wx (σ̄ + η v₀) (docs/model.md §9) in the mixed
  // representation (Strip::mixed_accelerations; u, v mixed), the law's rates on the interface sites.
  void rhs_body(double t, const double* u, const double* v, const double* a, const double* s, std::vector<double>& f) {
    const std::size_t n = this->n_, m = this->sites_;
    const B& b = this->bulk_;
    double* fu = f.data();
    double* fv = fu + n;
    double* fa = fv + n;
    double* fs = fa + m;
    const double eta = this->law_.params().eta;
    double* traction = tmp_.data();
    for (std::size_t i = 0; i < m; ++i) traction[i] = s[i] + eta * v[i];
    const std::span<const double> us(u, n);
    b.mixed_accelerations(us, b.drive_force_at(t, b.mixed_edge_slip(us)), traction, std::span<double>(fv, n));
    std::copy_n(v, n, fu);
    const std::uint8_t* th = theta_.data();
    for (std::size_t i = 0; i < m; ++i) {
      const SiteRate r = this->law_.rate({v[i], a[i], s[i]}, th[i] != 0);
      fa[i] = r.area;
      fs[i] = r.sigma_bar;
    }
  }
  void rhs_current(double t, std::vector<double>& f) { rhs(t, current(0), current(1), current(2), current(3), f); }
  void rhs_stage(double t, const std::vector<double>& y, std::vector<double>& f) {
    rhs(t, y.data() + offset(0), y.data() + offset(1), y.data() + offset(2), y.data() + offset(3), f);
  }

  // W = I − c J(y) at the current state. Per node, the rows of A and σ̄ give
  //   x_A = p_A + q_A x_v,  x_σ = p_σ + q_σ x_v,  and the u row x_v = (x_u − b_u)/c;
  // the v row (times ρ w_i / c) is then a symmetric tridiagonal equation for x_u:
  //   (ρ w_i D_i / c²) x_u,i + (c S x_u)_i/c ... = w_i ((ρ/c) b_v − p_σ) + (ρ w_i D_i / c²) b_u,
  //   D_i = 1 + cη/ρ + (c/ρ) q_σ,   S the bulk's stiffness matrix (Bulk: elastic_diagonal, spring_K).
  void factor(double c) {
    ++stats_.factorizations;
    c_ = c;
    if constexpr (kChain) factor_chain(c);
    else factor_body(c);
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
  void factor_chain(double c) {
    const std::size_t n = this->n_;
    const Bulk& b = this->bulk_;
    const double rho = b.rho(), k = b.stiffness(), K = b.spring_K(), eta = this->law_.params().eta;
    const double* v = current(1);
    const double* a = current(2);
    const double* s = current(3);
    const double base = 1.0 + c * eta / rho, c_rho = c / rho, rho_c2 = rho / (c * c);
    const double off = -k;
    for (std::size_t i = 0; i < n; ++i) {
      const double qs = eliminate_site(i, c, v[i], a[i], s[i]);
      const double w = b.node_weight(i);
      const double dc = rho_c2 * w * (base + c_rho * qs);
      d_coef_[i] = dc;
      const double diag = dc + b.elastic_diagonal(i) + (i == 0 ? K : 0.0);
      const double m = i == 0 ? diag : diag - off * thomas_c_[i - 1];
      thomas_inv_[i] = 1.0 / m;
      thomas_c_[i] = off / m;
    }
  }

  // The strip: the same per-site elimination; the u system's interface coefficients d_i = η + q_σ,i (the
  // strip's matrix itself is factorised by Strip::solve_system for each c).
  void factor_body(double c) {
    const std::size_t m = this->sites_;
    const double eta = this->law_.params().eta;
    const double* v = current(1);
    const double* a = current(2);
    const double* s = current(3);
    for (std::size_t i = 0; i < m; ++i) {
      d_coef_[i] = eta + eliminate_site(i, c, v[i], a[i], s[i]);
    }
  }

  // The strip's W solve: per site x_A = p_A + q_A x_v0, x_σ = p_σ + q_σ x_v0; x_v = (x_u − b_u)/c; then
  //   [M/c + c(S + K b bᵀ) + E diag(wx d) Eᵀ] x_u = M b_v + (M/c) b_u + E wx (d b_u0 − c p_σ),
  // all in the mixed representation (Strip::solve_stage_mixed: rows j ≥ 1 take the modes of the rhs over wx).
  // The strip's W solve with the stage arithmetic around it fused into the strip's sweeps (no pass of its own over
  // the rows j ≥ 1): out = W⁻¹ (b − sub + hdT e_drive) (+ sub when add_back). The same arithmetic as
  // "out = b − sub; add_time_derivative; solve(out); out += sub" in another order of operations.
  void solve_fused(std::vector<double>& out, const std::vector<double>& b, const std::vector<double>* sub, bool add_back,
                   double hdT) {
    ++stats_.solves;
    const std::size_t n = this->n_, m = this->sites_;
    B& body = this->bulk_;
    const double* sb = sub != nullptr ? sub->data() : nullptr;
    // row 0 of u and v and the sites' blocks: the right-hand side itself
    for (const std::size_t o : {std::size_t{0}, n, 2 * n, 2 * n + m})
      for (std::size_t i = 0; i < m; ++i) out[o + i] = sb != nullptr ? b[o + i] - sb[o + i] : b[o + i];
    if (body.has_drive_spring()) out[n] += hdT;
    double* xu = out.data();
    double* xv = xu + n;
    double* xa = xv + n;
    double* xs = xa + m;
    const double c = c_, inv_c = 1.0 / c;
    for (std::size_t i = 0; i < m; ++i) {
      const double pa = xa[i] * inv_a1_[i];
      xa[i] = pa;
      xs[i] = (xs[i] + c_alpha_v_[i] * pa) * inv_s1_[i];
    }
    double* r = urhs_.data();
    const double* mass = mass_.data();
    for (std::size_t i = 0; i < m; ++i)
      r[i] = mass[i] * (xv[i] + inv_c * xu[i]) + body.interface_weight(i) * (d_coef_[i] * xu[i] - c * xs[i]);
    typename B::StageInput in{b.data(), b.data() + n};
    if (sb != nullptr) {
      in.sub_u = sb;
      in.sub_v = sb + n;
    }
    if (add_back) {
      in.add_u = sb;
      in.add_v = sb + n;
    }
    in.shift_v = body.has_drive_spring() ? hdT / (2.0 * static_cast<double>(m - 1)) : 0.0;
    body.solve_stage_mixed(c, std::span<const double>(d_coef_.data(), m), r, in, xu, xv);
    for (std::size_t i = 0; i < m; ++i) {
      xa[i] += q_area_[i] * xv[i];
      xs[i] += q_sigma_[i] * xv[i];
    }
    if (add_back)
      for (const std::size_t o : {std::size_t{0}, n, 2 * n, 2 * n + m})
        for (std::size_t i = 0; i < m; ++i) out[o + i] += sb[o + i];
  }

  void solve(std::vector<double>& x) {  // in place: x ← W⁻¹ x
    if constexpr (kChain) ++stats_.solves;  // (solve_fused counts its own)
    if constexpr (kChain) solve_chain(x);
    else solve_fused(x, x, nullptr, false, 0.0);
  }
  void solve_chain(std::vector<double>& x) {
    const std::size_t n = this->n_;
    double* xu = x.data();
    double* xv = xu + n;
    double* xa = xv + n;
    double* xs = xa + n;
    const double c = c_, rho_c = this->bulk_.rho() / c, inv_c = 1.0 / c, off = -this->bulk_.stiffness();
    double* d = tmp_.data();
    double prev = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double pa = xa[i] * inv_a1_[i];
      const double ps = (xs[i] + c_alpha_v_[i] * pa) * inv_s1_[i];
      xa[i] = pa;
      xs[i] = ps;
      const double r = this->bulk_.node_weight(i) * (rho_c * xv[i] - ps) + d_coef_[i] * xu[i];
      prev = (r - off * prev) * thomas_inv_[i];  // forward sweep
      d[i] = prev;
    }
    double next = 0.0;
    for (std::size_t i = n; i-- > 0;) {
      const double ui = d[i] - thomas_c_[i] * next;
      next = ui;
      const double vi = (ui - xu[i]) * inv_c;
      xu[i] = ui;
      xv[i] = vi;
      xa[i] += q_area_[i] * vi;
      xs[i] += q_sigma_[i] * vi;
    }
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
    // h d ∂f/∂t: only the drive spring depends on t explicitly (v row of node 0).
    // (On the strip the spring's force spreads over the edge column: K v_d wy(j)/(H M_0j) = K v_d/(ρ wx(0)) in
    // the v row of every node (0, j).)
    const double hdT =
        b.has_drive_spring() ? kGamma * h * b.spring_K() * b.driver_velocity() / (b.rho() * b.interface_weight(0)) : 0.0;
    if constexpr (kChain) {
      for (std::size_t j = 0; j < m; ++j) k1_[j] = f0_[j];
      add_time_derivative(k1_, hdT);
      solve(k1_);
    } else {
      solve_fused(k1_, f0_, nullptr, false, hdT);  // k1 = W⁻¹ (f0 + h d ∂f/∂t)
    }
    stage(0.5 * h, k1_, ynew_);
    rhs_stage(this->t_ + 0.5 * h, ynew_, f1_);
    if constexpr (kChain) {
      for (std::size_t j = 0; j < m; ++j) k2_[j] = f1_[j] - k1_[j];
      solve(k2_);
      for (std::size_t j = 0; j < m; ++j) k2_[j] += k1_[j];
    } else {
      solve_fused(k2_, f1_, &k1_, true, 0.0);  // k2 = W⁻¹ (f1 − k1) + k1
    }
    stage(h, k2_, ynew_);
    rhs_stage(this->t_ + h, ynew_, f2_);
    for (std::size_t j = 0; j < m; ++j)
      k3_[j] = f2_[j] - detail::kE32 * (k2_[j] - f1_[j]) - 2.0 * (k1_[j] - f0_[j]);
    add_time_derivative(k3_, hdT);
    solve(k3_);
    return error_norm(h);
  }
  // k += h d ∂f/∂t: the v rows of the nodes the drive spring pulls (the chain's node 0, the strip's edge column).
  void add_time_derivative(std::vector<double>& k, double hdT) const {
    const std::size_t n = this->n_;
    if constexpr (kChain) {
      k[n] += hdT;
    } else {
      if (hdT == 0.0) return;
      // Mixed: the node (0, 0), and in every mode of each row j ≥ 1 hdT/(2(nx−1)) (the modes of hdT δ_i0).
      const std::size_t m = this->sites_;
      k[n] += hdT;
      const double hm = hdT / (2.0 * static_cast<double>(m - 1));
      for (std::size_t q = n + m; q < 2 * n; ++q) k[q] += hm;
    }
  }

  // Weighted norm of the local error estimate h/6 (k1 − 2 k2 + k3), see ErrorNorm.
  double error_norm(double h) const {
    if constexpr (!kChain) {
      if (opt_.norm == ErrorNorm::field) return error_norm_mixed(h);
      return error_norm_nodes(h);
    }
    return error_norm_generic(h, ynew_, k1_, k2_, k3_, [this](std::size_t f) { return current(f); });
  }
  // The strip, ErrorNorm::field, in the mixed representation without a transform: the interface row's node values
  // exactly; for a row j ≥ 1 of u or v its largest node error bounded by |ê_0| + |ê_N| + 2 Σ_{0<k<N} |ê_k| (≥
  // max_i |(C ê)_i|), and the field's scale taken over the nodes whose values the modes give without a transform
  // (the interface row, and each row's ends i = 0 and nx − 1): a lower bound of the largest node value. Both make
  // the norm at least the node-value norm: the step is no less accurate than with node values (docs/numerics.md
  // §8.6).
  double error_norm_mixed(double h) const {
    const double rtol = opt_.rtol, atol = opt_.atol, h6 = h / 6.0;
    const double *yn = ynew_.data(), *k1 = k1_.data(), *k2 = k2_.data(), *k3 = k3_.data();
    const std::size_t m = this->sites_, N = m - 1;
    if (!bulk_scale_valid_) {  // the rows' end values of the current state: once per step
      for (std::size_t f = 0; f < 2; ++f) {
        const double* y = current(f);
        double sc = 0.0;
        for (std::size_t r = m; r < this->n_; r += m)
          sc = std::max({sc, std::abs(this->bulk_.mode_row_value(y + r, 0)), std::abs(this->bulk_.mode_row_value(y + r, N))});
        bulk_scale_[f] = sc;
      }
      bulk_scale_valid_ = true;
    }
    double norm = 0.0, probe = 0.0;  // probe: the sum of every |error| (a NaN or infinity anywhere)
    for (std::size_t f = 0; f < 4; ++f) {
      const std::size_t j0 = offset(f), len = block_size(f);
      const double* y = current(f);
      double scale = f < 2 ? bulk_scale_[f] : 0.0, emax = 0.0;
      for (std::size_t j = j0; j < j0 + std::min(len, m); ++j) {
        scale = std::max(scale, std::max(std::abs(y[j - j0]), std::abs(yn[j])));
        const double e = std::abs(k1[j] - 2.0 * k2[j] + k3[j]);
        emax = std::max(emax, e);
        probe += e;
      }
      for (std::size_t r = m; r < len; r += m) {  // rows j ≥ 1 of u and v: modes
        const std::size_t q = j0 + r;
        double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
        std::size_t k = 1;
        for (; k + 4 <= N; k += 4) {
          s0 += std::abs(k1[q + k] - 2.0 * k2[q + k] + k3[q + k]);
          s1 += std::abs(k1[q + k + 1] - 2.0 * k2[q + k + 1] + k3[q + k + 1]);
          s2 += std::abs(k1[q + k + 2] - 2.0 * k2[q + k + 2] + k3[q + k + 2]);
          s3 += std::abs(k1[q + k + 3] - 2.0 * k2[q + k + 3] + k3[q + k + 3]);
        }
        for (; k < N; ++k) s0 += std::abs(k1[q + k] - 2.0 * k2[q + k] + k3[q + k]);
        const double bound = std::abs(k1[q] - 2.0 * k2[q] + k3[q]) + std::abs(k1[q + N] - 2.0 * k2[q + N] + k3[q + N]) +
                             2.0 * ((s0 + s1) + (s2 + s3));
        emax = std::max(emax, bound);
        probe += bound;
      }
      norm = std::max(norm, h6 * emax / (atol + rtol * scale));
    }
    if (!std::isfinite(probe)) return std::numeric_limits<double>::infinity();
    return std::isfinite(norm) ? norm : std::numeric_limits<double>::infinity();
  }
  // The strip, ErrorNorm::local or rms: the generic norm on node values (three transforms of u and v each).
  double error_norm_nodes(double h) const {
    nodes_.resize(6);
    const std::size_t n = this->n_;
    const B& b = this->bulk_;
    for (auto& v : nodes_) v.resize(ynew_.size());
    const std::vector<double>* src[4] = {&ynew_, &k1_, &k2_, &k3_};
    for (std::size_t q = 0; q < 4; ++q) {
      nodes_[q] = *src[q];
      b.from_mixed(std::span<const double>(nodes_[q]).first(n), std::span<double>(nodes_[q]).first(n));
      b.from_mixed(std::span<const double>(nodes_[q]).subspan(n, n), std::span<double>(nodes_[q]).subspan(n, n));
    }
    nodes_[4].resize(n);
    nodes_[5].resize(n);
    b.from_mixed(mixed_u(), nodes_[4]);
    b.from_mixed(mixed_v(), nodes_[5]);
    return error_norm_generic(h, nodes_[0], nodes_[1], nodes_[2], nodes_[3], [this](std::size_t f) {
      return f == 0 ? nodes_[4].data() : f == 1 ? nodes_[5].data() : current(f);
    });
  }
  template <class Current>
  double error_norm_generic(double h, const std::vector<double>& ynew, const std::vector<double>& k1v,
                            const std::vector<double>& k2v, const std::vector<double>& k3v, Current&& cur) const {
    const double rtol = opt_.rtol, atol = opt_.atol, h6 = h / 6.0;
    double norm = 0.0, probe = 0.0;  // probe: a NaN or infinity anywhere (std::max would drop a NaN)
    for (std::size_t j = 0; j < ynew.size(); ++j) probe += ynew[j] + k3v[j];
    if (!std::isfinite(probe)) return std::numeric_limits<double>::infinity();
    const double *yn = ynew.data(), *k1 = k1v.data(), *k2 = k2v.data(), *k3 = k3v.data();
    for (std::size_t f = 0; f < 4; ++f) {
      const std::size_t j0 = offset(f), j1 = j0 + block_size(f);
      const double* y = cur(f);  // y[j − j0], j in [j0, j1)
      if (opt_.norm == ErrorNorm::field) {  // one weight per field: atol + rtol · max over the grid
        double scale = 0.0, emax = 0.0;
        for (std::size_t j = j0; j < j1; ++j) {
          scale = std::max(scale, std::max(std::abs(y[j - j0]), std::abs(yn[j])));
          emax = std::max(emax, std::abs(k1[j] - 2.0 * k2[j] + k3[j]));
        }
        norm = std::max(norm, h6 * emax / (atol + rtol * scale));
      } else if (opt_.norm == ErrorNorm::local) {
        for (std::size_t j = j0; j < j1; ++j)
          norm = std::max(norm, std::abs(h6 * (k1[j] - 2.0 * k2[j] + k3[j])) /
                                    (atol + rtol * std::max(std::abs(y[j - j0]), std::abs(yn[j]))));
      } else {
        for (std::size_t j = j0; j < j1; ++j) {
          const double e =
              h6 * (k1[j] - 2.0 * k2[j] + k3[j]) / (atol + rtol * std::max(std::abs(y[j - j0]), std::abs(yn[j])));
          norm += e * e;
        }
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
      const SiteState st{v[i], a[i], s[i]};
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
      h *= std::isfinite(err) ? std::clamp(detail::kSafety * std::pow(err, -1.0 / 3.0), 0.1, 0.5) : 0.25;
    }
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
                       current(3)[i] + b1 * k1_[is] + b2 * k2_[is]};
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

  // Stage 4: the step [t, t + h] is taken; h_dense is the step of its dense-output polynomial. The
  // state moves into y_prev_ (dense output) and ynew_ into the state. Returns whether it ended on the
  // stop time.
  bool accept(double h, double h_dense, bool f_end_valid) {
    double vmax = 0.0;
    if constexpr (!kChain) {
      // The strip: the stage vectors rotate (y_prev ← the state, the state ← ynew) instead of being copied; only
      // the law's A and σ̄, which live in the law, are copied.
      const std::size_t oa = offset(2), m2 = 2 * this->sites_;
      double* fields = const_cast<double*>(fields_ptr());
      std::copy_n(fields, m2, ystate_.data() + oa);
      std::swap(y_prev_, ystate_);
      std::swap(ystate_, ynew_);
      std::copy_n(ystate_.data() + oa, m2, fields);
    } else {
      for (std::size_t f = 0; f < 4; ++f) {
      double* y = current(f);
      const std::size_t o = offset(f), n = block_size(f);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = o + i;
        y_prev_[j] = y[i];
        y[i] = ynew_[j];
      }
      }
    }
    const std::size_t ov = offset(1);
    const double* vc = current(1);
    for (std::size_t i = 0; i < this->sites_; ++i) vmax = std::max({vmax, std::abs(y_prev_[ov + i]), std::abs(vc[i])});
    if constexpr (!kChain) {  // the interface row's node values at once, the rest when asked (sync_bulk)
      std::copy_n(mixed_u().data(), this->sites_, this->u_.data());
      std::copy_n(mixed_v().data(), this->sites_, this->v_.data());
      bulk_stale_ = true;
      bulk_scale_valid_ = false;
    }
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

  // Energy budget over the accepted step [t_prev, t] (docs/performance.md §2): the mechanical energy
  // at t from the state, the work and dissipation by Simpson's rule on the step's dense output (its
  // start, middle and end), so the residual is the integration error of the step (O(rtol)).
  void energy_over_step() {
    if constexpr (kChain) energy_over_step_chain();
    else energy_over_step_body();
  }
  // The strip: the same rule over all dofs (kinetic, elastic, the uniform stress's power on the top face, the
  // drive's on the edge column), the viscous and interfacial power on the interface sites.
  void energy_over_step_body() {
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
  void energy_over_step_chain() {
    EnergyBudget& e = *this->energy_;
    const std::size_t n = this->n_;
    const Bulk& b = this->bulk_;
    const double eta = this->law_.params().eta, sd = b.uniform_stress(), t0 = t_prev_, t1 = this->t_;
    if (en_v_.size() != n) {
      en_v_.assign(n, 0.0);
      en_s_.assign(n, 0.0);
    }
    double visc[3], inter[3], drive[3];
    const double ts[3] = {t0, 0.5 * (t0 + t1), t1};
    for (int q = 0; q < 3; ++q) {
      dense_state(ts[q], Field::slip_rate, en_v_);
      dense_state(ts[q], Field::sigma_bar, en_s_);
      double pv = 0.0, pi = 0.0, pu = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double w = b.node_weight(i), vi = en_v_[i];
        pv += w * eta * vi * vi;
        pi += w * en_s_[i] * vi;
        pu += w * sd * vi;
      }
      visc[q] = pv;
      inter[q] = pi;
      drive[q] = pu + b.driver_velocity() * b.drive_force(ts[q], dense_value(ts[q], Field::slip, 0)) +
                 b.rear_traction() * en_v_[0];
    }
    const double h6 = (t1 - t0) / 6.0;
    e.viscous += h6 * (visc[0] + 4.0 * visc[1] + visc[2]);
    e.interfacial += h6 * (inter[0] + 4.0 * inter[1] + inter[2]);
    e.drive_work += h6 * (drive[0] + 4.0 * drive[1] + drive[2]);
    e.time = t1;
    e.kinetic = this->kinetic_energy(this->v_);
    e.elastic = b.elastic_energy(this->u_);
    e.spring = b.spring_energy(t1, this->u_[0]);
  }

  AdaptiveOptions opt_;
  double t_prev_ = 0.0, h_next_, last_dt_, err_prev_ = 1.0;
  bool started_ = false, f0_valid_ = false;
  std::vector<double> y_prev_, ynew_, f0_, f1_, f2_, k1_, k2_, k3_, tmp_;  // stages [u | v | A | σ̄]
  std::vector<double> k1_prev_, k2_prev_;  // dense output of the last accepted step
  double h_prev_ = 0.0, t_stop_ = -1.0;
  std::vector<std::uint8_t> theta_, theta_prev_;
  std::vector<double> crossings_;
  std::vector<std::pair<double, double>> groups_;  // (θ_i, allowance_i) of the crossings, for group_fraction
  double group_tol_[2] = {0.0, 0.0};               // the tolerances of A and σ̄ of the current trial
  bool group_scales_valid_ = false;
  // W factorization: node elimination coefficients and the Thomas factors of the u system.
  double c_ = 0.0;
  std::vector<double> inv_a1_, q_area_, inv_s1_, c_alpha_v_, q_sigma_, d_coef_, thomas_c_, thomas_inv_;
  std::vector<double> en_v_, en_s_, en_u_;  // energy budget work arrays
  // The strip's mixed representation (Strip::to_mixed, docs/numerics.md §8.6): the first 2 dofs() of ystate_ are the
  // state [u | v] (its tail is the stage rotation's room for A, σ̄: accept); u_, v_ of
  // the core hold the interface row at every step end and the rest when asked, sync_bulk); mass_ and urhs_ the
  // interface row's node masses and its row of the u system's right-hand side (solve_fused).
  std::vector<double> mass_, urhs_, ystate_;
  std::span<const double> mixed_u() const { return std::span<const double>(ystate_).first(this->n_); }
  std::span<const double> mixed_v() const { return std::span<const double>(ystate_).subspan(this->n_, this->n_); }
  bool mixed_valid_ = false;
  mutable bool bulk_stale_ = false;
  mutable std::vector<double> dense_mixed_;
  mutable double bulk_scale_[2] = {0.0, 0.0};  // error_norm_mixed: the scale of u and v from rows j ≥ 1
  mutable bool bulk_scale_valid_ = false;
  mutable std::vector<std::vector<double>> nodes_;
  AdaptiveStats stats_;

  // The mixed state from the node values (at the start, and after set_initial).
  void make_mixed() {
    if constexpr (!kChain) {
      this->bulk_.to_mixed(this->u_, std::span<double>(ystate_).first(this->n_));
      this->bulk_.to_mixed(this->v_, std::span<double>(ystate_).subspan(this->n_, this->n_));
      mixed_valid_ = true;
      bulk_stale_ = false;
      bulk_scale_valid_ = false;
      f0_valid_ = false;
    }
  }
  // The node values of the whole body from the mixed state, when they are behind it.
  void sync_bulk() const {
    if constexpr (!kChain) {
      if (!bulk_stale_ || !mixed_valid_) return;
      auto* self = const_cast<AdaptiveSimulation*>(this);
      this->bulk_.from_mixed(mixed_u(), self->u_);
      this->bulk_.from_mixed(mixed_v(), self->v_);
      bulk_stale_ = false;
    }
  }
};

}  // namespace slipfront::core
