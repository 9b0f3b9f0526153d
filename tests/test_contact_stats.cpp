// docs/model.md §7.2 (docs/contacts.md §2–§5): contact statistics by region and phase, their prediction
// from the continuum fields (compare::ContactPrediction) and the goodness of fit (compare::contact_fit).
//
// 1. The prediction is exact in 0D. One site at an imposed history v = 0.5 → 3 → 0 (a hold from t = 20
//    on) with α = 2, so that every attached contact is overloaded whenever v ≠ 0 (asserted; a restart
//    after the hold would re-stick the site and make its yield depend on the random A, so there is
//    none), ages at t = 9.9 and 34.9 (no contact attached at both): the contacts of the agent are
//    then independent two-state chains with the rates of the continuum law, and the lifetimes and ages
//    of all contacts of 50 seeds (N = 1000 each) are independent draws of the predicted distributions.
//    The whole population is tested (no thinning): Pearson X² on the class edges, two tests (lifetimes,
//    ages) at 5e-4 each, family-wise false-alarm rate 1e-3. Power: the prediction with the hazard
//    × 1.2 is rejected.
// 2. On a front (a fig1-like edge-loaded interface, L = 100, to t = 70: the slow front only), the agent
//    (N = 10⁴) alongside the continuum on the implicit integrator: every tested class of
//    /compare/contacts passes at the family-wise rate 1e-3 (Bonferroni over the tested rows; each row
//    tests a uniform subsample of m = 2000 contacts: false-alarm rate exact when the measured population
//    has the predicted distribution); the continuum's prediction with κ × 1.2 is rejected; the per-site
//    totals add up; the prediction's cohorts stay within their bound.
// 3. Threshold disorder (w = 0.3, uniform, fresh renewal): behind the front the attached contacts are
//    the strong ones (mean threshold above the drawn mean), ahead of it they are the drawn ones.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <cstdio>
#include <numeric>
#include <vector>

#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/contacts.hpp"
#include "compare/laws.hpp"
#include "compare/runner.hpp"
#include "continuum/friction_law.hpp"
#include "discrete/agent_law.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

constexpr double kDt = 0.01;
constexpr int kSteps = 3500;
double history_v(double t0) { return t0 < 9.9999 ? 0.5 : (t0 < 19.9999 ? 3.0 : 0.0); }
// t = 9.9 and 34.9 (during the hold): no contact is attached at both (hazard 24 over [10, 20])
bool snapshot_step(int n) { return n == 990 || n == 3490; }

core::InterfaceParams alpha2() {
  auto p = testing::paper_interface();
  p.alpha = 2.0;
  return p;
}

// The continuum's prediction of the pooled contacts of `seeds` runs of N contacts.
core::ContactTables predict_0d(double contacts, double hazard_scale) {
  const auto p = alpha2();
  continuum::FrictionLaw law(p, 1);
  law.track_ages(true);
  compare::ContactPrediction pred(1, contacts, hazard_scale);
  pred.start(law.contact_area());
  for (int n = 1; n <= kSteps; ++n) {
    const double v = history_v((n - 1) * kDt), a0 = law.contact_area()[0], sb0 = law.sigma_bar()[0];
    const double h[1] = {core::contact_stress(sb0 + p.eta * v, a0) > 1.0 ? p.kappa * std::abs(v) : 0.0};
    const double vv[1] = {v}, aa[1] = {a0};
    law.advance(kDt, vv);
    pred.step(kDt, aa, h);
    if (snapshot_step(n)) pred.snapshot();
    // the cohorts hold the law's A, and their mean age is its age field's (docs/contacts.md §3)
    if (hazard_scale == 1.0 && n % 500 == 0) {
      REQUIRE(pred.attached_mass(0) == Approx(law.contact_area()[0]).epsilon(1e-9));
      REQUIRE(pred.mean_age(0) == Approx(law.age_mass()[0] / law.contact_area()[0]).epsilon(1e-4));
    }
  }
  return pred.tables();
}

