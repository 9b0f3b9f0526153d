#pragma once
// The recorder: the one list of what a run stores (docs/output.md) — the series columns, the snapshot
// fields — filled from a view of a model's state at a time, whichever stepper (or, for an imposed slip
// rate, the law alone) produced it. The runner decides when; the recorder decides what.
//
// A state view (StepEndState, DenseState, ImposedRateState below) answers, at its time t():
//   contact_area(), sigma_bar(), slip_rate(), slip()   fields per node (slip(): empty where no bulk)
//   drive_force()                                       F = K (v_d t − u_0) (imposed rate: the stress σ)
//   max_slip_rate()                                     max |v|: over the last step (fixed-step
//                                                       steppers) or at t (dense output)
//   mean_age(out)                                       mean contact age ā per node (docs/model.md §7)
//                                                       into out; false when the law carries none
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "compare/cadence.hpp"
#include "compare/measure.hpp"
#include "compare/result.hpp"
#include "compare/scene.hpp"
#include "core/adaptive.hpp"
#include "core/stepper.hpp"

namespace slipfront::compare {

namespace detail {

inline void push(Columns& c, const char* name, double v) { c[name].push_back(v); }
/// Append a row; the first row reserves room for `rows` of its length, so that a column of snapshots is
/// allocated once (growing it by doubling copied and page-faulted ~3× the field data: docs/performance.md §14).
inline void append(Columns& c, const char* name, std::span<const double> v, std::size_t rows = 0) {
  auto& col = c[name];
  if (col.empty()) col.reserve(rows * v.size());
  col.insert(col.end(), v.begin(), v.end());
}
// The mean contact age of laws that carry it (core::LawHooks::ages, docs/model.md §7: FrictionLaw's age
// mass, AgentLaw's exact ages) when asked (output.ages); false otherwise.
template <class Law>
bool law_mean_age(const Law& law, std::span<double> out) {
  if constexpr (Law::hooks.ages) {
    if (law.tracks_ages()) {
      law.mean_age(out);
      return true;
    }
  }
  return false;
}

}  // namespace detail

/// A fixed-step stepper's state at the end of its last step (or the initial state).
template <class Sim>
struct StepEndState {
  const Sim& sim;
  double t() const { return sim.time(); }
  std::span<const double> contact_area() const { return sim.law().contact_area(); }
  std::span<const double> sigma_bar() const { return sim.law().sigma_bar(); }
  std::span<const double> slip_rate() const { return sim.slip_rate(); }
  std::span<const double> slip() const { return sim.slip(); }
  double drive_force() const { return sim.drive_force(); }
  double max_slip_rate() const { return sim.max_slip_rate(); }
  bool mean_age(std::span<double> out) const { return detail::law_mean_age(sim.law(), out); }
  /// The body (core::Bulk or core::Strip) and the displacement of all its dofs (the bulk snapshots).
  const auto& body() const { return sim.bulk(); }
  std::span<const double> displacement() const { return sim.displacement(); }
};

/// A state view of a body (core::RunBody): what the bulk snapshots read.
template <class State>
concept BodyState = requires(const State& st) {
  { st.displacement() } -> std::convertible_to<std::span<const double>>;
  requires core::RunBody<std::remove_cvref_t<decltype(st.body())>>;
};

/// The interface normal stress σ_yy(x, 0, t) of a body that computes it (core::InPlane::interface_normal_stress,
/// docs/model.md §10.4) into out (sites); false for a state without one (the chain, the antiplane strip: no normal
/// stress on their interface) — its series columns and snapshot field are then absent.
template <class State>
bool interface_normal_stress(const State& st, std::vector<double>& out) {
  if constexpr (BodyState<State>) {
    const auto& body = st.body();
    if constexpr (requires(std::span<const double> u, std::span<double> o) { body.interface_normal_stress(u, o); }) {
      out.resize(body.sites());
      body.interface_normal_stress(st.displacement(), out);
      return true;
    }
  }
  return false;
}

/// A stepper with dense output (AdaptiveSimulation): its state at any t in the last step, each field
/// interpolated on first use (a 1D series row needs v and u_0 only).
template <class Sim>
class DenseState {
 public:
  DenseState(const Sim& sim, double t, std::vector<double> (&buffers)[4]) : sim_(sim), t_(t), buf_(buffers) {}
  double t() const { return t_; }
  std::span<const double> contact_area() const { return field(core::Field::contact_area); }
  std::span<const double> sigma_bar() const { return field(core::Field::sigma_bar); }
  std::span<const double> slip_rate() const { return field(core::Field::slip_rate); }
  std::span<const double> slip() const { return field(core::Field::slip); }
  /// The drive force at t from the body's edge slip on the dense output (the chain: u_0; the strip: the edge
  /// column's mean ū₀ = Σ_j wy(j) u_0j / H, docs/model.md §9), read at the dofs it needs only.
  double drive_force() const {
    const auto& b = sim_.bulk();
    return b.drive_force_at(t_, b.edge_slip_of([this](std::size_t k) { return sim_.dense_value(t_, core::Field::slip, k); }));
  }
  /// The body and the displacement of all its dofs at t (the strip's bulk snapshots).
  const auto& body() const { return sim_.bulk(); }
  std::span<const double> displacement() const {
    all_u_.resize(sim_.bulk().dofs());
    sim_.dense_state(t_, core::Field::slip, all_u_);
    return all_u_;
  }
  double max_slip_rate() const { return core::max_abs_or_inf(slip_rate()); }
  /// ā at t: the law's age mass integrated from the step's start to t on the dense output, over A(t).
  bool mean_age(std::span<double> out) const {
    const auto& law = sim_.law();
    if constexpr (std::remove_cvref_t<decltype(law)>::hooks.dense_ages) {
      if (!law.tracks_ages()) return false;
      const auto area = contact_area();
      const auto at = sim_.dense_sampler();
      for (std::size_t i = 0; i < area.size(); ++i)
        out[i] = area[i] > 0.0 ? law.age_mass_at(i, t_, at) / area[i] : std::numeric_limits<double>::quiet_NaN();
      return true;
    } else {
      return detail::law_mean_age(law, out);
    }
  }

