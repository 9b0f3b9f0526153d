// Checkpoints and run outputs against a hostile disk and user (issue 18, "trust nothing read back"):
// every reproducer of the issue refused with the file or key and the reason — corrupted bytes (a
// campaign of single-byte flips over header and state), another build's commit, an edited
// configuration, size fields beyond the file, non-regular files, format 1 — before anything of a
// stored size is allocated; the checkpoint cadence in the estimate and [limits]; a checkpoint that
// cannot be written failing the run; stale checkpoint temporaries removed; one run per output
// directory. Restarts of untouched checkpoints stay bit for bit (tests/test_checkpoint.cpp).
#include <catch2/catch.hpp>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "apps/build_info.hpp"
#include "apps/checkpoint.hpp"
#include "apps/cli.hpp"
#include "apps/config.hpp"
#include "compare/alongside.hpp"
#include "compare/estimate.hpp"
#include "core/archive.hpp"
#include "core/checksum.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"
#include "study_fixtures.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using testing::TempDir;

namespace {

using slipfront::testing::contains;

// A small scene (11 nodes, 349 steps, continuum) and a checkpoint of it at t ~ 1, as `run` writes it.
struct Small {
  TempDir dir{"ckh"};
  fs::path config = dir.path / "tiny.toml";
  std::string resolved;
  double t = 0.0;
  std::string state;
  fs::path good = dir.path / "good.bin";
  std::string bytes;  ///< of `good`
  Small() {
    testing::write_text(config, testing::minimal_config());
    const compare::Scene scene = app::load_scene(config, {});
    resolved = app::to_toml(scene);
    compare::RunControl ctl;
    ctl.checkpoint_every = 0.5;
    std::vector<std::pair<double, std::string>> saved;
    ctl.checkpoint = [&](const std::string& s, double at) { saved.emplace_back(at, s); };
    compare::run_scene_alongside(scene, ctl);
    REQUIRE(saved.size() >= 3);
    t = saved[1].first;
    state = saved[1].second;
    app::write_checkpoint(good, resolved, t, state);
    bytes = testing::slurp(good);
  }
};

struct Outcome {
  int code = 0;
  std::string err;
};

// `slipfront run tiny.toml --out DIR/<out> --force --quiet --restart FILE [--set ...]`, in this process.
Outcome restart(const Small& s, const fs::path& file, const std::string& out, const std::vector<std::string>& set = {}) {
  app::RunOptions o;
  o.config = s.config;
  o.overrides = set;
  o.out = s.dir.path / out;
  o.force = true;
  o.quiet = true;
  o.restart = file;
  o.command_line = "test";
  std::ostringstream sout, serr;
  Outcome r;
  r.code = app::run_command(o, sout, serr);
  r.err = serr.str();
  return r;
}

// The bytes after the checksum line resealed with their checksum (a file edited by someone who also
// recomputed the checksum: what is behind the checksum must stand on its own).
std::string reseal(std::string bytes) {
  const std::size_t first = bytes.find('\n'), second = bytes.find('\n', first + 1);
  const std::string prefix = "checksum xxh3-64 ";
  bytes.replace(first + 1 + prefix.size(), 16, core::content_hash_hex(std::string_view(bytes).substr(second + 1)));
  return bytes;
}

// A format-2 file from its fields (sizes as text, so that they can lie), sealed.
std::string checkpoint_file(const std::string& commit, const std::string& time, const std::string& toml_size,
                            const std::string& toml, const std::string& state_size, const std::string& state) {
  return reseal("slipfront-checkpoint 3\nchecksum xxh3-64 0000000000000000\ncommit " + commit + "\ntime " + time +
                "\ntoml " + toml_size + "\n" + toml + "\nstate " + state_size + "\n" + state);
}

std::string replace_once(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  REQUIRE(at != std::string::npos);
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("checkpoint hostile: every reproducer of the issue is refused with the file and the reason, before work",
          "[checkpoint][hostile]") {
  const Small s;
  const std::string commit = app::build_info::git_commit;
  const std::string n = std::to_string(s.resolved.size()), m = std::to_string(s.state.size());
  std::string flipped = s.bytes;
  flipped[flipped.size() - s.state.size() / 2] ^= 0x10;
  core::Archive huge = core::Archive::writer();
  huge.tag("sequential");
  std::uint64_t models = std::uint64_t{1} << 60;
  huge(models);
  struct Case {
    const char* what;
    std::string bytes;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"a byte of the state flipped", flipped, "checksum mismatch: the file is corrupted"},
      {"the configuration edited (kappa 8 -> 9), checksum as it was", replace_once(s.bytes, "kappa = 8.0", "kappa = 9.0"),
       "checksum mismatch: the file is corrupted"},
      {"the configuration edited and resealed", reseal(replace_once(s.bytes, "kappa = 8.0", "kappa = 9.0")),
       "the checkpoint belongs to another configuration: interface.kappa: the checkpoint has 9.0, this run 8.0"},
      {"a key of the configuration removed and resealed", reseal(replace_once(replace_once(s.bytes, "eta = 0.1\n", ""),
                                                                              "toml " + n, "toml " + std::to_string(s.resolved.size() - 10))),
       "interface.eta: the checkpoint has none (the key is not used), this run 0.1"},
      {"another build's commit", reseal(replace_once(s.bytes, "commit " + commit, "commit 0123abc")),
       "written by slipfront 0123abc, this is slipfront " + commit +
           ": a checkpoint is read back only by the build that wrote it"},
      {"toml 9999999999", checkpoint_file(commit, "1", "9999999999", s.resolved, m, s.state),
       "toml size 9999999999 exceeds the"},
      {"toml size one too large", checkpoint_file(commit, "1", std::to_string(s.resolved.size() + 1), s.resolved, m, s.state),
       "no line end after the configuration"},
      {"state -1", checkpoint_file(commit, "1", n, s.resolved, "-1", s.state), "state size '-1' is not a byte count"},
      {"state 18446744073709551616 (2^64)", checkpoint_file(commit, "1", n, s.resolved, "18446744073709551616", s.state),
       "state size '18446744073709551616' is not a byte count"},
      {"state size beyond the file", checkpoint_file(commit, "1", n, s.resolved, std::to_string(s.state.size() + 1), s.state),
       "state size " + std::to_string(s.state.size() + 1) + " exceeds the " + m + " bytes left"},
      {"bytes after the state", checkpoint_file(commit, "1", n, s.resolved, std::to_string(s.state.size() - 3), s.state),
       "3 bytes after the state"},
      {"time nan", checkpoint_file(commit, "nan", n, s.resolved, m, s.state), "time 'nan' is not a finite number"},
      {"truncated to half", s.bytes.substr(0, s.bytes.size() / 2), "checksum mismatch: the file is corrupted"},
      {"the checksum line malformed", replace_once(s.bytes, "checksum xxh3-64 ", "checksum crc-64 "), "no checksum line"},
      {"format 1 (written by the previous commits)",
       "slipfront-checkpoint 1\ncommit fe0f37b\ntime 1\ntoml " + n + "\n" + s.resolved + "\nstate " + m + "\n" + s.state,
       "checkpoint format 1 (written by slipfront fe0f37b) has no checksum, so it cannot be verified; rerun the run from "
       "the start"},
      {"format 2 (written before the slip-event sequence)",
       replace_once(s.bytes, "slipfront-checkpoint 3", "slipfront-checkpoint 2"),
       "checkpoint format 2 (before the slip-event sequence was part of a model's results) is not one this slipfront "
       "reads (format 3)"},
      {"format 4", replace_once(s.bytes, "slipfront-checkpoint 3", "slipfront-checkpoint 4"),
       "checkpoint format '4' is not one this slipfront reads (format 3)"},
      {"an empty file", "", "no slipfront-checkpoint line"},
      {"a configuration file", testing::minimal_config(), "not a slipfront checkpoint (wrong first line)"},
      {"the state's archive claiming 2^60 finished models",
       checkpoint_file(commit, "1", n, s.resolved, std::to_string(huge.data().size()), huge.data()),
       "the checkpoint's state does not fit this run (checkpoint: vector size 1152921504606846976 exceeds the 0 bytes left)"},
  };
  int k = 0;
  for (const auto& c : cases) {
    INFO(c.what);
    const fs::path file = s.dir.path / ("case" + std::to_string(k++) + ".bin");
    testing::write_text(file, c.bytes);
    const Outcome r = restart(s, file, "out");
    INFO(r.err);
    CHECK(r.code == app::exit_code::usage);
    CHECK(contains(r.err, "slipfront: error: " + file.string() + ": "));
    CHECK(contains(r.err, c.reason));
    CHECK_FALSE(fs::exists(s.dir.path / "out" / "results.h5"));  // nothing ran
  }
  // the untouched checkpoint continues, to the uninterrupted run's results (bit for bit: test_checkpoint.cpp)
  const Outcome ok = restart(s, s.good, "out");
  INFO(ok.err);
  CHECK(ok.code == app::exit_code::ok);
  CHECK(fs::exists(s.dir.path / "out" / "results.h5"));
  CHECK_FALSE(fs::exists(s.dir.path / "out" / ".slipfront.lock"));  // released with the results in place
}

TEST_CASE("checkpoint hostile: non-regular and oversized files are refused before reading", "[checkpoint][hostile]") {
  const Small s;
  const fs::path fifo = s.dir.path / "fifo", sparse = s.dir.path / "sparse.bin";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);  // reading it would block forever
  testing::write_text(sparse, "");
  fs::resize_file(sparse, std::uintmax_t{2} << 30);  // 2 GiB, sparse: nothing on disk
  struct Case {
    fs::path file;
    std::vector<std::string> set;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"/dev/zero", {}, "it is a character device, not a regular file"},
      {fifo, {}, "it is a FIFO (named pipe), not a regular file"},
      {s.dir.path, {}, "it is a directory, not a regular file"},
      {sparse, {"limits.max_memory_gib=1"}, "it has 2147483648 bytes, more than the 1073741824 a checkpoint of this run may have"},
      {s.dir.path / "missing.bin", {}, "cannot open the file: No such file or directory"},
  };
  for (const auto& c : cases) {
    INFO(c.file);
    const auto t0 = std::chrono::steady_clock::now();
    const Outcome r = restart(s, c.file, "out", c.set);
    INFO(r.err);
    CHECK(r.code == app::exit_code::usage);
    CHECK(contains(r.err, c.file.string() + ": "));
    CHECK(contains(r.err, c.reason));
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 2.0);
  }
  // the program, its address space capped at 1 GiB: the size fields and /dev/zero allocate nothing of
  // their size (the issue: ~10 GB for `toml 9999999999`, 8.4 GB read from /dev/zero)
  const std::string bad = checkpoint_file(app::build_info::git_commit, "1", "9999999999", s.resolved,
                                          std::to_string(s.state.size()), s.state);
  testing::write_text(s.dir.path / "bad.bin", bad);
  for (const std::string file : {"bad.bin", "/dev/zero"}) {
    const auto r = testing::run_in_shell(s.dir.path, SLIPFRONT_BINARY,
                                         "run tiny.toml --out capped --quiet --restart " + file, "ulimit -v 1048576;");
    INFO(r.err);
    CHECK_FALSE(r.signalled);
    CHECK(r.code == 2);
    CHECK(contains(r.err, file + ": not a usable checkpoint: "));
  }
}

