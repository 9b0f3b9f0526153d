#pragma once
// The agent representation done the obvious way (a baseline for benchmarks and a cross-check of
// AgentLaw): every contact of every site is visited every step and makes one Bernoulli draw with
// the exact two-state transition probabilities of docs/model.md §2 (rates frozen at the start of the step):
//   attached, overloaded (τ > s):  stays with P(att→att) = (a + d e^{−rΔt})/r, d = κ|v|
//   attached, not overloaded:      stays (certain: no draw)
//   detached:                      attaches with P(det→att) = a (1 − e^{−rΔt})/r, with d = κ|v| if
//                                  τ > s else 0 (s: the threshold it will attach with)
// A contact that detaches gets a fresh threshold at once (renewal = fresh; quenched keeps it).
// Same step contract, same Y_i and σ̄ update, same contact statistics as AgentLaw, but event times
// are known only to the step: attachments and detachments are dated at the end of their step
// (lifetimes and ages are multiples of Δt). Cost O(N) per site and step, whatever happens.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/exact_update.hpp"
#include "core/interrupt.hpp"
#include "core/law.hpp"
#include "core/params.hpp"
#include "discrete/contact_stats.hpp"
#include "discrete/params.hpp"
#include "discrete/streams.hpp"
#include "discrete/thresholds.hpp"

namespace slipfront::discrete {

// core::LawHooks::steady_state: its mean-field steady state with every threshold overloaded (docs/model.md §2.2), the
// closed form of core/steady_sliding.hpp: exact at w = 0 and while the thresholds lie below the steady contact stress.
class NaiveAgentLaw : public core::OverloadedSteadyState<NaiveAgentLaw> {
 public:
  static constexpr core::LawHooks hooks{.contact_statistics = true, .checkpoints = true, .count_noise = true, .steady_state = true, .steady_front = true};
  NaiveAgentLaw(const core::InterfaceParams& ip, const DiscreteParams& dp, std::size_t sites)
      : ip_(ip), dp_(dp), g_((dp.validate(), ThresholdDistribution(dp.threshold, dp.width))) {
    if (sites == 0) throw std::invalid_argument("NaiveAgentLaw: no sites");
    if (ip.ages_contacts())  // docs/model.md §11: the baseline does not age its contacts
      throw core::ParamError("discrete.representation", "the naive representation does not age its contacts: aging "
                                                        "(interface.aging_b > 0) needs representation = \"agent\"");
    if (!dp.noise)
      throw core::ParamError("discrete.noise",
                                  "the agent representation has whole contacts: noise = false needs representation = count");
    n_contacts_ = static_cast<std::size_t>(dp.contacts_per_site);
    quenched_ = dp.renewal == "quenched";
    contacts_.resize(sites);
    engines_.resize(sites);
    n_att_.assign(sites, 0);
    area_.assign(sites, 1.0);
    sigma_bar_.assign(sites, 0.0);
    if (dp.contact_statistics) stats_ = ContactStats(sites, threshold_edges(dp.width));
    for (std::size_t i = 0; i < sites; ++i) {
      core::poll_stop();
      set_site(i, 1.0, 0.0);
    }
  }

  // --- the step contract (core::InterfaceLaw) -------------------------------------------
  std::size_t size() const { return area_.size(); }
  const core::InterfaceParams& params() const { return ip_; }
  std::span<const double> contact_area() const { return area_; }
  std::span<const double> sigma_bar() const { return sigma_bar_; }
  /// N: every contact attaches and detaches by its own draw (core::LawHooks::count_noise).
  double noise_contacts() const { return static_cast<double>(n_contacts_); }

  /// As AgentLaw::set_site: n = round(A N) attached (thresholds from g, age 0), the rest detached;
  /// restarts the site's stream.
  void set_site(std::size_t i, double area, double sigma_bar) {
    if (!(area >= 0.0 && area <= 1.0)) throw std::invalid_argument("NaiveAgentLaw::set_site: A must lie in [0, 1]");
    engines_[i] = site_engine(dp_.seed, i);
    const auto n = static_cast<std::size_t>(std::llround(area * static_cast<double>(n_contacts_)));
    auto& cs = contacts_[i];
    cs.assign(n_contacts_, Contact{});
    for (std::size_t k = 0; k < n_contacts_; ++k) cs[k] = {draw_threshold(engines_[i]), t_, k < n};
    n_att_[i] = n;
    area_[i] = static_cast<double>(n) / static_cast<double>(n_contacts_);
    sigma_bar_[i] = sigma_bar;
  }

