// The validity map's analysis (issue 13, compare/validity.hpp): the mode classifier on synthetic two-mode
// samples, the crossover on data generated with a known law, and the collapse exponent recovered from a
// synthetic study with a known N* ~ (alpha - 1)^p.
#include <catch2/catch.hpp>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <vector>

#include "compare/validity.hpp"
#include "scenes.hpp"

using namespace slipfront;

TEST_CASE("validity: the mode classifier recovers the fraction of a synthetic two-mode sample", "[validity]") {
  // Ratios c_discrete/c_continuum from two modes, 1.0 and 1.6 with spread 0.08 (the measured fig1 modes,
  // docs/validity.md): the threshold 1.3 lies 3.75 spreads from both, so a run is misclassified with
  // probability 2e-4. For true fractions 0.1, 0.3, 0.7 over 64 runs the classified fraction equals the number
  // of runs drawn from the first mode (fixed seed 11: false-alarm rate of this exact check ~ 64 · 2e-4 = 1%),
  // and the 95% Wilson interval contains the true fraction. Runs with no transient (NaN) count as re-stuck.
  boost::random::mt19937_64 rng(11);
  boost::random::normal_distribution<double> spread(0.0, 0.08);
  for (double f : {0.1, 0.3, 0.7}) {
    std::vector<double> r;
    int first = 0;
    for (int k = 0; k < 64; ++k) {
      const bool cont = k < static_cast<int>(std::lround(f * 64));
      first += cont;
      r.push_back((cont ? 1.0 : 1.6) + spread(rng));
    }
    const auto m = compare::classify_modes(r, std::vector<double>(r.size(), 0.0));
    CHECK(m.runs == 64);
    CHECK(m.continuum_like == first);
    CHECK(m.low <= f);
    CHECK(m.high >= f);
    CHECK(m.high - m.low < 0.3);
  }
  const std::vector<double> with_nan{1.0, std::nan(""), 1.7, 0.95, 1.0};
  const std::vector<double> shift{0.0, 0.0, 0.08, -0.02, -0.27};  // the last: the early instability of small N
  const auto m = compare::classify_modes(with_nan, shift);
  CHECK(m.continuum_like == 2);
  CHECK(m.fraction == Approx(0.4));
  // Wilson interval of 32 of 64: 0.5 +- 0.119 (closed form)
  std::vector<double> half(64, 1.6);
  for (int k = 0; k < 32; ++k) half[k] = 1.0;
  const auto h = compare::classify_modes(half, std::vector<double>(64, 0.0));
  CHECK(h.low == Approx(0.3808).epsilon(1e-3));
  CHECK(h.high == Approx(0.6192).epsilon(1e-3));
}

TEST_CASE("validity: the crossover N* of data following a known law", "[validity]") {
  // error(N) = 0.01 (N / 2000)^(-2): a power law, which log-log interpolation reproduces exactly, so N* = 2000
  // to 1e-12 at the level 1%; edge cases: below the level from the first N, above it at the last.
  const std::vector<double> n{100, 300, 1000, 3000, 10000};
  std::vector<double> e;
  for (double N : n) e.push_back(0.01 * std::pow(N / 2000.0, -2.0));
  const auto c = compare::crossover_n(n, e, 0.01);
  CHECK(c.n_star == Approx(2000.0).epsilon(1e-12));
  CHECK_FALSE(c.below_at_start);
  CHECK_FALSE(c.never_below);
  CHECK(compare::crossover_n(n, e, 1e3).below_at_start);
  CHECK(compare::crossover_n(n, e, 1e-9).never_below);
  // a bump above the level after a first crossing: N* is where it stays below
  std::vector<double> bumpy{0.2, 0.005, 0.02, 0.001, 0.0005};
  const auto b = compare::crossover_n(n, bumpy, 0.01);
  CHECK(b.n_star > 1000.0);  // after the last point above (0.02 at N = 1000), before 3000
  CHECK(b.n_star < 3000.0);
}

TEST_CASE("validity: the collapse exponent of a synthetic study with a known law", "[validity]") {
  // A synthetic validity_friction study: for alpha - 1 in {0.02, 0.05, 0.1, 0.2}, the discrete steady friction
  // is 10% off the continuum below N*(alpha) = 30 (alpha - 1)^(-1.5) (re-sticking) and 1e-4 above, on a
  // fine N grid (factor 1.25); 4 seeds. The analysis must find N* within one grid step and the exponent -1.5
  // within its 95% interval (and the point estimate within 0.1).
  std::vector<compare::StudyRun> runs;
  std::vector<compare::Scene> scenes;
  std::vector<std::vector<compare::ModelResult>> res;
  for (double am1 : {0.02, 0.05, 0.1, 0.2}) {
    const double nstar = 30.0 * std::pow(am1, -1.5);
    for (double N = 50; N < 50000; N *= 1.25) {
      for (int seed = 1; seed <= 4; ++seed) {
        compare::Scene s = testing::imposed_rate_scene();
        s.interface.alpha = 1.0 + am1;
        s.discrete.contacts_per_site = static_cast<long>(std::lround(N));
        compare::ModelResult c, d;
        c.model = "continuum";
        d.model = "discrete";
        for (double v : {0.1, 1.0, 10.0}) {
          const double sc = 1.0 + v;
          c.friction_law["sigma"].push_back(sc);
          d.friction_law["sigma"].push_back(sc * (1.0 + (static_cast<double>(s.discrete.contacts_per_site) < nstar ? 0.1 : 1e-4) +
                                                  1e-5 * seed));
        }
        compare::StudyRun r;
        r.seed = seed;
        runs.push_back(r);
        scenes.push_back(s);
        res.push_back({c, d});
      }
    }
  }
  compare::StudyReport rep;
  compare::analyse_validity_friction(rep, runs, scenes, res);
  const auto& x = rep.tables.at("validity_crossover");
  for (std::size_t k = 0; k < x.at("alpha").size(); ++k) {
    const double truth = 30.0 * std::pow(x.at("alpha_minus_1")[k], -1.5);
    INFO("alpha - 1 = " << x.at("alpha_minus_1")[k] << ": N* " << x.at("N_star_1")[k] << ", truth " << truth);
    CHECK(x.at("N_star_1_low")[k] <= truth * 1.26);
    CHECK(x.at("N_star_1_high")[k] >= truth / 1.26);
  }
  const double p = rep.scalars.at("validity_friction_Nstar1_exponent");
  CHECK(p == Approx(-1.5).margin(0.1));
  CHECK(rep.scalars.at("validity_friction_Nstar1_exponent_ci_low") <= -1.5);
  CHECK(rep.scalars.at("validity_friction_Nstar1_exponent_ci_high") >= -1.5);
}
