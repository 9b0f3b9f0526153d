#pragma once
// Explicit time stepping of bulk + interface law (MODEL §1), templated on the law so that the
// continuum law and the discrete ensembles share this code with no virtual call per node.
//
// One step t^n → t^{n+1} (central differences, see docs/numerics.md):
//   1. kick    v^{n−1/2} → v^{n+1/2} from the forces at t^n (elastic, drive, σ̄^n), η v centred
//   2. law     A, σ̄: t^n → t^{n+1} with v^{n+1/2} frozen over the step (exact exponential update)
//   3. drift   u^{n+1} = u^n + Δt v^{n+1/2}
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "continuum/bulk.hpp"
#include "continuum/friction_law.hpp"

namespace slipfront::continuum {

/// A NaN or infinity appeared: reported with the step, the time and the first bad site.
struct NumericalError : std::runtime_error {
  std::int64_t step;
  double time;
  std::size_t site;
  NumericalError(std::int64_t s, double t, std::size_t i, const std::string& what)
      : std::runtime_error("non-finite " + what + " at step " + std::to_string(s) + " (t = " +
                           std::to_string(t) + "), site " + std::to_string(i)),
        step(s), time(t), site(i) {}
};

/// Energy budget (drive work = kinetic + elastic + viscous + interfacial work), accumulated when
/// asked for. Every term holds at the same time `time` = t^n of the last step's start (the kinetic
/// energy at t^n needs v^{n+1/2}); each is second-order accurate in Δt, and so is the residual.
struct EnergyBudget {
  double time = 0;                                      ///< t^n
  double kinetic = 0, elastic = 0, spring = 0;          ///< at t^n
  double drive_work = 0, viscous = 0, interfacial = 0;  ///< integrated over [0, t^n]
  double mechanical0 = std::numeric_limits<double>::quiet_NaN();
  double mechanical() const { return kinetic + elastic + spring; }
  double residual() const { return drive_work - (mechanical() - mechanical0) - viscous - interfacial; }
};

template <class Law>
class Simulation {
 public:
  static constexpr const char* integrator_name = "explicit";
  Simulation(Bulk bulk, Law law, double eta, double dt)
      : bulk_(std::move(bulk)), law_(std::move(law)), eta_(eta), dt_(dt),
        u_(bulk_.nodes(), 0.0), v_(bulk_.nodes(), 0.0), v_prev_(bulk_.nodes(), 0.0) {
    if (law_.size() != bulk_.nodes()) throw std::invalid_argument("Simulation: law and bulk sizes differ");
    if (!(dt > 0.0)) throw std::invalid_argument("Simulation: dt must be > 0");
  }

  // --- state -------------------------------------------------------------------------------
  double time() const { return t0_ + static_cast<double>(steps_) * dt_; }
  std::int64_t steps() const { return steps_; }
  double dt() const { return dt_; }
  const Bulk& bulk() const { return bulk_; }
  const Law& law() const { return law_; }
  Law& law() { return law_; }
  std::span<const double> slip() const { return u_; }
  /// Slip rate of the last step, v^{n−1/2} (before the first step: the initial rate).
  std::span<const double> slip_rate() const { return v_; }
  double drive_force() const { return bulk_.drive_force(time(), u_[0]); }
  double max_slip_rate() const { return max_v_; }
  bool yielded() const { return yielded_; }  ///< some site yielded during the last step

  void set_initial(std::size_t i, double u, double v) {
    u_[i] = u;
    v_[i] = v;
    max_v_ = std::max(max_v_, std::abs(v));
  }
  void track_energy(bool on) { energy_ = on ? std::optional<EnergyBudget>(EnergyBudget{}) : std::nullopt; }
  const std::optional<EnergyBudget>& energy() const { return energy_; }

  // --- the step ------------------------------------------------------------------------------
  void step() {
    v_prev_.swap(v_);  // keep v^{n−1/2} (energy budget)
    kick();
    if (energy_) energy_at_start();
    const std::vector<double>* sb_start = nullptr;
    if (energy_) { sb_buf_.assign(law_.sigma_bar().begin(), law_.sigma_bar().end()); sb_start = &sb_buf_; }
    yielded_ = law_.advance(dt_, v_).any_yield;
    drift();
    ++steps_;
    if (energy_) energy_over_step(*sb_start);
    if (!std::isfinite(max_v_)) report_non_finite();
  }

