#pragma once
// Adaptive, linearly implicit time stepping of bulk + continuum friction law (MODEL §1), for scenes
// where long quiet stretches (elastic loading, the slow front, healing) alternate with short fast
// ones (the transient front). Same method-of-lines ODE as the explicit scheme (continuum/stepper.hpp):
// the grid, lumped masses, half cells, edge spring and free ends of continuum/bulk.hpp, per node
//   u' = v
//   ρ v' = (elastic_i + F_i)/w_i + σ_d − σ̄_i − η v_i
//   A' = 1 − A − Θ_i κ A |v|               (MODEL §1 friction law)
//   σ̄' = α A v − Θ_i σ̄ |v|
// integrated as one stiff system (docs/performance.md):
//   - a 2-stage Rosenbrock method (Shampine–Reichelt "ode23s": order 2, L-stable, embedded order-3
//     error estimate, order-2 dense output) with the exact Jacobian. The Jacobian is block
//     tridiagonal; each W = I − h d J solve eliminates (v, A, σ̄) node by node and leaves a
//     symmetric tridiagonal system for u (Thomas): O(nodes) per solve, no sparse LU;
//   - error-controlled step sizes (PI controller), by default a max norm per field (ErrorNorm);
//   - Θ piecewise constant inside every step, switched by event location: the zeros of
//     g_i = |σ̄_i + η v_i| − A_i (|σ|/A = 1) are located on the dense output of each accepted step
//     (Illinois regula falsi to 1e-13 in time) and the step ends at the first one, where Θ_i flips
//     (with every other site that has crossed by then). A hysteresis band (switch_band, relative
//     1e-9) keeps a site that just flipped from flipping back at once.
// The explicit scheme stays the reference; this one buys speed at a stated tolerance.
//
// Public API: that of Simulation<FrictionLaw> (stepper.hpp) so the runner can drive either one;
// step() advances one accepted, variable step. Extras: dense output over the last step
// (previous_time(), dense_state()), a stop time, work counters.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "continuum/bulk.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/stepper.hpp"

namespace slipfront::continuum {

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
  double rtol = 1e-3;        ///< relative tolerance of the local error per step (see ErrorNorm)
  double atol = 1e-5;        ///< absolute tolerance (same units as the unknowns)
  double dt_max = 1.0;       ///< largest step
  double dt_initial = 1e-3;  ///< first trial step (shortened automatically if too large)
  double dt_min = 1e-12;     ///< a step below this is reported as a failure (NumericalError)
  ErrorNorm norm = ErrorNorm::field;
  EventEnd event_end = EventEnd::interpolate;
  /// 0: every step ends at the first switching it would cross (exact). > 0: it ends at the last
  /// switching within event_window (time) of the first, flipping all of them there: each switching
  /// is then late by up to event_window (an O(event_window) error the error estimate does not see).
  double event_window = 0.0;
  /// Hysteresis of the Θ switching: a stuck site starts sliding when |σ|/A crosses 1 + band, a
  /// sliding one sticks when it crosses 1 − band (each step ends there, so the band is all the
  /// delay there is: ~band/(d(|σ|/A)/dt), 1e-8 time units for fig1).
  double switch_band = 1e-9;
  void validate() const;     ///< throws ParamError("time.<key>", reason)
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

class AdaptiveSimulation {
 public:
  AdaptiveSimulation(Bulk bulk, FrictionLaw law, double eta, AdaptiveOptions opt);

  // --- state (same meaning as Simulation<FrictionLaw>) -------------------------------------
  double time() const { return t_; }
  std::int64_t steps() const { return stats_.accepted; }
  double dt() const { return last_dt_; }  ///< size of the last accepted step (before any: dt_initial)
  const Bulk& bulk() const { return bulk_; }
  /// A and σ̄ live in the law object between steps: law().set_site() and set_initial() set the
  /// initial state before the first step (Θ is taken from it then); later calls are not supported.
  const FrictionLaw& law() const { return law_; }
  FrictionLaw& law() { return law_; }
  std::span<const double> slip() const { return {y_.data(), n_}; }
  std::span<const double> slip_rate() const { return {y_.data() + n_, n_}; }  ///< v at time()
  double drive_force() const { return bulk_.drive_force(t_, y_[0]); }
  double max_slip_rate() const { return max_v_; }  ///< max_i |v_i| at the two ends of the last step
  bool yielded() const { return yielded_; }        ///< some site had Θ = 1 during the last step
  void set_initial(std::size_t i, double u, double v);
  /// The energy budget is not tracked by this integrator (energy() stays empty).
  void track_energy(bool) {}
  const std::optional<EnergyBudget>& energy() const { return energy_; }

  // --- the step --------------------------------------------------------------------------------
  void step();

