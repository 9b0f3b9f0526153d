#pragma once
// One model on a bulk scene (edge and homogeneous loading, spring block), one step at a time
// (docs/architecture.md §2): the stepper advances, the shared measurements (compare/measure.hpp) observe
// the step, and the recorder (compare/record.hpp) stores what is due. Templated on the interface law and
// the stepper, so both models and the three integrators share every line of it; run_loop drives it alone
// (run_dynamic) or beside another (run_scene_alongside).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "compare/cadence.hpp"
#include "compare/contacts.hpp"
#include "compare/dispatch.hpp"
#include "compare/initial.hpp"
#include "compare/load_coupling.hpp"
#include "compare/measure.hpp"
#include "compare/record.hpp"
#include "compare/result.hpp"
#include "compare/run_loop.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "core/contacts.hpp"

namespace slipfront::compare {

namespace detail {
// The contact tables of a law with contact statistics, into the result.
template <class Law>
void store_contacts(const Law& law, ModelResult& r) {
  auto tables = law.contact_tables();
  for (auto& [name, col] : tables.columns) r.contacts[name] = std::move(col);
  for (auto& [name, tab] : tables.tables) r.contacts_2d[name] = Table2D{tab.cols, std::move(tab.data)};
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
/// for each of two thresholds (docs/model.md §3 tip: the largest x with A < threshold; the A_tip and A_tip_alt of
/// the measurements). Nodes beyond the last one whose A may fall below a threshold during the step stay above it
/// throughout. The bound on |1 − A_i(t)| over the step is the stepper's dense_deviation_bound when it has one, else
/// 1.25 × the largest of |1 − A_i| at the start, middle and end (a quadratic interpolant: the Lebesgue constant of
/// three equispaced points). Returns, per threshold, that node + 2 (one more for the tip's interpolation; at most
/// the node count), or 1 when every node stays above. One pass from the last node for both thresholds: each node's
/// bound is computed once (the scan covers every node ahead of the front, at every step).
template <class S>
  requires requires(const S& sim, double t, std::size_t i) { sim.dense_value(t, core::Field::contact_area, i); }
std::pair<std::size_t, std::size_t> tip_nodes(const S& sim, std::size_t nodes, double threshold_a, double threshold_b) {
  using core::Field;
  const double t0 = sim.previous_time(), t1 = sim.time(), margin_a = 1.0 - threshold_a, margin_b = 1.0 - threshold_b;
  std::size_t a = 0, b = 0;  // 0: not found yet
  for (std::size_t i = nodes; i-- > 0;) {
    double bound;
    if constexpr (requires { sim.dense_deviation_bound(Field::contact_area, i, 1.0); }) {
      bound = sim.dense_deviation_bound(Field::contact_area, i, 1.0);
    } else {
      bound = 1.25 * std::max({std::abs(1.0 - sim.dense_value(t0, Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(0.5 * (t0 + t1), Field::contact_area, i)),
                               std::abs(1.0 - sim.dense_value(t1, Field::contact_area, i))});
    }
    if (a == 0 && !(bound < margin_a)) a = std::min(nodes, i + 2);
    if (b == 0 && !(bound < margin_b)) b = std::min(nodes, i + 2);
    if (a != 0 && b != 0) break;
  }
  return {a == 0 ? 1 : a, b == 0 ? 1 : b};
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
/// Whether a run predicts contact statistics from its own fields (compare/contacts.hpp, docs/model.md
/// §7.2): on — a law that declares core::LawHooks::contact_hazard, on an integrator that advances it in frozen-rate steps (FrozenRateSteps), integrates
/// the law's detachment_hazard along its fields (the continuum's prediction of what the agent measures,
/// contact_prediction_for in compare/runner.hpp; or the agent's prediction from its own fields);
/// hazard_scale ≠ 1 gives a deliberately wrong prediction (tests); the tables are stored under
/// prefix + their names.
/// threshold_edges: the edges of the threshold prediction (empty: discrete::threshold_edges at the scene's w, the
/// agent's; a test that predicts at another w gives the agent's here, so that the tables compare).
struct ContactPredictionSetup {
  enum class Mode { off, on } mode = Mode::off;
  double hazard_scale = 1.0;
  std::string prefix;
  std::vector<double> threshold_edges;
};

template <class Law, class Stepper = core::ExplicitSimulation<Law>>
class DynamicRun {
 public:
  /// `stop` (the run's stop request) is polled inside the steady-front start's solve (front_start): a stop there
  /// ends the run interrupted before its first step (start_stopped).
  DynamicRun(const Scene& s, Law law, std::string model, ContactPredictionSetup prediction = {},
             const std::function<bool()>& stop = {})
      : s_(s), wall0_(std::chrono::steady_clock::now()), front_(front_start_for<Law>(s, stop)),
        body_scene_(coupled_body_scene(s)), sim_(make_stepper<Stepper>(body_scene_, std::move(law), front_)),
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
    set_initial_conditions(s, sim_, front_);
    if (s.interface.couples_load()) start_load_coupling();
    if (start_stopped()) {
      r_.status = RunStatus::interrupted;
      r_.message = "stopped on request in the steady-front start's solve (drive.start = \"steady_front\"), before the "
                   "first step: the state is the nucleation start's";
    } else if (front_) {
      r_.scalars["steady_front_c"] = front_->c;
      r_.scalars["steady_front_v_tip"] = front_->v_tip;
      r_.scalars["steady_front_v_behind"] = front_->v_behind;
      r_.scalars["rear_traction"] = sim_.bulk().rear_traction();
    }
    if (prediction.mode == ContactPredictionSetup::Mode::on) start_prediction(prediction);
    const StepEndState<Stepper> now{sim_};
    if (one_d_) sample_tips(now);
    record_contacts(0.0);
    recorder_.after_step(0.0, 0.0, false, [&](double) { return now; }, tracker_, sim_.energy());
  }

  // SteppedRun (compare/run_loop.hpp)
  static constexpr std::int64_t progress_every = 1024;
  static constexpr bool checkpointable = true;
  bool done() const {
    if (r_.status != RunStatus::complete) return true;
    if (s_.time.stop_at_arrest && tracker_.phase() == 3) return true;  // docs/cli.md time.stop_at_arrest
    if constexpr (DenseStepper<Stepper>) return sim_.time() >= s_.time.t_end * (1.0 - 1e-12);
    else return sim_.steps() >= nsteps_;
  }
  const Stepper& sim() const { return sim_; }
  /// The steady-front start's solve was stopped (the run is interrupted at t = 0; a checkpoint is not resumed into it).
  bool start_stopped() const { return front_ && front_->stopped; }
  const std::string& model() const { return r_.model; }
  double time() const { return sim_.time(); }
  double end() const { return s_.time.t_end; }

  /// One step with its measurements and records; a non-finite state ends the run as failed.
  void step() {
    try {
      const double t0 = sim_.time();
      if (predict_) remember_start();
      if (coupling_) couple_normal_load();  // docs/model.md §12.5: p = −σ_yy(x, 0, t0), frozen over the step
      sim_.step();                    // 1. step
      observe(t0, sim_.time());       // 2. observe
      record(t0, sim_.time());        // 3. record
    } catch (const core::NumericalError& e) {
      r_.status = RunStatus::failed;
      r_.message = e.what();
    } catch (const LoadCouplingError& e) {
      r_.status = RunStatus::failed;
      r_.message = e.what();
    }
  }

  /// Checkpoints (core::Archive): the stepper with its law, the measurements, the recorder and
  /// the result so far — all a restarted run needs to continue bit for bit.
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("dynamic run");
    if (coupling_) {  // docs/model.md §12.5: the law's resting areas, installed before its state is restored over them
      ar(*coupling_);
      if (ar.loading()) install_coupled_load(coupling_->last_factors());
    }
    ar(r_, sim_, tracker_, cycles_, behind_, recorder_, contacts_due_, nsteps_, quiet_);
    // the continuum's contact prediction (docs/model.md §7.2), made by the constructor from the scene: present
    // in the checkpoint exactly when the restarted run made one
    bool predicts = predict_.has_value();
    ar(predicts);
    if (predicts != predict_.has_value())
      throw core::ArchiveError("checkpoint: the contact prediction of the checkpoint and of this run differ");
    if (predict_) ar(*predict_);
    ar(predict_prefix_, a0_, sb0_, hazard_);
    if constexpr (Law::hooks.class_hazards) ar(n0_, totals_);
    ar(after_arrest_closed_);
  }

  /// docs/model.md §7.2: whether this run has had its next instability after the arrest (phase 4, next event).
  bool had_next_instability() const { return tracker_.phase() == core::FrontClasses::next_event; }
  /// Ends the after-arrest phase of the contact statistics now (in lockstep: at the earliest next instability
  /// of the compared models): from here on a run in phase 3 classes its contacts as next_event (not classed).
  void close_after_arrest() {
    if (after_arrest_closed_) return;
    after_arrest_closed_ = true;
    observe_front();
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
    const double rest = min_resting_area();  // docs/model.md §12.5: a tip threshold the resting area is below
    void_tip_events(r_.events, s_.measure.A_tip, "measure.A_tip", rest);
    void_tip_events(r_.events_alt, s_.measure.A_tip_alt, "measure.A_tip_alt", rest);
    if (s_.output.sequence && s_.drive.loading == Loading::edge)  // docs/model.md §3.2
      r_.sequence = slip_sequence(r_.series.at("t"), r_.series.at("max_v"), r_.series.at("tip_x"), s_.measure, r_.x.back());
    // docs/model.md §3: σ_ss(v_behind) = σ_d behind a steady front, in the law's own steady state
    if constexpr (Law::hooks.steady_state)
      if (homogeneous && std::isfinite(behind_.value()))
        r_.scalars["sigma_ss_at_v_behind"] = sim_.law().steady_sliding(behind_.value()).sigma;
    r_.scalars["steps"] = static_cast<double>(sim_.steps());
    if (coupling_) {  // docs/output.md: the coupled load's range and where a law could not take it (§12.5)
      r_.scalars["load_ratio_max"] = coupling_->max_ratio();
      r_.scalars["load_ratio_min"] = coupling_->min_ratio();
      r_.scalars["load_clamped_site_steps"] = static_cast<double>(coupling_->clamped_site_steps());
      r_.scalars["load_tension_site_steps"] = static_cast<double>(coupling_->tension_site_steps());
    }
    if constexpr (Stepper::error_control) {
      r_.scalars["substeps"] = static_cast<double>(sim_.substeps());
      r_.scalars["max_linearisation_defect"] = sim_.max_defect();
    }
    if constexpr (requires { sim_.stats().event_steps; }) {  // the Rosenbrock integrator (core/adaptive.hpp)
      const auto& st = sim_.stats();
      r_.scalars["rejected_steps"] = static_cast<double>(st.rejected);
      r_.scalars["event_steps"] = static_cast<double>(st.event_steps);
      r_.scalars["switchings"] = static_cast<double>(st.switchings);
      r_.scalars["rhs_evaluations"] = static_cast<double>(st.rhs);
      r_.scalars["stage_solves"] = static_cast<double>(st.solves);
    }
    if constexpr (requires { sim_.stats().leap_rejected; }) {  // the step-controlled integrator (core/leap.hpp)
      const auto& st = sim_.stats();
      r_.scalars["trial_solves"] = static_cast<double>(st.solves);
      r_.scalars["defect_halvings"] = static_cast<double>(st.defect_halvings);
      r_.scalars["leap_rejected"] = static_cast<double>(st.leap_rejected);
      r_.scalars["located_onsets"] = static_cast<double>(st.located);
      r_.scalars["relinearised_solves"] = static_cast<double>(st.relinearised);
      r_.scalars["forced_steps"] = static_cast<double>(st.forced);
    }
    r_.scalars["t_reached"] = sim_.time();
    r_.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
    return std::move(r_);
  }

 private:
  // The smallest resting area the law was given (a normal-load profile or the coupling, docs/model.md §12): 1 without.
  double min_resting_area() const {
    double a = 1.0;
    if (coupling_) a = std::min(a, coupling_->min_resting_area());
    if (s_.interface.has_load_profile())
      for (const double x : r_.x) a = std::min(a, s_.interface.resting_area_at(x));
    return a;
  }
  // A front tip is the largest x with A below the threshold; where the resting area itself is below it, sites at rest
  // count as "behind the front" and the tip's speeds and arrest measure the load, not a front: NaN, with the reason.
  static void void_tip_events(Events& e, double threshold, const char* key, double rest) {
    if (!(rest < threshold)) return;
    const std::string why = std::string("the resting area (p/p_0)^m falls to ") + core::format_number(rest, 4) +
                            " < " + key + " = " + core::format_number(threshold) +
                            ": sites at rest are below the tip threshold, so this tip does not mark a front "
                            "(docs/model.md §12.5); use a threshold below the smallest resting area";
    for (auto [name, value] : {std::pair<const char*, double*>{"c_slow", &e.c_slow}, {"c_transient", &e.c_transient},
                               {"c_transient_peak", &e.c_transient_peak}, {"x_arrest", &e.x_arrest},
                               {"c_front", &e.c_front}, {"c_front_middle", &e.c_front_middle}}) {
      *value = std::numeric_limits<double>::quiet_NaN();
      e.reasons[name] = why;
    }
  }

  // docs/model.md §12.5: the in-plane strip's own normal load. The continuum takes any resting area; the ensembles'
  // contacts at p_0 are their capacity under re-attachment (compare/load_coupling.hpp: clamped and counted).
  void start_load_coupling() {
    if constexpr (Law::hooks.normal_load && requires(std::span<double> o) { sim_.bulk().interface_normal_stress(sim_.displacement(), o); }) {
      coupling_.emplace(s_.interface, s_.bulk.normal_load, !std::is_same_v<Law, continuum::FrictionLaw>);
      couple_normal_load();
    } else {
      throw core::ParamError("interface.load_coupling", "this model's law or body takes no coupled normal load "
                                                        "(core::LawHooks::normal_load on the in-plane strip)");
    }
  }
  void couple_normal_load() {
    if constexpr (Law::hooks.normal_load && requires(std::span<double> o) { sim_.bulk().interface_normal_stress(sim_.displacement(), o); }) {
      normal_stress_.resize(sim_.bulk().sites());
      sim_.bulk().interface_normal_stress(sim_.displacement(), normal_stress_);
      install_coupled_load(coupling_->resting_areas(normal_stress_, r_.x, sim_.time(), sim_.slip_rate(), sim_.dt()));
    }
  }
  void install_coupled_load(std::span<const double> factor) {
    if constexpr (Law::hooks.normal_load)
      if (!factor.empty()) sim_.law().set_normal_load(factor);
  }

  // 2. The shared measurements see the step [t0, t1]: on the dense output (observe_dense), or at the
  // step end — the contact prediction, max|v| and yield (t*, t^, arrest), the tips when a sample is due,
  // the stick–slip cycles of a 0D block.
  void observe(double t0, double t1) {
    if constexpr (DenseStepper<Stepper>) {
      if constexpr (FrozenRateSteps<Stepper>)
        if (predict_) predict_step();
      observe_dense(t0, t1);
    } else {
      if (predict_) predict_step();
      tracker_.observe_step(t0, t1, sim_.yielded(), sim_.max_slip_rate());
      if (one_d_ && tracker_.sample_due(t1)) sample_tips(StepEndState<Stepper>{sim_});
      if (!one_d_) cycles_.observe(t1, sim_.drive_force(), sim_.slip_rate()[0], r_.cycles);
    }
  }

  // 3. What is due in [t0, t1] is stored: contact snapshots (fixed steps), series rows and field
  // snapshots (at the exact cadence times on the dense output).
  void record(double t0, double t1) {
    if constexpr (DenseStepper<Stepper>) {
      if constexpr (FrozenRateSteps<Stepper>) record_contacts(t1);
      recorder_.after_step(t0, t1, true, [&](double t) { return DenseState<Stepper>(sim_, t, buffers_); }, tracker_,
                           sim_.energy());
    } else {
      record_contacts(t1);
      const StepEndState<Stepper> now{sim_};
      recorder_.after_step(t0, t1, false, [&](double) { return now; }, tracker_, sim_.energy());
    }
  }

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
    const std::size_t phase = tracker_.phase() == 3 && after_arrest_closed_ ? core::FrontClasses::next_event
                                                                              : tracker_.phase();
    const auto f = front_classes(r_.x, tracker_.last_tip_alt(), s_.measure.tip_band, phase);
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

  // docs/model.md §7.2: the prediction integrates the law's detachment hazard along its fields (fixed
  // steps: the step's A and σ̄ at its start and its slip rate).
  // The mean-field law (core::LawHooks::class_hazards): the same per threshold class, with each class's
  // attached fraction at the step's start, its hazard and its relaxation total (docs/model.md §2.2).
  void start_prediction(const ContactPredictionSetup& setup) {
    const auto n_contacts = static_cast<double>(s_.discrete.contacts_per_site);
    if constexpr (Law::hooks.contact_hazard && FrozenRateSteps<Stepper>) {
      predict_.emplace(r_.x.size(), n_contacts, setup.hazard_scale);
      predict_->start(sim_.law().contact_area());
      predict_prefix_ = setup.prefix;
      // thresholds: the continuum's contacts all have the threshold 1, a prediction only when the scene's are too
      const discrete::ThresholdDistribution g(s_.discrete.threshold, s_.discrete.width);
      if (g.degenerate()) predict_thresholds(setup, g, 1);
    } else if constexpr (Law::hooks.class_hazards && FrozenRateSteps<Stepper>) {
      predict_.emplace(r_.x.size(), n_contacts, setup.hazard_scale, 0.1, 1e4, sim_.law().prediction_classes());
      predict_->start(sim_.law().attached_classes());
      predict_prefix_ = setup.prefix;
      predict_thresholds(setup, sim_.law().distribution(), sim_.law().prediction_classes());
    } else {
      throw std::invalid_argument("a contact prediction needs a law with a detachment hazard "
                                  "(core::LawHooks::contact_hazard or class_hazards) on an integrator with frozen-rate steps (not the Rosenbrock one)");
    }
  }
  // The threshold prediction of `classes` quantile classes of g, on the agent's edges for the scene's w (or the
  // setup's): compare/contacts.hpp, threshold_spread.
  void predict_thresholds(const ContactPredictionSetup& setup, const discrete::ThresholdDistribution& g,
                          std::size_t classes) {
    auto edges = setup.threshold_edges.empty() ? discrete::threshold_edges(s_.discrete.width) : setup.threshold_edges;
    auto spread = threshold_spread(g, classes, edges);
    predict_->set_thresholds(std::move(edges), std::move(spread));
  }
  void remember_start() {
    const auto a = sim_.law().contact_area(), sb = sim_.law().sigma_bar();
    a0_.assign(a.begin(), a.end());
    sb0_.assign(sb.begin(), sb.end());
    if constexpr (Law::hooks.class_hazards) {
      const auto n = sim_.law().attached_classes();
      n0_.assign(n.begin(), n.end());
    }
  }
  void predict_step() {
    if constexpr (Law::hooks.contact_hazard && FrozenRateSteps<Stepper>) {
      const auto v = sim_.slip_rate();
      hazard_.resize(v.size());
      for (std::size_t i = 0; i < v.size(); ++i) hazard_[i] = sim_.law().detachment_hazard({v[i], a0_[i], sb0_[i]});
      predict_->step(sim_.dt(), a0_, hazard_);
    } else if constexpr (Law::hooks.class_hazards && FrozenRateSteps<Stepper>) {
      const auto v = sim_.slip_rate();
      const std::size_t B = sim_.law().prediction_classes();
      hazard_.resize(n0_.size());
      totals_.resize(n0_.size());
      const std::span<const double> n0(n0_);
      for (std::size_t i = 0; i < v.size(); ++i)
        sim_.law().class_rates(i, v[i], a0_[i], sb0_[i], n0.subspan(i * B, B), std::span(hazard_).subspan(i * B, B),
                               std::span(totals_).subspan(i * B, B));
      predict_->step(sim_.dt(), n0_, hazard_, totals_);
    }
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
    const auto [m_tip, m_alt] = tip_nodes(sim_, n, s_.measure.A_tip, s_.measure.A_tip_alt);
    multiples_in(t0, t1, s_.measure.sample_dt, [&](double t) {
      const double tip = sample_tips_dense(sim_, tracker_, r_.x, s_.measure, t, m_tip, m_alt);
      observe_front();
      if (s_.drive.loading == core::Loading::homogeneous) {
        sim_.dense_state(t, Field::slip_rate, v);
        behind_.observe(tip, r_.x, v);
      }
    });
  }

  // docs/model.md §12.5: with the coupling the body carries no top load; p_0 is the contacts' reference load, superposed
  static Scene coupled_body_scene(const Scene& s) {
    Scene b = s;
    if (s.interface.couples_load()) b.bulk.normal_load = 0.0;
    return b;
  }

  const Scene& s_;
  std::chrono::steady_clock::time_point wall0_;
  ModelResult r_;
  std::optional<FrontStart> front_;  // a steady-front start
  Scene body_scene_;                 // the scene the body is built from (coupled_body_scene)
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
  std::vector<double> n0_, totals_;           // ... per threshold class (core::LawHooks::class_hazards)
  bool after_arrest_closed_ = false;          // close_after_arrest: phase 3 is over (another model's next event)
  std::optional<LoadCoupling> coupling_;      // docs/model.md §12.5 (interface.load_coupling = "sigma_yy")
  std::vector<double> normal_stress_;         // σ_yy(x_i, 0) at the step's start
};

/// Bulk scenes run alone: one DynamicRun driven by run_loop (checkpoints written after `header`), and,
/// with `resume`, continued from a checkpoint's state.
template <class Law, class Stepper = core::ExplicitSimulation<Law>>
ModelResult run_dynamic(const Scene& s, Law law, const std::string& model, const RunControl& ctl,
                        const CheckpointHeader& header = {}, core::Archive* resume = nullptr,
                        const ContactPredictionSetup& prediction = {}) {
  DynamicRun<Law, Stepper> run(s, std::move(law), model, prediction, ctl.stop);
  if (resume && !run.start_stopped()) (*resume)(run);
  run_loop(run, ctl, model, header);
  return run.finish();
}

}  // namespace slipfront::compare