compare::Table2D table(const core::ContactTables& t, const char* name) {
  const auto& x = t.tables.at(name);
  return {x.cols, x.data};
}

}  // namespace

TEST_CASE("contact prediction: exact in 0D with deterministic rates (lifetimes and ages, 50 seeds)", "[contacts]") {
  const int seeds = 50;
  const long n_contacts = 1000;
  discrete::DiscreteParams dp;
  dp.contacts_per_site = n_contacts;
  dp.representation = "agent";
  dp.contact_statistics = true;
  compare::Table2D life, age;
  bool overloaded = true;
  for (int k = 0; k < seeds; ++k) {
    dp.seed = 500 + static_cast<std::uint64_t>(k);
    discrete::AgentLaw law(alpha2(), dp, 1);
    for (int n = 1; n <= kSteps; ++n) {
      const double t0 = (n - 1) * kDt, v = history_v(t0), vv[1] = {v};
      const bool y = law.advance(kDt, vv).any_yield;
      if (v != 0.0 && t0 > 1.0) overloaded &= y;
      if (snapshot_step(n)) law.record_contacts(n * kDt);
    }
    const auto t = law.contact_tables();
    for (auto [dst, name] : {std::pair{&life, "class_lifetime_counts"}, std::pair{&age, "class_age_counts"}}) {
      const auto& src = t.tables.at(name);
      if (dst->data.empty()) *dst = {src.cols, std::vector<double>(src.data.size(), 0.0)};
      for (std::size_t j = 0; j < src.data.size(); ++j) dst->data[j] += src.data[j];
    }
  }
  REQUIRE(overloaded);  // precondition: Y = 1 whenever v ≠ 0 (independent contacts)
  const double inf = std::numeric_limits<double>::infinity();
  const auto right = predict_0d(static_cast<double>(seeds * n_contacts), 1.0);
  const auto wrong = predict_0d(static_cast<double>(seeds * n_contacts), 1.2);
  // no front in 0D: every contact is in class 2 (phase 0, ahead)
  const auto fl = compare::contact_fit("lifetime", life, table(right, "class_lifetime_counts"), inf)[2];
  const auto fa = compare::contact_fit("age", age, table(right, "class_age_counts"), inf)[2];
  const auto fw = compare::contact_fit("lifetime", life, table(wrong, "class_lifetime_counts"), inf)[2];
  const auto fwa = compare::contact_fit("age", age, table(wrong, "class_age_counts"), inf)[2];
  std::printf("0D prediction: lifetimes n = %.0f (predicted %.1f), X2 = %.1f, dof %.0f, p = %.3g, KS %.2e | ages n = %.0f "
              "(predicted %.1f), X2 = %.1f, dof %.0f, p = %.3g, KS %.2e\n",
              fl.measured_total, fl.predicted_total, fl.chi2, fl.dof, fl.p_value, fl.ks_distance, fa.measured_total,
              fa.predicted_total, fa.chi2, fa.dof, fa.p_value, fa.ks_distance);
  std::printf("0D prediction, hazard x 1.2: lifetimes X2 = %.1f, p = %.3g, KS %.3f; ages X2 = %.1f, p = %.3g\n", fw.chi2,
              fw.p_value, fw.ks_distance, fwa.chi2, fwa.p_value);
  if (std::getenv("SLIPFRONT_TEST_VERBOSE")) {
    const auto& pr = right.tables.at("class_lifetime_counts").data;
    const auto edges = discrete::class_time_edges();
    for (std::size_t b = 0; b + 1 < edges.size(); ++b)
      if (life.data[2 * life.cols + b] > 0)
        std::printf("  [%.4g, %.4g): measured %8.0f predicted %10.1f (%+.2f sd)\n", edges[b], edges[b + 1],
                    life.data[2 * life.cols + b], pr[2 * life.cols + b],
                    (life.data[2 * life.cols + b] - pr[2 * life.cols + b]) / std::sqrt(pr[2 * life.cols + b]));
  }
  CHECK(fl.measured_total > 5e5);
  CHECK(fl.p_value > 5e-4);
  CHECK(fa.p_value > 5e-4);
  // the expected totals: relative difference within 4 Poisson standard errors
  CHECK(std::abs(fl.measured_total - fl.predicted_total) < 4.0 * std::sqrt(fl.predicted_total));
  CHECK(fw.p_value < 1e-3);
  CHECK(fwa.p_value < 1e-3);
}

