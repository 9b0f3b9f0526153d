#pragma once
// Fixed-step implicit time stepping of bulk + interface law (issue 5): any InterfaceLaw (the continuum
// FrictionLaw and the discrete ensembles alike), with no wave stability limit, so the step is chosen
// by accuracy (docs/numerics.md §7).
//
// One step t^n → t^{n+1} = t^n + Δt, unknown W_i = the slip rate frozen over the step (the law's
// contract), node velocities V by the trapezoidal rule (Newmark average acceleration):
//   u^{n+1} = u^n + Δt W,   V^{n+1} = 2W − V^n,
//   ρ w_i (V^{n+1} − V^n)/Δt = (F(u^n) + F(u^{n+1}))_i/2 + w_i (σ_d − (σ̄^n + σ̄^{n+1})/2 − η W)
// with F the bulk's force (Bulk::forces; the drive at t^{n+1/2}). The interface stress at t^{n+1}
// enters linearised, σ̄^{n+1}_i ≈ c0_i + c1_i W_i: the law's own update over the step with its yield
// state (Θ_i, or the overloaded fraction Y_i) and relaxation rate frozen at the previous step's W
// (InterfaceLaw::linearisation). That makes one symmetric, diagonally dominant tridiagonal system per step,
//   [w_i (2ρ/Δt + η + c1_i/2) + Δt S_ii/2] W_i − (Δt k/2)(W_{i−1} + W_{i+1})
//       = w_i (2ρ V_i/Δt + σ_d − (σ̄_i + c0_i)/2) + F_i(u^n),
// solved by Thomas elimination: unconditionally stable for the elastic waves and for the interface
// stiffness α. Then the law advances with W exactly as in the explicit scheme (its own yield test, its
// own random draws) and u, V follow. Second order in Δt for smooth solutions; through a threshold
// switching the yield state of the linearisation lags by one step (first order there, as in the
// explicit scheme).
//
// Energy (when tracked): the trapezoidal rule closes the discrete budget exactly — drive work =
// kinetic + elastic + spring + viscous + interfacial work to round-off, with the interfacial work
// that of the stress the bulk felt, (σ̄^n + c0 + c1 W)/2; every term holds at time().
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/body.hpp"
#include "core/bulk.hpp"
#include "core/law.hpp"
#include "core/stepper.hpp"

namespace slipfront::core {

/// What a fixed implicit step must resolve (docs/numerics.md §7), checked before a run (Scene::validate):
///   drive     Δt · sqrt(K / (ρ w_0)) ≤ 1: the drive spring's oscillation of the edge node, which the
///             trapezoidal rule neither resolves nor damps beyond that (fig1: 0.63 at Δt = 0.02)
///   detach    Δt · (1 + κ v_event) ≤ 0.3: the contact turnover at the slip rate that defines the
///             measured events, over which the step's linearised interface stress lags (fig1: 0.1)
/// Past either bound the integrator gives wrong events with no other sign (issue 10: κ = 100, η = 0.01
/// at Δt = 0.02 reports a transient that does not exist; K = 10³ doubles c_transient).
struct ImplicitResolution {
  double drive = 0.0, detach = 0.0;
  static constexpr double drive_bound = 1.0, detach_bound = 0.3;
  bool ok() const { return drive <= drive_bound && detach <= detach_bound; }
};
template <Body B>
ImplicitResolution implicit_resolution(const B& bulk, const InterfaceParams& law, double v_event, double dt) {
  ImplicitResolution r;
  r.drive = dt * std::sqrt(bulk.spring_K() / bulk.edge_mass());
  r.detach = dt * (1.0 + law.kappa * v_event);
  return r;
}

template <InterfaceLaw Law, Body B = Bulk>
class ImplicitSimulation : public StepperCore<Law, B> {
  using Core = StepperCore<Law, B>;

 public:
  static constexpr const char* integrator_name = "implicit";
  static constexpr bool error_control = true;  ///< set_error_control, substeps, max_defect