TEST_CASE("checkpoint hostile: single-byte flips anywhere in a checkpoint are all refused", "[checkpoint][hostile]") {
  // 100 positions spread over the header (magic, checksum, commit, time, sizes, configuration) and 150
  // over the state; each byte changed in one bit (cycling through the 8), or inverted every 7th.
  const Small s;
  const std::size_t header = s.bytes.size() - s.state.size();
  std::vector<std::size_t> positions;
  for (std::size_t k = 0; k < 100; ++k) positions.push_back(k * header / 100);
  for (std::size_t k = 0; k < 150; ++k) positions.push_back(header + k * s.state.size() / 150);
  positions.push_back(s.bytes.size() - 1);
  std::map<std::string, int> reasons;
  int refused = 0, restarted = 0;
  for (std::size_t k = 0; k < positions.size(); ++k) {
    std::string bytes = s.bytes;
    bytes[positions[k]] = static_cast<char>(bytes[positions[k]] ^ (k % 7 == 6 ? 0xff : 1 << (k % 8)));
    const fs::path file = s.dir.path / "flipped.bin";
    testing::write_text(file, bytes);
    const Outcome r = restart(s, file, "out");
    INFO("byte " << positions[k] << " of " << s.bytes.size() << ": " << r.err);
    const bool refused_here = r.code == app::exit_code::usage && contains(r.err, file.string() + ": not a usable checkpoint: ");
    CHECK(refused_here);
    if (!refused_here) {
      ++restarted;
      continue;
    }
    ++refused;
    const std::string why = r.err.substr(r.err.find("not a usable checkpoint: ") + 25);
    reasons[why.substr(0, why.find_first_of("(:'\n"))]++;
  }
  std::cout << "checkpoint flip campaign: " << positions.size() << " single-byte flips (" << 100 << " in the "
            << header << "-byte header, " << positions.size() - 100 << " in the " << s.state.size()
            << "-byte state): " << refused << " refused, " << restarted << " restarted\n";
  for (const auto& [why, count] : reasons) std::cout << "  " << count << " x " << why << "\n";
  CHECK(positions.size() >= 200);
  CHECK(refused == static_cast<int>(positions.size()));
  CHECK(restarted == 0);
}