 private:
  std::span<const double> field(core::Field f) const {
    const auto k = static_cast<std::size_t>(f);
    auto& b = buf_[k];
    if (!(loaded_ & (1u << k))) {
      b.resize(sim_.bulk().sites());
      sim_.dense_state(t_, f, b);
      loaded_ |= 1u << k;
    }
    return b;
  }
  const Sim& sim_;
  double t_;
  std::vector<double> (&buf_)[4];
  mutable unsigned loaded_ = 0;
  mutable std::vector<double> all_u_;
};

/// One site driven at an imposed slip rate v (0D, no bulk): the law's state; the drive force is the
/// frictional stress σ = σ̄ + η v.
template <class Law>
struct ImposedRateState {
  const Law& law;
  double time, v;
  double t() const { return time; }
  std::span<const double> contact_area() const { return law.contact_area(); }
  std::span<const double> sigma_bar() const { return law.sigma_bar(); }
  std::span<const double> slip_rate() const { return {&v, 1}; }
  std::span<const double> slip() const { return {}; }
  double drive_force() const { return law.sigma_bar()[0] + law.params().eta * v; }
  double max_slip_rate() const { return std::abs(v); }
  bool mean_age(std::span<double> out) const { return detail::law_mean_age(law, out); }
};

/// What a run stores, and when: series rows every output.series_dt, snapshots every
/// output.snapshot_dt (1D scenes), each at the first step end at or after each multiple (fixed-step
/// runs, exact = false) or at the exact multiples (dense output, exact = true); the body's snapshot fields
/// (the strip's) every output.bulk_dt likewise (at the exact multiples on the adaptive integrator's dense
/// output; nothing on a body without them).
class Recorder {
 public:
  Recorder(const Scene& s, ModelResult& r)
      : eta_(s.interface.eta), one_d_(core::is_one_dimensional(s.drive.loading)),
        series_every_(s.output.series_dt), snapshot_every_(one_d_ && s.output.snapshot_dt > 0 ? s.output.snapshot_dt : -1),
        bulk_every_(one_d_ && s.bulk_output.dt > 0 ? s.bulk_output.dt : -1),
        bulk_stride_(static_cast<std::size_t>(std::max(1, s.bulk_output.stride))), series_due_(series_every_),
        snap_due_(snapshot_every_), bulk_due_(bulk_every_),
        snapshot_rows_(snapshot_every_ > 0 ? static_cast<std::size_t>(s.time.t_end / snapshot_every_) + 2 : 0), r_(r) {}

