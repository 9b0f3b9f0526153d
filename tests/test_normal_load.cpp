// A prescribed normal load (docs/model.md §12, issue 40 item 1): the resting area of a site follows its load as
// a = (p/p_0)^m, through re-attachment (the A equation relaxes towards a at unit rate) or at once (the existing
// contacts' areas scale with p). What is checked:
//   - uniform p = p_0 and m = 0 are today's model bit for bit (the run layer does not tell the law; a law told
//     a = 1 everywhere computes today's bits: continuum, mean_field, count with the noise off);
//   - a step in p at rest: re-attachment relaxes A as a_new + (a_old − a_new) e^{−t} (continuum and mean field to
//     1e-12; the count and agent ensembles by z-tests over sites against the exact binomial variance), instantaneous jumps
//     A and σ̄ by a_new/a_old at once and then nothing moves;
//   - the implicit step's linearisation relaxes towards the resting area (c0 + c1 W = the exact step's σ̄);
//   - the noise-off identity with a non-uniform profile: continuum, mean_field and the noise-off count law on
//     fig1 through first yield agree to 1e-12 (both channels), with the same event times;
//   - the count ensemble converges to the mean field as N^-1/2 under a load (fitted exponent);
//   - hostile keys refused with the key and the reason.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "apps/config.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "discrete/agent_law.hpp"
#include "discrete/count_law.hpp"
#include "discrete/mean_field_law.hpp"
#include "convergence.hpp"
#include "refusals.hpp"
#include "scenes.hpp"

using namespace slipfront;

namespace {

core::InterfaceParams loaded(const std::string& channel) {
  core::InterfaceParams p = testing::paper_interface();
  p.load_x = {0.0, 1.0};
  p.load_p = {1.0, 1.0};  // (the laws read only the channel; the factors are given to set_normal_load)
  p.load_channel = channel;
  return p;
}

discrete::DiscreteParams count_params(long n, std::uint64_t seed, bool noise) {
  discrete::DiscreteParams d;
  d.contacts_per_site = n;
  d.representation = "count";
  d.seed = seed;
  d.noise = noise;
  return d;
}

template <class Law>
void run(Law& law, double v, double T, double dt) {
  const std::vector<double> vv(law.size(), v);
  const auto steps = static_cast<long>(std::llround(T / dt));
  for (long k = 0; k < steps; ++k) law.advance(dt, vv);
}

// A slip-rate history with rest, sliding and a reversal, over which the laws' bits are compared.
template <class Law>
std::vector<double> history(Law law) {
  std::vector<double> out;
  for (const double v : {0.0, 0.05, 1.0, -0.3, 0.0}) {
    run(law, v, 3.0, 0.01);
    for (const double a : law.contact_area()) out.push_back(a);
    for (const double s : law.sigma_bar()) out.push_back(s);
  }
  return out;
}

// fig1 (testing::fig1_scene) on L = 100 to t = 40 (through first yield at t* = 25.71), snapshots every 5, with the
// three deterministic models: the continuum, mean_field (w = 0) and the noise-off count law.
compare::Scene fig1_short_loaded(const std::string& channel) {
  compare::Scene s = testing::noise_off_count(testing::fig1_scene());
  s.name = "fig1_load_identity";
  s.models = {"continuum", "mean_field", "discrete"};
  s.bulk.length = 100.0;
  s.time.t_end = 40.0;
  s.output.snapshot_dt = 5.0;
  s.interface.load_x = {0.0, 30.0, 60.0};
  s.interface.load_p = {1.0, 1.0, 0.6};
  s.interface.load_exponent = 1.0;
  s.interface.load_channel = channel;
  return s;
}

double fields_diff(const compare::ModelResult& a, const compare::ModelResult& b) {
  double worst = 0.0;
  const std::size_t nx = a.x.size();
  REQUIRE(a.snapshot_t == b.snapshot_t);
  for (const char* field : {"A", "sigma_bar", "u", "v"})
    for (std::size_t k = 0; k < a.snapshot_t.size(); ++k) {
      const auto x = std::span<const double>(a.snapshots.at(field)).subspan(k * nx, nx);
      const auto y = std::span<const double>(b.snapshots.at(field)).subspan(k * nx, nx);
      worst = std::max(worst, testing::max_relative_difference(x, y));
    }
  return worst;
}

}  // namespace

