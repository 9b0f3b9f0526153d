// The model mean_field (docs/model.md §2.2, issue 21): the N → ∞ limit of the microcontact ensemble, a
// deterministic population balance over threshold classes (discrete::MeanFieldLaw). What is checked:
//   - w = 0: it is the continuum law bit for bit, both renewals. With one class every operation is
//     FrictionLaw's except the total the class relaxes to: quenched T = 1/B = 1; fresh T = A + (1 − A), which
//     round-to-nearest also makes exactly 1 for every A in [0, 1] (fl(1 − A) = 1 − A + δ with |δ| ≤ 2^-54, so
//     the sum 1 + δ rounds to 1, ties to even). Checked on fig1 (explicit and implicit) and the 0D steady law
//     down to A = 1e-3; event times identical.
//   - w > 0: it equals the count representation with the noise off at the same binning bit for bit (fresh and
//     quenched, uniform and gaussian thresholds, explicit and implicit integrators, the 0D steady law): the two
//     are separate implementations of the same step, so any difference is a bug in one of them.
//   - through the program: a disordered fig1 (w = 0.2) with the three models writes /mean_field/ with the
//     layout of the other models, and a three-model lockstep run restarts from a checkpoint bit for bit.
//   - hostile inputs: unknown or repeated model names, bad threshold keys when only mean_field reads them, the
//     output.ages with nothing that carries ages.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5in.hpp"
#include "compare/alongside.hpp"
#include "compare/contacts.hpp"
#include "compare/difference.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "discrete/mean_field_law.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

using testing::same;

// fig1 (testing::fig1_scene: edge loading, ρ = 0.01, μ = 300, κ = 8, α = 1.05, η = 0.1, K = 2.5, v_d = 0.3,
// dx = 0.5) to t = 40: through first yield (t* = 25.71 at w = 0, earlier with disorder) and the slow front.
compare::Scene fig1_short(std::vector<std::string> models) {
  compare::Scene s = testing::fig1_scene();
  s.name = "fig1_mean_field";
  s.models = std::move(models);
  s.time.t_end = 40.0;
  s.output.snapshot_dt = 5.0;
  s.discrete.noise = false;
  s.discrete.representation = "count";
  return s;
}

compare::Scene disordered(compare::Scene s, const char* threshold, double w, const char* renewal, int bins) {
  s.discrete.threshold = threshold;
  s.discrete.width = w;
  s.discrete.renewal = renewal;
  s.discrete.bins = bins;
  return s;
}

compare::Scene implicit(compare::Scene s) {
  s.time.integrator = core::Integrator::implicit_trapezoidal;
  s.time.dt = 0.02;
  return s;
}

// Largest relative difference of every snapshot field and series column (testing::max_relative_difference per
// row); also whether every value is the same bit for bit.
struct Agreement {
  double worst = 0.0;
  bool bitwise = true;
};
Agreement agreement(const compare::ModelResult& a, const compare::ModelResult& b) {
  Agreement out;
  REQUIRE(a.snapshot_t == b.snapshot_t);
  for (const char* f : {"A", "sigma_bar", "u", "v"})
    for (std::size_t k = 0; k < a.snapshot_t.size(); ++k) {
      const auto x = testing::snapshot_row(a, f, k), y = testing::snapshot_row(b, f, k);
      out.worst = std::max(out.worst, testing::max_relative_difference(x, y));
      out.bitwise = out.bitwise && same(std::vector<double>(x.begin(), x.end()), std::vector<double>(y.begin(), y.end()));
    }
  for (const auto& [name, col] : a.series) {
    REQUIRE(b.series.count(name) == 1);
    out.worst = std::max(out.worst, testing::max_relative_difference(col, b.series.at(name)));
    out.bitwise = out.bitwise && same(col, b.series.at(name));
  }
  return out;
}

void require_same_events(const compare::ModelResult& a, const compare::ModelResult& b) {
  for (const auto& [name, field] : compare::event_fields) {
    INFO("event " << name);
    CHECK(same(a.events.*field, b.events.*field));
    CHECK(same(a.events_alt.*field, b.events_alt.*field));
  }
}

}  // namespace