  /// docs/model.md §2 over [t, t + dt], v frozen; any_yield as AgentLaw.
  core::LawStepInfo advance(double dt, std::span<const double> v) {
    if (v.size() != size()) throw std::invalid_argument("NaiveAgentLaw::advance: one slip rate per site");
    const double alpha = ip_.alpha, kappa = ip_.kappa, eta = ip_.eta;
    const double t1 = t_ + dt;
    const core::TwoStateTransition free_tr = core::two_state_transition(1.0, 0.0, dt);
    bool any = false;
    for (std::size_t i = 0; i < size(); ++i) {
      const double vi = v[i], speed = std::abs(vi), a0 = area_[i], sb = sigma_bar_[i];
      if (!std::isfinite(vi)) {
        sigma_bar_[i] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      const double tau = core::contact_stress(sb + eta * vi, a0);
      const double detach = kappa * speed;
      const core::TwoStateTransition over_tr = core::two_state_transition(1.0, detach, dt);
      Engine& e = engines_[i];
      std::size_t members = 0, n = n_att_[i];
      for (Contact& c : contacts_[i]) {
        const bool over = tau > c.threshold;
        if (c.attached) {
          if (!over) continue;
          ++members;
          if (detach > 0.0 && uniform01(e) >= over_tr.stay_attached) {
            stats_.record_lifetime(i, c.since, t1 - c.since);
            c.attached = false;
            c.since = t1;
            if (!quenched_) c.threshold = draw_threshold(e);
            --n;
          }
        } else if (uniform01(e) < (over ? over_tr : free_tr).become_attached) {
          stats_.record_detached(i, c.since, t1 - c.since);
          c.attached = true;
          c.since = t1;
          ++n;
        }
      }
      const std::size_t n0 = n_att_[i];
      const double y = n0 > 0 ? static_cast<double>(members) / static_cast<double>(n0) : 1.0;
      any |= speed > 0.0 && (members > 0 || n0 == 0);
      const double a1 = static_cast<double>(n) / static_cast<double>(n_contacts_);
      n_att_[i] = n;
      area_[i] = a1;
      sigma_bar_[i] = core::relax(sb, alpha * 0.5 * (a0 + a1) * vi, y * speed, dt);
    }
    t_ = t1;
    return {any};
  }

  /// Y_i: the overloaded fraction of the attached contacts of site i at slip rate v (1 when none is
  /// attached).
  double overloaded_fraction(std::size_t i, double v) const {
    if (n_att_[i] == 0) return 1.0;
    const double tau = core::contact_stress(sigma_bar_[i] + ip_.eta * v, area_[i]);
    std::size_t over = 0;
    for (const Contact& c : contacts_[i]) over += c.attached && tau > c.threshold ? 1 : 0;
    return static_cast<double>(over) / static_cast<double>(n_att_[i]);
  }
  /// The implicit step's linearisation (core/law.hpp), one site at a time, with y = Y_i at the
  /// previous step's rate.
  auto linearisation(double dt) const {
    return [this, k = core::StressStepConstants(ip_, dt)](std::size_t i, double wp, double& c0, double& c1) {
      const double y = wp != 0.0 ? overloaded_fraction(i, wp) : 0.0;
      core::linearise_stress(area_[i], sigma_bar_[i], y, wp, k, c0, c1);
    };
  }

  // --- contact statistics ----------------------------------------------------------------------
  void record_contacts(double t) {
    if (!stats_.enabled()) return;
    stats_.begin_snapshot(t);
    for (std::size_t i = 0; i < contacts_.size(); ++i)
      for (const Contact& c : contacts_[i])
        if (c.attached) stats_.attached(stats_.class_of(i), t_ - c.since, c.threshold);
    stats_.end_snapshot();
  }
  /// As AgentLaw::observe_front (docs/model.md §7.2).
  void observe_front(const core::FrontClasses& f) { stats_.set_front(f); }
  core::ContactTables contact_tables() const { return stats_.tables(); }
  const ContactStats& contact_stats() const { return stats_; }
  /// Checkpoints (core::Archive).
  template <class Ar>
  void serialize(Ar& ar) {
    ar.tag("naive law");
    ar(contacts_, n_att_, area_, sigma_bar_, t_, stats_);
    for (auto& e : engines_) serialize_engine(ar, e);
  }

  // --- inspection ------------------------------------------------------------------------------
  const DiscreteParams& discrete_params() const { return dp_; }
  double time() const { return t_; }
  std::size_t attached_count(std::size_t i) const { return n_att_[i]; }
  const Engine& engine(std::size_t i) const { return engines_[i]; }

 private:
  struct Contact {
    double threshold = 1.0;
    double since = 0.0;  ///< time of the last attachment (attached) or detachment (detached)
    bool attached = false;
  };
  double draw_threshold(Engine& e) const { return g_.degenerate() ? 1.0 : g_.from_uniform(uniform01(e)); }

  core::InterfaceParams ip_;
  DiscreteParams dp_;
  ThresholdDistribution g_;
  std::size_t n_contacts_ = 1;
  bool quenched_ = false;
  double t_ = 0.0;
  std::vector<std::vector<Contact>> contacts_;
  std::vector<Engine> engines_;
  std::vector<std::size_t> n_att_;
  std::vector<double> area_, sigma_bar_;
  ContactStats stats_;
};

}  // namespace slipfront::discrete