TEST_CASE("checkpoint hostile: the checkpoint cadence is in the estimate, refused through [limits] before work",
          "[checkpoint][hostile][estimate]") {
  // fig1 (both models): the issue's --checkpoint-every 1e-300, a checkpoint every one of 97107 steps
  const TempDir dir("ckh-cadence");
  const std::string cfg = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1.toml";
  const auto r = testing::run_in_shell(dir.path, SLIPFRONT_BINARY, "run " + cfg + " --out out --checkpoint-every 1e-300");
  INFO(r.err);
  CHECK(r.code == 2);
  CHECK(contains(r.err, "fig1.toml: --checkpoint-every: every 1e-300: 97107 checkpoints of up to "));
  CHECK(contains(r.err, "(one every step)"));
  CHECK(contains(r.err, "more than limits.max_checkpoint_gib = 100; checkpoint less often (T >= "));
  CHECK_FALSE(fs::exists(dir.path / "out"));  // nothing created
  // time and memory: the same cadence within the data limit, refused by limits.max_hours; a small
  // memory limit, by limits.max_memory_gib
  const auto hours = testing::run_in_shell(dir.path, SLIPFRONT_BINARY,
                                           "run " + cfg + " --out out --checkpoint-every 1e-300 "
                                           "--set limits.max_checkpoint_gib=1e6 --set limits.max_hours=0.1");
  CHECK(hours.code == 2);
  CHECK(contains(hours.err, "on top of the run's"));
  CHECK(contains(hours.err, "more than limits.max_hours = 0.1"));
  const auto memory = testing::run_in_shell(dir.path, SLIPFRONT_BINARY,
                                            "run " + cfg + " --out out --checkpoint-every 10 --set limits.max_memory_gib=0.07");
  CHECK(memory.code == 2);
  CHECK(contains(memory.err, "while one is written (two copies of it on top of the run's"));
  CHECK_FALSE(fs::exists(dir.path / "out"));

  // the estimate against the checkpoints a run writes (fig1 on L = 120 to t = 60, both models in
  // lockstep, count law): the number exactly, the largest and the total within 25%
  compare::Scene scene = testing::fig1_scene();
  scene.models = {"continuum", "discrete"};
  scene.bulk.length = 120.0;
  scene.time.t_end = 60.0;
  scene.validate();
  compare::RunControl ctl;
  ctl.checkpoint_every = 5.0;
  std::vector<double> sizes;
  ctl.checkpoint = [&](const std::string& state, double) { sizes.push_back(static_cast<double>(state.size())); };
  compare::run_scene_alongside(scene, ctl);
  const compare::Estimate e = compare::estimate(scene);
  const compare::CheckpointEstimate c = compare::estimate_checkpoints(scene, e, 5.0);
  double total = 0.0;
  for (const double b : sizes) total += b;
  INFO("checkpoints " << sizes.size() << ", largest " << sizes.back() << " B (estimated " << c.largest_bytes << "), total "
                      << total << " B (estimated " << c.bytes << ")");
  CHECK(c.writes == static_cast<double>(sizes.size()));
  CHECK(c.largest_bytes == Approx(sizes.back()).epsilon(0.25));
  CHECK(c.bytes == Approx(total).epsilon(0.25));
  CHECK(compare::describe(c).rfind("checkpoints (--checkpoint-every 5): 12 of up to ", 0) == 0);
}