TEST_CASE("mean_field: at w = 0 it is the continuum law bit for bit, fresh and quenched", "[mean_field]") {
  for (const char* renewal : {"quenched", "fresh"})
    for (const bool imp : {false, true}) {
      compare::Scene s = fig1_short({"continuum", "mean_field"});
      s.discrete.renewal = renewal;
      if (imp) s = implicit(s);
      INFO(renewal << (imp ? ", implicit" : ", explicit"));
      s.validate();
      const auto r = compare::run_scene(s, {});
      REQUIRE(r.size() == 2);
      REQUIRE(r[0].status == compare::RunStatus::complete);
      REQUIRE(r[1].status == compare::RunStatus::complete);
      REQUIRE(r[1].model == "mean_field");
      const Agreement g = agreement(r[0], r[1]);
      std::printf("mean_field vs continuum at w = 0, %s, %s: max relative difference %.3g, bit for bit: %s\n", renewal,
                  imp ? "implicit" : "explicit", g.worst, g.bitwise ? "yes" : "no");
      CHECK(g.bitwise);
      CHECK(g.worst == 0.0);
      require_same_events(r[0], r[1]);
      CHECK(r[0].events.t_star == Approx(25.71).epsilon(0.01));  // the run went through first yield
      CHECK(r[1].labels.at("threshold") == "delta");
      CHECK(r[1].scalars.at("bins") == 1.0);
    }
  // 0D steady law up to v = 100 (A = 1/(1 + κv) down to 1e-3: fresh renewal's T = A + (1 − A) with A ≪ 1/2)
  for (const char* renewal : {"quenched", "fresh"}) {
    compare::Scene f = testing::imposed_rate_scene();
    f.models = {"continuum", "mean_field"};
    f.discrete.renewal = renewal;
    f.drive.sweep_points = 11;
    f.drive.v_min = 1e-3;
    f.drive.v_max = 1e2;
    f.time.steps = 2000;
    f.validate();
    const auto r = compare::run_scene(f, {});
    REQUIRE(r.size() == 2);
    const auto &a = r[0].friction_law.at("sigma"), &b = r[1].friction_law.at("sigma");
    const double worst = testing::max_relative_difference(a, b);
    std::printf("mean_field vs continuum steady law at w = 0, %s: max relative difference %.3g, bit for bit: %s\n",
                renewal, worst, same(a, b) ? "yes" : "no");
    CHECK(same(a, b));
    CHECK(worst == 0.0);
    const auto &ac = r[0].friction_law.at("A"), &am = r[1].friction_law.at("A");
    CHECK(same(ac, am));
  }
}

TEST_CASE("mean_field: equals the count representation with the noise off at the same binning, w > 0",
          "[mean_field]") {
  struct Case {
    const char* threshold;
    double w;
    const char* renewal;
    int bins;
    bool implicit;
  };
  for (const Case c : {Case{"uniform", 0.2, "fresh", 64, false}, Case{"uniform", 0.2, "quenched", 64, false},
                       Case{"gaussian", 0.3, "fresh", 16, true}, Case{"weibull", 0.3, "quenched", 16, true}}) {
    compare::Scene s = disordered(fig1_short({"mean_field", "discrete"}), c.threshold, c.w, c.renewal, c.bins);
    s.bulk.length = 100.0;  // the slow front is near x = 15 at t = 40: a third of fig1's sites is enough
    if (c.implicit) s = implicit(s);
    INFO(c.threshold << " w = " << c.w << ", " << c.renewal << ", " << c.bins << " bins"
                     << (c.implicit ? ", implicit" : ", explicit"));
    s.validate();
    const auto r = compare::run_scene(s, {});
    REQUIRE(r.size() == 2);
    REQUIRE(r[0].status == compare::RunStatus::complete);
    REQUIRE(r[1].status == compare::RunStatus::complete);
    const Agreement g = agreement(r[0], r[1]);
    CHECK(g.bitwise);
    CHECK(g.worst == 0.0);
    require_same_events(r[0], r[1]);
    // disorder moved first yield well before the continuum's t* = 25.71 (the weak contacts yield first)
    CHECK(r[0].events.t_star < 24.0);
    const auto area_end = testing::snapshot_row(r[0], "A", r[0].snapshot_t.size() - 1);
    CHECK(*std::min_element(area_end.begin(), area_end.end()) < 0.99);  // a front has left A < 1 behind
  }
  // 0D steady friction law (imposed v, docs/model.md §3): the same bit for bit at every rate
  compare::Scene f = disordered(testing::imposed_rate_scene(), "uniform", 0.3, "fresh", 32);
  f.models = {"mean_field", "discrete"};
  f.discrete.noise = false;
  f.drive.sweep_points = 9;
  f.drive.v_min = 0.01;
  f.drive.v_max = 10.0;
  f.time.steps = 2000;
  f.validate();
  const auto r = compare::run_scene(f, {});
  REQUIRE(r.size() == 2);
  CHECK(same(r[0].friction_law.at("sigma"), r[1].friction_law.at("sigma")));
  CHECK(same(r[0].friction_law.at("A"), r[1].friction_law.at("A")));
}

