// The shared references of a study (docs/studies.md "The shared references", issue 22 item 3: skip work no run
// needs): runs whose scenes differ only in keys the continuum (discrete.*) or mean_field (the seed, N, the
// representation, ...) does not read, and that run their models one after the other or do not compare that model's
// fields online, run it once. Runs the real program.
//
// Asserted, on a small front study (fig1's edge loading, L = 150, t_end = 80, N = 300 and 1000, 3 seeds: 6 runs) on
// the adaptive integrator, on the implicit one (in lockstep) without and with online field comparisons, with the
// three models, and on an imposed-rate sweep (friction_law, 6 runs), each with share_references = true (the default)
// and false (its earlier name share_continuum once):
//   - the two study.h5 agree bit for bit (tables, scalars, definitions, notes; not the study file's text);
//   - every run file agrees bit for bit but for the labels /<model>@shared_from_run and the wall times;
//   - with sharing, every run's shared model names one run, the study's first (one scene of that model), whichever
//     worker computed it; without it, none does;
//   - where the discrete model's fields are compared online with its reference (in lockstep, output.compare_dt > 0:
//     mean_field when it runs, else the continuum) that reference is not shared; the other one is.
// Deterministic: no false-alarm rate.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <set>
#include <string>

#include "compare/alongside.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"
#include "study_fixtures.hpp"

namespace fs = std::filesystem;
using namespace slipfront::testing;

namespace {

const std::string bin = SLIPFRONT_BINARY;

// the study file `study` with `extra` lines added after its first line
fs::path variant(const fs::path& study, const std::string& name, const std::string& extra) {
  std::ifstream in(study);
  std::string first, rest, line;
  std::getline(in, first);
  while (std::getline(in, line)) rest += line + "\n";
  const fs::path out = study.parent_path() / name;
  std::ofstream(out) << first << "\n" << extra << rest;
  return out;
}

// the run files of a study directory, by run id
std::vector<std::string> run_ids(const fs::path& dir) {
  std::vector<std::string> ids;
  for (const auto& e : fs::directory_iterator(dir / "runs")) ids.push_back(e.path().filename().string());
  std::sort(ids.begin(), ids.end());
  return ids;
}

void check_shared(const fs::path& dir, const fs::path& study, const std::string& set_line,
                  const std::set<std::string>& expect_shared, const std::string& off_key = "share_references") {
  const fs::path on = variant(study, "on.toml", set_line);
  const fs::path off = variant(study, "off.toml", set_line + off_key + " = false\n");
  const Output a = run({bin, "study", on.string(), "--out", "on", "-j", "2", "-q"}, dir);
  INFO(a.err);
  REQUIRE(a.code == 0);
  const Output b = run({bin, "study", off.string(), "--out", "off", "-j", "2", "-q"}, dir);
  INFO(b.err);
  REQUIRE(b.code == 0);
  const fs::path sa = dir / "on", sb = dir / "off";
  auto sd = study_differences(sa / "study.h5", sb / "study.h5");
  std::erase(sd, std::string("/study@toml differs"));  // the study files differ in share_references
  for (const auto& k : sd) UNSCOPED_INFO(k);
  CHECK(sd.empty());
  const auto ids = run_ids(sa);
  REQUIRE(ids == run_ids(sb));
  REQUIRE(ids.size() == 6);
  std::map<std::string, std::set<std::string>> computed_by;  // model -> the runs that computed it
  for (const auto& id : ids) {
    INFO("run " << id);
    const auto ca = read_h5(sa / "runs" / id / "results.h5"), cb = read_h5(sb / "runs" / id / "results.h5");
    const auto d = differences(ca, cb, [](const std::string& k) {
      if (k.size() >= 13 && k.compare(k.size() - 13, 13, "@wall_seconds") == 0) return true;
      return k == "/continuum@shared_from_run" || k == "/mean_field@shared_from_run" ||
             (k.rfind("/meta@", 0) == 0 && k != "/meta@status" && k != "/meta@config_hash");
    });
    for (const auto& k : d) UNSCOPED_INFO(k);
    CHECK(d.empty());
    for (const std::string model : {"continuum", "mean_field"}) {
      INFO(model);
      const std::string label = "/" + model + "@shared_from_run";
      CHECK(cb.strings.count(label) == 0);
      const auto it = ca.strings.find(label);
      CHECK((it != ca.strings.end()) == (expect_shared.count(model) > 0));
      if (it != ca.strings.end()) computed_by[model].insert(it->second);
    }
  }
  for (const auto& model : expect_shared) {
    INFO(model);
    REQUIRE(computed_by[model].size() == 1);  // one scene of the model in the study: one run named
    CHECK(*computed_by[model].begin() == ids.front());  // the first, not whichever worker got there first
  }
}

}  // namespace