TEST_CASE("checkpoint hostile: a checkpoint that cannot be written fails the run (exit 1), its results written",
          "[checkpoint][hostile][cli]") {
  const TempDir dir("ckh-fail");
  testing::write_text(dir.path / "tiny.toml", testing::minimal_config());
  fs::create_directories(dir.path / "out" / "checkpoint.bin" / "in the way");  // a directory: the rename fails
  const auto r = testing::run_in_shell(dir.path, SLIPFRONT_BINARY, "run tiny.toml --out out --quiet --checkpoint-every 0.5");
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK(contains(r.err, "slipfront: error: a checkpoint could not be written: cannot write out/checkpoint.bin: "));
  REQUIRE(fs::exists(dir.path / "out" / "results.h5"));
  const auto h5 = testing::read_h5(dir.path / "out" / "results.h5");
  CHECK(h5.strings.at("/meta@status") == "complete");  // the results themselves are whole
  CHECK(contains(h5.strings.at("/meta@message"), "a checkpoint could not be written"));
  for (const auto& e : fs::directory_iterator(dir.path / "out"))  // no temporary left
    CHECK(e.path().filename().string().rfind(".checkpoint.bin.tmp.", 0) != 0);
}

TEST_CASE("checkpoint hostile: stale checkpoint temporaries of dead processes are removed, live ones kept",
          "[checkpoint][hostile][cli]") {
  const TempDir dir("ckh-stale");
  testing::write_text(dir.path / "tiny.toml", testing::minimal_config());
  fs::create_directories(dir.path / "out");
  const pid_t child = ::fork();  // a pid that is surely dead: a child that has exited and been reaped
  if (child == 0) ::_exit(0);
  REQUIRE(child > 0);
  int status = 0;
  ::waitpid(child, &status, 0);
  const fs::path dead = dir.path / "out" / (".checkpoint.bin.tmp." + std::to_string(child));
  const fs::path alive = dir.path / "out" / (".checkpoint.bin.tmp." + std::to_string(::getpid()));
  for (const auto& p : {dead, alive}) testing::write_text(p, std::string(4096, 'x'));
  const auto r = testing::run_in_shell(dir.path, SLIPFRONT_BINARY, "run tiny.toml --out out --quiet");
  CHECK(r.code == 0);
  CHECK_FALSE(fs::exists(dead));
  CHECK(fs::exists(alive));
}