 private:
  // v^{n+1/2} (ρ + η Δt/2) = v^{n−1/2} (ρ − η Δt/2) + Δt (f_i / w_i + σ_d − σ̄_i)
  void kick() {
    const std::size_t n = u_.size();
    const double dt = dt_, rho = bulk_.rho(), k = bulk_.stiffness(), sd = bulk_.uniform_stress();
    const double damp = rho - 0.5 * eta_ * dt, inv = 1.0 / (rho + 0.5 * eta_ * dt);
    const std::span<const double> sb = law_.sigma_bar();
    const double* u = u_.data();
    const double* vo = v_prev_.data();
    double* vn = v_.data();
    double vmax = 0.0;
    auto update = [&](std::size_t i, double force_per_length) {
      vn[i] = (vo[i] * damp + dt * (force_per_length + sd - sb[i])) * inv;
      vmax = std::max(vmax, std::abs(vn[i]));
      if (!std::isfinite(vn[i])) vmax = std::numeric_limits<double>::infinity();
    };
    if (n == 1) {  // 0D spring block
      update(0, bulk_.drive_force(time(), u[0]) / bulk_.node_weight(0));
    } else {
      const double inv_w_in = 1.0 / bulk_.node_weight(1), inv_w_end = 1.0 / bulk_.node_weight(0);
      update(0, (k * (u[1] - u[0]) + bulk_.drive_force(time(), u[0])) * inv_w_end);
      const double kw = k * inv_w_in;
      double check = 0.0;  // NaN/inf propagate through the sum; std::max would drop a NaN
      for (std::size_t i = 1; i + 1 < n; ++i) {
        const double vi = (vo[i] * damp + dt * (kw * (u[i + 1] - 2.0 * u[i] + u[i - 1]) + sd - sb[i])) * inv;
        vn[i] = vi;
        vmax = std::max(vmax, std::abs(vi));
        check += vi;
      }
      update(n - 1, k * (u[n - 2] - u[n - 1]) * inv_w_end);
      if (!std::isfinite(check)) vmax = std::numeric_limits<double>::infinity();
    }
    max_v_ = vmax;
  }

  void drift() {
    const std::size_t n = u_.size();
    for (std::size_t i = 0; i < n; ++i) u_[i] += dt_ * v_[i];
  }

  // Mechanical energy at t^n with v^n = (v^{n−1/2} + v^{n+1/2})/2.
  void energy_at_start() {
    EnergyBudget& e = *energy_;
    const std::size_t n = u_.size();
    double kin = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double vn = 0.5 * (v_prev_[i] + v_[i]);
      kin += 0.5 * bulk_.rho() * bulk_.node_weight(i) * vn * vn;
    }
    e.time = time();
    e.kinetic = kin;
    e.elastic = bulk_.elastic_energy(u_);
    e.drive_work = acc_drive_;
    e.viscous = acc_viscous_;
    e.interfacial = acc_interfacial_;
    e.spring = bulk_.spring_energy(time(), u_[0]);
    if (std::isnan(e.mechanical0)) e.mechanical0 = e.mechanical();
    f_start_ = bulk_.drive_force(time(), u_[0]);
  }

  // Work and dissipation over [t^n, t^{n+1}] by the midpoint rule on v^{n+1/2}.
  void energy_over_step(const std::vector<double>& sb_start) {
    const std::size_t n = u_.size();
    const std::span<const double> sb = law_.sigma_bar();
    double visc = 0.0, inter = 0.0, uniform = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double w = bulk_.node_weight(i), vi = v_[i];
      visc += w * eta_ * vi * vi;
      inter += w * 0.5 * (sb_start[i] + sb[i]) * vi;
      uniform += w * bulk_.uniform_stress() * vi;
    }
    const double f_end = bulk_.drive_force(time(), u_[0]);
    acc_viscous_ += dt_ * visc;
    acc_interfacial_ += dt_ * inter;
    acc_drive_ += dt_ * (uniform + bulk_.driver_velocity() * 0.5 * (f_start_ + f_end));
  }

  [[noreturn]] void report_non_finite() const {
    for (std::size_t i = 0; i < v_.size(); ++i)
      if (!std::isfinite(v_[i]) || !std::isfinite(u_[i])) throw NumericalError(steps_, time(), i, "slip rate");
    throw NumericalError(steps_, time(), 0, "slip rate");
  }

  Bulk bulk_;
  Law law_;
  double eta_, dt_, t0_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<double> u_, v_, v_prev_;
  double max_v_ = 0.0;
  bool yielded_ = false;
  std::optional<EnergyBudget> energy_;
  std::vector<double> sb_buf_;
  double f_start_ = 0.0;
  double acc_drive_ = 0.0, acc_viscous_ = 0.0, acc_interfacial_ = 0.0;  // over [0, t^{n+1}]
};

}  // namespace slipfront::continuum