TEST_CASE("study: the shared references give the study and the run files of every run computing its own",
          "[study][shared]") {
  SECTION("fig1's edge loading on the adaptive integrator") {
    const TempDir dir("shared-adaptive");
    check_shared(dir.path, write_front_study(dir.path), "set = [\"time.integrator=adaptive\"]\n", {"continuum"});
  }
  SECTION("an imposed-rate sweep") {
    const TempDir dir("shared-sweep");
    check_shared(dir.path, write_sweep_study(dir.path), "", {"continuum"}, "share_continuum");
  }
  SECTION("the implicit integrator, the models in lockstep with no field comparison (output.compare_dt = 0)") {
    const TempDir dir("shared-implicit");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=0\"]\n", {"continuum"});
  }
  SECTION("in lockstep with the discrete fields compared online against the continuum: nothing shared") {
    const TempDir dir("shared-compared");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=5\"]\n", {});
  }
  // the three models in lockstep (implicit dt = 0.02, uniform thresholds w = 0.2), fields compared at compare_dt
  auto three_in_lockstep = [](const char* compare_dt) {
    return std::string("set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=") + compare_dt +
           "\", 'models=[\"continuum\",\"mean_field\",\"discrete\"]', \"discrete.threshold=uniform\", "
           "\"discrete.width=0.2\"]\n";
  };
  SECTION("three models in lockstep, the discrete fields compared online against mean_field: the continuum shared") {
    const TempDir dir("shared-three");
    check_shared(dir.path, write_front_study(dir.path), three_in_lockstep("5"), {"continuum"});
  }
  SECTION("three models in lockstep without field comparisons: the continuum and mean_field shared") {
    const TempDir dir("shared-three-off");
    check_shared(dir.path, write_front_study(dir.path), three_in_lockstep("0"), {"continuum", "mean_field"});
  }
  SECTION("three models on the adaptive integrator, gaussian thresholds: the continuum and mean_field shared") {
    const TempDir dir("shared-three-adaptive");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=adaptive\", 'models=[\"continuum\",\"mean_field\",\"discrete\"]', "
                 "\"discrete.threshold=gaussian\", \"discrete.width=0.1\"]\n",
                 {"continuum", "mean_field"});
  }
}

// Which models are shared and which keys they read: the decisions the sharing rests on (compare/alongside.hpp).
TEST_CASE("study: shareable_references and reference_ignores", "[study][shared]") {
  using slipfront::compare::reference_ignores;
  using slipfront::compare::shareable_references;
  using V = std::vector<std::string>;
  // the continuum reads no discrete.* key; mean_field the threshold law, width, renewal and bins
  for (const char* k : {"discrete.seed", "discrete.contacts_per_site", "discrete.representation", "discrete.noise",
                        "discrete.threads", "discrete.contact_statistics"}) {
    INFO(k);
    CHECK(reference_ignores("continuum", k));
    CHECK(reference_ignores("mean_field", k));
  }
  for (const char* k : {"discrete.threshold", "discrete.width", "discrete.renewal", "discrete.bins"}) {
    INFO(k);
    CHECK(reference_ignores("continuum", k));
    CHECK(!reference_ignores("mean_field", k));
  }
  for (const char* m : {"continuum", "mean_field", "discrete"}) {
    INFO(m);
    CHECK(!reference_ignores(m, "bulk.length"));
    CHECK(!reference_ignores(m, "models"));
    CHECK(!reference_ignores(m, "time.dt"));
  }
  CHECK(!reference_ignores("discrete", "discrete.seed"));  // the discrete model is never shared

  slipfront::compare::Scene s = fig1_scene();  // a fixed-step integrator: the models in lockstep
  s.time.integrator = slipfront::core::Integrator::central_difference;
  s.models = {"continuum", "discrete"};
  s.output.compare_dt = 1.0;
  CHECK(shareable_references(s) == V{});  // the continuum's fields are compared online
  s.output.compare_dt = 0.0;
  CHECK(shareable_references(s) == V{"continuum"});
  s.models = {"continuum", "mean_field", "discrete"};
  s.output.compare_dt = 1.0;
  CHECK(shareable_references(s) == V{"continuum"});  // mean_field is the reference compared online
  s.output.compare_dt = 0.0;
  CHECK(shareable_references(s) == V{"continuum", "mean_field"});
  s.discrete.contact_statistics = true;  // the prediction reads discrete.contacts_per_site
  CHECK(shareable_references(s) == V{});
  s.discrete.contact_statistics = false;
  s.models = {"mean_field"};  // alone: nothing to share it with
  CHECK(shareable_references(s) == V{});
  s.models = {"continuum", "mean_field"};
  s.output.compare_dt = 1.0;  // no discrete model: no field comparison
  CHECK(shareable_references(s) == V{"continuum", "mean_field"});
}
