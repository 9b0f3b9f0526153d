#include "compare/alongside.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>

#include "compare/contacts.hpp"
#include "compare/difference.hpp"
#include "compare/laws.hpp"
#include "compare/lockstep.hpp"
#include "compare/runner.hpp"

namespace slipfront::compare {
namespace {

// Field distances between two lockstep runs at a cadence (docs/model.md §2 item 2: fields at fixed times).
class FieldComparison {
 public:
  explicit FieldComparison(double every) : due_(every > 0 ? every : -1) {}
  /// Whether a comparison is due at t (then `record` it: the fields are read only when due).
  bool due(double t) { return due_.due(t); }
  void record(double t, const LockstepRun::Fields& a, const LockstepRun::Fields& b) {
    detail::push(c_, "t", t);
    detail::push(c_, "A_distance", relative_rms_distance(a.area, b.area));
    detail::push(c_, "sigma_bar_distance", relative_rms_distance(a.sigma_bar, b.sigma_bar));
    detail::push(c_, "v_distance", relative_rms_distance(a.slip_rate, b.slip_rate));
    detail::push(c_, "u_distance", relative_rms_distance(a.slip, b.slip));
    if (!a.normal_stress.empty() && !b.normal_stress.empty())  // the in-plane strip's interface normal stress
      detail::push(c_, "sigma_yy_distance", relative_rms_distance(a.normal_stress, b.normal_stress));
  }
  Columns take() { return std::move(c_); }
  template <class Ar>
  void serialize(Ar& ar) {
    ar(due_, c_);
  }

 private:
  Cadence due_;
  Columns c_;
};

// The definitions of the field distances of a lockstep run against the reference model `r`.
void define_fields(Comparison& c, const std::string& r, const Scene& s) {
  if (s.bulk.body() == core::BodyKind::inplane)
    c.definitions["fields/sigma_yy_distance"] = "the same relative L2 distance for the interface normal stress "
                                                "sigma_yy(x, 0) (the in-plane strip only; 0 where both vanish)";
  const std::pair<const char*, std::string> defs[] = {
      {"fields/A_distance", "||A_discrete - A_" + r + "||_2 / ||A_" + r + "||_2 over the nodes at time t"},
      {"fields/sigma_bar_distance", "the same relative L2 distance for sigma_bar"},
      {"fields/v_distance", "the same relative L2 distance for the slip rate v"},
      {"fields/u_distance", "the same relative L2 distance for the slip u"},
      {"fields/t", "comparison times: the first step at or after each multiple of output.compare_dt"}};
  for (const auto& [k, v] : defs) c.definitions[k] = v;
}

// The runs of a lockstep as one SteppedRun (compare/run_loop.hpp), in the order of the table. Each step advances
// every run (a model that has ended, failed or been interrupted stays where it is) and compares the fields of the
// compared model with its reference's when both are at the same time: the first run whose row names references
// (the discrete model), against the first of them that runs (mean_field when it runs, docs/model.md §2.2: the
// ensemble's own N → ∞ limit; else the continuum).
class Lockstep {
 public:
  static constexpr std::int64_t progress_every = 1024;
  static constexpr bool checkpointable = true;
  Lockstep(const Scene& s, std::vector<std::unique_ptr<LockstepRun>>& runs)
      : s_(s), runs_(runs), fields_(s.output.compare_dt) {
    for (const auto& r : runs_) {
      if (compared_) break;
      for (const auto& name : r->kind().references)
        if (LockstepRun* ref = find(name); !name.empty() && ref) {
          compared_ = r.get(), reference_ = ref;
          break;
        }
    }
  }
  bool done() const {
    return std::all_of(runs_.begin(), runs_.end(), [](const auto& r) { return r->done(); });
  }
  double time() const { return runs_.front()->time(); }
  double end() const { return s_.time.t_end; }
  /// The models in the order of the table, joined by '+'.
  std::string label() const {
    std::string out;
    for (const auto& r : runs_) out += (out.empty() ? "" : "+") + r->model();
    return out;
  }
  void start() { observe_fields(); }
  void step() {
    for (auto& r : runs_)
      if (!r->done()) r->step();
    // docs/model.md §7.2: the after-arrest phase of the contact statistics ends at the earliest next
    // instability of the models compared, for all of them (like with like: one cycle in every model)
    if (std::any_of(runs_.begin(), runs_.end(), [](const auto& r) { return r->had_next_instability(); }))
      for (auto& r : runs_) r->close_after_arrest();
    observe_fields();
  }
  void interrupt() {
    for (auto& r : runs_)
      if (!r->done()) r->interrupt();
  }
  bool start_stopped() const {
    return std::any_of(runs_.begin(), runs_.end(), [](const auto& r) { return r->start_stopped(); });
  }
  /// The compared model and its reference (nullptr: no comparison).
  const LockstepRun* compared() const { return compared_; }
  const LockstepRun* reference() const { return reference_; }
  Columns take_fields() { return fields_.take(); }
  template <class Ar>
  void serialize(Ar& ar) {
    // continuum+discrete keep the tag and layout of the checkpoints written before mean_field existed
    const std::string tag = label() == "continuum+discrete" ? std::string("lockstep") : "lockstep " + label();
    ar.tag(tag.c_str());
    for (auto& r : runs_) ar(*r);
    ar(fields_);
  }