TEST_CASE("mean_field: /compare takes mean_field as the discrete model's reference, and noise off it finds no difference",
          "[mean_field][compare]") {
  // fig1 to t = 40, w = 0.2 uniform quenched, 16 classes, the count representation with the noise off: the discrete
  // model IS its reference here, so every difference the comparison layer reports must be exactly 0
  compare::Scene s = disordered(fig1_short({"continuum", "mean_field", "discrete"}), "uniform", 0.2, "quenched", 16);
  s = implicit(s);
  s.output.compare_dt = 5.0;
  s.validate();
  const auto r = compare::run_scene_alongside(s, {});
  REQUIRE(r.models.size() == 3);
  const auto& cmp = r.comparison;
  CHECK(cmp.reference == "mean_field");
  REQUIRE(cmp.fields.at("t").size() == 9);  // t = 0, 5, ..., 40
  for (const char* f : {"A_distance", "sigma_bar_distance", "v_distance", "u_distance"})
    for (const double x : cmp.fields.at(f)) CHECK(x == 0.0);
  std::size_t events = 0;
  for (const auto& [k, v] : cmp.metrics)
    if (k.size() > 9 && k.substr(k.size() - 9) == "_rel_diff") {
      INFO(k);
      CHECK(v == 0.0);
      ++events;
    }
  CHECK(events >= 2);  // t_star on both fronts (t_hat comes later, ≈ 69 at this w)
  CHECK(cmp.metrics.at("drive_force_history_distance") == 0.0);
  // without mean_field the reference is the continuum, as before (and there the disorder shows: t* moved)
  compare::Scene two = s;
  two.models = {"continuum", "discrete"};
  const auto r2 = compare::run_scene_alongside(two, {});
  CHECK(r2.comparison.reference == "continuum");
  CHECK(r2.comparison.metrics.at("t_star_rel_diff") < -0.1);
}

TEST_CASE("mean_field: at w = 0 its contact prediction is the continuum's bit for bit, and /compare tests it",
          "[mean_field][contacts]") {
  // fig1 on L = 60, dx = 1 to t = 60 (first yield, the slow front), implicit dt = 0.02, the agent with contact
  // statistics (N = 200): the continuum and the mean-field law both predict the agent's lifetimes and ages
  // (docs/model.md §7.2, §2.2); with one class, T = 1 and the same hazard the two predictions are one computation
  compare::Scene s = implicit(testing::fig1_scene());
  s.models = {"continuum", "mean_field", "discrete"};
  s.bulk.length = 60.0;
  s.grid.dx = 1.0;
  s.time.t_end = 60.0;
  s.output.snapshot_dt = 5.0;
  s.output.contact_snapshot_dt = 5.0;
  s.discrete.representation = "agent";
  s.discrete.contacts_per_site = 200;
  s.discrete.contact_statistics = true;
  s.discrete.seed = 4;
  s.validate();
  const auto r = compare::run_scene_alongside(s, {});
  REQUIRE(r.models.size() == 3);
  const auto &c = r.models[0], &m = r.models[1];
  REQUIRE(m.model == "mean_field");
  REQUIRE(c.contacts_2d.count("class_lifetime_counts") == 1);
  CHECK(same(c.contacts, m.contacts));
  REQUIRE(c.contacts_2d.size() == m.contacts_2d.size());
  for (const auto& [k, t] : c.contacts_2d) {
    INFO(k);
    CHECK(same(t.data, m.contacts_2d.at(k).data));
  }
  double lifetimes = 0.0;
  for (const double x : m.contacts_2d.at("class_lifetime_counts").data) lifetimes += x;
  CHECK(lifetimes > 1000.0);  // the prediction saw detachments (the slow front)
  // /compare: the agent against the mean-field prediction (the reference's own), rows written
  CHECK(r.comparison.reference == "mean_field");
  CHECK(r.comparison.metrics.count("contacts_min_p") == 1);
  CHECK(testing::contains(r.comparison.definitions.at("contacts/predicted_total"), "mean_field fields"));
}

