#pragma once
// Time stepping of bulk + interface law (docs/model.md §1): the state and accessors every stepper
// shares (StepperCore), and the explicit reference scheme (ExplicitSimulation). The fixed-step
// implicit integrator (core/implicit.hpp) and the adaptive one (core/adaptive.hpp) derive
// from the same core, so the runner, the measurements and the tests read every stepper alike.
//
// One explicit step t^n → t^{n+1} (central differences, docs/numerics.md):
//   1. kick    v^{n−1/2} → v^{n+1/2} from the forces at t^n (elastic, drive, σ̄^n), η v centred
//   2. law     A, σ̄: t^n → t^{n+1} with v^{n+1/2} frozen over the step (the law's exact update)
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

#include "core/archive.hpp"
#include "core/body.hpp"
#include "core/bulk.hpp"
#include "core/law.hpp"

namespace slipfront::core {

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

/// max_i |x_i|, or +inf when any x_i is NaN or infinite (a NaN would be lost by std::max; x − x is 0
/// for finite x and NaN otherwise, and never overflows). Four independent lanes: max is exact in any
/// order, and the sums only tell finite from not.
inline double max_abs_or_inf(std::span<const double> x) {
  double m0 = 0.0, m1 = 0.0, m2 = 0.0, m3 = 0.0, s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  const std::size_t n = x.size(), n4 = n - n % 4;
  for (std::size_t i = 0; i < n4; i += 4) {
    m0 = std::max(m0, std::abs(x[i]));
    m1 = std::max(m1, std::abs(x[i + 1]));
    m2 = std::max(m2, std::abs(x[i + 2]));
    m3 = std::max(m3, std::abs(x[i + 3]));
    s0 += x[i] - x[i];
    s1 += x[i + 1] - x[i + 1];
    s2 += x[i + 2] - x[i + 2];
    s3 += x[i + 3] - x[i + 3];
  }
  for (std::size_t i = n4; i < n; ++i) {
    m0 = std::max(m0, std::abs(x[i]));
    s0 += x[i] - x[i];
  }
  const double m = std::max(std::max(m0, m1), std::max(m2, m3));
  return std::isfinite((s0 + s1) + (s2 + s3)) ? m : std::numeric_limits<double>::infinity();
}

/// Energy budget (drive work = kinetic + elastic + spring + viscous + interfacial work), accumulated
/// when asked for. Every term holds at the same time `time`; each stepper says which (the explicit
/// scheme: t^n, one step behind, since the kinetic energy at t^n needs v^{n+1/2}).
struct EnergyBudget {
  double time = 0;                                      ///< time at which every term holds
  double kinetic = 0, elastic = 0, spring = 0;          ///< at `time`
  double drive_work = 0, viscous = 0, interfacial = 0;  ///< integrated over [0, time]
  double mechanical0 = std::numeric_limits<double>::quiet_NaN();
  double mechanical() const { return kinetic + elastic + spring; }
  double residual() const { return drive_work - (mechanical() - mechanical0) - viscous - interfacial; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar(time, kinetic, elastic, spring, drive_work, viscous, interfacial, mechanical0);
  }
};

/// What every stepper holds and shows: the body (core/body.hpp: the 1D chain by default), the law (which
/// alone holds A and σ̄), displacement and velocity of every degree of freedom of the body, time, step
/// count, and the energy budget when tracked. Only a stepper's step() advances them. Slip and slip rate
/// are the interface's: the first sites() degrees of freedom.
template <InterfaceLaw Law, Body B = Bulk>
class StepperCore {
 public:
  using body_type = B;
  double time() const { return t_; }
  std::int64_t steps() const { return steps_; }
  const B& bulk() const { return bulk_; }
  const Law& law() const { return law_; }
  Law& law() { return law_; }
  std::span<const double> slip() const { return std::span<const double>(u_).first(sites_); }
  /// The slip rate each stepper reports: the rate of its last step (explicit v^{n−1/2}, implicit W)
  /// or the rate at time() (adaptive); before the first step, the initial rate.
  std::span<const double> slip_rate() const { return std::span<const double>(v_).first(sites_); }
  /// Displacement and velocity of every degree of freedom of the body (the strip's interior too).
  std::span<const double> displacement() const { return u_; }
  std::span<const double> velocity() const { return v_; }
  double drive_force() const { return bulk_.drive_force(t_, std::span<const double>(u_)); }
  double max_slip_rate() const { return max_v_; }  ///< max_i |v_i| over the last step
  bool yielded() const { return yielded_; }        ///< some site yielded during the last step
  /// Initial displacement and velocity of degree of freedom i (the law's set_site sets A and σ̄ of the
  /// sites), before the first step.
  void set_initial(std::size_t i, double u, double v) {
    u_[i] = u;
    v_[i] = v;
    if (i < sites_) max_v_ = std::max(max_v_, std::abs(v));
  }
  void track_energy(bool on) { energy_ = on ? std::optional<EnergyBudget>(EnergyBudget{}) : std::nullopt; }
  const std::optional<EnergyBudget>& energy() const { return energy_; }

 protected:
  /// The state every stepper has (checkpoints): slip, slip rate, time, counters, energy, and the law's.
  template <class Ar>
  void serialize_core(Ar& ar) {
    ar(u_, v_, t_, max_v_, steps_, yielded_, energy_);
    if constexpr (Law::hooks.checkpoints) law_.serialize(ar);
    else throw ArchiveError("this interface law cannot be checkpointed");
  }