namespace {

// fig1's interface and bulk on L = 100 to t = 70 (t* = 25.7: a slow front of ~ 35 length units), the
// implicit integrator at dt = 0.02, the agent with N = 10⁴ and contact statistics every 5.
compare::Scene front_scene() {
  auto s = testing::fig1_scene();
  s.name = "contacts_small";
  s.bulk.length = 100.0;
  s.time.t_end = 70.0;
  s.time.integrator = core::Integrator::implicit_trapezoidal;
  s.time.dt = 0.02;
  s.output.snapshot_dt = 5.0;
  s.output.compare_dt = 0.0;
  s.models = {"continuum", "discrete"};
  s.discrete.representation = "agent";
  s.discrete.contacts_per_site = 10000;
  s.discrete.contact_statistics = true;
  s.discrete.seed = 2;
  s.validate();
  return s;
}

void print_fit(const compare::Comparison& c) {
  const auto& k = c.contacts;
  for (std::size_t i = 0; i < k.at("phase").size(); ++i)
    if (k.at("measured_total")[i] > 0)
      std::printf("  %s %-12s %-6s n = %9.0f predicted %11.1f KS %.4f X2 %7.1f dof %2.0f p %.3g%s\n",
                  k.at("statistic")[i] == 0 ? "lifetime" : "age     ",
                  core::phase_name(static_cast<std::size_t>(k.at("phase")[i])),
                  core::region_name(static_cast<std::size_t>(k.at("region")[i])), k.at("measured_total")[i],
                  k.at("predicted_total")[i], k.at("ks_distance")[i], k.at("chi2")[i], k.at("dof")[i],
                  k.at("p_value")[i], k.at("tested")[i] ? "" : "  (not tested)");
}

}  // namespace