TEST_CASE("mean_field: the contact prediction by threshold class keeps the law's own attached fraction",
          "[mean_field][contacts]") {
  // One site at imposed slip rates (a history 0.3 → 3 → 0.5), w = 0.3, 16 classes, both renewals: the prediction's
  // attached mass is the law's A (its births and decays are the law's class updates), and every attachment ends
  // attached or detached (attachments = detachments + attached − attached at t = 0). Tolerance: the prediction drops
  // cohorts below 1e-14 of a site (compare/contacts.hpp), at most one per class per step: 6000 × 16 × 1e-14 ≈ 1e-9
  // (round-off adds ~steps × classes × 2^-53 ≈ 1e-11). Measured: 1.0e-12 (a first bound of 1e-12 had ignored both).
  for (const char* renewal : {"fresh", "quenched"}) {
    INFO(renewal);
    discrete::DiscreteParams d;
    d.threshold = "uniform";
    d.width = 0.3;
    d.bins = 16;
    d.renewal = renewal;
    discrete::MeanFieldLaw law(testing::paper_interface(), d, 1);
    compare::ContactPrediction p(1, 1000.0, 1.0, 0.1, 1e4, law.prediction_classes());
    p.start(law.attached_classes());
    std::vector<double> n0, hazard(16), total(16);
    const double dt = 0.01;
    double worst = 0.0;
    for (int k = 0; k < 6000; ++k) {
      const double v = k < 2000 ? 0.3 : k < 4000 ? 3.0 : 0.5;
      const double a0 = law.contact_area()[0], sb0 = law.sigma_bar()[0];
      n0.assign(law.attached_classes().begin(), law.attached_classes().end());
      law.class_rates(0, v, a0, sb0, n0, hazard, total);
      const double vv[1] = {v};
      law.advance(dt, vv);
      p.step(dt, n0, hazard, total);
      worst = std::max(worst, std::abs(p.attached_mass(0) - law.contact_area()[0]));
    }
    std::printf("mean-field contact prediction (%s): max |attached mass - A| = %.3g\n", renewal, worst);
    CHECK(worst < 6000 * 16 * 1e-14);
    CHECK(law.contact_area()[0] < 0.6);  // it slid: the overloaded classes lost contacts
    const auto t = p.tables();
    const double att = t.columns.at("attachments_total_per_site")[0], det = t.columns.at("detachments_total_per_site")[0];
    CHECK(att == Approx(det + 1000.0 * (law.contact_area()[0] - 1.0)).epsilon(1e-9));
    double lifetimes = 0.0;
    for (const double x : t.tables.at("class_lifetime_counts").data) lifetimes += x;
    CHECK(lifetimes == Approx(det).epsilon(1e-9));
  }
}

