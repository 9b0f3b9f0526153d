// Slow tier (label "slow"): the agent's contact statistics on the disordered contacts scene against the
// mean-field prediction at the scene's w (docs/model.md §2.2, §7.2; issue 21: "the contact-level prediction of the
// disordered scene is made from the wrong fields").
//
// Scene (built here, as configs/contacts_disorder.toml): fig1, implicit dt = 0.02, the agent with N = 1e4, uniform
// thresholds w = 0.2, fresh renewal, seed 2, contact snapshots every 5, tip band 5, to t = 120 — before the agent's
// second slip event (t ≈ 132 at this seed; the mean-field's comes later, so "after arrest" would compare different
// cycles beyond it). Statistic: per (statistic, phase, region) row, Pearson X² of a uniform subsample of m = 2000
// measured contacts against the predicted proportions (compare/contacts.hpp: contact_fit); false-alarm rate 0.01 per
// row, Bonferroni over the tested rows for the family (0.01).
//
// What is asserted:
//   - the mean-field prediction is closer to the agent than the continuum's (w = 0) in the rows that matter: summed
//     over the tested rows, its KS distance is smaller, and it fails fewer rows at the family rate;
//   - a deliberately wrong width (w × 1.5 = 0.3) is rejected: its smallest p-value is below the family threshold.
// What is printed, not asserted (a finding, docs/discrete.md): the rows the mean-field prediction still fails at
// N = 1e4 — on the first run, 3 of 15 (slow front: lifetimes ahead, ages in the tip band; after arrest: ages ahead).
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

#include "compare/alongside.hpp"
#include "compare/laws.hpp"
#include "compare/runner.hpp"
#include "discrete/mean_field_law.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

compare::Scene contacts_disorder() {
  compare::Scene s = testing::fig1_scene();
  s.name = "contacts_disorder_mean_field";
  s.models = {"continuum", "mean_field", "discrete"};
  s.time.t_end = 120.0;
  s.time.integrator = core::Integrator::implicit_trapezoidal;
  s.time.dt = 0.02;
  s.measure.tip_band = 5.0;
  s.output.snapshot_dt = 5.0;
  s.output.contact_snapshot_dt = 5.0;
  s.discrete.contacts_per_site = 10000;
  s.discrete.threshold = "uniform";
  s.discrete.width = 0.2;
  s.discrete.representation = "agent";
  s.discrete.seed = 2;
  s.discrete.contact_statistics = true;
  return s;
}

struct Rows {
  double tested = 0, failed = 0, ks_sum = 0, min_p = 1;
};
Rows rows(const compare::Comparison& c, const char* who) {
  Rows r;
  const auto& col = c.contacts;
  const double tested = c.metrics.at("contacts_tested"), alpha = 0.01 / tested;
  for (std::size_t k = 0; k < col.at("tested").size(); ++k) {
    if (col.at("tested")[k] == 0.0) continue;
    r.tested += 1;
    r.ks_sum += col.at("ks_distance")[k];
    r.min_p = std::min(r.min_p, col.at("p_value")[k]);
    const bool fail = col.at("p_value")[k] < alpha;
    r.failed += fail ? 1 : 0;
    std::printf("  %-10s %s phase %.0f region %.0f: measured %.4g predicted %.4g KS %.4f X2 %.1f/%.0f p %.3g%s\n", who,
                col.at("statistic")[k] == 0.0 ? "lifetime" : "age     ", col.at("phase")[k], col.at("region")[k],
                col.at("measured_total")[k], col.at("predicted_total")[k], col.at("ks_distance")[k], col.at("chi2")[k],
                col.at("dof")[k], col.at("p_value")[k], fail ? "  FAIL" : "");
  }
  return r;
}

}  // namespace

TEST_CASE("mean_field (slow): the agent's contact statistics at w = 0.2 against the mean-field prediction",
          "[slow][mean_field][contacts]") {
  const compare::Scene s = contacts_disorder();
  s.validate();
  const auto r = compare::run_scene_alongside(s, {});
  REQUIRE(r.models.size() == 3);
  for (const auto& m : r.models) REQUIRE(m.status == compare::RunStatus::complete);
  const auto &c = r.models[0], &mf = r.models[1], &d = r.models[2];
  REQUIRE(r.comparison.reference == "mean_field");
  const Rows with_mf = rows(r.comparison, "mean_field");
  const Rows with_c = rows(compare::compare_results(s, c, d), "continuum");
  // a wrong width: the mean-field prediction at w = 0.3 (its own run: the agent is not run again)
  compare::Scene wrong = s;
  wrong.discrete.width = 0.3;
  auto make = [&](std::size_t n) { return compare::mean_field_law(wrong, n); };
  const auto mf_wrong = compare::run_model<discrete::MeanFieldLaw>(wrong, make, "mean_field", {});
  REQUIRE(mf_wrong.contacts_2d.count("class_lifetime_counts") == 1);
  const Rows with_wrong = rows(compare::compare_results(s, mf_wrong, d, &mf_wrong), "w x 1.5");
  std::printf("rows failed at the family rate 0.01 (of tested): mean_field %.0f/%.0f, continuum %.0f/%.0f, w x 1.5 "
              "%.0f/%.0f; summed KS: %.3f, %.3f, %.3f; events t^: continuum %.2f, mean_field %.2f, agent %.2f\n",
              with_mf.failed, with_mf.tested, with_c.failed, with_c.tested, with_wrong.failed, with_wrong.tested,
              with_mf.ks_sum, with_c.ks_sum, with_wrong.ks_sum, c.events.t_hat, mf.events.t_hat, d.events.t_hat);
  CHECK(with_mf.tested >= 10);
  CHECK(with_mf.ks_sum < with_c.ks_sum);
  CHECK(with_mf.failed < with_c.failed);
  CHECK(with_wrong.min_p < 0.01 / with_wrong.tested);
  CHECK(with_wrong.ks_sum > with_mf.ks_sum);
}
