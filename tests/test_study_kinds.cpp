// The table of study kinds (issue 17): one row per kind gives its name, what it analyses and its
// analysis; a study file is validated against it and analyse_study dispatches on it.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/study.hpp"
#include "studies/study.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;

namespace {

// A study file of kind `kind` on the minimal scene, written into `dir`.
fs::path write_study(const fs::path& dir, const std::string& kind) {
  std::ofstream(dir / "tiny.toml") << testing::minimal_config();
  const fs::path study = dir / "study.toml";
  std::ofstream(study) << "study = \"kinds\"\nkind = \"" << kind << "\"\nscene = \"tiny.toml\"\n";
  return study;
}

// Everything a report holds, as text, to tell two reports apart.
std::string digest(const studies::StudyReport& r) {
  std::string s;
  for (const auto& [name, columns] : r.tables) {
    s += "table " + name + ":";
    for (const auto& [column, values] : columns) s += " " + column + "[" + std::to_string(values.size()) + "]";
    s += "\n";
  }
  for (const auto& [name, value] : r.scalars) s += "scalar " + name + "\n";
  for (const auto& [name, text] : r.definitions) s += "definition " + name + ": " + text + "\n";
  for (const auto& note : r.notes) s += "note " + note + "\n";
  return s;
}

}  // namespace

TEST_CASE("study kinds: one row per kind, named once, described, and only `runs` and the kinds without scene runs "
          "without an analysis",
          "[study][kinds]") {
  const auto kinds = studies::study_kinds();
  REQUIRE(kinds.size() >= 2);
  std::set<std::string> names;
  for (const studies::StudyKind& k : kinds) {
    INFO(k.name);
    CHECK(!k.name.empty());
    CHECK(!k.description.empty());
    CHECK(names.insert(std::string(k.name)).second);
    CHECK((k.analyse == nullptr) == (k.name == "runs" || k.compute != nullptr));
    // a computation, and a plan of runs from the base scene (resolution), are checked before any work
    CHECK((k.compute == nullptr && k.plan == nullptr) == (k.check == nullptr));
    CHECK((k.plan == nullptr) == (k.name != "resolution"));
    REQUIRE(studies::find_study_kind(k.name) == &k);
  }
  CHECK(names.count("runs") == 1);
  CHECK(studies::find_study_kind("nope") == nullptr);
  CHECK(studies::find_study_kind("") == nullptr);
}

TEST_CASE("study kinds: analyse_study runs each kind's own analysis, none for `runs`, and refuses an unknown kind",
          "[study][kinds]") {
  // An empty study: every analysis takes it (tables without rows, notes), and what analyse_study
  // reports for a kind is exactly what the kind's row computes.
  const std::vector<compare::StudyRun> runs;
  const std::vector<compare::Scene> scenes;
  const std::vector<std::vector<compare::ModelResult>> results;
  std::set<std::string> reports;
  for (const studies::StudyKind& k : studies::study_kinds()) {
    INFO(k.name);
    compare::StudySpec spec;
    spec.name = "empty";
    spec.kind = std::string(k.name);
    studies::StudyReport expected;
    if (k.analyse) k.analyse(expected, spec, runs, scenes, results);
    studies::StudyReport report;
    REQUIRE_NOTHROW(report = studies::analyse_study(spec, runs, scenes, results));
    CHECK(digest(report) == digest(expected));
    if (!k.analyse) CHECK(digest(report).empty());
    if (k.analyse) CHECK(reports.insert(digest(report)).second);  // each row its own analysis
  }
  compare::StudySpec spec;
  spec.kind = "nope";
  CHECK_THROWS_AS(studies::analyse_study(spec, runs, scenes, results), std::invalid_argument);
}

TEST_CASE("study kinds: a study file is accepted with every kind of the table and refused with any other, naming "
          "them all in table order",
          "[study][kinds]") {
  const testing::TempDir dir("study-kinds");
  for (const studies::StudyKind& k : studies::study_kinds()) {
    INFO(k.name);
    CHECK(app::load_study(write_study(dir.path, std::string(k.name))).kind == k.name);
  }
  std::string list;
  for (const studies::StudyKind& k : studies::study_kinds()) list += (list.empty() ? "" : ", ") + std::string(k.name);
  try {
    app::load_study(write_study(dir.path, "nope"));
    FAIL("an unknown study kind was accepted");
  } catch (const app::ConfigError& e) {
    const std::string what = e.what();
    CHECK(what.find("kind") != std::string::npos);
    CHECK(what.find("unknown study kind 'nope' (known: " + list + ")") != std::string::npos);
  }
}

namespace {

// scripts/report.py against tables of kinds (each the JSON of `slipfront study --list-kinds --json`, in the files
// argv[2:]), one line a table: "<file>: ok <kind>,<kind>,..." (its kinds in order), or "<file>:" and what is wrong:
// "missing X" (a kind of the table whose plots, report.study_plots, are not its own `X_study`), "extra X" (a function
// `X_study` of report.py, X not a kind of the table), "front X" (X of report.FRONT_STUDY_KINDS not in the table).
// One Python process for all (report.py imports matplotlib: seconds).
const std::string report_check = R"(import json, os, sys
sys.path.insert(0, os.path.dirname(sys.argv[1]))
import report
for path in sys.argv[2:]:
    kinds = [k["name"] for k in json.load(open(path))["kinds"]]
    bad = [f"missing {k}" for k in kinds if report.study_plots(k).__name__ != f"{k}_study"]
    bad += [f"extra {n[:-6]}" for n, f in vars(report).items() if n.endswith("_study") and callable(f) and n[:-6] not in kinds]
    bad += [f"front {k}" for k in report.FRONT_STUDY_KINDS if k not in kinds]
    print(os.path.basename(path) + ": " + (" ".join(bad) if bad else "ok " + ",".join(kinds)))
)";

}  // namespace