TEST_CASE("mean_field: the threshold prediction spreads each class over its quantile interval of g",
          "[mean_field][contacts][thresholds]") {
  // threshold_spread (compare/contacts.hpp): each class's row sums to 1, its mean (bin midpoints) is the class's
  // conditional mean s_b within half a bin, and the classes together are g binned (B · 1/B of each bin's G-mass);
  // degenerate g: everything in the bin of 1. Then the prediction of one site after a sliding history (w = 0.3,
  // 16 classes, fresh renewal): its snapshot's threshold row is Σ_b N n_b (spread row b) — the law's own classes —
  // in the site's region, the class table's row of that phase equals it, and the weak classes are depleted (the
  // attached mean threshold above g's mean 1 by more than 0.05). Up to the cohorts the prediction drops (bound below).
  for (const char* kind : {"uniform", "gaussian", "weibull"}) {
    INFO(kind);
    const discrete::ThresholdDistribution g(kind, 0.3);
    const auto edges = discrete::threshold_edges(0.3);
    const std::size_t B = 16, nt = edges.size() - 1;
    const auto spread = compare::threshold_spread(g, B, edges);
    REQUIRE(spread.size() == B * nt);
    std::vector<double> all(nt, 0.0);
    for (std::size_t b = 0; b < B; ++b) {
      double sum = 0.0, mean = 0.0;
      for (std::size_t j = 0; j < nt; ++j) {
        const double w = spread[b * nt + j], mid = std::isfinite(edges[j + 1]) ? 0.5 * (edges[j] + edges[j + 1]) : edges[j];
        CHECK(w >= 0.0);
        sum += w;
        mean += w * mid;
        all[j] += w / static_cast<double>(B);
      }
      CHECK(sum == Approx(1.0).epsilon(1e-12));
      const double s_b = g.conditional_mean(static_cast<double>(b) / B, static_cast<double>(b + 1) / B);
      // the overflow bin [s_max, ∞) is counted at s_max: only weibull's last class reaches it
      if (spread[b * nt + nt - 1] == 0.0) CHECK(std::abs(mean - s_b) <= 0.5 * (edges[1] - edges[0]));
    }
    for (std::size_t j = 0; j < nt; ++j) {
      const double G1 = std::isfinite(edges[j + 1]) ? g.cdf(edges[j + 1]) : 1.0;
      CHECK(all[j] == Approx(G1 - g.cdf(edges[j])).margin(1e-12));
    }
  }
  {
    const discrete::ThresholdDistribution delta("delta", 0.0);
    const auto edges = discrete::threshold_edges(0.0);
    const auto spread = compare::threshold_spread(delta, 1, edges);
    const std::size_t j = discrete::Histogram(edges).bin(1.0);
    CHECK(spread[j] == 1.0);
    CHECK(std::accumulate(spread.begin(), spread.end(), 0.0) == 1.0);
  }
  discrete::DiscreteParams d;
  d.threshold = "uniform";
  d.width = 0.3;
  d.bins = 16;
  discrete::MeanFieldLaw law(testing::paper_interface(), d, 1);
  const std::size_t B = law.prediction_classes();
  compare::ContactPrediction p(1, 1000.0, 1.0, 0.1, 1e4, B);
  auto edges = discrete::threshold_edges(d.width);
  const std::size_t nt = edges.size() - 1;
  const auto spread = compare::threshold_spread(law.distribution(), B, edges);
  p.set_thresholds(edges, spread);
  p.start(law.attached_classes());
  core::FrontClasses f;
  f.phase = 1;  // slow front; the site is ahead (behind_end = tip_end = 0)
  p.set_front(f);
  std::vector<double> n0, hazard(B), total(B);
  for (int k = 0; k < 2000; ++k) {
    const double v = k < 1000 ? 3.0 : 0.5, a0 = law.contact_area()[0], sb0 = law.sigma_bar()[0];
    n0.assign(law.attached_classes().begin(), law.attached_classes().end());
    law.class_rates(0, v, a0, sb0, n0, hazard, total);
    const double vv[1] = {v};
    law.advance(0.01, vv);
    p.step(0.01, n0, hazard, total);
  }
  p.snapshot();
  const auto t = p.tables();
  const auto& rows = t.tables.at("region_threshold_counts");
  REQUIRE(rows.cols == 3 * nt);
  REQUIRE(rows.data.size() == 3 * nt);
  const auto& cls = t.tables.at("class_threshold_counts");
  REQUIRE(cls.data.size() == 12 * nt);
  CHECK(t.columns.at("threshold_hist_edges") == edges);
  double total_count = 0.0, mean = 0.0, worst = 0.0;
  for (std::size_t j = 0; j < nt; ++j) {
    double expect = 0.0;
    for (std::size_t b = 0; b < B; ++b) expect += 1000.0 * law.attached(0)[b] * spread[b * nt + j];
    INFO("bin " << j);
    worst = std::max(worst, std::abs(rows.data[2 * nt + j] - expect));
    CHECK(rows.data[j] == 0.0);       // behind: no site
    CHECK(rows.data[nt + j] == 0.0);  // tip: no site
    CHECK(cls.data[(3 * 1 + 2) * nt + j] == rows.data[2 * nt + j]);
    total_count += rows.data[2 * nt + j];
    mean += rows.data[2 * nt + j] * (std::isfinite(edges[j + 1]) ? 0.5 * (edges[j] + edges[j + 1]) : edges[j]);
  }
  // the prediction's class masses are the law's n_b up to the cohorts it drops (below 1e-14 of a site, at most one
  // per class and step: 2000 × 1e-14 of N per class, the earlier test's bound)
  std::printf("mean-field threshold prediction after sliding: attached mean threshold %.4f (g: 1); max |row - "
              "sum_b N n_b spread_b| = %.3g\n", mean / total_count, worst);
  CHECK(worst < 1000.0 * 2000 * 1e-14);
  CHECK(total_count == Approx(1000.0 * law.contact_area()[0]).margin(1000.0 * 2000 * 16 * 1e-14));
  CHECK(mean / total_count > 1.05);
}

