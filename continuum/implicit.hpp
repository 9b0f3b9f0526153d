#pragma once
// Fixed-step implicit time stepping of bulk + interface law (issue 5): the same step contract as the
// explicit Simulation<Law> (any law: the continuum FrictionLaw and the discrete ensembles alike), but
// with no wave stability limit, so the step is chosen by accuracy (docs/numerics.md).
//
// One step t^n → t^{n+1} = t^n + Δt, unknown W_i = the slip rate frozen over the step (the law's
// contract), node velocities V by the trapezoidal rule (Newmark average acceleration):
//   u^{n+1} = u^n + Δt W,   V^{n+1} = 2W − V^n,
//   ρ w_i (V^{n+1} − V^n)/Δt = k D(u^n + u^{n+1})/2 + F̄ + w_i (σ_d − (σ̄^n + σ̄^{n+1})/2 − η W)
// with F̄ = K (v_d t^{n+1/2} − (u_0^n + u_0^{n+1})/2) the mean drive force. The interface stress at
// t^{n+1} enters linearised: σ̄^{n+1}_i ≈ c0_i + c1_i W_i, the law's exact update over the step with
// the yield state Θ_i (or the overloaded fraction Y_i) and the relaxation rate Θ|v| frozen at the
// previous step's W (the source α Ā W stays linear in W). That makes one symmetric, diagonally
// dominant tridiagonal system per step (Thomas), unconditionally stable for the elastic waves and for
// the interface stiffness α. Then the law advances with W exactly as in the explicit scheme (its own
// yield test, its own random draws) and u, V follow. Second order in Δt for smooth solutions; through
// a threshold switching the yield state of the linearisation lags by one step (first order there,
// as in the explicit scheme).
//
// Energy (when tracked): the trapezoidal rule closes the discrete budget exactly — drive work =
// kinetic + elastic + spring + viscous + interfacial work to round-off, with the interfacial work
// that of the stress the bulk felt, (σ̄^n + c0 + c1 W)/2.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "continuum/bulk.hpp"
#include "continuum/exact_update.hpp"
#include "continuum/friction_law.hpp"
#include "continuum/stepper.hpp"

namespace slipfront::continuum {

/// Laws that know the overloaded fraction Y_i of their attached contacts (the count representation);
/// the others are linearised with the continuum yield test Θ_i (mean threshold 1).
template <class Law>
concept KnowsOverloadedFraction = requires(const Law& l, std::size_t i, double v) {
  { l.overloaded_fraction(i, v) } -> std::convertible_to<double>;
};

template <class Law>
class ImplicitSimulation {
  struct StepConstants {
    double alpha, kappa, eta;
    double e1, w1;     ///< e^{−Δt} and (1 − e^{−Δt}): A' of a site with no overloaded contact
    double s_min;      ///< weakest threshold (1 for the continuum law)
  };

 public:
  static constexpr const char* integrator_name = "implicit";

  ImplicitSimulation(Bulk bulk, Law law, double eta, double dt)
      : bulk_(std::move(bulk)), law_(std::move(law)), eta_(eta), dt_(dt), u_(bulk_.nodes(), 0.0),
        V_(bulk_.nodes(), 0.0), W_(bulk_.nodes(), 0.0), c0_(bulk_.nodes()), c1_(bulk_.nodes()),
        rhs_(bulk_.nodes()), cp_(bulk_.nodes()) {
    if (law_.size() != bulk_.nodes()) throw std::invalid_argument("ImplicitSimulation: law and bulk sizes differ");
    if (!(dt > 0.0)) throw std::invalid_argument("ImplicitSimulation: dt must be > 0");
  }