TEST_CASE("normal load: uniform p = p_0 and m = 0 are today's model bit for bit", "[normal_load]") {
  // Run layer: a profile whose resting areas are all 1 (p = p_0 everywhere, or m = 0) is not given to the law.
  compare::Scene base = fig1_short_loaded("reattachment");
  base.interface.load_x.clear();
  base.interface.load_p.clear();
  base.discrete.noise = true;  // the noisy count law too: its random stream must be untouched
  base.discrete.contacts_per_site = 200;
  base.time.t_end = 30.0;
  base.validate();
  const auto r0 = compare::run_scene(base, {});
  for (const auto& [xs, ps, m] : {std::tuple{std::vector<double>{0.0, 50.0}, std::vector<double>{1.0, 1.0}, 1.0},
                                  std::tuple{std::vector<double>{0.0, 50.0}, std::vector<double>{1.0, 0.5}, 0.0}}) {
    compare::Scene s = base;
    s.interface.load_x = xs;
    s.interface.load_p = ps;
    s.interface.load_exponent = m;
    s.validate();
    const auto r = compare::run_scene(s, {});
    REQUIRE(r.size() == r0.size());
    for (std::size_t k = 0; k < r.size(); ++k) {
      INFO("model " << k << ", m = " << m);
      CHECK(testing::same(r[k].series, r0[k].series));
      for (const char* field : {"A", "sigma_bar", "u", "v"})
        CHECK(testing::same(r[k].snapshots.at(field), r0[k].snapshots.at(field)));
    }
  }
  // Law level: told a = 1 at every site, the deterministic laws compute today's bits (1 · w = w, relax(A, 1, ...)).
  const auto p = loaded("reattachment");
  const std::vector<double> ones(3, 1.0);
  continuum::FrictionLaw c0(p, 3), c1(p, 3);
  c1.set_normal_load(ones);
  CHECK(testing::same(history(c0), history(c1)));
  discrete::MeanFieldLaw m0(p, count_params(1, 1, false), 3), m1(p, count_params(1, 1, false), 3);
  m1.set_normal_load(ones);
  CHECK(testing::same(history(m0), history(m1)));
  discrete::CountLaw n0(p, count_params(100, 1, false), 3), n1(p, count_params(100, 1, false), 3);
  n1.set_normal_load(ones);
  CHECK(testing::same(history(n0), history(n1)));
}