TEST_CASE("mean_field: the law's state, classes and overloaded fraction", "[mean_field]") {
  discrete::DiscreteParams d;
  d.threshold = "uniform";
  d.width = 0.2;
  d.bins = 8;
  d.renewal = "quenched";
  d.contacts_per_site = 0;  // not read: the mean-field law has no N (DiscreteParams::validate would refuse it)
  discrete::MeanFieldLaw law(testing::paper_interface(), d, 3);
  REQUIRE(law.bins() == 8);
  REQUIRE(std::is_sorted(law.thresholds().begin(), law.thresholds().end()));
  CHECK(law.thresholds().front() == Approx(1.0 - std::sqrt(3.0) * 0.2 * (1.0 - 1.0 / 8.0)).epsilon(1e-12));
  law.set_site(1, 0.5, 0.5);  // τ = |σ̄|/A = 1 at v = 0: the classes with s_b < 1 are overloaded, half of them
  CHECK(law.contact_area()[1] == 0.5);
  CHECK(law.overloaded_fraction(1, 0.0) == 0.5);
  CHECK(law.detached(1, 0) == Approx(0.125 - 0.0625));
  // one step at v = 1: only the overloaded classes detach, the others attach towards 1/B
  const double v[3] = {0.0, 1.0, 0.0};
  CHECK(law.advance(0.01, v).any_yield);
  const auto n = law.attached(1);
  CHECK(n[0] < 0.0625);
  CHECK(n[7] > 0.0625);
  CHECK(law.contact_area()[0] == Approx(1.0).epsilon(1e-14));  // a stuck site with every contact attached stays so
}