  ImplicitSimulation(B bulk, Law law, double dt)
      : Core(std::move(bulk), std::move(law), "ImplicitSimulation"), dt_(dt), V_(this->n_, 0.0),
        c0_(this->sites_), c1_(this->sites_), trial_(this->n_), c0e_(this->sites_), c1e_(this->sites_) {
    if (!(dt > 0.0)) throw std::invalid_argument("ImplicitSimulation: dt must be > 0");
  }
  /// Error control around switchings (docs/numerics.md §7): a step whose linearisation, re-evaluated at
  /// the step's own slip rates, predicts an interface stress differing by more than `tolerance` (stress
  /// units: the contact strength is 1) from the one the step used, is redone as two half steps, down to
  /// dt / 2^max_halvings. 0: off (every step is one step).
  void set_error_control(double tolerance, int max_halvings) {
    tol_ = tolerance;
    max_halvings_ = max_halvings;
  }
  /// Largest linearisation defect of an accepted (sub)step, and how many substeps were taken in all.
  double max_defect() const { return max_defect_; }
  std::int64_t substeps() const { return substeps_; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("implicit");
    this->serialize_core(ar);
    ar(V_, max_defect_, substeps_);
  }
  double dt() const { return dt_; }
  /// Initial displacement and velocity (node velocity V = W = v) of degree of freedom i.
  void set_initial(std::size_t i, double u, double v) {
    Core::set_initial(i, u, v);
    V_[i] = v;
  }

  void step() {
    start_energy();
    yielded_any_ = false;
    vmax_step_ = 0.0;
    substep(this->t_, static_cast<double>(this->steps_ + 1) * dt_, 0);
    this->yielded_ = yielded_any_;
    this->max_v_ = vmax_step_;
    this->t_ = static_cast<double>(++this->steps_) * dt_;
    if (!std::isfinite(this->max_v_)) this->report_non_finite();
  }

 protected:
  // (protected: the step-controlled integrator, core/leap.hpp, takes its steps from these parts)
  // One (sub)step [t, t + h]: 1. the law's linearisation, 2. the body's linear system for W, 3. with
  // error control, the defect of the linearisation at W (a half step pair instead when too large), 4. u,
  // V from W and the law's own update with W.
  void substep(double t, double t_next, int depth) {
    const double h = depth == 0 ? dt_ : t_next - t;
    solve_trial(t, h);                                     // 1. interface σ̄' ≈ c0 + c1 W, 2. W into trial_
    if (tol_ > 0.0) {
      const double defect = linearisation_defect(h);       // 3.
      if (defect > tol_ && depth < max_halvings_) {
        const double mid = t + 0.5 * h;
        substep(t, mid, depth + 1);
        substep(mid, t_next, depth + 1);
        return;
      }
      max_defect_ = std::max(max_defect_, defect);
    }
    accept_trial(t, h, t_next);  // 4.
  }

  // The budget's reference energy, at the first step (a budget only when tracked).
  void start_energy() {
    if (this->energy_ && std::isnan(this->energy_->mechanical0)) {
      mechanical_now();
      this->energy_->mechanical0 = this->energy_->mechanical();
    }
  }

  // The trial W (in trial_) taken as the (sub)step [t, t + h] ending at t_next: u, V from W, the work over it,
  // the law's own update with W (its yield flag into yielded_any_), the energy at t_next.
  void accept_trial(double t, double h, double t_next) {
    ++substeps_;
    const double u0 = this->bulk_.edge_slip(this->displacement());
    commit(h);
    if (this->energy_) work_over_step(t, h, u0);
    yielded_any_ |= this->law_.advance(h, this->slip_rate()).any_yield;
    if (this->energy_) mechanical_now(t_next);
  }

  // max_i |(c0' + c1' W) − (c0 + c1 W)|: the linearisation at the step's own rates W against the one the
  // step used (frozen at the previous rates). Zero where neither the yield state nor the relaxation
  // rate moved; large across a switching or a fast change of |v|.
  double linearisation_defect(double h) {
    core::linearise(this->law_, h, std::span<const double>(trial_).first(this->sites_), c0e_, c1e_);
    double d = 0.0;
    for (std::size_t i = 0; i < this->sites_; ++i) {
      const double w = trial_[i];
      d = std::max(d, std::abs((c0e_[i] + c1e_[i] * w) - (c0_[i] + c1_[i] * w)));
    }
    return std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
  }