TEST_CASE("normal load: a step in p at rest relaxes A at unit rate (re-attachment) or jumps (instantaneous)",
          "[normal_load]") {
  // Re-attachment, a_old = 0.5 → a_new = 0.9 and 1 → 0.4: A(t) = a_new + (a_old − a_new) e^{−t} (docs/model.md §12.1),
  // exact for the continuum and the mean field (exact updates: 1e-12). The count ensemble (N = 400, 500 sites,
  // seed 5): every contact is an independent two-state chain with rates a_new, 1 − a_new, so n(t) is a sum of two
  // binomials with the exact variance N [A0 P_aa (1 − P_aa) + (1 − A0) P_da (1 − P_da)]; the site mean is z-tested,
  // |z| < 3.9 at 3 times × 2 steps, for the count and the agent ensemble (seed 6; the same chain, contact by contact)
  // (two-sided false-alarm rate 1e-4 each, < 1.2e-3 in all).
  for (const auto& [a_old, a_new] : {std::pair{0.5, 0.9}, {1.0, 0.4}}) {
    const auto p = loaded("reattachment");
    const std::size_t sites = 500;
    const long n = 400;
    continuum::FrictionLaw c(p, 1);
    discrete::MeanFieldLaw mf(p, count_params(1, 1, false), 1);
    discrete::CountLaw ens(p, count_params(n, 5, true), sites);
    auto agent_p = count_params(n, 6, true);
    agent_p.representation = "agent";
    discrete::AgentLaw agent(p, agent_p, sites);
    const std::vector<double> old1(1, a_old), new1(1, a_new), old_n(sites, a_old), new_n(sites, a_new);
    c.set_normal_load(old1);
    mf.set_normal_load(old1);
    ens.set_normal_load(old_n);
    agent.set_normal_load(old_n);
    c.set_site(0, a_old, 0.0);
    mf.set_site(0, a_old, 0.0);
    for (std::size_t i = 0; i < sites; ++i) {
      ens.set_site(i, a_old, 0.0);
      agent.set_site(i, a_old, 0.0);
    }
    c.set_normal_load(new1);
    mf.set_normal_load(new1);
    ens.set_normal_load(new_n);
    agent.set_normal_load(new_n);
    CHECK(c.contact_area()[0] == a_old);  // contacts already formed keep their area
    double t = 0.0;
    for (const double t_next : {0.3, 1.0, 3.0}) {
      run(c, 0.0, t_next - t, 0.01);
      run(mf, 0.0, t_next - t, 0.01);
      run(ens, 0.0, t_next - t, 0.01);
      run(agent, 0.0, t_next - t, 0.01);
      t = t_next;
      const double expect = a_new + (a_old - a_new) * std::exp(-t);
      const double p_aa = a_new + (1.0 - a_new) * std::exp(-t), p_da = a_new * (1.0 - std::exp(-t));
      const double var = (a_old * p_aa * (1.0 - p_aa) + (1.0 - a_old) * p_da * (1.0 - p_da)) / static_cast<double>(n);
      auto z_of = [&](std::span<const double> areas) {
        double mean = 0.0;
        for (const double a : areas) mean += a / static_cast<double>(sites);
        return (mean - expect) / std::sqrt(var / static_cast<double>(sites));
      };
      const double z = z_of(ens.contact_area()), z_agent = z_of(agent.contact_area());
      std::printf("step %.1f -> %.1f, t = %.1f: closed form %.6f continuum %.6f mean field %.6f; z count %+.2f agent %+.2f\n",
                  a_old, a_new, t, expect, c.contact_area()[0], mf.contact_area()[0], z, z_agent);
      CHECK(std::abs(c.contact_area()[0] - expect) < 1e-12);
      CHECK(std::abs(mf.contact_area()[0] - expect) < 1e-12);
      CHECK(std::abs(z) < 3.9);
      CHECK(std::abs(z_agent) < 3.9);
    }
  }
  // Instantaneous: the same step multiplies A and σ̄ by a_new/a_old at once (each contact's stretch is unchanged, its
  // area and stiffness scale: docs/model.md §12.2); at rest nothing moves after it.
  const auto p = loaded("instantaneous");
  const std::vector<double> half(4, 0.5), more(4, 0.8);
  continuum::FrictionLaw c(p, 4);
  discrete::MeanFieldLaw mf(p, count_params(1, 1, false), 4);
  discrete::CountLaw ens(p, count_params(1000, 5, true), 4);
  auto agent_p = count_params(1000, 6, true);
  agent_p.representation = "agent";
  discrete::AgentLaw agent(p, agent_p, 4);
  for (std::size_t i = 0; i < 4; ++i) {
    c.set_site(i, 1.0, 0.3);
    mf.set_site(i, 1.0, 0.3);
    ens.set_site(i, 1.0, 0.3);
    agent.set_site(i, 1.0, 0.3);
  }
  auto check_jump = [](const auto& law, double area, double sigma, const char* what) {
    INFO(what);
    for (std::size_t i = 0; i < law.size(); ++i) {
      CHECK(law.contact_area()[i] == Approx(area).epsilon(1e-14));
      CHECK(law.sigma_bar()[i] == Approx(sigma).epsilon(1e-14));
    }
  };
  auto each = [&](auto&& f) {
    f(c, "continuum");
    f(mf, "mean field");
    f(ens, "count");
    f(agent, "agent");
  };
  each([&](auto& law, const char* what) {
    law.set_normal_load(half);
    check_jump(law, 0.5, 0.15, what);  // 1 -> 0.5
    run(law, 0.0, 2.0, 0.01);
    check_jump(law, 0.5, 0.15, what);  // at rest after the step
    law.set_normal_load(more);
    check_jump(law, 0.8, 0.24, what);  // 0.5 -> 0.8
  });
}

