#include "compare/study_plan.hpp"

#include <algorithm>
#include <cstdio>

namespace slipfront::compare {
namespace {

std::string run_id(std::size_t i) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04zu", i);
  return buf;
}

// The domains of the study file's numeric keys (docs/studies.md, "Study files").
using core::KeyDomain;
using K = core::KeyKind;
constexpr KeyDomain study_domains[] = {
    {"seeds", K::integer, 1.0, 2147483647.0, false, false, false, "",
     "(runs per point; the study's runs are bounded by limits.max_runs)"},
    {"fit_from", K::number, 0.0, core::parameter_cap},
    {"limits.max_runs", K::integer, 1.0, 1e9, false, false, false, "", "(runs of the study: points x seeds)"},
    {"limits.max_memory_gib", K::number, 0.0, 1e6, true},
};

}  // namespace

std::span<const core::KeyDomain> study_key_domains() { return study_domains; }

double count_runs(const StudySpec& spec) {
  if (spec.groups.empty()) return std::max(1, spec.seeds);
  double points = 0.0;
  for (const StudyGroup& g : spec.groups) {
    double product = 1.0;
    for (const auto& [key, values] : g.vary) product *= static_cast<double>(values.size());
    points += product;
  }
  return points * std::max(1, spec.seeds);
}

std::vector<StudyRun> sample_runs(const StudySpec& spec) {
  StudySpec first = spec;
  first.seeds = 1;
  for (StudyGroup& g : first.groups)
    for (auto& [key, values] : g.vary) values.resize(std::min<std::size_t>(values.size(), 1));
  return expand(first);
}

std::vector<StudyRun> expand(const StudySpec& spec) {
  std::vector<StudyRun> out;
  const std::vector<StudyGroup> groups = spec.groups.empty() ? std::vector<StudyGroup>{StudyGroup{}} : spec.groups;
  for (const auto& g : groups) {
    // Cartesian product of the group's varied keys (first key slowest).
    std::vector<std::size_t> idx(g.vary.size(), 0);
    for (;;) {
      for (int seed = 1; seed <= std::max(1, spec.seeds); ++seed) {
        StudyRun r;
        r.group = g.name;
        r.seed = seed;
        r.overrides = spec.common;
        for (std::size_t k = 0; k < g.vary.size(); ++k) {
          const auto& [key, values] = g.vary[k];
          r.point[key] = values[idx[k]];
          r.overrides.push_back(key + "=" + values[idx[k]]);
        }
        if (spec.seeds > 1) r.overrides.push_back("discrete.seed=" + std::to_string(seed));
        r.id = run_id(out.size());
        out.push_back(std::move(r));
      }
      std::size_t k = g.vary.size();
      while (k > 0) {
        --k;
        if (++idx[k] < g.vary[k].second.size()) break;
        idx[k] = 0;
        if (k == 0) { k = g.vary.size() + 1; break; }
      }
      if (g.vary.empty() || k == g.vary.size() + 1) break;
    }
  }
  return out;
}

}  // namespace slipfront::compare