  StepperCore(B bulk, Law law, const char* who)
      : bulk_(std::move(bulk)), law_(std::move(law)), n_(bulk_.dofs()), sites_(bulk_.sites()), u_(n_, 0.0), v_(n_, 0.0) {
    if (law_.size() != sites_) throw std::invalid_argument(std::string(who) + ": law and body sizes differ");
  }
  [[noreturn]] void report_non_finite() const {
    for (std::size_t i = 0; i < n_; ++i)
      if (!std::isfinite(u_[i]) || !std::isfinite(v_[i])) throw NumericalError(steps_, t_, i, "slip rate");
    throw NumericalError(steps_, t_, 0, "slip rate");
  }
  /// Kinetic energy of node velocities V (all degrees of freedom).
  double kinetic_energy(std::span<const double> V) const { return bulk_.kinetic_energy(V); }

  B bulk_;
  Law law_;
  std::size_t n_, sites_;      ///< degrees of freedom, interface sites (equal on the chain)
  std::vector<double> u_, v_;  ///< displacement and velocity per degree of freedom
  double t_ = 0.0, max_v_ = 0.0;
  std::int64_t steps_ = 0;
  bool yielded_ = false;
  std::optional<EnergyBudget> energy_;
};

/// The explicit reference scheme (central differences, the wave stability limit of the body's stable_dt).
template <InterfaceLaw Law, Body B = Bulk>
class ExplicitSimulation : public StepperCore<Law, B> {
  using Core = StepperCore<Law, B>;

 public:
  static constexpr const char* integrator_name = "explicit";
  static constexpr bool error_control = false;  ///< set_error_control, substeps (implicit only)
  ExplicitSimulation(B bulk, Law law, double dt)
      : Core(std::move(bulk), std::move(law), "ExplicitSimulation"), dt_(dt), v_prev_(this->n_, 0.0) {
    if (!(dt > 0.0)) throw std::invalid_argument("ExplicitSimulation: dt must be > 0");
  }
  double dt() const { return dt_; }
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("explicit");
    this->serialize_core(ar);
    ar(acc_drive_, acc_viscous_, acc_interfacial_);
  }

  void step() {
    v_prev_.swap(this->v_);  // keep v^{n−1/2}
    kick();                     // v^{n+1/2}
    if (this->energy_) energy_at_start();
    this->yielded_ = this->law_.advance(dt_, this->slip_rate()).any_yield;
    drift();
    this->t_ = static_cast<double>(++this->steps_) * dt_;
    if (this->energy_) energy_over_step();
    if (!std::isfinite(this->max_v_)) this->report_non_finite();
  }

 private:
  // v^{n−1/2} → v^{n+1/2} from the forces at t^n (the body's kick: chain, core/bulk.hpp; strip, core/strip.hpp)
  void kick() {
    this->bulk_.kick(dt_, this->law_.params().eta, this->drive_force(), this->u_, this->law_.sigma_bar(), v_prev_,
                     this->v_);
    // max|v| in a second pass over v: accumulators captured by the kick's callback would live in memory
    // (a store through vn might alias them), one store-reload per node: the fig1 run was 25% slower.
    // The interface's slip rates only (the strip's interior is not a slip rate); a non-finite value
    // inside the strip reaches the interface within steps.
    this->max_v_ = max_abs_or_inf(this->slip_rate());
  }

  void drift() {
    double* u = this->u_.data();
    const double* v = this->v_.data();
    for (std::size_t i = 0; i < this->n_; ++i) u[i] += dt_ * v[i];
  }

  // Mechanical energy at t^n with v^n = (v^{n−1/2} + v^{n+1/2})/2; remembers σ̄^n and F^n for the work.
  void energy_at_start() {
    EnergyBudget& e = *this->energy_;
    const auto v = this->velocity();
    mid_.resize(this->n_);
    for (std::size_t i = 0; i < this->n_; ++i) mid_[i] = 0.5 * (v_prev_[i] + v[i]);
    e.time = this->t_;
    e.kinetic = this->kinetic_energy(mid_);
    e.elastic = this->bulk_.elastic_energy(this->displacement());
    e.spring = this->bulk_.spring_energy(this->t_, this->displacement());
    e.drive_work = acc_drive_;
    e.viscous = acc_viscous_;
    e.interfacial = acc_interfacial_;
    if (std::isnan(e.mechanical0)) e.mechanical0 = e.mechanical();
    f_start_ = this->drive_force();
    const auto sb = this->law_.sigma_bar();
    sb_start_.assign(sb.begin(), sb.end());
  }

  // Work and dissipation over [t^n, t^{n+1}] by the midpoint rule on v^{n+1/2}.
  void energy_over_step() {
    const std::span<const double> sb = this->law_.sigma_bar(), v = this->slip_rate();
    const double eta = this->law_.params().eta;
    double visc = 0.0, inter = 0.0;
    for (std::size_t i = 0; i < this->sites_; ++i) {
      const double w = this->bulk_.interface_weight(i), vi = v[i];
      visc += w * eta * vi * vi;
      inter += w * 0.5 * (sb_start_[i] + sb[i]) * vi;
    }
    const double uniform = this->bulk_.uniform_power(this->velocity());
    acc_viscous_ += dt_ * visc;
    acc_interfacial_ += dt_ * inter;
    acc_drive_ += dt_ * (uniform + this->bulk_.driver_velocity() * 0.5 * (f_start_ + this->drive_force()) +
                         this->bulk_.rear_traction() * this->bulk_.edge_slip(this->velocity()));
  }

  double dt_;
  std::vector<double> v_prev_;          ///< v^{n−1/2} during the step
  std::vector<double> mid_, sb_start_;  ///< energy budget work arrays
  double f_start_ = 0.0, acc_drive_ = 0.0, acc_viscous_ = 0.0, acc_interfacial_ = 0.0;
};

}  // namespace slipfront::core
