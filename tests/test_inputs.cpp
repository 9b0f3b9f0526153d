// Trust nothing read back (issue 18), in process: configuration files are read by one reader that takes
// regular files only and at most 1 MiB (devices, FIFOs, sockets, directories and larger files refused
// with the file and the reason, a FIFO without a writer never waited on), TOML integers become C++
// integers through one checked conversion, and a study file is refused, key by key, where the issue
// found it accepted or misread: seeds beyond 32 bits, seeds = 1e9, names that leave the output tree,
// limits outside their domain. Repeated vary values are one point, with a note.
#include <catch2/catch.hpp>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "apps/config.hpp"
#include "apps/study.hpp"
#include "apps/toml_integer.hpp"
#include "studies/study.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using app::ConfigError;
using testing::TempDir;

namespace {

using slipfront::testing::contains;

// The ConfigError of f(), or a failed check.
template <class F>
ConfigError refusal(F&& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e;
  }
  FAIL("accepted");
  throw;  // (not reached)
}

// A Unix socket bound at `path` (closed when the test ends; the path stays).
struct BoundSocket {
  int fd = -1;
  explicit BoundSocket(const fs::path& path) {
    fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    const std::string p = path.string();
    REQUIRE(p.size() < sizeof addr.sun_path);
    std::copy(p.begin(), p.end(), addr.sun_path);
    REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  }
  ~BoundSocket() { ::close(fd); }
};

}  // namespace

TEST_CASE("inputs: configuration files are regular files of at most 1 MiB: anything else is refused with its type",
          "[inputs][config]") {
  const TempDir dir("inputs-files");
  const fs::path fifo = dir.path / "fifo.toml";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);  // no writer: opening it for reading would wait forever
  const BoundSocket socket(dir.path / "socket.toml");
  fs::create_directories(dir.path / "directory.toml");
  testing::write_text(dir.path / "big.toml", std::string(app::max_config_bytes + 1, '#'));
  fs::create_symlink("/dev/zero", dir.path / "link-to-zero.toml");

  struct Case {
    fs::path file;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"/dev/zero", "is a character device, not a regular file"},
      {"/dev/urandom", "is a character device, not a regular file"},
      {"/dev/null", "is a character device, not a regular file"},
      {dir.path / "link-to-zero.toml", "is a character device, not a regular file"},
      {fifo, "is a FIFO (named pipe), not a regular file"},
      {dir.path / "socket.toml", "is a socket, not a regular file"},
      {dir.path / "directory.toml", "is a directory, not a regular file"},
      {dir.path / "big.toml", "is 1048577 bytes, more than the limit of 1048576 bytes"},
      {dir.path / "absent.toml", "cannot open the file: No such file or directory"},
  };
  for (const Case& c : cases) {
    INFO(c.file.string());
    const auto t0 = std::chrono::steady_clock::now();
    const ConfigError read = refusal([&] { (void)app::read_config_file(c.file); });
    CHECK(read.file == c.file.string());
    CHECK(read.key.empty());
    CHECK(contains(read.reason, c.reason));
    // the scene loader (check, run) and the study loader go through the same reader
    const ConfigError scene = refusal([&] { (void)app::load_scene(c.file, {}); });
    CHECK(scene.reason == read.reason);
    const ConfigError study = refusal([&] { (void)app::load_study(c.file); });
    CHECK(study.reason == read.reason);
    CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(2));  // nothing read until bad_alloc
  }

  // at the limit: read whole (a smaller limit stands in for 1 MiB)
  testing::write_text(dir.path / "exact.toml", std::string(100, 'x'));
  CHECK(app::read_config_file(dir.path / "exact.toml", 100) == std::string(100, 'x'));
  const ConfigError over = refusal([&] { (void)app::read_config_file(dir.path / "exact.toml", 99); });
  CHECK(over.reason == "is 100 bytes, more than the limit of 99 bytes for a configuration file (is it the right file?)");
  // files whose size says nothing (procfs reports 0) are still read at most to the limit
  CHECK_FALSE(app::read_config_file("/proc/self/status").empty());
  const ConfigError proc = refusal([&] { (void)app::read_config_file("/proc/self/status", 10); });
  CHECK(contains(proc.reason, "is at least 11 bytes, more than the limit of 10 bytes"));
}

