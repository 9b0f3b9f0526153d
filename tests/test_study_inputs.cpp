// Trust nothing read back (issue 18), the program as a user runs it: every reproducer of the issue is
// refused before any work with the file or key and the reason (exit 2, within seconds, nothing
// created), or shown correct. Configurations from devices and FIFOs (check, run, a study's scene);
// studies too large for their [limits] (seeds beyond 32 bits, 10^9 seeds, 10^6 runs); names leaving
// the output tree; kinds whose analysis needs a model the runs do not list; repeated vary values.
#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "studies/study.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"
#include "study_fixtures.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using namespace slipfront::testing;

namespace {

const std::string bin = SLIPFRONT_BINARY;


// Every path under `dir` (to show that a refusal created nothing).
std::vector<std::string> tree(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

// The program, at most 20 s (a blocked read or a 14 GB allocation would not end in time), and its wall time.
struct Timed {
  Output o;
  double seconds = 0.0;
};
Timed run_timed(const std::vector<std::string>& args, const fs::path& cwd) {
  const auto t0 = std::chrono::steady_clock::now();
  Timed t;
  t.o = run(args, cwd, {}, {}, 20.0);
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

}  // namespace

TEST_CASE("study inputs: configurations from devices, FIFOs and directories are refused at once, by every verb",
          "[study][inputs]") {
  const TempDir dir("sinputs-devices");
  write_text(dir.path / "tiny.toml", minimal_config());
  REQUIRE(::mkfifo((dir.path / "fifo.toml").c_str(), 0600) == 0);  // no writer
  fs::create_directories(dir.path / "folder.toml");
  struct Case {
    std::string file, reason;
  };
  const std::vector<Case> cases = {{"/dev/zero", "is a character device, not a regular file"},
                                   {"/dev/urandom", "is a character device, not a regular file"},
                                   {"fifo.toml", "is a FIFO (named pipe), not a regular file"},
                                   {"folder.toml", "is a directory, not a regular file"}};
  const std::vector<std::string> before = tree(dir.path);
  for (const Case& c : cases) {
    for (const char* verb : {"check", "run"}) {
      INFO(verb << " " << c.file);
      const Timed t = run_timed({bin, verb, c.file}, dir.path);
      INFO(t.o.err);
      CHECK(t.o.code == 2);
      CHECK(contains(t.o.err, "slipfront: error: " + c.file + ": " + c.reason));
      CHECK(t.seconds < 5.0);
    }
    // a study whose scene is that file: refused naming the study's key and the file
    const std::string study = "study-" + fs::path(c.file).filename().string();
    write_text(dir.path / study, "study = \"s\"\nkind = \"runs\"\nscene = \"" + c.file + "\"\n");
    INFO("study with scene = " << c.file);
    const Timed t = run_timed({bin, "study", study, "--out", "out"}, dir.path);
    INFO(t.o.err);
    CHECK(t.o.code == 2);
    CHECK(contains(t.o.err, "slipfront: error: " + study + ": scene: "));
    CHECK(contains(t.o.err, c.reason));
    CHECK(t.seconds < 5.0);
    // and the study file itself
    const Timed s = run_timed({bin, "study", c.file, "--out", "out"}, dir.path);
    CHECK(s.o.code == 2);
    CHECK(contains(s.o.err, "slipfront: error: " + c.file + ": " + c.reason));
    fs::remove(dir.path / study);
  }
  CHECK(tree(dir.path) == before);  // nothing created
}

TEST_CASE("study inputs: studies beyond their [limits] are refused before any run directory or per-run allocation",
          "[study][inputs]") {
  const TempDir dir("sinputs-size");
  write_sweep_study(dir.path);  // sweep.toml: the imposed-rate scene of the resume tests
  const std::string head = "kind = \"runs\"\nscene = \"sweep.toml\"\n";
  std::string big_vary;  // 100000 points
  for (int k = 0; k < 1000; ++k) big_vary += (k ? ", " : "") + std::to_string(1.001 + 0.0001 * k);
  std::string eta;
  for (int k = 0; k < 100; ++k) eta += (k ? ", " : "") + std::to_string(0.1 + 0.001 * k);
  const std::string big = "[vary]\n\"interface.alpha\" = [" + big_vary + "]\n\"interface.eta\" = [" + eta + "]\n";
  struct Case {
    const char* what;
    std::string body, key, reason;
  };
  const std::vector<Case> cases = {
      {"2^32 + 1 seeds (was one seed per point, complete)", "seeds = 4294967297\n", "seeds",
       "must be in [1, 2147483647]"},
      {"2^31 seeds", "seeds = 2147483648\n", "seeds", "must be in [1, 2147483647]"},
      {"2^63 - 1 seeds", "seeds = 9223372036854775807\n", "seeds", "must be in [1, 2147483647]"},
      {"10^9 seeds (was 14.7 GB then bad_alloc)", "seeds = 1000000000\n", "limits.max_runs",
       "the study would make 1e+09 runs ((1) points x 1000000000 seeds"},
      {"seeds = 1e9 (was refused for a wrong reason)", "seeds = 1e9\n", "seeds",
       "expected an integer, got a float (1e+09)"},
      {"10^6 runs (was 920,906 empty run directories)", "seeds = 10\n" + big, "limits.max_runs",
       "the study would make 1e+06 runs ((100000) points x 10 seeds"},
      {"10^5 runs within max_runs, beyond max_memory_gib",
       big + "[limits]\nmax_runs = 100000\nmax_memory_gib = 0.1\n", "limits.max_memory_gib",
       "the study would hold about"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    write_text(dir.path / "big.toml", "study = \"big\"\n" + head + c.body);
    const Timed t = run_timed({bin, "study", "big.toml", "--out", "out"}, dir.path);
    INFO(t.o.err);
    CHECK(t.o.code == 2);
    CHECK(contains(t.o.err, "slipfront: error: big.toml: " + c.key + ": " + c.reason));
    CHECK(t.seconds < 5.0);
    CHECK_FALSE(fs::exists(dir.path / "out"));
    CHECK_FALSE(fs::exists(dir.path / "out" / "studies"));
  }
}

TEST_CASE("study inputs: a study name cannot leave the output tree", "[study][inputs]") {
  const TempDir dir("sinputs-name");
  write_sweep_study(dir.path);
  fs::create_directories(dir.path / "a" / "b" / "c");
  for (const std::string name : {"../../../escape", "/tmp/slipfront-escape", "x/../../escape", ""}) {
    INFO(name);
    write_text(dir.path / "a" / "b" / "c" / "s.toml", "study = \"" + name + "\"\nkind = \"runs\"\nscene = \"../../../sweep.toml\"\n");
    const Timed t = run_timed({bin, "study", "s.toml"}, dir.path / "a" / "b" / "c");
    INFO(t.o.err);
    CHECK(t.o.code == 2);
    CHECK(contains(t.o.err, "slipfront: error: s.toml: study: must"));
    CHECK_FALSE(fs::exists(dir.path / "escape"));
    CHECK_FALSE(fs::exists(dir.path / "a" / "b" / "c" / "out"));
  }
  CHECK_FALSE(fs::exists("/tmp/slipfront-escape"));
}

TEST_CASE("study inputs: a kind whose analysis needs a model the runs do not list is refused at load",
          "[study][inputs]") {
  const TempDir dir("sinputs-models");
  write_sweep_study(dir.path);
  int refused = 0;
  for (const studies::StudyKind& k : studies::study_kinds()) {
    for (const char* model : {"continuum", "discrete"}) {
      const bool needed_missing = std::string(model) == "continuum" ? k.needs.discrete : k.needs.continuum;
      if (!needed_missing) continue;  // (a kind this model feeds: its runs are tested elsewhere)
      INFO(k.name << " with models = [" << model << "]");
      write_text(dir.path / "k.toml", "study = \"k\"\nkind = \"" + std::string(k.name) +
                                          "\"\nscene = \"sweep.toml\"\nset = ['models=[\"" + model + "\"]']\n");
      const Timed t = run_timed({bin, "study", "k.toml", "--out", "out"}, dir.path);
      INFO(t.o.err);
      CHECK(t.o.code == 2);
      // (a kind without scene runs checks its base scene)
      const std::string who = k.compute ? "the base scene" : "run 0000";
      CHECK(contains(t.o.err, "slipfront: error: k.toml: kind: the analysis of kind '" + std::string(k.name) +
                                  "' needs " + studies::describe(k.needs) + ", but " + who + " has models = [\"" + model +
                                  "\"]"));
      CHECK_FALSE(fs::exists(dir.path / "out"));
      ++refused;
    }
  }
  CHECK(refused >= 10);
  // the case: transient_friction run with the discrete model alone (was: complete, every exponent NaN)
  write_text(dir.path / "t.toml", "study = \"t\"\nkind = \"transient_friction\"\nscene = \"sweep.toml\"\n"
                                  "set = ['models=[\"discrete\"]']\n[vary]\n\"discrete.contacts_per_site\" = [100, 1000, 10000]\n");
  const Timed t = run_timed({bin, "study", "t.toml", "--out", "out"}, dir.path);
  CHECK(t.o.code == 2);
  CHECK(contains(t.o.err, "needs the continuum and the discrete model, but run 0000 has models = [\"discrete\"] (no "
                          "continuum)"));
}

TEST_CASE("study inputs: repeated vary values run once, with a note printed and kept in study.h5", "[study][inputs]") {
  const TempDir dir("sinputs-dup");
  write_sweep_study(dir.path);  // sweeps.toml: N = 100, 1000, 10000, 2 seeds
  std::string text = slurp(dir.path / "sweeps.toml");
  text.replace(text.find("[100, 1000, 10000]"), 18, "[100, 1000, 100, 10000, 1e3]");
  write_text(dir.path / "dup.toml", text);
  const Timed t = run_timed({bin, "study", "dup.toml", "--out", "dup", "-j", "2"}, dir.path);
  INFO(t.o.err);
  REQUIRE(t.o.code == 0);
  CHECK(contains(t.o.out, "runs: 6 run now, 0 skipped"));  // 3 points x 2 seeds, not 5 x 2
  CHECK(contains(t.o.err, "slipfront: note: dup.toml: vary.discrete.contacts_per_site: the value 100 is repeated: it is "
                          "run once"));
  CHECK(contains(t.o.err, "the value 1000.0 (the same point as 1000) is repeated"));
  CHECK(run_files(dir.path / "dup").size() == 6);
  const H5Content s = read_h5(dir.path / "dup" / "study.h5");
  CHECK(contains(s.strings.at("/study@notes"), "vary.discrete.contacts_per_site: the value 100 is repeated"));
  // the same analysis as the study without the repeats: the seeds per point are the study's 2
  const Timed ref = run_timed({bin, "study", "sweeps.toml", "--out", "ref", "-j", "2", "-q"}, dir.path);
  REQUIRE(ref.o.code == 0);
  const H5Content r = read_h5(dir.path / "ref" / "study.h5");
  for (const auto& [key, values] : r.datasets)
    if (key.rfind("/study/tables/", 0) == 0) {
      INFO(key);
      CHECK(s.datasets.at(key) == values);
    }
  CHECK(s.datasets.at("/study/tables/friction_law_error/seeds") == std::vector<double>{2, 2, 2});
}