TEST_CASE("normal load: the implicit step's linearisation relaxes towards the resting area", "[normal_load]") {
  // core::linearise_stress with the site's resting area a (docs/model.md §12.1): for a slip rate W equal to the
  // previous step's, c0 + c1 W is the stress the law's own exact step gives (the yield state and rate frozen alike),
  // to round-off, for a stuck and a sliding site of the continuum and the mean-field law under a = 0.6. Without `rest`
  // (A relaxing towards 1) the stuck site's c1 would be off by α (1 − a) w(1) Δt / 2 ≈ 2e-5 (W: 1e-6 at W = 0.05).
  const auto p = loaded("reattachment");
  const std::vector<double> rest(2, 0.6);
  const double dt = 0.01;
  const std::vector<double> w = {0.05, 2.0};  // site 0 stuck (σ̄ = 0.1 < A), site 1 sliding (σ̄ = 0.7 > A)
  auto check = [&](auto law, const char* what) {
    law.set_normal_load(rest);
    law.set_site(0, 0.5, 0.1);
    law.set_site(1, 0.5, 0.7);
    std::vector<double> c0(2), c1(2);
    core::linearise(law, dt, w, c0, c1);
    law.advance(dt, w);
    for (std::size_t i = 0; i < 2; ++i) {
      INFO(what << ", site " << i);
      CHECK(std::abs(c0[i] + c1[i] * w[i] - law.sigma_bar()[i]) < 1e-14);
    }
  };
  check(continuum::FrictionLaw(p, 2), "continuum");
  check(discrete::MeanFieldLaw(p, count_params(1, 1, false), 2), "mean field");
  check(discrete::CountLaw(p, count_params(100, 1, false), 2), "noise-off count");
}

TEST_CASE("normal load: noise-off identity on fig1 with a non-uniform profile, both channels", "[normal_load][identity]") {
  // p/p_0 = 1, 1, 0.6 at x = 0, 30, 60 (m = 1), fig1 on L = 100 to t = 40: continuum, mean_field (w = 0) and the
  // noise-off count law agree to 1e-12 relative (docs/model.md §2 item 1 under §12's load), with identical event times.
  for (const char* channel : {"reattachment", "instantaneous"}) {
    const compare::Scene s = fig1_short_loaded(channel);
    s.validate();
    const auto r = compare::run_scene(s, {});
    REQUIRE(r.size() == 3);
    for (const auto& m : r) REQUIRE(m.status == compare::RunStatus::complete);
    const double d_mf = fields_diff(r[0], r[1]), d_count = fields_diff(r[0], r[2]);
    // the far end rests at its resting area 0.6: the profile reached the law
    const std::size_t nx = r[0].x.size();
    const double far = r[0].snapshots.at("A")[(r[0].snapshot_t.size() - 1) * nx + nx - 1];
    std::printf("identity under a load (%s): mean field %.3g, count %.3g; t* = %.6f; A(L) = %.6f\n", channel, d_mf,
                d_count, r[0].events.t_star, far);
    CHECK(far == Approx(0.6).epsilon(1e-12));
    CHECK(d_mf <= 1e-12);
    CHECK(d_count <= 1e-12);
    CHECK(r[0].events.t_star == Approx(25.71).epsilon(0.01));  // the edge carries p_0: the formula of §1
    for (std::size_t k = 1; k < 3; ++k) {
      CHECK(testing::same(r[0].events.t_star, r[k].events.t_star));
      CHECK(testing::same(r[0].events.t_hat, r[k].events.t_hat));
    }
  }
}

