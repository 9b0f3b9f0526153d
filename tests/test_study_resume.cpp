// Resumable studies (issue 13 item 3, issue 10): a study killed midway and rerun with the same
// command skips the runs already complete (same config hash and resolved TOML), redoes the others,
// and ends with the study.h5 of an uninterrupted study; run files made for another configuration are
// refused without --force. Runs the real program, as a user would.
#include <catch2/catch.hpp>
#include <hdf5.h>
#include <sys/stat.h>

#include <chrono>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "apps/study.hpp"
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

// modification time (ns) and inode of a file: a file rewritten (even with the same bytes) changes both
std::pair<long long, long long> stamp(const fs::path& p) {
  struct stat st {};
  REQUIRE(::stat(p.c_str(), &st) == 0);
  return {static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec,
          static_cast<long long>(st.st_ino)};
}

// "runs: 3 run now, 5 skipped" -> {3, 5}
std::pair<int, int> run_counts(const std::string& out) {
  std::smatch m;
  REQUIRE(std::regex_search(out, m, std::regex(R"(runs: (\d+) run now, (\d+) skipped)")));
  return {std::stoi(m[1]), std::stoi(m[2])};
}

std::string meta_string(const fs::path& file, const std::string& key) { return read_h5(file).strings.at("/meta@" + key); }

}  // namespace

TEST_CASE("resume: a study killed with SIGKILL midway, rerun, skips the complete runs and gives the study.h5 of an "
          "uninterrupted one",
          "[study][resume]") {
  const TempDir dir("resume-kill");
  const fs::path study = write_front_study(dir.path);

  // the reference: uninterrupted
  const Output ref = run({bin, "study", study.string(), "--out", "ref", "-j", "2", "-q"}, dir.path);
  INFO(ref.err);
  REQUIRE(ref.code == 0);
  CHECK(run_counts(ref.out) == std::pair{6, 0});

  // killed (SIGKILL: nothing is cleaned up) once two run files are complete
  const Child c = spawn({bin, "study", study.string(), "--out", "killed", "-j", "2", "-q"}, dir.path, dir.path / "o.txt",
                        dir.path / "e.txt");
  std::vector<fs::path> complete;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < give_up) {
    int n = 0;
    if (fs::exists(dir.path / "killed" / "runs"))
      for (const auto& f : run_files(dir.path / "killed")) n += run_status(f) == "complete";
    if (n >= 2) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  REQUIRE(::kill(c.pid, SIGKILL) == 0);
  CHECK(wait_for(c, 10) == 128 + SIGKILL);
  std::vector<std::pair<long long, long long>> stamps;
  for (const auto& f : run_files(dir.path / "killed"))
    if (run_status(f) == "complete") {
      complete.push_back(f);
      stamps.push_back(stamp(f));
    }
  INFO("complete when killed: " << complete.size());
  REQUIRE(complete.size() >= 2);
  REQUIRE(complete.size() < 6);  // killed midway, not after the end
  CHECK_FALSE(fs::exists(dir.path / "killed" / "study.h5"));

  // the same command again
  const Output again = run({bin, "study", study.string(), "--out", "killed", "-j", "2"}, dir.path);
  INFO(again.err);
  REQUIRE(again.code == 0);
  const auto [ran, skipped] = run_counts(again.out);
  CHECK(skipped == static_cast<int>(complete.size()));
  CHECK(ran == 6 - skipped);
  CHECK(again.err.find(std::to_string(complete.size()) + " complete already (skipped)") != std::string::npos);
  for (std::size_t k = 0; k < complete.size(); ++k) {
    INFO(complete[k].string());
    CHECK(stamp(complete[k]) == stamps[k]);  // not rewritten
  }
  const H5Content s = read_h5(dir.path / "killed" / "study.h5");
  CHECK(s.numbers.at("/study/runs@skipped") == static_cast<double>(complete.size()));
  CHECK(s.numbers.at("/study/runs@computed") == static_cast<double>(6 - complete.size()));
  for (const auto& f : run_files(dir.path / "killed")) {
    INFO(f.string());
    CHECK(run_status(f) == "complete");
    for (const auto& e : fs::directory_iterator(f.parent_path())) CHECK(e.path().filename() == "results.h5");
  }

  // the same analysis, and the same runs bit for bit
  const auto d = study_differences(dir.path / "ref" / "study.h5", dir.path / "killed" / "study.h5");
  for (const auto& x : d) UNSCOPED_INFO(x);
  CHECK(d.empty());
  const auto ref_files = run_files(dir.path / "ref"), files = run_files(dir.path / "killed");
  REQUIRE(ref_files.size() == files.size());
  for (std::size_t k = 0; k < files.size(); ++k) {
    const auto dk = run_file_differences(ref_files[k], files[k]);
    INFO(files[k].string() << (dk.empty() ? "" : ": " + dk.front()));
    CHECK(dk.empty());
  }
}