TEST_CASE("contact statistics on a front: the agent agrees with the continuum's prediction, kappa x 1.2 does not",
          "[contacts][front]") {
  const auto s = front_scene();
  const auto r = compare::run_scene_alongside(s, compare::RunControl{});
  const auto& c = r.models[0];
  const auto& d = r.models[1];
  REQUIRE(c.model == "continuum");
  REQUIRE(d.status == slipfront::compare::RunStatus::complete);
  const auto& cmp = r.comparison;
  REQUIRE(cmp.metrics.count("contacts_tested"));
  print_fit(cmp);
  const double tested = cmp.metrics.at("contacts_tested"), min_p = cmp.metrics.at("contacts_min_p");
  std::printf("front: %.0f rows tested, smallest p %.3g (Bonferroni threshold %.2g), largest KS %.4f; t^: none by t_end\n",
              tested, min_p, 1e-3 / tested, cmp.metrics.at("contacts_max_ks_distance"));
  CHECK(tested >= 6);  // slow front: lifetimes and ages behind, at the tip, ahead; ages before yield
  CHECK(min_p > 1e-3 / tested);

  // per-site totals add up; the attachments exceed the detachments by the contacts lost (N(1 − A))
  const auto& dets = d.contacts.at("detachments_total_per_site");
  CHECK(std::accumulate(dets.begin(), dets.end(), 0.0) == Approx(d.contacts.at("lifetime_total")[0]));
  const auto& pdet = c.contacts.at("detachments_total_per_site");
  const double pd = std::accumulate(pdet.begin(), pdet.end(), 0.0), md = std::accumulate(dets.begin(), dets.end(), 0.0);
  std::printf("front: detachments measured %.0f, predicted %.1f (%+.2f%%)\n", md, pd, 100.0 * (md / pd - 1.0));
  CHECK(std::abs(md / pd - 1.0) < 0.02);
  // the cohorts' bound: ln(age_cap/dt)/ln(1 + width/2) + 2 with age_cap = 1e4, width 0.1
  const double bound = std::log(1e4 / 0.02) / std::log(1.05) + 2.0;
  std::printf("front: at most %.0f cohorts per site (bound %.0f)\n", c.scalars.at("contact_prediction_max_cohorts"), bound);
  CHECK(c.scalars.at("contact_prediction_max_cohorts") <= bound);

  // A deliberately wrong prediction from the same fields: the hazard × 1.2.
  const core::Bulk probe(s.bulk, s.drive, s.interface, s.grid.dx);
  compare::ContactPredictionSetup wrong;
  wrong.mode = compare::ContactPredictionSetup::Mode::on;
  wrong.hazard_scale = 1.2;
  compare::DynamicRun<continuum::FrictionLaw, core::ImplicitSimulation<continuum::FrictionLaw>> run(
      s, continuum::FrictionLaw(s.interface, probe.nodes()), "continuum", wrong);
  while (!run.done()) run.step();
  const auto cw = compare::compare_results(s, run.finish(), d);
  print_fit(cw);
  std::printf("front, hazard x 1.2: smallest p %.3g, largest KS %.4f\n", cw.metrics.at("contacts_min_p"),
              cw.metrics.at("contacts_max_ks_distance"));
  CHECK(cw.metrics.at("contacts_min_p") < 1e-3 / cw.metrics.at("contacts_tested"));
}

