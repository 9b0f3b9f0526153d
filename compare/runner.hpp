#pragma once
// Runs one model on one scene: the loop that drives a stepper (1D, spring block) or the law alone
// (imposed slip rate), feeds the shared measurements (compare/measure.hpp) and hands what the scene
// asks to store to the recorder (compare/record.hpp). Templated on the interface law and the stepper
// so the continuum and discrete models, and the three integrators, share every line of it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "compare/contacts.hpp"
#include "compare/fit.hpp"
#include "compare/measure.hpp"
#include "compare/record.hpp"
#include "compare/run_control.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "core/adaptive.hpp"
#include "core/bulk.hpp"
#include "continuum/friction_law.hpp"
#include "core/implicit.hpp"
#include "core/law.hpp"
#include "continuum/steady_front.hpp"
#include "core/stepper.hpp"
#include "discrete/contact_stats.hpp"

namespace slipfront::compare {

/// What a checkpoint of a model run is written after: the state of the scene run around it (the models
/// already finished), so that the whole run can be resumed.
using CheckpointHeader = std::function<void(core::Archive&)>;

/// The time step a fixed-step scene will use: time.dt, or time.cfl × the explicit limit, shortened so
/// that t_end is a whole number of steps.
double dynamic_time_step(const Scene& s);
/// The number of fixed steps to t_end (dynamic_time_step); throws core::ParamError naming
/// time.t_end when it would not fit a 64-bit count (the run could not even start).
std::int64_t fixed_step_count(const Scene& s);

/// Slip-rate grid of an imposed-rate sweep (log spaced, docs/model.md §4 friction_law).
std::vector<double> sweep_rates(const core::DriveParams& d);

/// Homogeneous loading with drive.start = "steady_front": the steady front at σ_d (docs/model.md §6),
/// solved by continuum::solve_steady_front; nothing otherwise. Throws core::ParamError naming
/// drive.sigma_d when there is no front there.
std::optional<continuum::SteadyFront> front_start(const Scene& s);

// --- the integrator, chosen in one place --------------------------------------------------------
/// Tags of time.integrator: Tag::stepper<Law> is the stepper class for a law. The adaptive integrator
/// advances deterministic rate laws (core::SmoothLaw); a stochastic law runs on the explicit
/// scheme then (it has no rates to integrate), alongside on the same scene.
struct ExplicitTag {
  template <class Law>
  using stepper = core::ExplicitSimulation<Law>;
};
struct ImplicitTag {
  template <class Law>
  using stepper = core::ImplicitSimulation<Law>;
};
namespace detail {
template <class Law, bool Smooth = core::SmoothLaw<Law>>
struct AdaptiveStepper {
  using type = core::ExplicitSimulation<Law>;
};
template <class Law>
struct AdaptiveStepper<Law, true> {
  using type = core::AdaptiveSimulation<Law>;
};
}  // namespace detail
struct AdaptiveTag {
  template <class Law>
  using stepper = typename detail::AdaptiveStepper<Law>::type;
};
/// Calls f(Tag{}) for the scene's time.integrator.
template <class F>
decltype(auto) with_integrator(const Scene& s, F&& f) {
  switch (s.time.integrator) {
    case core::Integrator::implicit_trapezoidal: return f(ImplicitTag{});
    case core::Integrator::adaptive_rosenbrock: return f(AdaptiveTag{});
    case core::Integrator::central_difference: break;
  }
  return f(ExplicitTag{});
}

/// Steppers with dense output (the adaptive integrator): measurements and records at exact times.
template <class S>
concept DenseStepper = requires(const S& sim, double t, std::span<double> out) {
  sim.previous_time();
  sim.dense_state(t, core::Field::slip_rate, out);
};

namespace detail {

template <class Law>
void store_contacts(const Law& law, ModelResult& r) {
  auto tables = law.contact_tables();
  for (auto& [name, col] : tables.columns) r.contacts[name] = std::move(col);
  for (auto& [name, tab] : tables.tables) r.contacts_2d[name] = Table2D{tab.cols, std::move(tab.data)};
}

// docs/model.md §1 initial state: at rest and stuck (edge loading, spring block: u = v = 0, A = 1,
// σ̄ = 0), or, under homogeneous loading, the stuck state A = 1, σ̄ = σ_d, u = σ_d/α with a nucleation
// patch 0 ≤ x < ℓ_n in steady sliding at σ_d on the strengthening branch — or the solved steady front
// with its tip at drive.front_x (docs/model.md §6), plus the slip-rate kick drive.kick_dv behind it.
template <class Stepper>
void set_initial_conditions(const Scene& s, Stepper& sim, const std::optional<continuum::SteadyFront>& front) {
  if (s.drive.loading != core::Loading::homogeneous) return;
  if (front) {
    const auto& x = sim.bulk().x();
    const auto f = continuum::sample_steady_front(*front, x, s.drive.front_x);
    for (std::size_t i = 0; i < x.size(); ++i) {
      const bool kicked = x[i] <= s.drive.front_x && x[i] >= s.drive.front_x - s.drive.kick_length;
      sim.law().set_site(i, f.area[i], f.sigma_bar[i]);
      sim.set_initial(i, f.slip[i], f.slip_rate[i] + (kicked ? s.drive.kick_dv : 0.0));
    }
    return;
  }
  const auto& ip = s.interface;
  const double sd = s.drive.sigma_d;
  const double vs = continuum::strengthening_branch_velocity(ip, sd);
  const auto& x = sim.bulk().x();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::isfinite(vs) && x[i] < s.drive.nucleation_length) {
      const auto ss = continuum::steady_sliding(ip, vs);
      sim.law().set_site(i, ss.area, ss.sigma_bar);
      sim.set_initial(i, sd / ip.alpha, vs);
    } else {
      sim.law().set_site(i, 1.0, sd);
      sim.set_initial(i, sd / ip.alpha, 0.0);
    }
  }
}