  // --- extras ------------------------------------------------------------------------------------
  /// No step will cross t (a scene's t_end, an output time): the step that would is shortened to
  /// end on it exactly. Inactive once reached.
  void set_stop_time(double t) { t_stop_ = t; }
  double previous_time() const { return t_prev_; }  ///< start of the last accepted step
  /// Dense output (order 2) of one field at t ∈ [previous_time(), time()], all nodes.
  void dense_state(double t, Field f, std::span<double> out) const;
  /// Dense output of one value (inline: the runner's tip restriction calls it per node).
  double dense_value(double t, Field f, std::size_t i) const {
    const std::size_t j = static_cast<std::size_t>(f) * n_ + i;
    if (stats_.accepted == 0 || h_prev_ <= 0.0) return y_[j];
    const double th = std::clamp((t - t_prev_) / h_prev_, 0.0, 1.0);
    const double b1 = th * (1.0 - th) * kDenseScale * h_prev_, b2 = th * (th - 2.0 * kGamma) * kDenseScale * h_prev_;
    return y_prev_[j] + b1 * k1_prev_[j] + b2 * k2_prev_[j];
  }
  /// Bound on |target − y_i(t)| over the whole last step, from the dense output's coefficients:
  /// y(θ) = y_prev + h (θ(1 − θ) k1 + θ(θ − 2d) k2)/(1 − 2d), with max |θ(1 − θ)| = 1/4 and
  /// max |θ(θ − 2d)| = 1 − 2d on [0, 1].
  double dense_deviation_bound(Field f, std::size_t i, double target) const {
    const std::size_t j = static_cast<std::size_t>(f) * n_ + i;
    if (stats_.accepted == 0 || h_prev_ <= 0.0) return std::abs(target - y_[j]);
    return std::abs(target - y_prev_[j]) + h_prev_ * (0.25 * kDenseScale * std::abs(k1_prev_[j]) + std::abs(k2_prev_[j]));
  }
  static constexpr double kGamma = 0.29289321881345247560;      ///< d = 1/(2 + √2) of the method
  static constexpr double kDenseScale = 1.0 / (1.0 - 2.0 * kGamma);  ///< 1/(1 − 2d) of its dense output
  /// Θ of each site during the last step (1 sliding, 0 stuck).
  std::span<const std::uint8_t> theta() const { return theta_prev_; }
  const AdaptiveStats& stats() const { return stats_; }
  const AdaptiveOptions& options() const { return opt_; }

 private:
  // y = [u | v | A | σ̄], blocks of n_.
  void load_law_state();
  void store_law_state();
  void start();
  void rhs(double t, const std::vector<double>& y, std::vector<double>& f);
  void rhs_site(std::size_t i, const std::vector<double>& y, std::vector<double>& f) const;
  void factor(double c, const std::vector<double>& y);
  void solve(std::vector<double>& x);  // in place: x ← W⁻¹ x
  // One Rosenbrock step of size h from (t_, y_); fills ynew_, k1_, k2_; returns the error norm.
  double attempt(double h);
  double error_norm(double h) const;
  double trial_step(double& h, bool& rejected);
  double first_switching(double h);
  void end_on_dense_output(double frac, double h);
  bool accept(double h, double h_dense, bool f_end_valid);
  void propose_next(double h, double err, bool rejected);
  double switch_function(std::size_t i, double v, double area, double sb) const;  // e_i, crossing at > 0
  double event_fraction(std::size_t i, double h) const;  // θ ∈ (0,1] where e_i crosses 0 on the dense output
  bool flip_crossed(const std::vector<double>& y);       // flip Θ of every site whose |σ|/A crossed 1

  Bulk bulk_;
  FrictionLaw law_;
  double eta_;
  AdaptiveOptions opt_;
  std::size_t n_;
  double t_ = 0.0, t_prev_ = 0.0, h_next_, last_dt_, err_prev_ = 1.0, max_v_ = 0.0;
  bool started_ = false, yielded_ = false, f0_valid_ = false;
  std::vector<double> y_, y_prev_, ynew_, f0_, f1_, f2_, k1_, k2_, k3_, tmp_;
  std::vector<double> k1_prev_, k2_prev_;  // dense output of the last accepted step
  double h_prev_ = 0.0, t_stop_ = -1.0;
  std::vector<std::uint8_t> theta_, theta_prev_;
  std::vector<double> crossings_;
  // W factorization: node elimination coefficients and the Thomas factors of the u system.
  double c_ = 0.0;
  std::vector<double> inv_a1_, q_area_, inv_s1_, c_alpha_v_, q_sigma_, d_coef_, thomas_c_, thomas_inv_;
  std::optional<EnergyBudget> energy_;
  AdaptiveStats stats_;
};

}  // namespace slipfront::continuum