  // --- state (the interface of Simulation<Law>) ------------------------------------------------
  double time() const { return static_cast<double>(steps_) * dt_; }
  std::int64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  const Bulk& bulk() const { return bulk_; }
  const Law& law() const { return law_; }
  Law& law() { return law_; }
  std::span<const double> slip() const { return u_; }
  /// Slip rate of the last step, W (before the first step: the initial rate).
  std::span<const double> slip_rate() const { return W_; }
  /// Node velocities V^n at t^n (trapezoidal rule).
  std::span<const double> node_velocity() const { return V_; }
  double drive_force() const { return bulk_.drive_force(time(), u_[0]); }
  double max_slip_rate() const { return max_v_; }
  bool yielded() const { return yielded_; }

  void set_initial(std::size_t i, double u, double v) {
    u_[i] = u;
    V_[i] = W_[i] = v;
    max_v_ = std::max(max_v_, std::abs(v));
  }
  void track_energy(bool on) { energy_ = on ? std::optional<EnergyBudget>(EnergyBudget{}) : std::nullopt; }
  const std::optional<EnergyBudget>& energy() const { return energy_; }

  // --- the step ---------------------------------------------------------------------------------
  void step() {
    if (energy_ && std::isnan(energy_->mechanical0)) {
      mechanical_now();
      energy_->mechanical0 = energy_->mechanical();
    }
    const double u0 = u_[0];
    forward_sweep();
    back_substitution();
    if (energy_) work_over_step(u0);
    yielded_ = law_.advance(dt_, W_).any_yield;
    ++steps_;
    if (energy_) mechanical_now();
    if (!std::isfinite(max_v_)) report_non_finite();
  }

 private:
  // σ̄^{n+1}_i ≈ c0_i + c1_i W_i: the law's update with Θ_i (Y_i) and |v| frozen at the last W.
  // Sites below the weakest threshold (the stuck majority) cost no exponential and no call.
  void linearise(std::size_t i, double a, double sb, const StepConstants& k) {
    const double wp = W_[i];
    double y = 0.0;
    if (wp != 0.0 && contact_stress(sb + k.eta * wp, a) > k.s_min) {
      if constexpr (KnowsOverloadedFraction<Law>) y = law_.overloaded_fraction(i, wp);
      else y = 1.0;
    }
    if (y == 0.0) {  // no relaxation: σ̄' = σ̄ + α Ā W Δt
      c0_[i] = sb;
      c1_[i] = k.alpha * 0.5 * (a + (a * k.e1 + k.w1)) * dt_;
    } else {
      const double speed = std::abs(wp), lam = y * speed;
      const double a_new = relax(a, 1.0, 1.0 + y * k.kappa * speed, dt_);
      c0_[i] = sb * std::exp(-lam * dt_);
      c1_[i] = k.alpha * 0.5 * (a + a_new) * relax_weight(lam, dt_);
    }
  }

  // Linearise, assemble the tridiagonal system for W (multiplied through by the node weight w_i)
  // and eliminate (Thomas, constant off-diagonal −Δt k/2) in one pass over the sites.
  void forward_sweep() {
    const std::size_t n = u_.size();
    const auto& p = law_.params();
    StepConstants kc{p.alpha, p.kappa, p.eta, std::exp(-dt_), relax_weight(1.0, dt_), 1.0};
    if constexpr (requires { law_.thresholds(); }) kc.s_min = law_.thresholds().front();
    const double dt = dt_, rho = bulk_.rho(), k = bulk_.stiffness(), sd = bulk_.uniform_stress();
    const double m = 2.0 * rho / dt + eta_, off = -0.5 * dt * k;
    const std::span<const double> area = law_.contact_area(), sb = law_.sigma_bar();
    const double* u = u_.data();
    const double mass = 2.0 * rho / dt;
    auto row = [&](std::size_t i, double w, double diag_extra, double elastic) {
      linearise(i, area[i], sb[i], kc);
      const double diag = w * (m + 0.5 * c1_[i]) + diag_extra;
      const double rhs = w * (mass * V_[i] + sd - 0.5 * (sb[i] + c0_[i])) + elastic;
      const double inv = 1.0 / (i == 0 ? diag : diag - off * cp_[i - 1]);
      cp_[i] = off * inv;
      rhs_[i] = (i == 0 ? rhs : rhs - off * rhs_[i - 1]) * inv;
    };
    const double K = bulk_.spring_K(), drive = K * (bulk_.driver_velocity() * (time() + 0.5 * dt) - u[0]);
    if (n == 1) {  // 0D spring block: no elastic neighbour
      row(0, bulk_.node_weight(0), 0.5 * dt * K, drive);
      return;
    }
    const double w_end = bulk_.node_weight(0), w_in = bulk_.node_weight(1), half = 0.5 * dt * k;
    row(0, w_end, half + 0.5 * dt * K, k * (u[1] - u[0]) + drive);
    for (std::size_t i = 1; i + 1 < n; ++i) row(i, w_in, 2.0 * half, k * (u[i + 1] - 2.0 * u[i] + u[i - 1]));
    row(n - 1, w_end, half, k * (u[n - 2] - u[n - 1]));
  }

