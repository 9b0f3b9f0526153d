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
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

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
inline ImplicitResolution implicit_resolution(const Bulk& bulk, const InterfaceParams& law, double v_event, double dt) {
  ImplicitResolution r;
  r.drive = dt * std::sqrt(bulk.spring_K() / (bulk.rho() * bulk.node_weight(0)));
  r.detach = dt * (1.0 + law.kappa * v_event);
  return r;
}

template <InterfaceLaw Law>
class ImplicitSimulation : public StepperCore<Law> {
  using Core = StepperCore<Law>;

 public:
  static constexpr const char* integrator_name = "implicit";
  static constexpr bool error_control = true;  ///< set_error_control, substeps, max_defect

  ImplicitSimulation(Bulk bulk, Law law, double dt)
      : Core(std::move(bulk), std::move(law), "ImplicitSimulation"), dt_(dt), V_(this->n_, 0.0),
        c0_(this->n_), c1_(this->n_), rhs_(this->n_), cp_(this->n_), trial_(this->n_), c0e_(this->n_), c1e_(this->n_) {
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
  /// Initial slip and slip rate (node velocity V = W = v) of node i.
  void set_initial(std::size_t i, double u, double v) {
    Core::set_initial(i, u, v);
    V_[i] = v;
  }

  void step() {
    if (this->energy_ && std::isnan(this->energy_->mechanical0)) {
      mechanical_now();
      this->energy_->mechanical0 = this->energy_->mechanical();
    }
    yielded_any_ = false;
    vmax_step_ = 0.0;
    substep(this->t_, static_cast<double>(this->steps_ + 1) * dt_, 0);
    this->yielded_ = yielded_any_;
    this->max_v_ = vmax_step_;
    this->t_ = static_cast<double>(++this->steps_) * dt_;
    if (!std::isfinite(this->max_v_)) this->report_non_finite();
  }

 private:
  // One (sub)step [t, t + h]: 1. the law's linearisation, 2. the tridiagonal system for W, 3. with error
  // control, the defect of the linearisation at W (a half step pair instead when too large), 4. u, V
  // from W and the law's own update with W.
  void substep(double t, double t_next, int depth) {
    const double h = depth == 0 ? dt_ : t_next - t;
    forward_sweep(t, h);                                   // 1. interface σ̄' ≈ c0 + c1 W, 2. bulk ...
    solve_trial();                                         //    ... W into trial_
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
    ++substeps_;
    const double u0 = this->u_[0];
    commit(h);  // 4.
    if (this->energy_) work_over_step(t, h, u0);
    yielded_any_ |= this->law_.advance(h, this->slip_rate()).any_yield;
    if (this->energy_) mechanical_now(t_next);
  }

  // max_i |(c0' + c1' W) − (c0 + c1 W)|: the linearisation at the step's own rates W against the one the
  // step used (frozen at the previous rates). Zero where neither the yield state nor the relaxation
  // rate moved; large across a switching or a fast change of |v|.
  double linearisation_defect(double h) {
    core::linearise(this->law_, h, trial_, c0e_, c1e_);
    double d = 0.0;
    for (std::size_t i = 0; i < this->n_; ++i) {
      const double w = trial_[i];
      d = std::max(d, std::abs((c0e_[i] + c1e_[i] * w) - (c0_[i] + c1_[i] * w)));
    }
    return std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
  }

  // Assemble the tridiagonal system for W (multiplied through by the node weight w_i) and eliminate
  // (Thomas, constant off-diagonal −Δt k/2) in one pass over the sites.
  void forward_sweep(double t, double dt) {
    const Bulk& b = this->bulk_;
    const double rho = b.rho(), sd = b.uniform_stress(), eta = this->law_.params().eta;
    const double m = 2.0 * rho / dt + eta, off = -0.5 * dt * b.stiffness(), mass = 2.0 * rho / dt;
    const std::span<const double> sb = this->law_.sigma_bar();
    const double* u = this->u_.data();
    const double drive = b.spring_K() * (b.driver_velocity() * (t + 0.5 * dt) - u[0]) + b.rear_traction();  // F at t^{n+1/2}
    const double half_dt = 0.5 * dt, spring = half_dt * b.spring_K();
    // The forces first (into rhs_), then one loop: each site's linearisation (1.) and its row of the
    // elimination. As a callback of forces() the elimination was not inlined (a call per node, 15% of
    // the fig1 run at dt = 0.02); with the linearisation in a pass of its own, its cost added to the
    // latency of the elimination's chain of divisions instead of hiding behind it (15% again).
    double* r = rhs_.data();
    b.forces(this->slip(), drive, [r](std::size_t i, double force) { r[i] = force; });
    double* cp = cp_.data();
    const auto lin = this->law_.linearisation(dt);
    const double* w_prev = this->v_.data();
    for (std::size_t i = 0; i < this->n_; ++i) {
      lin(i, w_prev[i], c0_[i], c1_[i]);
      const double w = b.node_weight(i);
      const double diag = w * (m + 0.5 * c1_[i]) + (half_dt * b.elastic_diagonal(i) + (i == 0 ? spring : 0.0));
      const double rhs = w * (mass * V_[i] + sd - 0.5 * (sb[i] + c0_[i])) + r[i];
      const double inv = 1.0 / (i == 0 ? diag : diag - off * cp[i - 1]);
      cp[i] = off * inv;
      r[i] = (i == 0 ? rhs : rhs - off * r[i - 1]) * inv;
    }
  }

  // W from the eliminated system (back substitution).
  void solve_trial() {
    const std::size_t n = this->n_;
    double* W = trial_.data();
    W[n - 1] = rhs_[n - 1];
    for (std::size_t i = n - 1; i-- > 0;) W[i] = rhs_[i] - cp_[i] * W[i + 1];
  }

  // The step is taken: W, then u^{n+1} = u^n + Δt W and V^{n+1} = 2W − V^n.
  void commit(double h) {
    const std::size_t n = this->n_;
    double* W = this->v_.data();
    double* u = this->u_.data();
    double vmax = 0.0, check = 0.0;
    for (std::size_t i = n; i-- > 0;) {
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
    e.elastic = this->bulk_.elastic_energy(this->slip());
    e.spring = this->bulk_.spring_energy(t, this->u_[0]);
  }
  void mechanical_now() { mechanical_now(this->t_); }

  // Work over the step with the forces the bulk felt (before the law overwrites σ̄); u0 = u_0^n.
  void work_over_step(double t, double dt, double u0) {
    EnergyBudget& e = *this->energy_;
    const Bulk& b = this->bulk_;
    const std::span<const double> sb = this->law_.sigma_bar(), W = this->slip_rate();
    const double eta = this->law_.params().eta;
    double visc = 0.0, inter = 0.0, uniform = 0.0;
    for (std::size_t i = 0; i < this->n_; ++i) {
      const double w = b.node_weight(i), wi = W[i];
      visc += w * eta * wi * wi;
      inter += w * 0.5 * (sb[i] + c0_[i] + c1_[i] * wi) * wi;
      uniform += w * b.uniform_stress() * wi;
    }
    const double th = t + 0.5 * dt;
    const double f_mean = b.spring_K() * (b.driver_velocity() * th - u0 - 0.5 * dt * W[0]);
    e.viscous += dt * visc;
    e.interfacial += dt * inter;
    e.drive_work += dt * (uniform + b.driver_velocity() * f_mean + b.rear_traction() * W[0]);
  }

  double dt_;
  std::vector<double> V_;                   ///< node velocities V^n (trapezoidal rule)
  std::vector<double> c0_, c1_, rhs_, cp_;  ///< per-step work arrays
  std::vector<double> trial_, c0e_, c1e_;   ///< the step's W before it is taken; the linearisation at it
  double tol_ = 0.0, max_defect_ = 0.0, vmax_step_ = 0.0;
  int max_halvings_ = 0;
  std::int64_t substeps_ = 0;
  bool yielded_any_ = false;
};

}  // namespace slipfront::core