 private:
  LockstepRun* find(std::string_view name) const {
    for (const auto& r : runs_)
      if (r->model() == name) return r.get();
    return nullptr;
  }
  // the compared model against its reference, when both advanced to the same time (neither failed)
  void observe_fields() {
    if (compared_ && reference_->time() == compared_->time() && fields_.due(compared_->time()))
      fields_.record(compared_->time(), reference_->fields(), compared_->fields());
  }
  const Scene& s_;
  std::vector<std::unique_ptr<LockstepRun>>& runs_;
  LockstepRun* compared_ = nullptr;
  LockstepRun* reference_ = nullptr;
  FieldComparison fields_;
};

// Per (phase, region) class: the contact snapshots at which both models were in the same phase and both had
// contacts in the class (a class's ages and thresholds are tested only when there are at least 3).
std::vector<double> matched_age_snapshots(const ModelResult& c, const ModelResult& d, const Table2D& age_measured) {
  std::vector<double> age_snapshots(core::FrontClasses::count, 0.0);
  if (age_measured.data.empty()) return age_snapshots;
  const auto& pm = d.contacts.at("contact_snapshot_phase");
  const auto& rows_m = d.contacts_2d.at("region_age_counts");
  const auto& rows_p = c.contacts_2d.at("region_age_counts");
  const std::size_t nb = age_measured.cols;
  for (std::size_t k = 0; k < pm.size(); ++k) {
    if (pm[k] != c.contacts.at("contact_snapshot_phase")[k] || pm[k] >= core::FrontClasses::phases) continue;
    for (std::size_t r = 0; r < core::FrontClasses::regions; ++r) {
      double m = 0.0, p = 0.0;
      for (std::size_t j = 0; j < nb; ++j) {
        m += rows_m.data[k * rows_m.cols + r * nb + j];
        p += rows_p.data[k * rows_p.cols + r * nb + j];
      }
      if (m > 0.0 && p > 0.0) age_snapshots[static_cast<std::size_t>(pm[k]) * core::FrontClasses::regions + r] += 1.0;
    }
  }
  return age_snapshots;
}

// The definitions of contacts/ and its metrics (a table).
void define_contact_rows(Comparison& cmp, const std::string& reference) {
  const std::pair<const char*, std::string> defs[] = {
      {"contacts_tested", "number of (statistic, class) rows of contacts/ tested: at least 500 measured contacts and 2 merged bins"},
      {"contacts_min_p", "smallest p_value over the tested rows of contacts/ (false-alarm rate per row alpha: reject at p < alpha; "
                         "Bonferroni over contacts_tested rows for the family)"},
      {"contacts_max_ks_distance", "largest ks_distance over the tested rows of contacts/"},
      {"contacts/statistic", "0: lifetimes of completed attachments (classed at the detachment); 1: ages of attached contacts "
                             "at the contact snapshots at which both models were in the same phase (docs/model.md §7.2); "
                             "2: yield thresholds of the attached contacts at the same snapshots (threshold_hist_edges)"},
      {"contacts/phase", "0 before first yield, 1 slow front, 2 transient, 3 after arrest (each model's own events)"},
      {"contacts/region", "0 behind the front, 1 in the tip band (|x - x_f| <= measure.tip_band), 2 ahead (x_f: the "
                          "A_tip_alt tip of each model)"},
      {"contacts/measured_total", "contacts counted by the agent in this statistic and class"},
      {"contacts/predicted_total", "expected count predicted from the " + reference + " fields (N x the expected fraction)"},
      {"contacts/ks_distance", "max over the class_time_edges (thresholds: threshold_hist_edges) of |F_measured - F_predicted| "
                               "(whole population, binned CDFs)"},
      {"contacts/thinned_size", "m: size of the uniform subsample of the measured contacts tested (min(2000, measured_total))"},
      {"contacts/chi2", "Pearson X^2 of the subsample against the predicted proportions, bins merged until each expects >= 5"},
      {"contacts/dof", "merged bins - 1"},
      {"contacts/p_value", "P(chi^2_dof >= chi2) (Boost.Math): false-alarm rate alpha when the measured population has the "
                           "predicted distribution; resolution ~1/sqrt(m)"},
      {"contacts/tested", "1 when the row is tested: measured_total >= 500, dof >= 1, and for ages and thresholds at least "
                          "3 matched contact snapshots with contacts in the class in both models"}};
  for (const auto& [k, v] : defs) cmp.definitions[k] = v;
}

// docs/model.md §7.2: the agent's lifetime and age histograms by region and phase against the prediction of
// c — the continuum's, or the mean-field law's at the scene's w (docs/model.md §2.2) — (compare/contacts.hpp:
// contact_fit), one row per statistic and class.
void compare_contacts(const ModelResult& c, const ModelResult& d, Comparison& cmp) {
  double min_p = 1.0, max_ks = 0.0, tested = 0.0;
  // Ages are sampled at the contact snapshots only, so they are compared at the snapshots at which both
  // models were in the same phase (matched_age_tables), and a class is tested only if at least 3 such
  // snapshots had contacts in it: near a fast event (the transient, the arrest) one snapshot of each
  // model compares different moments of it.
  const auto [age_measured, age_predicted] = matched_age_tables(d, c);
  const std::vector<double> age_snapshots = matched_age_snapshots(c, d, age_measured);
  // Thresholds of the attached contacts: sampled at the same snapshots, matched the same way (a class has contacts
  // in its threshold rows exactly when it has them in its age rows).
  // On other edges (a prediction at another w than the agent's, without its edges) they are not compared.
  const auto edges_m = d.contacts.find("threshold_hist_edges"), edges_p = c.contacts.find("threshold_hist_edges");
  const bool same_edges = edges_m != d.contacts.end() && edges_p != c.contacts.end() && edges_m->second == edges_p->second;
  const auto [threshold_measured, threshold_predicted] =
      same_edges ? matched_tables(d, c, "region_threshold_counts") : std::pair<Table2D, Table2D>{};
  for (const char* stat : {"lifetime", "age", "threshold"}) {
    const std::string st = stat;
    const bool snapshots = st != "lifetime";
    const std::string name = "class_" + st + "_counts";
    const Table2D none;
    auto table = [&](const ModelResult& r, const Table2D& matched_age, const Table2D& matched_threshold) -> const Table2D& {
      if (st == "age") return matched_age;
      if (st == "threshold") return matched_threshold;
      const auto it = r.contacts_2d.find(name);
      return it == r.contacts_2d.end() ? none : it->second;
    };
    const Table2D& measured = table(d, age_measured, threshold_measured);
    const Table2D& predicted = table(c, age_predicted, threshold_predicted);
    if (measured.data.empty() || predicted.data.empty()) continue;
    for (ContactFit f : contact_fit(stat, measured, predicted)) {
      if (snapshots && age_snapshots[f.phase * core::FrontClasses::regions + f.region] < 3.0) f.tested = false;
      auto& col = cmp.contacts;
      detail::push(col, "statistic", st == "lifetime" ? 0.0 : st == "age" ? 1.0 : 2.0);
      detail::push(col, "phase", static_cast<double>(f.phase));
      detail::push(col, "region", static_cast<double>(f.region));
      detail::push(col, "measured_total", f.measured_total);
      detail::push(col, "predicted_total", f.predicted_total);
      detail::push(col, "ks_distance", f.ks_distance);
      detail::push(col, "thinned_size", f.thinned_size);
      detail::push(col, "chi2", f.chi2);
      detail::push(col, "dof", f.dof);
      detail::push(col, "p_value", f.p_value);
      detail::push(col, "tested", f.tested ? 1.0 : 0.0);
      if (f.tested) {
        min_p = std::min(min_p, f.p_value);
        max_ks = std::max(max_ks, f.ks_distance);
        tested += 1.0;
      }
    }
  }
  if (cmp.contacts.empty()) return;
  cmp.metrics["contacts_tested"] = tested;
  cmp.metrics["contacts_min_p"] = min_p;
  cmp.metrics["contacts_max_ks_distance"] = max_ks;
  define_contact_rows(cmp, c.model);
}

}  // namespace

// The in-plane strip's interface normal stress σ_yy(x, 0, t) (docs/output.md): the histories of its extremes and its
// snapshots, where both models wrote them (the other bodies have none: no metric).
void compare_normal_stress(const ModelResult& c, const ModelResult& d, Comparison& cmp) {
  const std::string& ref = c.model;
  for (const char* col : {"min_sigma_yy", "max_sigma_yy"}) {
    if (!c.series.count(col) || !d.series.count(col)) continue;
    cmp.metrics[std::string(col) + "_history_distance"] = relative_rms_distance(c.series.at(col), d.series.at(col));
    cmp.definitions[std::string(col) + "_history_distance"] =
        std::string("relative RMS distance over the series times of ") + col + "(t): sqrt(sum (discrete - " + ref +
        ")^2 / sum " + ref + "^2)";
  }
  const auto a = c.snapshots.find("sigma_yy"), b = d.snapshots.find("sigma_yy");
  if (a == c.snapshots.end() || b == d.snapshots.end()) return;
  // the snapshots of both at the same times (a run cut short has fewer: the common ones, its first rows)
  const std::size_t rows = std::min(c.snapshot_t.size(), d.snapshot_t.size());
  bool same_times = true;
  for (std::size_t k = 0; k < rows; ++k) same_times = same_times && c.snapshot_t[k] == d.snapshot_t[k];
  const std::size_t nx = c.x.size();
  const std::size_t n = std::min({rows * nx, a->second.size(), b->second.size()});
  cmp.metrics["sigma_yy_snapshot_distance"] =
      same_times ? relative_rms_distance(std::span(a->second).first(n), std::span(b->second).first(n)) : nan;
  cmp.definitions["sigma_yy_snapshot_distance"] =
      "relative L2 distance of the interface normal stress over every node of the snapshots both models wrote: "
      "sqrt(sum (sigma_yy_discrete - sigma_yy_" + ref + ")^2 / sum sigma_yy_" + ref +
      "^2) (the in-plane strip; NaN if the snapshot times differ)";
}

Comparison compare_results(const Scene& s, const ModelResult& c, const ModelResult& d, const ModelResult* predictor) {
  Comparison cmp;
  cmp.reference = c.model;
  const std::string& ref = c.model;  // the reference: continuum, or mean_field (docs/model.md §2.2)
  for (const auto& [name, field] : event_fields)
    for (const bool alt : {false, true}) {
      const double a = (alt ? c.events_alt : c.events).*field, b = (alt ? d.events_alt : d.events).*field;
      if (std::isnan(a) && std::isnan(b)) continue;
      const std::string key = std::string(name) + (alt ? "_alt" : "");
      cmp.metrics[key + "_rel_diff"] = relative_difference(a, b);
      cmp.metrics[key + "_abs_diff"] = b - a;
      cmp.definitions[key + "_rel_diff"] = "(discrete - " + ref + ") / |" + ref + "| of the event " + key +
                                           " (docs/model.md §3; _alt: on the A_tip_alt front); 0 where both are 0, NaN where "
                                           "one model has no such event or only the " + ref + " value is 0 (see _abs_diff)";
      cmp.definitions[key + "_abs_diff"] = "discrete - " + ref + " of the event " + key + "; NaN where one model has no such event";
    }
  const bool zero_d = !core::is_one_dimensional(s.drive.loading);
  const char* col = zero_d && s.drive.loading == core::Loading::imposed_rate ? "sigma" : "drive_force";
  if (c.series.count(col) && d.series.count(col)) {
    cmp.metrics[std::string(col) + "_history_distance"] = relative_rms_distance(c.series.at(col), d.series.at(col));
    cmp.definitions[std::string(col) + "_history_distance"] =
        std::string("relative RMS distance over the series times of ") + col +
        "(t): sqrt(sum (discrete - " + ref + ")^2 / sum " + ref + "^2)";
  }
  compare_normal_stress(c, d, cmp);
  if (c.series.count("tip_x") && d.series.count("tip_x")) {
    const auto& a = c.series.at("tip_x");
    const auto& b = d.series.at("tip_x");
    double s2 = 0;
    int n = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
      if (std::isfinite(a[i]) && std::isfinite(b[i])) { s2 += (a[i] - b[i]) * (a[i] - b[i]); ++n; }
    cmp.metrics["tip_x_rms_difference"] = n ? std::sqrt(s2 / n) : nan;
    cmp.definitions["tip_x_rms_difference"] =
        "RMS over the series times where both fronts exist of x_tip(discrete) - x_tip(" + ref + ")";
  }
  // the contact statistics against the predictor's prediction (docs/model.md §7.2: the reference's own)
  if (predictor) compare_contacts(*predictor, d, cmp);
  if (c.friction_law.count("sigma") && d.friction_law.count("sigma")) {
    const auto& a = c.friction_law.at("sigma");
    const auto& b = d.friction_law.at("sigma");
    double mx = 0, s2 = 0;
    for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
      const double r = relative_difference(a[k], b[k]);
      detail::push(cmp.friction_law, "v", c.friction_law.at("v")[k]);
      detail::push(cmp.friction_law, "rel_diff", r);
      mx = std::max(mx, std::abs(r));
      s2 += r * r;
    }
    cmp.metrics["friction_law_max_rel_diff"] = mx;
    cmp.metrics["friction_law_rms_rel_diff"] = a.empty() ? nan : std::sqrt(s2 / static_cast<double>(a.size()));
    const std::string sr = "sigma_" + ref;
    cmp.definitions["friction_law_max_rel_diff"] = "max over v of |sigma_discrete - " + sr + "| / " + sr;
    cmp.definitions["friction_law_rms_rel_diff"] = "RMS over v of (sigma_discrete - " + sr + ") / " + sr;
    cmp.definitions["friction_law/rel_diff"] = "(sigma_discrete - " + sr + ") / " + sr + " at each v";
  }
  return cmp;
}