TEST_CASE("normal load: the count ensemble converges to the mean field as N^-1/2 under a load", "[normal_load]") {
  // Re-attachment, a = 0.6 at every site: steady sliding at v = 1 to t = 10 (A_ss = a/(1 + κv) = 0.0667, contact
  // stress α + ηv/A ≈ 2.55, far above the threshold), then a hold of 5 (A → a). At each N (250 .. 8000, 64 sites,
  // seed 11) the RMS over sites of A_i − A_mf; fitted err ≈ C N^p (compare::fit_power_law). The RMS of 64 sites has a
  // relative error of ~1/sqrt(128) = 9 %, so p has a standard error of ~0.03 over 6 points spanning ln 32:
  // |p + 1/2| < 0.15 is a ~5-sigma test (false-alarm rate < 1e-5 each).
  const auto p = loaded("reattachment");
  const std::vector<double> rest1(1, 0.6), rest(64, 0.6);
  discrete::MeanFieldLaw mf(p, count_params(1, 1, false), 1);
  mf.set_normal_load(rest1);
  mf.set_site(0, 0.6, 0.0);
  run(mf, 1.0, 10.0, 0.02);
  const double slide_mf = mf.contact_area()[0];
  run(mf, 0.0, 5.0, 0.05);
  const double hold_mf = mf.contact_area()[0];
  CHECK(slide_mf == Approx(0.6 / (1.0 + p.kappa)).epsilon(1e-6));
  std::vector<double> ns, err_slide, err_hold;
  for (const long n : {250L, 500L, 1000L, 2000L, 4000L, 8000L}) {
    discrete::CountLaw ens(p, count_params(n, 11, true), 64);
    ens.set_normal_load(rest);
    for (std::size_t i = 0; i < 64; ++i) ens.set_site(i, 0.6, 0.0);
    run(ens, 1.0, 10.0, 0.02);
    err_slide.push_back(testing::rms_about(ens.contact_area(), slide_mf));
    run(ens, 0.0, 5.0, 0.05);
    err_hold.push_back(testing::rms_about(ens.contact_area(), hold_mf));
    ns.push_back(static_cast<double>(n));
    std::printf("N = %5ld: RMS error of A sliding %.3e, after the hold %.3e\n", n, err_slide.back(), err_hold.back());
  }
  testing::check_inverse_sqrt_rate(ns, {{"sliding", err_slide}, {"after the hold", err_hold}}, 0.15);
}