  // W from the eliminated system, then u^{n+1} = u^n + Δt W and V^{n+1} = 2W − V^n.
  void back_substitution() {
    const std::size_t n = u_.size();
    double vmax = 0.0, check = 0.0;
    auto update = [&](std::size_t i, double w) {
      W_[i] = w;
      u_[i] += dt_ * w;
      V_[i] = 2.0 * w - V_[i];
      vmax = std::max(vmax, std::abs(w));
      check += w;
    };
    update(n - 1, rhs_[n - 1]);
    for (std::size_t i = n - 1; i-- > 0;) update(i, rhs_[i] - cp_[i] * W_[i + 1]);
    max_v_ = std::isfinite(check) ? vmax : std::numeric_limits<double>::infinity();
  }

  void mechanical_now() {
    EnergyBudget& e = *energy_;
    const std::size_t n = u_.size();
    double kin = 0.0;
    for (std::size_t i = 0; i < n; ++i) kin += 0.5 * bulk_.rho() * bulk_.node_weight(i) * V_[i] * V_[i];
    e.time = time();
    e.kinetic = kin;
    e.elastic = bulk_.elastic_energy(u_);
    e.spring = bulk_.spring_energy(time(), u_[0]);
  }

  // Work over the step with the forces the bulk felt (before the law overwrites σ̄); u0 = u_0^n.
  void work_over_step(double u0) {
    EnergyBudget& e = *energy_;
    const std::span<const double> sb = law_.sigma_bar();
    double visc = 0.0, inter = 0.0, uniform = 0.0;
    for (std::size_t i = 0; i < u_.size(); ++i) {
      const double w = bulk_.node_weight(i), wi = W_[i];
      visc += w * eta_ * wi * wi;
      inter += w * 0.5 * (sb[i] + c0_[i] + c1_[i] * wi) * wi;
      uniform += w * bulk_.uniform_stress() * wi;
    }
    const double th = time() + 0.5 * dt_;
    const double f_mean = bulk_.spring_K() * (bulk_.driver_velocity() * th - u0 - 0.5 * dt_ * W_[0]);
    e.viscous += dt_ * visc;
    e.interfacial += dt_ * inter;
    e.drive_work += dt_ * (uniform + bulk_.driver_velocity() * f_mean);
  }

  [[noreturn]] void report_non_finite() const {
    for (std::size_t i = 0; i < W_.size(); ++i)
      if (!std::isfinite(W_[i]) || !std::isfinite(u_[i])) throw NumericalError(steps_, time(), i, "slip rate");
    throw NumericalError(steps_, time(), 0, "slip rate");
  }

  Bulk bulk_;
  Law law_;
  double eta_, dt_;
  std::int64_t steps_ = 0;
  std::vector<double> u_, V_, W_;
  std::vector<double> c0_, c1_, rhs_, cp_;  // per-step work arrays
  double max_v_ = 0.0;
  bool yielded_ = false;
  std::optional<EnergyBudget> energy_;
};

}  // namespace slipfront::continuum