TEST_CASE("inputs: checked_integer narrows a TOML integer only when it fits", "[inputs][config]") {
  struct Case {
    const char* value;
    bool fits_int, fits_uint64;
  };
  const std::vector<Case> cases = {
      {"1", true, true},
      {"-1", true, false},
      {"2147483647", true, true},
      {"2147483648", false, true},           // 2^31: was cast to -2147483648
      {"4294967297", false, true},           // 2^32 + 1: was cast to 1
      {"9223372036854775807", false, true},  // 2^63 - 1: was cast to -1
      {"-9223372036854775808", false, false},
  };
  for (const Case& c : cases) {
    INFO(c.value);
    const toml::table t = toml::parse(std::string("k = ") + c.value);
    const toml::node& n = *t.get("k");
    const std::int64_t v = n.as_integer()->get();
    if (c.fits_int) {
      CHECK(app::checked_integer<int>(n, "f.toml", "k") == v);
    } else {
      const ConfigError e = refusal([&] { (void)app::checked_integer<int>(n, "f.toml", "k"); });
      CHECK(std::string(e.what()) ==
            "f.toml: k: the integer " + std::string(c.value) + " is out of range (-2147483648 .. 2147483647)");
    }
    if (c.fits_uint64) CHECK(app::checked_integer<std::uint64_t>(n, "f.toml", "k") == static_cast<std::uint64_t>(v));
    else CHECK_THROWS_AS(app::checked_integer<std::uint64_t>(n, "f.toml", "k"), ConfigError);
  }
  // floats: taken where the scene schema says "integer" (4e1), never in a study file
  const toml::table t = toml::parse("a = 4e1\nb = 1.5\nc = 1e300\nd = \"3\"");
  CHECK(app::checked_integer<int>(*t.get("a"), "f.toml", "a", app::IntegralFloats::accepted) == 40);
  CHECK(refusal([&] { (void)app::checked_integer<int>(*t.get("a"), "f.toml", "a"); }).reason ==
        "expected an integer, got a float (40.0); write it as the integer 40");
  CHECK(refusal([&] { (void)app::checked_integer<int>(*t.get("b"), "f.toml", "b", app::IntegralFloats::accepted); })
            .reason == "expected an integer, got a float (1.5)");
  CHECK(refusal([&] { (void)app::checked_integer<long>(*t.get("c"), "f.toml", "c", app::IntegralFloats::accepted); })
            .reason == "expected an integer, got a float (1e+300)");
  CHECK(refusal([&] { (void)app::checked_integer<int>(*t.get("d"), "f.toml", "d"); }).reason ==
        "expected an integer, got the string \"3\"");
  // the scene schema's integer keys use it: an int key beyond 32 bits is refused, not wrapped
  const ConfigError bins = refusal([] {
    (void)app::parse_scene("models = [\"discrete\"]\n" + testing::minimal_config() + "[discrete]\nbins = 4294967297\n",
                           "s.toml", {});
  });
  CHECK(bins.key == "discrete.bins");
  CHECK(bins.reason == "the integer 4294967297 is out of range (-2147483648 .. 2147483647)");
}