std::vector<std::string> shareable_references(const Scene& s) {
  if (s.models.size() < 2 || s.discrete.contact_statistics) return {};
  // in lockstep the fields of the discrete model are compared online with its reference, at output.compare_dt > 0
  const std::string reference = discrete_reference(s);
  const bool compared_online = runs_in_lockstep(s) && s.lists("discrete") && s.output.compare_dt > 0.0;
  std::vector<std::string> out;
  for (const auto& k : model_kinds)  // a deterministic model that is some model's reference (compare/models.hpp)
    if (!k.seeded && is_reference_model(k.name) && s.lists(std::string(k.name)) && !(compared_online && k.name == reference))
      out.emplace_back(k.name);
  return out;
}

bool reference_ignores(const std::string& model, const std::string& key) {
  if (key.rfind("discrete.", 0) != 0) return false;
  const ModelKind* k = find_model_kind(model);
  if (!k || k->seeded) return false;
  if (std::find(k->discrete_keys.begin(), k->discrete_keys.end(), "discrete.*") != k->discrete_keys.end()) return false;
  return std::find(k->discrete_keys.begin(), k->discrete_keys.end(), key) == k->discrete_keys.end();
}

SceneResult run_scene_with_references(const Scene& s, const std::map<std::string, const ModelResult*>& given,
                                      const RunControl& ctl) {
  const auto ok = shareable_references(s);
  for (const auto& [m, r] : given)
    if (std::find(ok.begin(), ok.end(), m) == ok.end() || !r || r->model != m)
      throw std::invalid_argument("run_scene_with_references: the scene's " + m +
                                  " cannot be given (shareable_references)");
  Scene rest = s;
  std::erase_if(rest.models, [&](const std::string& m) { return given.count(m) > 0; });
  // the other models as run_scene_alongside runs them (each model's result is the one it gives alone, in lockstep
  // or not), with their comparison when the reference is among them
  SceneResult others = rest.models.size() >= 2 ? run_scene_alongside(rest, ctl)
                       : rest.models.empty()   ? SceneResult{}
                                               : SceneResult{run_scene(rest, ctl), {}};
  SceneResult out;
  out.comparison = std::move(others.comparison);
  std::size_t k = 0;
  for (const auto& m : s.models) out.models.push_back(given.count(m) ? *given.at(m) : std::move(others.models.at(k++)));
  const std::string reference = discrete_reference(s);
  if (s.lists("discrete") && given.count(reference)) {  // the discrete model's reference was given
    const ModelResult& ref = *given.at(reference);
    const ModelResult& disc = *std::find_if(out.models.begin(), out.models.end(),
                                            [](const ModelResult& r) { return r.model == "discrete"; });
    out.comparison = compare_results(s, ref, disc, &ref);
    if (runs_in_lockstep(s)) define_fields(out.comparison, reference, s);  // as the lockstep run (no rows: compare_dt 0)
  }
  return out;
}