// What a law is asked to carry beyond its state: the mean contact age (output.ages, docs/model.md §7).
// Before any set_site: ages start at 0.
template <class Law>
void configure_law(const Scene& s, Law& law) {
  if constexpr (Law::hooks.ages) law.track_ages(s.output.ages);
}

// docs/model.md §7.2: the continuum predicts the contact statistics the agent measures (fixed-step runs of
// a scene with discrete.contact_statistics and a representation that records them).
inline bool predicts_contacts(const Scene& s) {
  const bool discrete = std::find(s.models.begin(), s.models.end(), "discrete") != s.models.end();
  return discrete && s.discrete.contact_statistics && s.discrete.representation != "count";
}

// The stepper of a scene; a steady-front start puts the front's far-field traction μ v_b/c on the rear
// edge (the strain u_x = −v_b/c it has far behind), so the interface behind slides steadily up to x = 0.
template <class Stepper, class Law>
Stepper make_stepper(const Scene& s, Law law, const std::optional<continuum::SteadyFront>& front) {
  configure_law(s, law);
  core::DriveParams drive = s.drive;
  if (front) drive.rear_traction = -s.bulk.mu * front->far_field_strain;
  core::Bulk bulk(s.bulk, drive, s.interface, s.grid.dx);
  if constexpr (DenseStepper<Stepper>) {
    Stepper sim(std::move(bulk), std::move(law), core::AdaptiveOptions::from(s.time));
    sim.set_stop_time(s.time.t_end);
    return sim;
  } else {
    Stepper sim(std::move(bulk), std::move(law), dynamic_time_step(s));
    if constexpr (requires { sim.set_error_control(1.0, 1); })
      sim.set_error_control(s.time.implicit_tolerance, s.time.implicit_max_halvings);
    return sim;
  }
}

}  // namespace detail

/// The regions of docs/model.md §7.2 on the nodes x: behind (x < front − band), tip band
/// (|x − front| ≤ band), ahead (x > front + band); with no front (NaN) every node is ahead.
inline core::FrontClasses front_classes(std::span<const double> x, double front, double band, std::size_t phase) {
  core::FrontClasses f;
  f.phase = phase;
  if (std::isnan(front)) return f;
  f.behind_end = static_cast<std::size_t>(std::lower_bound(x.begin(), x.end(), front - band) - x.begin());
  f.tip_end = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), front + band) - x.begin());
  return f;
}