TEST_CASE("inputs: study files are refused key by key where the issue found them misread", "[inputs][study]") {
  const TempDir dir("inputs-study");
  testing::write_text(dir.path / "tiny.toml", testing::minimal_config());
  const auto study = [&](const std::string& body) {
    const fs::path f = dir.path / "study.toml";
    testing::write_text(f, body);
    return f;
  };
  const std::string head = "kind = \"runs\"\nscene = \"tiny.toml\"\n";
  struct Case {
    std::string body, key, reason;
  };
  const std::vector<Case> cases = {
      // seeds: a TOML integer in [1, 2^31 - 1], never narrowed unchecked, never a float
      {"study = \"s\"\n" + head + "seeds = 4294967297\n", "seeds", "must be in [1, 2147483647]"},
      {"study = \"s\"\n" + head + "seeds = 2147483648\n", "seeds", "must be in [1, 2147483647]"},
      {"study = \"s\"\n" + head + "seeds = 9223372036854775807\n", "seeds", "must be in [1, 2147483647]"},
      {"study = \"s\"\n" + head + "seeds = 1e9\n", "seeds",
       "expected an integer, got a float (1e+09); write it as the integer 1000000000"},
      {"study = \"s\"\n" + head + "seeds = 8.0\n", "seeds", "expected an integer, got a float (8.0)"},
      {"study = \"s\"\n" + head + "seeds = 0\n", "seeds", "must be in [1, 2147483647]"},
      {"study = \"s\"\n" + head + "seeds = -3\n", "seeds", "must be in [1, 2147483647]"},
      {"study = \"s\"\n" + head + "seeds = \"4\"\n", "seeds", "expected an integer, got the string \"4\""},
      {"study = \"s\"\n" + head + "fit_from = nan\n", "fit_from", "must be"},
      {"study = \"s\"\n" + head + "fit_from = -1\n", "fit_from", "must be"},
      // share_references (and its earlier name share_continuum): a TOML boolean, one of the two
      {"study = \"s\"\n" + head + "share_references = \"yes\"\n", "share_references", "must be true or false"},
      {"study = \"s\"\n" + head + "share_continuum = \"yes\"\n", "share_continuum", "must be true or false"},
      {"study = \"s\"\n" + head + "share_continuum = 1\n", "share_continuum", "must be true or false"},
      {"study = \"s\"\n" + head + "share_references = true\nshare_continuum = false\n", "share_continuum",
       "earlier name of share_references, and both are given"},
      // the name obeys the scene-name rule: it names out/studies/<study>
      {"study = \"../../../escape\"\n" + head, "study", "must be a relative name without '..'"},
      {"study = \"/tmp/escape\"\n" + head, "study", "must be a relative name without '..'"},
      {"study = \"a/../../b\"\n" + head, "study", "must be a relative name without '..'"},
      {"study = \"\"\n" + head, "study", "must not be empty"},
      {"study = \"a\\u0007b\"\n" + head, "study", "must not contain control characters"},
      // the study's own limits
      {"study = \"s\"\n" + head + "[limits]\nmax_runs = 0\n", "limits.max_runs", "must be in [1, 1000000000]"},
      {"study = \"s\"\n" + head + "[limits]\nmax_runs = 1e5\n", "limits.max_runs", "expected an integer, got a float"},
      {"study = \"s\"\n" + head + "[limits]\nmax_runs = 9223372036854775807\n", "limits.max_runs", "must be in [1, 1000000000]"},
      {"study = \"s\"\n" + head + "[limits]\nmax_memory_gib = 0\n", "limits.max_memory_gib", "must be"},
      {"study = \"s\"\n" + head + "[limits]\nmax_memory_gib = inf\n", "limits.max_memory_gib", "must be"},
      {"study = \"s\"\n" + head + "[limits]\nmax_run = 3\n", "limits.max_run", "unknown key (known keys of [limits]"},
      {"study = \"s\"\n" + head + "limits = 3\n", "limits", "must be a table [limits]"},
  };
  for (const Case& c : cases) {
    INFO(c.body);
    const ConfigError e = refusal([&] { (void)app::load_study(study(c.body)); });
    INFO(e.what());
    CHECK(e.file == (dir.path / "study.toml").string());
    CHECK(e.key == c.key);
    CHECK(contains(e.reason, c.reason));
  }
  // every numeric key of the study file has its row in the study's key-domain table
  for (const char* key : {"seeds", "fit_from", "limits.max_runs", "limits.max_memory_gib"}) {
    INFO(key);
    CHECK(core::find_key_domain(compare::study_key_domains(), key) != nullptr);
  }
  // in range: read as given
  const compare::StudySpec ok = app::load_study(
      study("study = \"nested/name\"\n" + head + "seeds = 2147483647\n[limits]\nmax_runs = 7\nmax_memory_gib = 2\n"));
  CHECK(ok.seeds == 2147483647);
  CHECK(ok.name == "nested/name");
  CHECK(ok.limits.max_runs == 7.0);
  CHECK(ok.limits.max_memory_gib == 2.0);
  CHECK(ok.share_references);  // the default
  CHECK(!app::load_study(study("study = \"s\"\n" + head + "share_references = false\n")).share_references);
  CHECK(!app::load_study(study("study = \"s\"\n" + head + "share_continuum = false\n")).share_references);
  CHECK(compare::count_runs(ok) == 2147483647.0);  // counted, not expanded
}