  /// After a step [t0, t1] (or at the start, t0 = t1 = 0 with exact = false): every row due in it.
  /// state_at(t) gives the state view at t (any t in [t0, t1] when exact; t1 otherwise); tracker gives
  /// the latest tip positions (1D); energy, the budget when tracked.
  template <class StateAt>
  void after_step(double t0, double t1, bool exact, StateAt&& state_at, const FrontTracker& tracker,
                  const std::optional<core::EnergyBudget>& energy) {
    if (!exact) {
      if (series_due_.due(t1)) series_row(state_at(t1), tracker, energy);
      if (snap_due_.due(t1)) snapshot(state_at(t1));
      if (bulk_due_.due(t1)) bulk_snapshot(state_at(t1));
      return;
    }
    multiples_in(t0, t1, series_every_, [&](double t) { series_row(state_at(t), tracker, energy); });
    multiples_in(t0, t1, snapshot_every_, [&](double t) { snapshot(state_at(t)); });
    multiples_in(t0, t1, bulk_every_, [&](double t) { bulk_snapshot(state_at(t)); });
  }

  /// One series row (docs/output.md /series): t, drive_force, max_v; 1D: tip_x, tip_x_alt (and min_sigma_yy,
  /// max_sigma_yy on a body with an interface normal stress); one site:
  /// A, sigma_bar, sigma, slip_rate (and slip where there is a bulk); the energy budget when tracked
  /// (its terms hold at energy_time; all 0 before the first step).
  template <class State>
  void series_row(const State& st, const FrontTracker& tracker, const std::optional<core::EnergyBudget>& energy) {
    Columns& c = r_.series;
    detail::push(c, "t", st.t());
    detail::push(c, "drive_force", st.drive_force());
    detail::push(c, "max_v", st.max_slip_rate());
    if (one_d_) {
      detail::push(c, "tip_x", tracker.last_tip());
      detail::push(c, "tip_x_alt", tracker.last_tip_alt());
      if (interface_normal_stress(st, normal_)) {  // the in-plane strip: the most compressive and most tensile σ_yy
        const auto [lo, hi] = std::minmax_element(normal_.begin(), normal_.end());
        detail::push(c, "min_sigma_yy", *lo);
        detail::push(c, "max_sigma_yy", *hi);
      }
    } else {
      const double sb = st.sigma_bar()[0], v = st.slip_rate()[0];
      detail::push(c, "A", st.contact_area()[0]);
      detail::push(c, "sigma_bar", sb);
      detail::push(c, "sigma", sb + eta_ * v);
      detail::push(c, "slip_rate", v);
      if (const auto u = st.slip(); !u.empty()) detail::push(c, "slip", u[0]);
      double age = 0.0;
      if (st.mean_age({&age, 1})) detail::push(c, "age", age);
    }
    if (energy) {
      const bool started = !std::isnan(energy->mechanical0);
      detail::push(c, "energy_drive_work", started ? energy->drive_work : 0.0);
      detail::push(c, "energy_mechanical", started ? energy->mechanical() - energy->mechanical0 : 0.0);
      detail::push(c, "energy_viscous", started ? energy->viscous : 0.0);
      detail::push(c, "energy_interfacial", started ? energy->interfacial : 0.0);
      detail::push(c, "energy_residual", started ? energy->residual() : 0.0);
      detail::push(c, "energy_time", started ? energy->time : 0.0);
    }
  }