SceneResult run_scene_alongside(const Scene& s, const RunControl& ctl) {
  auto separately = [&] {
    // One model, 0D imposed-rate scenes (no bulk to share), or the adaptive continuum integrator (no
    // common step): the models run one after the other and are compared at the end (no field distances).
    SceneResult out;
    out.models = run_scene(s, ctl);
    const ModelResult* ref = nullptr;
    const ModelResult* d = nullptr;
    for (const auto& r : out.models) {
      if (r.model == discrete_reference(s)) ref = &r;
      if (r.model == "discrete") d = &r;
    }
    if (d && ref) out.comparison = compare_results(s, *ref, *d, ref);
    return out;
  };
  if (!runs_in_lockstep(s)) return separately();
  return run_in_lockstep<ShippedModels>(s, ctl);
}

SceneResult run_lockstep_runs(const Scene& s, std::vector<std::unique_ptr<LockstepRun>> runs, const RunControl& ctl) {
  if (runs.size() < 2) throw std::invalid_argument("run_lockstep_runs: a lockstep needs two runs or more");
  Lockstep all(s, runs);
  // a stop in a steady-front start's solve: every run ends interrupted at t = 0, no checkpoint is resumed into it
  const bool start_stopped = all.start_stopped();
  if (start_stopped) all.interrupt();
  if (!ctl.restart.empty() && !start_stopped) {  // continue from a checkpoint (RunControl)
    core::Archive ar = core::Archive::reader(ctl.restart);
    ar(all);
  } else {
    all.start();
  }
  run_loop(all, ctl, all.label());
  std::map<std::string, ModelResult> done;
  for (auto& r : runs) {
    const std::string name = r->model();  // before finish() hands the result (with its name) over
    done[name] = r->finish();
  }
  SceneResult out;
  if (all.compared()) {
    const ModelResult& ref = done.at(std::string(all.reference()->kind().name));
    out.comparison = compare_results(s, ref, done.at(std::string(all.compared()->kind().name)), &ref);
    out.comparison.fields = all.take_fields();
    define_fields(out.comparison, ref.model, s);
  }
  for (const auto& m : s.models) out.models.push_back(std::move(done.at(m)));  // in the scene's order
  return out;
}

}  // namespace slipfront::compare
