#pragma once
// Shared by the contact-statistics tests of whole fig1 scenes (test_contacts_fig1.cpp on the chain,
// test_slow_contacts_strip.cpp on the strip): the summary of a /compare/contacts table and the prediction
// of the agent's statistics from the agent's own fields (docs/contacts.md §5).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "compare/alongside.hpp"
#include "compare/dispatch.hpp"
#include "compare/runner.hpp"
#include "core/implicit.hpp"
#include "discrete/agent_law.hpp"

namespace slipfront::testing {

struct ContactSummary {
  double tested = 0, worst_p = 1, worst_p_before_arrest = 1;
};

/// Prints every row with contacts and returns the number of tested rows and their smallest p-values
/// (overall, and before the arrest: phases 0-2).
inline ContactSummary summarise_contacts(const compare::Comparison& c, const char* label) {
  ContactSummary out;
  const auto& k = c.contacts;
  std::printf("%s:\n", label);
  for (std::size_t i = 0; i < k.at("phase").size(); ++i) {
    if (k.at("measured_total")[i] <= 0) continue;
    const auto phase = static_cast<std::size_t>(k.at("phase")[i]);
    const bool tested = k.at("tested")[i] != 0;
    std::printf("  %s %-12s %-6s n = %10.0f predicted %12.1f KS %.4f X2 %8.1f dof %2.0f p %.3g%s\n",
                k.at("statistic")[i] == 0 ? "lifetime" : "age     ", core::phase_name(phase),
                core::region_name(static_cast<std::size_t>(k.at("region")[i])), k.at("measured_total")[i],
                k.at("predicted_total")[i], k.at("ks_distance")[i], k.at("chi2")[i], k.at("dof")[i], k.at("p_value")[i],
                tested ? "" : "  (not tested)");
    if (!tested) continue;
    out.tested += 1;
    out.worst_p = std::min(out.worst_p, k.at("p_value")[i]);
    if (phase < 3) out.worst_p_before_arrest = std::min(out.worst_p_before_arrest, k.at("p_value")[i]);
  }
  return out;
}

/// One model of scene s on the implicit integrator on the body B, alone, with contact predictions per `setup`;
/// make_law(sites) builds its law.
template <core::Body B, class MakeLaw>
compare::ModelResult implicit_run(const compare::Scene& s, MakeLaw make_law, const char* model,
                                  const compare::ContactPredictionSetup& setup) {
  auto law = make_law(compare::make_body<B>(s, s.drive).sites());
  using Law = decltype(law);
  compare::DynamicRun<Law, core::ImplicitSimulation<Law, B>> run(s, std::move(law), model, setup);
  while (!run.done()) run.step();
  return run.finish();
}

/// Moves the tables of `from` whose names start with `prefix` to `to`, without the prefix.
template <class Tables>
void move_prefixed(Tables& from, Tables& to, const std::string& prefix) {
  for (auto it = from.begin(); it != from.end();)
    if (it->first.rfind(prefix, 0) == 0) {
      to[it->first.substr(prefix.size())] = it->second;
      it = from.erase(it);
    } else {
      ++it;
    }
}

/// The agent run of scene s (implicit integrator, on the scene's body B) predicting its contact statistics from
/// its own fields: the run's result goes to `agent`, the prediction is returned as the tables of a "continuum"
/// result, ready for compare::compare_results(s, prediction, agent).
template <core::Body B>
compare::ModelResult self_prediction(const compare::Scene& s, compare::ModelResult& agent) {
  compare::ContactPredictionSetup self;
  self.mode = compare::ContactPredictionSetup::Mode::on;
  self.prefix = "self_";
  agent = implicit_run<B>(s, [&](std::size_t n) { return discrete::AgentLaw(s.interface, s.discrete, n); }, "discrete",
                          self);
  compare::ModelResult pred;
  pred.model = "continuum";
  move_prefixed(agent.contacts, pred.contacts, self.prefix);
  move_prefixed(agent.contacts_2d, pred.contacts_2d, self.prefix);
  return pred;
}

/// The continuum's prediction with its hazard scaled (a deliberately wrong prediction), on the scene's body B.
template <core::Body B>
compare::ModelResult scaled_hazard_prediction(const compare::Scene& s, double scale) {
  compare::ContactPredictionSetup wrong;
  wrong.mode = compare::ContactPredictionSetup::Mode::on;
  wrong.hazard_scale = scale;
  return implicit_run<B>(s, [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); }, "continuum", wrong);
}

/// The contact-level test of a whole scene (docs/contacts.md §5), each row a chi-square on a uniform subsample of
/// m = 2000 contacts at the family-wise false-alarm rate 1e-3 (Bonferroni over the tested rows):
/// 1. against the continuum's prediction every row before the arrest passes (the after-arrest rows are printed);
/// 2. against the prediction from the agent's own fields every row passes — before the arrest only when
///    `own_fields_after_arrest` is false (the rows are printed);
/// 3. the continuum's prediction with the hazard × 1.2 is rejected before the arrest.
template <core::Body B>
void check_contact_scene(const compare::Scene& s, bool own_fields_after_arrest) {
  const auto r = compare::run_scene_alongside(s, compare::RunControl{});
  REQUIRE(r.models[1].status == compare::RunStatus::complete);
  std::printf("%s: agent t^ = %.3f, t_arrest = %.3f; continuum t^ = %.3f, t_arrest = %.3f\n", s.name.c_str(),
              r.models[1].events.t_hat, r.models[1].events.t_arrest, r.models[0].events.t_hat, r.models[0].events.t_arrest);
  const auto cont = summarise_contacts(r.comparison, "agent vs the continuum's prediction");
  std::printf("  %.0f rows tested; smallest p before the arrest %.3g, overall %.3g (Bonferroni threshold %.2g)\n",
              cont.tested, cont.worst_p_before_arrest, cont.worst_p, 1e-3 / cont.tested);
  CHECK(cont.tested >= 10);
  CHECK(cont.worst_p_before_arrest > 1e-3 / cont.tested);

  compare::ModelResult agent;
  const compare::ModelResult own = self_prediction<B>(s, agent);
  REQUIRE(agent.contacts_2d.at("class_lifetime_counts").data == r.models[1].contacts_2d.at("class_lifetime_counts").data);
  const auto self = summarise_contacts(compare::compare_results(s, own, agent), "agent vs the prediction from its own fields");
  std::printf("  %.0f rows tested; smallest p before the arrest %.3g, overall %.3g (Bonferroni threshold %.2g)\n",
              self.tested, self.worst_p_before_arrest, self.worst_p, 1e-3 / self.tested);
  CHECK(self.tested >= 10);
  CHECK((own_fields_after_arrest ? self.worst_p : self.worst_p_before_arrest) > 1e-3 / self.tested);

  const auto w = summarise_contacts(compare::compare_results(s, scaled_hazard_prediction<B>(s, 1.2), r.models[1]),
                                    "agent vs kappa x 1.2");
  std::printf("  kappa x 1.2: smallest p before the arrest %.3g\n", w.worst_p_before_arrest);
  CHECK(w.worst_p_before_arrest < 1e-3 / w.tested);
}

}  // namespace slipfront::testing