TEST_CASE("study kinds: `slipfront study --list-kinds --json` is the table, and report.py has the plots of every kind "
          "of it and of no other",
          "[study][kinds][report]") {
  const testing::TempDir dir("study-kinds-json");
  const auto listed = testing::run({SLIPFRONT_BINARY, "study", "--list-kinds", "--json"}, dir.path);
  REQUIRE(listed.code == 0);
  CHECK(listed.out == app::study_kinds_json() + "\n");
  std::string names;
  for (const studies::StudyKind& k : studies::study_kinds()) names += (names.empty() ? "" : ",") + std::string(k.name);
  testing::write_text(dir.path / "table.json", listed.out);
  // The check bites both ways: a kind the report does not know, and a kind the report draws that the table lacks.
  testing::write_text(dir.path / "new_kind.json",
                      R"({"kinds": [{"name": "new_kind"}, )" + listed.out.substr(listed.out.find('[') + 1));
  const std::string first = "{\"name\": \"friction_law\"";
  std::string without = listed.out;
  const auto at = without.find(first);
  REQUIRE(at != std::string::npos);
  without.erase(at, without.find('}', at) + 2 - at);  // the row and its comma
  testing::write_text(dir.path / "without.json", without);

  const auto checked = testing::run({"/usr/bin/python3", "-c", report_check,
                                     std::string(SLIPFRONT_SOURCE_DIR) + "/scripts/report.py",
                                     (dir.path / "table.json").string(), (dir.path / "new_kind.json").string(),
                                     (dir.path / "without.json").string()},
                                    dir.path);
  INFO(checked.err);
  REQUIRE(checked.code == 0);
  CHECK(checked.out == "table.json: ok " + names + "\n"  // every kind of the table, in its order, has its plots
                       "new_kind.json: missing new_kind\n"
                       "without.json: extra friction_law\n");
}

TEST_CASE("study kinds: front_speeds reports the RMS over seeds of the discrete model's relative difference and its "
          "rate in N",
          "[study][kinds][front_speeds]") {
  // Synthetic runs (no scene is run): at each N four seeds whose c_transient differs from the continuum's by
  // (1, -1, 2, -2) x 0.03 N^-1/2 (relative) and a fifth without a transient front (NaN: left out). The table's
  // c_transient_rms_rel_diff is then 0.03 sqrt(2.5) N^-1/2 exactly, its fitted exponent -1/2 (the points lie on the line:
  // the interval is the point), and the seed mean's bias 0. A continuum speed of 20.
  const std::vector<double> Ns{100, 1000, 10000, 100000};
  const double seed_offsets[] = {1.0, -1.0, 2.0, -2.0};
  const double c0 = 20.0, nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<compare::StudyRun> runs;
  std::vector<std::vector<compare::ModelResult>> results;
  for (double N : Ns)
    for (int k = 0; k < 5; ++k) {
      compare::StudyRun r;
      r.point["discrete.contacts_per_site"] = std::to_string(static_cast<long>(N));
      r.seed = k + 1;
      runs.push_back(r);
      std::vector<compare::ModelResult> m(2);
      m[0].model = "continuum";
      m[0].events.c_transient = c0;
      m[1].model = "discrete";
      m[1].events.c_transient = k < 4 ? c0 * (1.0 + 0.03 * seed_offsets[k] / std::sqrt(N)) : nan;
      results.push_back(m);
    }
  compare::StudySpec spec;
  spec.name = "synthetic";
  spec.kind = "front_speeds";
  const std::vector<compare::Scene> scenes(runs.size());
  const auto rep = studies::analyse_study(spec, runs, scenes, results);
  const auto& t = rep.tables.at("front_speeds");
  REQUIRE(t.at("N") == Ns);
  for (std::size_t i = 0; i < Ns.size(); ++i) {
    INFO("N = " << Ns[i]);
    CHECK(t.at("c_transient_rms_rel_diff")[i] == Approx(0.03 * std::sqrt(2.5) / std::sqrt(Ns[i])).epsilon(1e-9));
    CHECK(std::abs(t.at("c_transient_rel_diff")[i]) < 1e-12);
    CHECK(t.at("c_transient_finite")[i] == 4.0);
  }
  CHECK(rep.scalars.at("front_c_transient_rms_exponent") == Approx(-0.5).epsilon(1e-9));
  CHECK(rep.scalars.at("front_c_transient_rms_exponent_ci_low") == Approx(-0.5).epsilon(1e-6));
  CHECK(rep.scalars.at("front_c_transient_rms_exponent_ci_high") == Approx(-0.5).epsilon(1e-6));
  CHECK(rep.definitions.count("front_speeds/c_transient_rms_rel_diff") == 1);
}