TEST_CASE("resume: partial runs are redone, other configurations refused without --force, --force reruns all",
          "[study][resume]") {
  const TempDir dir("resume-rules");
  const fs::path study = write_sweep_study(dir.path);
  const std::vector<std::string> cmd = {bin, "study", study.string(), "--out", "s", "-j", "2"};
  const Output first = run(cmd, dir.path);
  INFO(first.err);
  REQUIRE(first.code == 0);
  CHECK(run_counts(first.out) == std::pair{6, 0});
  const auto files = run_files(dir.path / "s");
  REQUIRE(files.size() == 6);
  std::vector<std::pair<long long, long long>> stamps;
  for (const auto& f : files) stamps.push_back(stamp(f));
  fs::copy_file(dir.path / "s" / "study.h5", dir.path / "first.h5");

  // run 0002 partial: rewritten with status interrupted and the same configuration
  {
    const auto spec = app::load_study(study);
    const auto runs = compare::expand(spec);
    const compare::Scene scene = app::load_scene(spec.scene_file, runs[2].overrides);
    app::RunMeta meta;
    meta.status = compare::RunStatus::interrupted;
    app::write_results(files[2], scene, app::to_toml(scene), {}, meta);
    CHECK(run_status(files[2]) == "interrupted");
    stamps[2] = stamp(files[2]);
  }
  // run 0005 without /meta config_hash (as written before it existed): cannot be verified, made again
  {
    const hid_t f = H5Fopen(files[5].c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    REQUIRE(f >= 0);
    CHECK(H5Adelete_by_name(f, "/meta", "config_hash", H5P_DEFAULT) >= 0);
    H5Fclose(f);
    stamps[5] = stamp(files[5]);
  }
  // a temporary left by a killed writer, and run 0004 missing
  std::ofstream(files[0].parent_path() / ".results.h5.tmp.999999") << "half a file";
  fs::remove(files[4]);
  const Output resumed = run(cmd, dir.path);
  INFO(resumed.err);
  REQUIRE(resumed.code == 0);
  CHECK(run_counts(resumed.out) == std::pair{3, 3});
  CHECK(resumed.err.find("3 complete already (skipped), 3 to run (2 partial, failed or unverified, 1 new)") !=
        std::string::npos);
  for (std::size_t k : {0u, 1u, 3u}) CHECK(stamp(files[k]) == stamps[k]);
  CHECK(stamp(files[2]) != stamps[2]);
  CHECK(stamp(files[5]) != stamps[5]);
  CHECK(meta_string(files[5], "config_hash").rfind("crc64-xz:", 0) == 0);
  CHECK(run_status(files[2]) == "complete");
  CHECK(run_status(files[4]) == "complete");
  CHECK_FALSE(fs::exists(files[0].parent_path() / ".results.h5.tmp.999999"));
  CHECK(study_differences(dir.path / "first.h5", dir.path / "s" / "study.h5").empty());

  // another configuration (here through --set): refused, nothing touched
  for (std::size_t k = 0; k < files.size(); ++k) stamps[k] = stamp(files[k]);
  const auto study_stamp = stamp(dir.path / "s" / "study.h5");
  std::vector<std::string> changed = cmd;
  changed.insert(changed.end(), {"--set", "time.steps=600"});
  const Output refused = run(changed, dir.path);
  CHECK(refused.code == 2);
  CHECK(refused.err.find("6 of 6 run files") != std::string::npos);
  CHECK(refused.err.find("another configuration") != std::string::npos);
  CHECK(refused.err.find("runs/0000/results.h5: line") != std::string::npos);
  CHECK(refused.err.find("`steps = 500` in the file, `steps = 600` now") != std::string::npos);
  CHECK(refused.err.find("--force") != std::string::npos);
  for (std::size_t k = 0; k < files.size(); ++k) CHECK(stamp(files[k]) == stamps[k]);
  CHECK(stamp(dir.path / "s" / "study.h5") == study_stamp);

  // --force: everything again, with the new configuration
  changed.push_back("--force");
  const Output forced = run(changed, dir.path);
  INFO(forced.err);
  REQUIRE(forced.code == 0);
  CHECK(run_counts(forced.out) == std::pair{6, 0});
  for (std::size_t k = 0; k < files.size(); ++k) CHECK(stamp(files[k]) != stamps[k]);
  CHECK(read_h5(files[0]).strings.at("/config@toml").find("steps = 600") != std::string::npos);
  CHECK(meta_string(files[0], "config_hash") ==
        app::config_hash(read_h5(files[0]).strings.at("/config@toml")));

  // a study.h5 of another study in the directory is not replaced without --force
  const fs::path other = dir.path / "other.toml";
  std::string text = slurp(study);
  text.replace(text.find("\"sweeps\""), 8, "\"others\"");
  std::ofstream(other) << text;
  const Output clash = run({bin, "study", other.string(), "--out", "s", "-q"}, dir.path);
  CHECK(clash.code == 2);
  CHECK(clash.err.find("belongs to the study 'sweeps'") != std::string::npos);
}

TEST_CASE("resume: SIGTERM stops a study and the message counts complete and interrupted runs apart", "[study][resume]") {
  const TempDir dir("resume-term");
  const fs::path study = write_front_study(dir.path, 150.0);  // ~0.5 s of CPU a run
  const Child c = spawn({bin, "study", study.string(), "--out", "s", "-j", "2", "-q"}, dir.path, dir.path / "o.txt",
                        dir.path / "e.txt");
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < give_up && run_status(dir.path / "s" / "runs" / "0000" / "results.h5").empty() &&
         run_status(dir.path / "s" / "runs" / "0001" / "results.h5").empty())
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the next runs are under way
  REQUIRE(::kill(c.pid, SIGTERM) == 0);
  CHECK(wait_for(c, 30) == 130);
  int complete = 0, interrupted = 0;
  for (const auto& f : run_files(dir.path / "s")) {
    const std::string s = run_status(f);
    complete += s == "complete";
    interrupted += s == "interrupted";
  }
  INFO(slurp(dir.path / "e.txt"));
  CHECK(interrupted >= 1);
  const H5Content s = read_h5(dir.path / "s" / "study.h5");
  CHECK(s.strings.at("/meta@status") == "interrupted");
  const std::string message = s.strings.at("/meta@message");
  INFO(message);
  CHECK(message.find("stopped: " + std::to_string(complete) + " of 6 runs complete") == 0);
  CHECK(message.find(std::to_string(interrupted) + " interrupted") != std::string::npos);
  CHECK(message.find("run the same command again to resume") != std::string::npos);
  CHECK(slurp(dir.path / "e.txt").find(message) != std::string::npos);
}