/// Dense steppers, after a step [t0, t1]: how many leading nodes the tip samples of that step need
/// for `threshold` (docs/model.md §3 tip: the largest x with A < threshold). Nodes beyond the last one
/// whose A may fall below the threshold during the step stay above it throughout. The bound on
/// |1 − A_i(t)| over the step is the stepper's dense_deviation_bound when it has one, else 1.25 × the
/// largest of |1 − A_i| at the start, middle and end (a quadratic interpolant: the Lebesgue constant of
/// three equispaced points). Returns that node + 2 (one more for the tip's interpolation; at most the
/// node count), or 1 when every node stays above.
template <class S>
  requires requires(const S& sim, double t, std::size_t i) { sim.dense_value(t, core::Field::contact_area, i); }
std::size_t tip_nodes(const S& sim, std::size_t nodes, double threshold) {
  using core::Field;
  const double t0 = sim.previous_time(), t1 = sim.time(), margin = 1.0 - threshold;
  for (std::size_t i = nodes; i-- > 0;) {
    double bound;
    if constexpr (requires { sim.dense_deviation_bound(Field::contact_area, i, 1.0); }) {
      bound = sim.dense_deviation_bound(Field::contact_area, i, 1.0);
    } else {
      bound = 1.25 * std::max({std::abs(1.0 - sim.dense_value(t0, Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(0.5 * (t0 + t1), Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(t1, Field::contact_area, i))});
    }
    if (!(bound < margin)) return std::min(nodes, i + 2);
  }
  return 1;
}

/// Dense steppers: record the tips at time t inside the last step, each searched lazily over the
/// nodes tip_nodes() left for its threshold (m_tip, m_alt). Returns the A_tip position.
template <class S>
double sample_tips_dense(const S& sim, FrontTracker& tracker, std::span<const double> x, const core::MeasureParams& p,
                         double t, std::size_t m_tip, std::size_t m_alt) {
  auto area = [&](std::size_t i) { return sim.dense_value(t, core::Field::contact_area, i); };
  return tracker.record_tips(t, tip_position_lazy(x, m_tip, p.A_tip, area), tip_position_lazy(x, m_alt, p.A_tip_alt, area));
}

/// One model on a bulk scene (edge and homogeneous loading, spring block), advanced one step at a time
/// so that several runs can go in lockstep (run_scene_alongside). Each step:
///   1. step      the stepper advances (any stepper of continuum/: explicit, implicit, adaptive)
///   2. observe   the shared measurements see the step: max |v| (t^, arrest), tip samples, cycles,
///                the rate behind a front — at the step end, or on the dense output of the step
///   3. record    the recorder stores what is due in the step (series, snapshots, contact statistics)
/// finish() hands over the result.
/// Whether a run predicts contact statistics from its fields (compare/contacts.hpp, docs/model.md §7.2):
/// automatic — the continuum law on a fixed-step integrator when detail::predicts_contacts(scene); on —
/// any law on a fixed-step integrator (the hazard Θκ|v| with Θ = [|σ̄ + ηv|/A > 1]: for a discrete law this
/// is its own overloaded fraction only when w = 0), e.g. the agent's prediction from its own fields;
/// hazard_scale ≠ 1 gives a deliberately wrong prediction (tests); the tables are stored under
/// prefix + their names.
struct ContactPredictionSetup {
  enum class Mode { automatic, on, off } mode = Mode::automatic;
  double hazard_scale = 1.0;
  std::string prefix;
};

template <class Law, class Stepper = core::ExplicitSimulation<Law>>
class DynamicRun {
 public:
  DynamicRun(const Scene& s, Law law, std::string model, ContactPredictionSetup prediction = {})
      : s_(s), wall0_(std::chrono::steady_clock::now()), front_(front_start(s)),
        sim_(detail::make_stepper<Stepper>(s, std::move(law), front_)),
        one_d_(core::is_one_dimensional(s.drive.loading)), tracker_(s.measure, sim_.bulk().x()),
        cycles_(s.measure), behind_(s.measure), recorder_(s, r_), contacts_due_(s.output.contact_every()) {
    r_.model = std::move(model);
    r_.x = sim_.bulk().x();
    r_.scalars["stable_dt"] = sim_.bulk().stable_dt();
    r_.labels["integrator"] = Stepper::integrator_name;
    if constexpr (DenseStepper<Stepper>) {
      r_.scalars["rtol"] = s.time.rtol;
    } else {
      nsteps_ = fixed_step_count(s);
      r_.scalars["dt"] = sim_.dt();
    }
    sim_.track_energy(s.output.energy);
    detail::set_initial_conditions(s, sim_, front_);
    if (front_) {
      r_.scalars["steady_front_c"] = front_->c;
      r_.scalars["steady_front_v_tip"] = front_->v_tip;
      r_.scalars["steady_front_v_behind"] = front_->v_behind;
      r_.scalars["rear_traction"] = sim_.bulk().rear_traction();
    }
    if constexpr (!DenseStepper<Stepper>) {
      using Mode = ContactPredictionSetup::Mode;
      const bool automatic = std::is_same_v<Law, continuum::FrictionLaw> && detail::predicts_contacts(s);
      if (prediction.mode == Mode::on || (prediction.mode == Mode::automatic && automatic)) {
        predict_.emplace(r_.x.size(), static_cast<double>(s.discrete.contacts_per_site), prediction.hazard_scale);
        predict_->start(sim_.law().contact_area());
        predict_prefix_ = prediction.prefix;
      }
    }
    const StepEndState<Stepper> now{sim_};
    if (one_d_) sample_tips(now);
    record_contacts(0.0);
    recorder_.after_step(0.0, 0.0, false, [&](double) { return now; }, tracker_, sim_.energy());
  }

  bool done() const {
    if (r_.status != RunStatus::complete) return true;
    if constexpr (DenseStepper<Stepper>) return sim_.time() >= s_.time.t_end * (1.0 - 1e-12);
    else return sim_.steps() >= nsteps_;
  }
  const Stepper& sim() const { return sim_; }
  const std::string& model() const { return r_.model; }
  double time() const { return sim_.time(); }

  /// One step with its measurements and records; a non-finite state ends the run with status "failed".
  void step() {
    try {
      const double t0 = sim_.time();
      if (predict_) remember_start();
      sim_.step();  // 1.
      const double t1 = sim_.time();
      if constexpr (DenseStepper<Stepper>) {
        observe_dense(t0, t1);  // 2.
        recorder_.after_step(t0, t1, true, [&](double t) { return DenseState<Stepper>(sim_, t, buffers_); }, tracker_,
                             sim_.energy());  // 3.
      } else {
        const StepEndState<Stepper> now{sim_};
        if (predict_) predict_step();  // 2.
        tracker_.observe_step(t0, t1, sim_.yielded(), sim_.max_slip_rate());
        if (one_d_ && tracker_.sample_due(t1)) sample_tips(now);
        if (!one_d_) cycles_.observe(t1, sim_.drive_force(), sim_.slip_rate()[0], r_.cycles);
        record_contacts(t1);  // 3.
        recorder_.after_step(t0, t1, false, [&](double) { return now; }, tracker_, sim_.energy());
      }
    } catch (const core::NumericalError& e) {
      r_.status = RunStatus::failed;
      r_.message = e.what();
    }
  }

  /// Checkpoints (core::Archive): the stepper with its law, the measurements, the recorder and
  /// the result so far — all a restarted run needs to continue bit for bit.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("dynamic run");
    ar(r_, sim_, tracker_, cycles_, behind_, recorder_, contacts_due_, nsteps_, quiet_);
    // the continuum's contact prediction (docs/model.md §7.2), made by the constructor from the scene: present
    // in the checkpoint exactly when the restarted run made one
    bool predicts = predict_.has_value();
    ar(predicts);
    if (predicts != predict_.has_value())
      throw core::ArchiveError("checkpoint: the contact prediction of the checkpoint and of this run differ");
    if (predict_) ar(*predict_);
    ar(predict_prefix_, a0_, sb0_, hazard_);
  }

  void interrupt() {
    r_.status = RunStatus::interrupted;
    r_.message = "stopped at t = " + std::to_string(sim_.time());
  }

  ModelResult finish() {
    using core::Loading;
    if constexpr (Law::hooks.contact_statistics) detail::store_contacts(sim_.law(), r_);
    if (predict_) {
      auto tables = predict_->tables();
      for (auto& [name, col] : tables.columns) r_.contacts[predict_prefix_ + name] = std::move(col);
      for (auto& [name, tab] : tables.tables)
        r_.contacts_2d[predict_prefix_ + name] = Table2D{tab.cols, std::move(tab.data)};
      r_.scalars["contact_prediction_max_cohorts"] = static_cast<double>(predict_->max_cohorts());
    }
    const bool homogeneous = s_.drive.loading == Loading::homogeneous;
    r_.events = tracker_.finish(homogeneous);
    r_.events_alt = tracker_.finish(homogeneous, true);
    r_.events.v_behind = r_.events_alt.v_behind = behind_.value();
    if (homogeneous && std::isfinite(behind_.value()))  // docs/model.md §3: σ_ss(v_behind) = σ_d behind a steady front
      r_.scalars["sigma_ss_at_v_behind"] = continuum::steady_sliding(s_.interface, behind_.value()).sigma;
    r_.scalars["steps"] = static_cast<double>(sim_.steps());
    if constexpr (requires { sim_.substeps(); }) {
      r_.scalars["substeps"] = static_cast<double>(sim_.substeps());
      r_.scalars["max_linearisation_defect"] = sim_.max_defect();
    }
    r_.scalars["t_reached"] = sim_.time();
    r_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    return std::move(r_);
  }

 private:
  template <class State>
  void sample_tips(const State& st) {
    const double tip = tracker_.sample_tip(st.t(), st.contact_area());
    if (s_.drive.loading == core::Loading::homogeneous) behind_.observe(tip, r_.x, st.slip_rate());
    observe_front();
  }

  // docs/model.md §7.2: where the sites are relative to the front (the A_tip_alt tip) and the phase, for
  // laws that class their contact statistics by them.
  void observe_front() {
    if (!Law::hooks.contact_statistics && !predict_) return;
    const auto f = front_classes(r_.x, tracker_.last_tip_alt(), s_.measure.tip_band, tracker_.phase());
    if constexpr (Law::hooks.contact_statistics) sim_.law().observe_front(f);
    if (predict_) predict_->set_front(f);
  }

  // Contact snapshots: the law's (agent) and the continuum's predicted ones, at the same cadence.
  void record_contacts(double t) {
    if (!Law::hooks.contact_statistics && !predict_) return;
    if (!contacts_due_.due(t)) return;
    if constexpr (Law::hooks.contact_statistics) sim_.law().record_contacts(t);
    if (predict_) predict_->snapshot();
  }

  // The prediction's view of a fixed step of the continuum law: A and σ̄ at its start, then the
  // hazard Θκ|v| with Θ decided by core::slides, as FrictionLaw::advance decides it (the same bits).
  void remember_start() {
    const auto a = sim_.law().contact_area(), sb = sim_.law().sigma_bar();
    a0_.assign(a.begin(), a.end());
    sb0_.assign(sb.begin(), sb.end());
  }
  void predict_step() {
    const auto v = sim_.slip_rate();
    const double eta = s_.interface.eta, kappa = s_.interface.kappa;
    hazard_.resize(v.size());
    for (std::size_t i = 0; i < v.size(); ++i)
      hazard_[i] = core::slides(sb0_[i], v[i], a0_[i], eta) ? kappa * std::abs(v[i]) : 0.0;
    predict_->step(sim_.dt(), a0_, hazard_);
  }

  // Dense stepper: over the accepted step [t0, t1] the tracker sees max|v| on sub-intervals of at most
  // sample_dt/2 (so t^ is interpolated as finely as with small steps), and the tips at the exact
  // multiples of sample_dt. The interpolant is quadratic in time at every node, so over the step
  // |v_i| ≤ 1.25 × the largest of |v_i| at its start, middle and end (the Lebesgue constant of three
  // equispaced points), and likewise for 1 − A_i. That bound spares the work nobody would see: a step
  // whose bound stays ≤ v_event outside a transient cannot move an event, and gets one observation
  // instead of sub-intervals; a node whose A stays above both tip thresholds over the whole step is not
  // interpolated for the tip samples.
  void observe_dense(double t0, double t1) {
    using core::Field;
    const std::size_t n = r_.x.size();
    std::vector<double>& v = buffers_[static_cast<std::size_t>(Field::slip_rate)];
    v.resize(n);
    sim_.dense_state(t0, Field::slip_rate, v);
    const double v_start = core::max_abs_or_inf(v);
    sim_.dense_state(0.5 * (t0 + t1), Field::slip_rate, v);
    const double bound = 1.25 * std::max({v_start, core::max_abs_or_inf(v), core::max_abs_or_inf(sim_.slip_rate())});
    if (!tracker_.in_transient() && bound <= s_.measure.v_event) {
      tracker_.observe_step(t0, t1, sim_.yielded(), bound);
      quiet_ = true;
    } else {
      if (quiet_) tracker_.observe_step(t0, t0, false, v_start);  // exact base for interpolating t^
      quiet_ = false;
      const auto m = std::max<std::int64_t>(
          1, static_cast<std::int64_t>(std::ceil((t1 - t0) / (0.5 * s_.measure.sample_dt) - 1e-9)));
      for (std::int64_t j = 0; j < m; ++j) {
        const double a = t0 + (t1 - t0) * static_cast<double>(j) / static_cast<double>(m);
        const double b = j + 1 == m ? t1 : t0 + (t1 - t0) * static_cast<double>(j + 1) / static_cast<double>(m);
        sim_.dense_state(0.5 * (a + b), Field::slip_rate, v);
        tracker_.observe_step(a, b, sim_.yielded(), core::max_abs_or_inf(v));
      }
    }
    if (!one_d_) cycles_.observe(t1, sim_.drive_force(), sim_.slip_rate()[0], r_.cycles);
    if (!one_d_) return;
    // Per threshold, the nodes whose A can be below it during the step; beyond them A stays above.
    const std::size_t m_tip = tip_nodes(sim_, n, s_.measure.A_tip), m_alt = tip_nodes(sim_, n, s_.measure.A_tip_alt);
    multiples_in(t0, t1, s_.measure.sample_dt, [&](double t) {
      const double tip = sample_tips_dense(sim_, tracker_, r_.x, s_.measure, t, m_tip, m_alt);
      observe_front();
      if (s_.drive.loading == core::Loading::homogeneous) {
        sim_.dense_state(t, Field::slip_rate, v);
        behind_.observe(tip, r_.x, v);
      }
    });
  }

  const Scene& s_;
  std::chrono::steady_clock::time_point wall0_;
  ModelResult r_;
  std::optional<continuum::SteadyFront> front_;  // a steady-front start
  Stepper sim_;
  bool one_d_;
  FrontTracker tracker_;
  CycleDetector cycles_;
  BehindRate behind_;
  Recorder recorder_;
  Cadence contacts_due_;
  std::int64_t nsteps_ = 0;
  bool quiet_ = false;                  // dense stepper: the last step got one max|v| observation
  std::vector<double> buffers_[4];      // dense-output buffers, one per core::Field
  std::optional<ContactPrediction> predict_;  // docs/model.md §7.2 (continuum law, fixed-step steppers)
  std::string predict_prefix_;
  std::vector<double> a0_, sb0_, hazard_;     // the prediction's view of the current step
};

/// Bulk scenes run alone: step to t_end, polling the stop request after every step; checkpoints as
/// `ctl` asks (written after `header`), and, with `resume`, continued from a checkpoint's state.
template <class Law, class Stepper = core::ExplicitSimulation<Law>>
ModelResult run_dynamic(const Scene& s, Law law, const std::string& model, const RunControl& ctl,
                        const CheckpointHeader& header = {}, core::Archive* resume = nullptr) {
  DynamicRun<Law, Stepper> run(s, std::move(law), model);
  if (resume) (*resume)(run);
  Cadence clock = Cadence::after(ctl.checkpointing() ? ctl.checkpoint_every : -1.0, run.time());
  auto save = [&] {
    core::Archive ar = core::Archive::writer();
    if (header) header(ar);
    ar(run);
    ctl.checkpoint(ar.data(), run.time());
  };
  for (std::int64_t n = 1; !run.done(); ++n) {
    run.step();
    if ((n & 1023) == 0) ctl.progress(model, run.time(), s.time.t_end);
    const bool stop = ctl.stop();
    if (clock.due(run.time()) || (stop && ctl.checkpointing() && !run.done())) save();
    if (stop) run.interrupt();
  }
  return run.finish();
}

/// Steady friction at imposed v (docs/model.md §3): run one site for t_end + slip_end/|v| in `steps`
/// exact steps and average σ = σ̄ + ηv over the last (1 − average_from) of the run by batch means.
struct SteadyPoint {
  double v, sigma, sigma_stderr, area;
};
template <class Law>
SteadyPoint steady_point(const Scene& s, Law law, double v) {
  const double T = s.time.t_end + s.time.slip_end / std::abs(v);
  const double dt = T / s.time.steps;
  BatchMeans sig(s.measure.average_from * T, T, s.measure.batches), area(s.measure.average_from * T, T, 2);
  const double vv[1] = {v};
  for (int n = 0; n < s.time.steps; ++n) {
    law.advance(dt, vv);
    const double t0 = n * dt, t1 = (n + 1) * dt;
    sig.add(t0, t1, law.sigma_bar()[0] + s.interface.eta * v);
    area.add(t0, t1, law.contact_area()[0]);
  }
  return {v, sig.mean(), sig.stderr_of_mean(), area.mean()};
}

/// Imposed slip rate (0D): a sweep over v (friction law) or one piecewise-constant history v(t).
template <class Law, class MakeLaw>
ModelResult run_imposed_rate(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl) {
  const auto wall0 = std::chrono::steady_clock::now();
  ModelResult r;
  r.model = model;
  r.x = {0.0};
  if (s.drive.sweep_points > 0) {
    const auto rates = sweep_rates(s.drive);
    for (std::size_t k = 0; k < rates.size(); ++k) {
      const SteadyPoint p = steady_point<Law>(s, make_law(std::size_t{1}), rates[k]);
      detail::push(r.friction_law, "v", p.v);
      detail::push(r.friction_law, "sigma", p.sigma);
      detail::push(r.friction_law, "sigma_stderr", p.sigma_stderr);
      detail::push(r.friction_law, "A", p.area);
      detail::push(r.friction_law, "sigma_closed_form", continuum::steady_sliding(s.interface, p.v).sigma);
      ctl.progress(model, static_cast<double>(k + 1), static_cast<double>(rates.size()));
      if (ctl.stop()) {
        r.status = RunStatus::interrupted;
        r.message = "stopped during the sweep";
        break;
      }
    }
    // The minimum of the steady law: a parabola in log v through the smallest tabulated σ and its
    // neighbours; for a deterministic rate law, golden-section search on the computed steady friction
    // between those neighbours (to 1e-7 in log v).
    const auto& vv = r.friction_law["v"];
    const auto& sv = r.friction_law["sigma"];
    if (const TabulatedMinimum m = parabola_minimum_log(vv, sv); sv.size() >= 3) {
      if (m.found) {
        r.scalars["v_m_fit"] = m.x;
        r.scalars["sigma_c_fit"] = m.y;
      }
      if constexpr (core::SmoothLaw<Law>) {
        auto f = [&](double lx) { return steady_point<Law>(s, make_law(std::size_t{1}), std::exp(lx)).sigma; };
        const double lx = golden_section_minimum(f, std::log(vv[m.index - 1]), std::log(vv[m.index + 1]), 1e-7);
        r.scalars["v_m_numeric"] = std::exp(lx);
        r.scalars["sigma_c_numeric"] = f(lx);
      }
    }
  } else {
    // One history: piecewise-constant v, steps aligned with the switch times.
    Law law = make_law(std::size_t{1});
    detail::configure_law(s, law);
    const auto& vs = s.drive.v;
    const auto& ts = s.drive.v_times;
    const double dt_target = s.time.dt > 0 ? s.time.dt : s.time.t_end / s.time.steps;
    FrontTracker tracker(s.measure, r.x);
    Recorder recorder(s, r);
    [[maybe_unused]] Cadence contacts_due(s.output.contact_every());
    double t = 0.0;
    const std::optional<core::EnergyBudget> no_energy;
    auto record = [&](double v) {
      if constexpr (Law::hooks.contact_statistics)
        if (contacts_due.due(t)) law.record_contacts(t);
      const SiteState<Law> now{law, t, v};
      recorder.after_step(t, t, false, [&](double) { return now; }, tracker, no_energy);
    };
    record(vs[0]);
    std::int64_t steps = 0;
    for (std::size_t k = 0; k < vs.size() && r.status == RunStatus::complete; ++k) {
      const double t_seg_end = k + 1 < vs.size() ? std::min(ts[k + 1], s.time.t_end) : s.time.t_end;
      if (t_seg_end <= ts[k]) break;
      const double segment_steps = std::ceil((t_seg_end - ts[k]) / dt_target - 1e-9);
      if (!(segment_steps < 9.0e18))
        throw core::ParamError("time.dt", "gives more than 9e18 steps in one segment of drive.v");
      const auto n = static_cast<std::int64_t>(segment_steps);
      const double dt = (t_seg_end - ts[k]) / static_cast<double>(n);
      const double v[1] = {vs[k]};
      for (std::int64_t j = 0; j < n; ++j) {
        const double t0 = t;
        const bool yielded = law.advance(dt, v).any_yield;
        t = ts[k] + static_cast<double>(j + 1) * dt;
        tracker.observe_step(t0, t, yielded, std::abs(v[0]));
        record(v[0]);
        if ((++steps & 1023) == 0) ctl.progress(model, t, s.time.t_end);
        if (ctl.stop()) {
          r.status = RunStatus::interrupted;
          r.message = "stopped at t = " + std::to_string(t);
          break;
        }
      }
    }
    if constexpr (Law::hooks.contact_statistics) detail::store_contacts(law, r);
    r.events = tracker.finish(false);
    r.scalars["steps"] = static_cast<double>(steps);
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return r;
}

/// Run one model on a scene, whichever loading and integrator it has. make_law(n_sites) builds the law.
template <class Law, class MakeLaw>
ModelResult run_model(const Scene& s, MakeLaw make_law, const std::string& model, const RunControl& ctl,
                      const CheckpointHeader& header = {}, core::Archive* resume = nullptr) {
  if (s.drive.loading == core::Loading::imposed_rate) {
    if (resume) throw core::ArchiveError("checkpoint: an imposed-rate scene has no checkpoints");
    return run_imposed_rate<Law>(s, make_law, model, ctl);
  }
  const core::Bulk probe(s.bulk, s.drive, s.interface, s.grid.dx);
  return with_integrator(s, [&](auto tag) {
    using Stepper = typename decltype(tag)::template stepper<Law>;
    return run_dynamic<Law, Stepper>(s, make_law(probe.nodes()), model, ctl, header, resume);
  });
}

/// Every model the scene lists, in order, each run alone.
std::vector<ModelResult> run_scene(const Scene& s, const RunControl& ctl);

}  // namespace slipfront::compare