  template <class Ar>
  void serialize(Ar& ar) {
    ar(series_due_, snap_due_, bulk_due_);
  }

  /// One snapshot row (docs/output.md /snapshots): A, sigma_bar, v, u over the nodes; sigma_yy (the interface
  /// normal stress) on a body that has one; age (the mean contact age, docs/model.md §7) when the law carries it.
  template <class State>
  void snapshot(const State& st) {
    const std::size_t rows = snapshot_rows_;
    if (r_.snapshot_t.empty()) r_.snapshot_t.reserve(rows);
    r_.snapshot_t.push_back(st.t());
    detail::append(r_.snapshots, "A", st.contact_area(), rows);
    detail::append(r_.snapshots, "sigma_bar", st.sigma_bar(), rows);
    detail::append(r_.snapshots, "v", st.slip_rate(), rows);
    detail::append(r_.snapshots, "u", st.slip(), rows);
    if (interface_normal_stress(st, normal_)) detail::append(r_.snapshots, "sigma_yy", normal_, rows);
    age_.resize(st.contact_area().size());
    if (st.mean_age(age_)) detail::append(r_.snapshots, "age", age_, rows);
  }

  /// One bulk snapshot (docs/output.md /<model>/bulk/): the body's snapshot fields (core::RunBody:
  /// the strip's u, tau_xz, tau_yz) at the kept nodes (kept_indices in x and y: every bulk_stride-th, the last
  /// column and the top row always), rows in order, columns inner, the components of a node innermost; the
  /// kept positions with the first one. Nothing for a body without snapshot fields (the chain).
  template <class State>
  void bulk_snapshot(const State& st) {
    if constexpr (BodyState<State>) {
      const auto& body = st.body();
      const auto fields = body.snapshot_fields();
      if (fields.empty()) return;
      const auto u = st.displacement();
      const auto cols = kept_indices(body.sites(), bulk_stride_), rows = kept_indices(body.rows(), bulk_stride_);
      if (r_.bulk_t.empty()) {
        r_.bulk_x.clear();
        r_.bulk_y.clear();
        for (const auto i : cols) r_.bulk_x.push_back(body.x()[i]);
        for (const auto j : rows) r_.bulk_y.push_back(body.row_height(j));
      }
      r_.bulk_t.push_back(st.t());
      std::vector<std::vector<double>*> out;  // the column of each field
      std::size_t width = 0;                  // values per node, all fields
      for (const auto& f : fields) {
        out.push_back(&r_.bulk[f.name]);
        width += f.components;
      }
      node_values_.resize(width);
      for (const auto j : rows)
        for (const auto i : cols) {
          body.snapshot_values(u, i, j, node_values_);
          const double* v = node_values_.data();
          for (std::size_t k = 0; k < fields.size(); ++k)
            for (std::size_t c = 0; c < fields[k].components; ++c) out[k]->push_back(*v++);
        }
    }
  }

 private:
  double eta_;
  bool one_d_;
  double series_every_, snapshot_every_, bulk_every_;
  std::size_t bulk_stride_;
  Cadence series_due_, snap_due_, bulk_due_;
  std::size_t snapshot_rows_;  ///< the rows a run to t_end takes (reserved at the first snapshot)
  ModelResult& r_;
  std::vector<double> age_;          ///< scratch row of mean ages
  std::vector<double> node_values_;  ///< scratch: a node's snapshot values (bulk_snapshot)
  std::vector<double> normal_;       ///< scratch: the interface normal stress σ_yy (the in-plane strip)
};

}  // namespace slipfront::compare