  // The body's system for W with the law's linearisation on the interface (Bulk::implicit_solve: one
  // tridiagonal elimination with the linearisation inside its loop; Strip::implicit_solve: preconditioned
  // conjugate gradients), started from the previous step's W.
  void solve_trial(double t, double dt) {
    std::copy(this->v_.begin(), this->v_.end(), trial_.begin());  // an iterative solve's first guess
    this->bulk_.implicit_solve(this->law_.linearisation(dt), this->slip_rate(), c0_, c1_, t, dt, this->law_.params().eta,
                               this->displacement(), V_, this->law_.sigma_bar(), trial_);
  }

  // The step is taken: W, then u^{n+1} = u^n + Δt W and V^{n+1} = 2W − V^n.
  // The slip rates' maximum and finiteness are the interface's (the first sites_ degrees of freedom).
  void commit(double h) {
    const std::size_t n = this->n_;
    double* W = this->v_.data();
    double* u = this->u_.data();
    for (std::size_t i = n; i-- > this->sites_;) {
      const double w = trial_[i];
      W[i] = w;
      u[i] += h * w;
      V_[i] = 2.0 * w - V_[i];
    }
    double vmax = 0.0, check = 0.0;
    for (std::size_t i = this->sites_; i-- > 0;) {
      const double w = trial_[i];
      W[i] = w;
      u[i] += h * w;
      V_[i] = 2.0 * w - V_[i];
      vmax = std::max(vmax, std::abs(w));
      check += w;
    }
    vmax_step_ = std::max(vmax_step_, std::isfinite(check) ? vmax : std::numeric_limits<double>::infinity());
  }

  void mechanical_now(double t) {
    EnergyBudget& e = *this->energy_;
    e.time = t;
    e.kinetic = this->kinetic_energy(V_);
    e.elastic = this->bulk_.elastic_energy(this->displacement());
    e.spring = this->bulk_.spring_energy(t, this->displacement());
  }
  void mechanical_now() { mechanical_now(this->t_); }

  // Work over the step with the forces the bulk felt (before the law overwrites σ̄); u0 = the edge slip
  // the spring saw at t^n (Body::edge_slip).
  void work_over_step(double t, double dt, double u0) {
    EnergyBudget& e = *this->energy_;
    const B& b = this->bulk_;
    const std::span<const double> sb = this->law_.sigma_bar(), W = this->slip_rate();
    const double eta = this->law_.params().eta;
    double visc = 0.0, inter = 0.0;
    for (std::size_t i = 0; i < this->sites_; ++i) {
      const double w = b.interface_weight(i), wi = W[i];
      visc += w * eta * wi * wi;
      inter += w * 0.5 * (sb[i] + c0_[i] + c1_[i] * wi) * wi;
    }
    const double uniform = b.uniform_power(this->velocity()), w0 = b.edge_slip(this->velocity());
    const double th = t + 0.5 * dt;
    const double f_mean = b.spring_K() * (b.driver_velocity() * th - u0 - 0.5 * dt * w0);
    e.viscous += dt * visc;
    e.interfacial += dt * inter;
    e.drive_work += dt * (uniform + b.driver_velocity() * f_mean + b.rear_traction() * w0);
  }

  double dt_;
  std::vector<double> V_;                   ///< node velocities V^n (trapezoidal rule)
  std::vector<double> c0_, c1_;             ///< the step's linearisation per site
  std::vector<double> trial_, c0e_, c1e_;   ///< the step's W before it is taken; the linearisation at it
  double tol_ = 0.0, max_defect_ = 0.0, vmax_step_ = 0.0;
  int max_halvings_ = 0;
  std::int64_t substeps_ = 0;
  bool yielded_any_ = false;
};

}  // namespace slipfront::core