TEST_CASE("inputs: repeated vary values are one point, with a note, and the rest keep their order", "[inputs][study]") {
  const TempDir dir("inputs-vary");
  const fs::path f = dir.path / "study.toml";
  testing::write_text(f, R"(study = "dup"
kind = "friction_law"
scene = "tiny.toml"
seeds = 3
[vary]
"discrete.contacts_per_site" = [100, 1000, 100, 1e2, 100.0, 10000]
"interface.alpha" = [1.05, 1.1, 1.05]
[[group]]
vary = { "bulk.mu" = [300, 300] }
[[group]]
vary = { "discrete.seed" = [9007199254740993, 9007199254740992] }
)");
  const compare::StudySpec s = app::load_study(f);
  REQUIRE(s.groups.size() == 3);
  const auto& n = s.groups[0].vary[0];
  CHECK(n.first == "discrete.contacts_per_site");
  CHECK(n.second == std::vector<std::string>{"100", "1000", "10000"});
  CHECK(s.groups[0].vary[1].second == std::vector<std::string>{"1.05", "1.1"});
  CHECK(s.groups[1].vary[0].second == std::vector<std::string>{"300"});
  CHECK(s.groups[2].vary[0].second.size() == 2);  // integers beyond 2^53 compared exactly, not as doubles
  REQUIRE(s.notes.size() == 5);
  CHECK(s.notes[0] == f.string() + ": vary.discrete.contacts_per_site: the value 100 is repeated: it is run once (a "
                                   "repeated value is one point, not extra seeds)");
  CHECK(contains(s.notes[1], "the value 100.0 (the same point as 100) is repeated"));
  CHECK(contains(s.notes[3], "vary.interface.alpha: the value 1.05 is repeated"));
  CHECK(contains(s.notes[4], "group[0].vary.bulk.mu: the value 300 is repeated"));
  // (3 N x 2 alpha + 1 + 2) points x 3 seeds: the repeats are not counted as extra seeds
  CHECK(compare::count_runs(s) == 27.0);
  CHECK(compare::expand(s).size() == 27);
  // the notes reach the analysis (study.h5 /study notes)
  const studies::StudyReport r = studies::analyse_study(s, {}, {}, {});
  CHECK(r.notes == s.notes);
}

TEST_CASE("inputs: each study kind states the models its analysis needs", "[inputs][study]") {
  compare::Scene all, continuum, discrete;
  all.models = {"continuum", "mean_field", "discrete"};
  continuum.models = {"continuum"};
  discrete.models = {"discrete"};
  // the models a kind needs that a scene listing only `listed` lacks, in the order continuum, mean_field, discrete
  const auto lacking = [](const studies::ModelsNeeded& n, const std::string& listed) {
    std::string m;
    for (const auto& [needed, name] : {std::pair{n.continuum, "continuum"}, std::pair{n.mean_field, "mean_field"},
                                       std::pair{n.discrete, "discrete"}})
      if (needed && listed != name) {
        if (!m.empty()) m += " and ";
        m += name;
      }
    return m;
  };
  for (const studies::StudyKind& k : studies::study_kinds()) {
    INFO(k.name);
    CHECK(studies::missing_models(k, all).empty());  // the three models feed every analysis
    CHECK(studies::missing_models(k, continuum) == lacking(k.needs, "continuum"));
    CHECK(studies::missing_models(k, discrete) == lacking(k.needs, "discrete"));
  }
  // disorder_limit compares mean_field with the continuum (and the discrete model with mean_field where it runs)
  CHECK(studies::missing_models(*studies::find_study_kind("disorder_limit"), continuum) == "mean_field");
  CHECK(studies::missing_models(*studies::find_study_kind("disorder_limit"), discrete) == "continuum and mean_field");
  const auto needs = [](std::string_view name) { return studies::find_study_kind(name)->needs; };
  for (const char* comparison : {"friction_law", "threshold_width", "transient_friction", "front_speeds",
                                 "validity_friction", "validity_fig1"}) {
    INFO(comparison);
    CHECK((needs(comparison).continuum && needs(comparison).discrete));
  }
  CHECK(studies::describe(needs("transient_friction")) == "the continuum and the discrete model");
  CHECK(studies::describe(needs("fig2")) == "the continuum model");
  CHECK(studies::describe(needs("runs")) == "any model");
  CHECK(studies::describe(needs("steady_fronts")) == "any model");
  CHECK(studies::describe(needs("disorder_limit")) == "the continuum and the mean_field model");
}