TEST_CASE("mean_field: a disordered fig1 with the three models runs through the program and writes /mean_field/",
          "[mean_field][cli]") {
  testing::TempDir dir("mean-field-cli");
  const std::filesystem::path cfg = std::filesystem::path(SLIPFRONT_SOURCE_DIR) / "configs" / "fig1.toml";
  // fig1 with w = 0.2 (uniform, fresh), N = 200, to t = 30 on the implicit integrator (dt = 0.02)
  const auto out = testing::run({SLIPFRONT_BINARY, "run", cfg.string(), "--out", (dir.path / "run").string(), "--set",
                                 "models=[\"continuum\",\"mean_field\",\"discrete\"]", "--set", "discrete.threshold=\"uniform\"",
                                 "--set", "discrete.width=0.2", "--set", "discrete.contacts_per_site=200", "--set",
                                 "time.t_end=30", "--set", "time.integrator=\"implicit\"", "--set", "time.dt=0.02"},
                                dir.path);
  INFO(out.err);
  REQUIRE(out.code == 0);
  const auto file = dir.path / "run" / "results.h5";
  const app::ResultsFile f = app::read_results(file);
  REQUIRE(f.header.models == std::vector<std::string>{"continuum", "mean_field", "discrete"});
  REQUIRE(f.header.status == compare::RunStatus::complete);
  const auto& mf = f.models[1];
  REQUIRE(mf.model == "mean_field");
  CHECK(mf.status == compare::RunStatus::complete);
  CHECK(mf.labels.at("threshold") == "uniform");
  CHECK(mf.labels.at("renewal") == "fresh");
  CHECK(mf.scalars.at("width") == 0.2);
  CHECK(mf.scalars.at("bins") == 64.0);
  CHECK(mf.labels.count("seed") == 0);  // what it does not read is not written
  // the layout of the other models: the same datasets under /mean_field as under /continuum
  const auto h5 = testing::read_h5(file);
  std::vector<std::string> cont, mean;
  for (const auto& [path, v] : h5.datasets) {
    if (path.rfind("/continuum/", 0) == 0) cont.push_back(path.substr(11));
    if (path.rfind("/mean_field/", 0) == 0) mean.push_back(path.substr(12));
  }
  CHECK(!mean.empty());
  CHECK(mean == cont);
  // the mean-field run in the file is the one run_scene gives alone (lockstep changes nothing)
  compare::Scene s = app::parse_scene(f.header.resolved_toml, "resolved", {});
  s.models = {"mean_field"};
  const auto alone = compare::run_scene(s, {});
  CHECK(same(alone[0].series.at("max_v"), mf.series.at("max_v")));
  CHECK(same(alone[0].events.t_star, mf.events.t_star));
  // and the population balance is no continuum: disorder moves first yield (≈ 25.7 without it)
  CHECK(mf.events.t_star < 0.8 * f.models[0].events.t_star);
  // /compare holds the discrete model against its reference, mean_field (issue 21 item 2), and says so
  CHECK(f.comparison.reference == "mean_field");
  CHECK(h5.strings.at("/compare@reference") == "mean_field");
  const auto& d = f.models[2];
  CHECK(same(f.comparison.metrics.at("t_star_rel_diff"), compare::relative_difference(mf.events.t_star, d.events.t_star)));
  CHECK(testing::contains(f.comparison.definitions.at("t_star_rel_diff"), "(discrete - mean_field)"));
}

TEST_CASE("mean_field: three models in lockstep restart from a checkpoint bit for bit", "[mean_field][checkpoint]") {
  compare::Scene s = disordered(testing::fig1_scene(), "uniform", 0.2, "quenched", 16);
  s.models = {"discrete", "mean_field", "continuum"};
  s.bulk.length = 60.0;
  s.grid.dx = 1.0;
  s.time.t_end = 40.0;
  s.output.series_dt = 0.5;
  s.output.snapshot_dt = 5.0;
  s.output.compare_dt = 5.0;
  s.discrete.contacts_per_site = 50;
  s.discrete.seed = 3;
  s.validate();
  REQUIRE(compare::runs_in_lockstep(s));
  const auto whole = compare::run_scene_alongside(s, {});
  REQUIRE(whole.models.size() == 3);
  CHECK(whole.models[0].model == "discrete");  // in the scene's order
  CHECK(whole.models[1].model == "mean_field");
  // the discrete model against mean_field (its own N → ∞ limit), online fields and events
  CHECK(whole.comparison.reference == "mean_field");
  REQUIRE(!whole.comparison.fields.empty());
  CHECK(whole.comparison.fields.at("A_distance").front() == 0.0);  // t = 0: both stuck, A = 1
  CHECK(whole.comparison.fields.at("A_distance").back() > 0.0);     // N = 50: noise
  CHECK(same(whole.comparison.metrics.at("t_star_abs_diff"),
             whole.models[0].events.t_star - whole.models[1].events.t_star));
  std::vector<std::pair<double, std::string>> saved;
  compare::RunControl ctl;
  ctl.checkpoint_every = 10.0;
  ctl.checkpoint = [&](const std::string& state, double t) { saved.emplace_back(t, state); };
  compare::run_scene_alongside(s, ctl);
  REQUIRE(saved.size() >= 2);
  compare::RunControl again;
  again.restart = saved[1].second;
  const auto resumed = compare::run_scene_alongside(s, again);
  for (std::size_t m = 0; m < 3; ++m) {
    INFO("model " << whole.models[m].model);
    CHECK(same(whole.models[m].series, resumed.models[m].series));
    CHECK(same(whole.models[m].snapshots, resumed.models[m].snapshots));
    CHECK(same(whole.models[m].events.t_star, resumed.models[m].events.t_star));
  }
  CHECK(same(whole.comparison.fields, resumed.comparison.fields));
  // a checkpoint of another model list is refused, not misread
  compare::Scene two = s;
  two.models = {"continuum", "discrete"};
  CHECK_THROWS_AS(compare::run_scene_alongside(two, again), core::ArchiveError);
}