TEST_CASE("contact statistics with threshold disorder: the front keeps the strong contacts", "[contacts][thresholds]") {
  // Fresh renewal (a new threshold at each attachment) and quenched (every contact keeps its threshold).
  // Behind the slow front the overloaded (weak) contacts detach at rate kappa|v| and the others stay: with
  // fresh renewal every re-attachment draws again, so the strong ones accumulate and the attached mean
  // threshold rises well above the drawn 1 (> +0.05; measured +0.11); quenched, a site's composition is
  // fixed and only the weak contacts' attached fraction 1/(1 + kappa v) drops, so the rise is bounded by it
  // (> +0.015; measured +0.028) and smaller than the fresh one (by more than 2x). Ahead of the front the
  // attached contacts are the drawn ones. Deterministic for the fixed seed; the margins are > 10 SE.
  double bias[2] = {0, 0};
  for (const char* renewal : {"fresh", "quenched"}) {
  const bool quenched = std::string(renewal) == "quenched";
  INFO("renewal " << renewal);
  auto s = front_scene();
  s.models = {"discrete"};
  s.discrete.contacts_per_site = 1000;
  s.discrete.threshold = "uniform";
  s.discrete.width = 0.3;
  s.discrete.renewal = renewal;
  const auto r = compare::run_scene(s, compare::RunControl{});
  const auto& d = r.at(0);
  const auto& tab = d.contacts_2d.at("class_threshold_counts");
  const auto& edges = d.contacts.at("threshold_hist_edges");
  const auto& drawn = d.contacts.at("threshold_drawn_counts");
  auto mean_of = [&](const double* row) {
    double n = 0, sum = 0;
    for (std::size_t b = 0; b < tab.cols; ++b) {
      const double mid = std::isfinite(edges[b + 1]) ? 0.5 * (edges[b] + edges[b + 1]) : edges[b];
      n += row[b];
      sum += row[b] * mid;
    }
    return std::pair{sum / n, n};
  };
  const auto [drawn_mean, n_drawn] = mean_of(drawn.data());
  const std::size_t slow = 3 * 1;  // phase 1 (slow front), rows behind, tip, ahead
  const auto [behind, nb] = mean_of(tab.data.data() + (slow + 0) * tab.cols);
  const auto [ahead, na] = mean_of(tab.data.data() + (slow + 2) * tab.cols);
  std::printf("thresholds (w = 0.3, %s renewal): drawn mean %.4f (n %.0f), attached behind the slow front %.4f (n %.0f), "
              "ahead %.4f (n %.0f)\n",
              renewal, drawn_mean, n_drawn, behind, nb, ahead, na);
  // uniform on [1 − 0.52, 1 + 0.52]: sd 0.3; the means of n contacts have SE 0.3/sqrt(n) (bins: ≤ 0.01)
  CHECK(std::abs(drawn_mean - 1.0) < 0.02);
  CHECK(std::abs(ahead - drawn_mean) < 0.02);
  CHECK(behind > drawn_mean + (quenched ? 0.015 : 0.05));
  bias[quenched ? 1 : 0] = behind - drawn_mean;
  // per snapshot by region (region_threshold_counts [ns, 3 nt]): the three regions of a classed snapshot add up to
  // its threshold histogram, and summed over the snapshots of a phase they are that phase's class rows
  const auto& regions = d.contacts_2d.at("region_threshold_counts");
  const auto& hist = d.contacts_2d.at("threshold_hist_counts");
  const auto& phase = d.contacts.at("contact_snapshot_phase");
  const std::size_t nt = tab.cols, ns = phase.size();
  REQUIRE(regions.cols == 3 * nt);
  REQUIRE(regions.data.size() == ns * 3 * nt);
  std::vector<double> by_class(12 * nt, 0.0);
  std::size_t classed = 0;
  for (std::size_t k = 0; k < ns; ++k) {
    if (phase[k] >= 4.0) continue;
    ++classed;
    const auto ph = static_cast<std::size_t>(phase[k]);
    for (std::size_t j = 0; j < nt; ++j) {
      const double* row = regions.data.data() + k * 3 * nt;
      CHECK(row[j] + row[nt + j] + row[2 * nt + j] == hist.data[k * nt + j]);
      for (std::size_t reg = 0; reg < 3; ++reg) by_class[(3 * ph + reg) * nt + j] += row[reg * nt + j];
    }
  }
  CHECK(classed >= 3);
  CHECK(by_class == tab.data);
  }
  CHECK(bias[0] > 2.0 * bias[1]);
}

TEST_CASE("contact statistics keys: output.ages, output.contact_snapshot_dt, measure.tip_band", "[contacts][config]") {
  const std::string base = testing::minimal_config();
  std::vector<std::string> notes;
  const auto s = app::parse_scene(base + "[output]\nages = true\n[measure]\ntip_band = 3\n", "t.toml", {}, &notes);
  CHECK(s.output.ages);
  CHECK(s.measure.tip_band == 3.0);
  CHECK(s.output.contact_every() == s.output.snapshot_dt);  // default: the field snapshots' cadence
  CHECK_THROWS_WITH(app::parse_scene(base + "[measure]\ntip_band = -1\n", "t.toml", {}, nullptr),
                    Catch::Contains("measure.tip_band") && Catch::Contains(">= 0"));
  // used only with discrete.contact_statistics: noted and reset otherwise
  notes.clear();
  const auto u = app::parse_scene(base + "[output]\ncontact_snapshot_dt = 5\n", "t.toml", {}, &notes);
  CHECK(u.output.contact_snapshot_dt < 0.0);
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].find("output.contact_snapshot_dt") != std::string::npos);
  const auto v = app::parse_scene("models = [\"continuum\", \"discrete\"]\n" + base +
                                      "[output]\ncontact_snapshot_dt = 0\n[discrete]\nrepresentation = \"agent\"\n"
                                      "contact_statistics = true\n",
                                  "t.toml", {}, nullptr);
  CHECK(v.output.contact_every() < 0.0);  // 0: no contact snapshots
}