TEST_CASE("normal load: hostile inputs name the key and the reason", "[normal_load][hostile]") {
  const auto& scene_text = testing::interface_scene;
  const auto& refused = testing::check_refused;
  const std::string load = "load_x = [0.0, 5.0]\nload_p = [1.0, 0.5]\n";
  const std::string edge = "[drive]\nloading = \"edge\"\nK = 2.5\nv_d = 0.3\n";
  const std::string imposed = "[drive]\nloading = \"imposed_rate\"\nv = 1.0\n";
  const std::string three = "models = [\"continuum\", \"mean_field\", \"discrete\"]\n";
  refused(scene_text("", "load_x = [0.0, 5.0]\nload_p = [1.0, -0.5]\n", edge, "", ""), "interface.load_p", ">= 0");
  refused(scene_text("", "load_x = [0.0, 5.0]\nload_p = [1.0, nan]\n", edge, "", ""), "interface.load_p", "");
  refused(scene_text("", "load_x = [5.0, 0.0]\nload_p = [1.0, 0.5]\n", edge, "", ""), "interface.load_x", "increasing");
  refused(scene_text("", "load_x = [0.0]\nload_p = [1.0, 0.5]\n", edge, "", ""), "interface.load_x", "as many entries");
  refused(scene_text("", load + "load_channel = \"coulomb\"\n", edge, "", ""), "interface.load_channel", "coulomb");
  refused(scene_text("", load + "load_exponent = -1\n", edge, "", ""), "interface.load_exponent", ">= 0");
  refused(scene_text("", load, imposed, "", ""), "interface.load_p", "0D");
  refused(scene_text("", load, "[drive]\nloading = \"homogeneous\"\nsigma_d = 0.5\nnucleation_length = 5\n", "", ""),
          "interface.load_p", "homogeneous");
  refused(scene_text("models = [\"discrete\"]\n", load, edge, "[discrete]\nrepresentation = \"agent\"\n",
                     "integrator = \"adaptive\"\n"),
          "time.integrator", "agent representation");
  refused(scene_text("", load + "aging_b = 0.1\n", edge, "", ""), "interface.aging_b", "normal-load");
  refused(scene_text("models = [\"discrete\"]\n", load, edge, "[discrete]\nrepresentation = \"naive\"\n", ""),
          "discrete.representation", "normal load");
  refused(scene_text("models = [\"discrete\"]\n", load, edge,
                     "[discrete]\nrepresentation = \"agent\"\ncontact_statistics = true\n", ""),
          "discrete.contact_statistics", "spontaneous detachment");
  refused(scene_text(three, "load_x = [0.0, 5.0]\nload_p = [1.5, 0.5]\n", edge, "", ""), "interface.load_p", "p <= p_0");
  refused(scene_text("", load, edge, "[output]\nages = true\n", ""), "output.ages", "spontaneous detachment");
  refused(scene_text("", "load_x = [0.0, 5.0]\nload_p = [1.0, 0.0]\nload_channel = \"instantaneous\"\n", edge, "", ""),
          "interface.load_p", "instantaneous");
  // accepted: both channels with the three models (count and agent), p > p_0 on the continuum alone, explicit and
  // implicit; the adaptive integrators with the continuum, mean_field and count (docs/model.md §12.8)
  CHECK_NOTHROW(app::parse_scene(scene_text(three, load, edge, "", "integrator = \"adaptive\"\n"), "a.toml", {}));
  CHECK_NOTHROW(app::parse_scene(scene_text(three, load, edge, "", ""), "a.toml", {}));
  CHECK_NOTHROW(app::parse_scene(scene_text(three, load, edge, "[discrete]\nrepresentation = \"agent\"\n", ""), "a.toml", {}));
  CHECK_NOTHROW(app::parse_scene(scene_text(three, load + "load_channel = \"instantaneous\"\n", edge, "", ""), "a.toml", {}));
  CHECK_NOTHROW(app::parse_scene(scene_text("", "load_x = [0.0, 5.0]\nload_p = [2.0, 0.5]\n", edge, "",
                                            "integrator = \"implicit\"\ndt = 0.01\n"),
                                 "a.toml", {}));
  // without a profile the load keys are not in the resolved configuration (today's)
  const auto s = app::parse_scene(scene_text("", "", edge, "", ""), "a.toml", {});
  CHECK_FALSE(s.interface.has_load_profile());
  // the laws refuse a load above p_0 through re-attachment on their own too
  discrete::CountLaw law(loaded("reattachment"), count_params(100, 1, true), 2);
  CHECK_THROWS_AS(law.set_normal_load(std::vector<double>{1.0, 1.2}), core::ParamError);
  auto agent = count_params(100, 1, true);
  agent.representation = "agent";
  discrete::AgentLaw agent_law(loaded("reattachment"), agent, 2);
  CHECK_THROWS_AS(agent_law.set_normal_load(std::vector<double>{1.0, 1.2}), core::ParamError);
}