TEST_CASE("checkpoint hostile: two runs into one --out: the second is refused while the first holds it",
          "[checkpoint][hostile][cli]") {
  // The first run (fig1, both models) is stopped (SIGSTOP) once it holds the directory, so that the
  // second surely starts while it does; continued, it completes and releases the directory.
  const TempDir dir("ckh-lock");
  const std::string cfg = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1.toml";
  const fs::path lock = dir.path / "out" / ".slipfront.lock";
  const testing::Child first = testing::spawn({SLIPFRONT_BINARY, "run", cfg, "--out", "out", "--quiet"}, dir.path,
                                              dir.path / "first.out", dir.path / "first.err");
  const std::string pid = std::to_string(first.pid);
  for (int k = 0; k < 5000 && testing::slurp(lock) != pid + "\n"; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ::kill(first.pid, SIGSTOP);
  REQUIRE(testing::slurp(lock) == pid + "\n");
  const auto second = testing::run_in_shell(dir.path, SLIPFRONT_BINARY, "run " + cfg + " --out out --quiet --force");
  ::kill(first.pid, SIGCONT);
  INFO(second.err);
  CHECK(second.code == 2);
  CHECK(contains(second.err, "slipfront: error: the output directory 'out' is in use by another slipfront run (pid " + pid +
                                 ", holding out/.slipfront.lock); wait for it to end, or choose another --out"));
  CHECK(testing::wait_for(first, 120.0) == 0);
  CHECK(fs::exists(dir.path / "out" / "results.h5"));
  CHECK_FALSE(fs::exists(lock));
  // the directory free again: a third run takes it (and a lock file left by a killed run does not stop it)
  testing::write_text(lock, "999999999\n");
  const auto third = testing::run_in_shell(dir.path, SLIPFRONT_BINARY, "run " + cfg + " --out out --quiet --force");
  INFO(third.err);
  CHECK(third.code == 0);
  CHECK_FALSE(fs::exists(lock));
}

namespace {
// The first of two invocations into `out` (args, from dir) stopped (SIGSTOP) once it holds the directory, the second
// run while it does, then the first continued to its end. The first must hold DIR/.slipfront.lock (its pid in it)
// within 20 s, or the test fails.
struct TwoWriters {
  testing::ShellResult second;
  int first_code = -1;
  std::string first_pid;
};
TwoWriters second_while_first_holds(const fs::path& dir, const std::vector<std::string>& first_args,
                                    const std::string& second_args) {
  const fs::path lock = dir / "out" / ".slipfront.lock";
  const testing::Child first = testing::spawn(first_args, dir, dir / "first.out", dir / "first.err");
  const std::string pid = std::to_string(first.pid);
  for (int k = 0; k < 20000 && testing::slurp(lock) != pid + "\n"; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ::kill(first.pid, SIGSTOP);
  const bool held = testing::slurp(lock) == pid + "\n";
  const auto second = testing::run_in_shell(dir, SLIPFRONT_BINARY, second_args);
  ::kill(first.pid, SIGCONT);
  const int code = testing::wait_for(first, 300.0);
  INFO(testing::slurp(dir / "first.err"));
  REQUIRE(held);
  return {second, code, pid};
}

std::string in_use(const std::string& pid) {
  return "slipfront: error: the output directory 'out' is in use by another slipfront run (pid " + pid +
         ", holding out/.slipfront.lock); wait for it to end, or choose another --out";
}
}  // namespace

TEST_CASE("checkpoint hostile: two studies into one --out: the second is refused while the first holds it (issue 36)",
          "[checkpoint][hostile][cli][study]") {
  // Was: both ended `complete`, exit 0; one study lost, the surviving study.h5 describing run files that held the
  // other study's parameters. Now the second is refused before any work and the first completes intact.
  const TempDir dir("ckh-study-lock");
  const fs::path study = testing::write_sweep_study(dir.path);
  const TwoWriters w = second_while_first_holds(
      dir.path, {SLIPFRONT_BINARY, "study", study.string(), "--out", "out", "-q", "-j", "1"},
      "study " + study.string() + " --out out -q -j 1 --set time.steps=600");
  INFO(w.second.err);
  CHECK(w.second.code == 2);
  CHECK(contains(w.second.err, in_use(w.first_pid)));
  CHECK(w.first_code == 0);
  // the first study's files, whole: every run made with its configuration (steps = 500), none with the second's
  const auto files = testing::run_files(dir.path / "out");
  CHECK(files.size() == 6);
  for (const auto& f : files) {
    const std::string toml = testing::read_h5(f).strings.at("/config@toml");
    CHECK(contains(toml, "steps = 500"));
    CHECK_FALSE(contains(toml, "steps = 600"));
  }
  CHECK(testing::read_h5(dir.path / "out" / "study.h5").strings.at("/meta@status") == "complete");
  CHECK_FALSE(fs::exists(dir.path / "out" / ".slipfront.lock"));
}

TEST_CASE("checkpoint hostile: two fronts into one --out: the second is refused while the first holds it (issue 36)",
          "[checkpoint][hostile][cli][fronts]") {
  // Was: one fronts.h5 silently lost. Now the second is refused, naming the directory and the holder.
  const TempDir dir("ckh-fronts-lock");
  const std::string cfg = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/homogeneous_front.toml";
  const TwoWriters w = second_while_first_holds(dir.path, {SLIPFRONT_BINARY, "fronts", cfg, "--out", "out"},
                                                "fronts " + cfg + " --out out --force --set drive.sigma_d=0.45");
  INFO(w.second.err);
  CHECK(w.second.code == 2);
  CHECK(contains(w.second.err, in_use(w.first_pid)));
  CHECK(w.first_code == 0);
  const auto h5 = testing::read_h5(dir.path / "out" / "fronts.h5");
  CHECK(h5.strings.at("/meta@status") == "complete");
  CHECK(contains(h5.strings.at("/config@toml"), "sigma_d = 0.5"));
  CHECK_FALSE(fs::exists(dir.path / "out" / ".slipfront.lock"));
}
