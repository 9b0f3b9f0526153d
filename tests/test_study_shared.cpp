// The shared continuum of a study (docs/studies.md "The shared continuum", issue 22 item 3: skip work no run
// needs): runs whose scenes differ only in discrete.* keys and the seed, and that run their models one after the
// other or whose continuum is not compared online, run the continuum once. Runs the real program.
//
// Asserted, on a small front study (fig1's edge loading, L = 150, t_end = 80, N = 300 and 1000, 3 seeds: 6 runs) on
// the adaptive integrator, on the implicit one (in lockstep) without and with online field comparisons, with the
// three models, and on an imposed-rate sweep (friction_law, 6 runs), each with share_continuum = true (the default)
// and false:
//   - the two study.h5 agree bit for bit (tables, scalars, definitions, notes; not the study file's text);
//   - every run file agrees bit for bit but for the label /continuum@shared_from_run and the wall times;
//   - with sharing, every run's continuum names the one run that computed it (one continuum scene: one run);
//     without it, none does;
//   - where the discrete model's fields are compared online with the continuum's (in lockstep, no mean_field,
//     output.compare_dt > 0) nothing is shared; with mean_field (their reference) the continuum is.
// Deterministic: no false-alarm rate.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <string>

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

void check_shared(const fs::path& dir, const fs::path& study, const std::string& set_line, bool expect_sharing) {
  const fs::path on = variant(study, "on.toml", set_line);
  const fs::path off = variant(study, "off.toml", set_line + "share_continuum = false\n");
  const Output a = run({bin, "study", on.string(), "--out", "on", "-j", "2", "-q"}, dir);
  INFO(a.err);
  REQUIRE(a.code == 0);
  const Output b = run({bin, "study", off.string(), "--out", "off", "-j", "2", "-q"}, dir);
  INFO(b.err);
  REQUIRE(b.code == 0);
  const fs::path sa = dir / "on", sb = dir / "off";
  auto sd = study_differences(sa / "study.h5", sb / "study.h5");
  std::erase(sd, std::string("/study@toml differs"));  // the study files differ in share_continuum
  for (const auto& k : sd) UNSCOPED_INFO(k);
  CHECK(sd.empty());
  const auto ids = run_ids(sa);
  REQUIRE(ids == run_ids(sb));
  REQUIRE(ids.size() == 6);
  std::set<std::string> computed_by;
  for (const auto& id : ids) {
    INFO("run " << id);
    const auto ca = read_h5(sa / "runs" / id / "results.h5"), cb = read_h5(sb / "runs" / id / "results.h5");
    const auto d = differences(ca, cb, [](const std::string& k) {
      if (k.size() >= 13 && k.compare(k.size() - 13, 13, "@wall_seconds") == 0) return true;
      return k == "/continuum@shared_from_run" ||
             (k.rfind("/meta@", 0) == 0 && k != "/meta@status" && k != "/meta@config_hash");
    });
    for (const auto& k : d) UNSCOPED_INFO(k);
    CHECK(d.empty());
    CHECK(cb.strings.count("/continuum@shared_from_run") == 0);
    const auto it = ca.strings.find("/continuum@shared_from_run");
    CHECK((it != ca.strings.end()) == expect_sharing);
    if (it != ca.strings.end()) computed_by.insert(it->second);
  }
  if (expect_sharing) {
    REQUIRE(computed_by.size() == 1);  // one continuum scene in the study: computed once, by one of its runs
    CHECK(std::count(ids.begin(), ids.end(), *computed_by.begin()) == 1);
  }
}

}  // namespace

TEST_CASE("study: the shared continuum gives the study and the run files of every run computing its own",
          "[study][shared]") {
  SECTION("fig1's edge loading on the adaptive integrator") {
    const TempDir dir("shared-adaptive");
    check_shared(dir.path, write_front_study(dir.path), "set = [\"time.integrator=adaptive\"]\n", true);
  }
  SECTION("an imposed-rate sweep") {
    const TempDir dir("shared-sweep");
    check_shared(dir.path, write_sweep_study(dir.path), "", true);
  }
  SECTION("the implicit integrator, the models in lockstep with no field comparison (output.compare_dt = 0)") {
    const TempDir dir("shared-implicit");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=0\"]\n", true);
  }
  SECTION("in lockstep with the discrete fields compared online against the continuum: nothing shared") {
    const TempDir dir("shared-compared");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=5\"]\n", false);
  }
  SECTION("three models in lockstep, the discrete fields compared online against mean_field: the continuum shared") {
    const TempDir dir("shared-three");
    check_shared(dir.path, write_front_study(dir.path),
                 "set = [\"time.integrator=implicit\", \"time.dt=0.02\", \"output.compare_dt=5\", "
                 "'models=[\"continuum\",\"mean_field\",\"discrete\"]', \"discrete.threshold=uniform\", "
                 "\"discrete.width=0.2\"]\n",
                 true);
  }
}