TEST_CASE("mean_field: hostile inputs name the key and the reason", "[mean_field][hostile]") {
  auto refused = [](compare::Scene s, const std::string& key, const std::string& part) {
    INFO("expected a refusal of " << key << " saying '" << part << "'");
    try {
      s.validate();
      FAIL("accepted");
    } catch (const core::ParamError& e) {
      CHECK(e.key == key);
      CHECK(testing::contains(e.what(), part));
    }
  };
  compare::Scene s = fig1_short({"continuum", "meanfield"});
  refused(s, "models", "unknown model 'meanfield' (expected continuum, mean_field or discrete)");
  refused(fig1_short({"mean_field", "continuum", "mean_field"}), "models", "twice");
  // mean_field reads the threshold keys and checks them although the discrete model does not run
  refused(disordered(fig1_short({"mean_field"}), "uniform", 0.7, "fresh", 64), "discrete.width", "1/sqrt(3)");
  refused(disordered(fig1_short({"mean_field"}), "lognormal", 0.2, "fresh", 64), "discrete.threshold", "lognormal");
  refused(disordered(fig1_short({"mean_field"}), "uniform", 0.2, "sometimes", 64), "discrete.renewal", "sometimes");
  refused(disordered(fig1_short({"mean_field"}), "uniform", 0.2, "fresh", 0), "discrete.bins", "");
  // ... and not those it does not read: N = 0 is refused for the discrete model only
  compare::Scene no_n = disordered(fig1_short({"mean_field"}), "uniform", 0.2, "fresh", 64);
  no_n.discrete.contacts_per_site = 0;
  CHECK_NOTHROW(no_n.validate());
  no_n.models = {"mean_field", "discrete"};
  refused(no_n, "discrete.contacts_per_site", "");
  // with time.integrator = adaptive the mean-field law runs on the step-controlled implicit integrator (core/leap.hpp)
  compare::Scene adaptive = disordered(fig1_short({"continuum", "mean_field"}), "uniform", 0.2, "fresh", 64);
  adaptive.time.integrator = core::Integrator::adaptive_rosenbrock;
  CHECK_NOTHROW(adaptive.validate());
  compare::Scene ages = fig1_short({"mean_field"});
  ages.output.ages = true;
  refused(ages, "output.ages", "mean_field model carries no contact age");
  // through the configuration: the file, the key and the reason; the keys mean_field does not read are noted
  std::string text = testing::minimal_config();
  text.replace(text.find("scene = \"tiny\""), 14, "scene = \"tiny\"\nmodels = [\"continuum\", \"mean-field\"]");
  try {
    (void)app::parse_scene(text, "tiny.toml", {});
    FAIL("accepted");
  } catch (const app::ConfigError& e) {
    CHECK(e.file == "tiny.toml");
    CHECK(e.key == "models");
    CHECK(testing::contains(e.reason, "unknown model 'mean-field'"));
  }
  std::vector<std::string> notes;
  const compare::Scene ok = app::parse_scene(testing::minimal_config(), "tiny.toml",
                                             {"models=[\"mean_field\"]", "discrete.threshold=\"uniform\"",
                                              "discrete.width=0.1", "discrete.contacts_per_site=50"},
                                             &notes);
  CHECK(ok.discrete.width == 0.1);
  CHECK(ok.discrete.contacts_per_site == discrete::DiscreteParams{}.contacts_per_site);  // reset: not read
  CHECK(std::any_of(notes.begin(), notes.end(), [](const std::string& n) {
    return testing::contains(n, "discrete.contacts_per_site");
  }));
}

