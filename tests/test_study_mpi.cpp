// Studies on MPI (issue 13 item 2): `mpirun -n K slipfront study` spreads the runs over K ranks and
// gives the thread pool's results bit for bit (every dataset of every run file) and the same
// study.h5 analysis; SIGTERM to mpirun stops every rank cleanly; the executable never links libmpi
// and refuses to run a study K times when the MPI engine cannot be loaded. Skipped (visibly: ctest
// reports "Skipped") where mpirun is not installed or slipfront was built without MPI.
#include <catch2/catch.hpp>

#include <chrono>
#include <iostream>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "apps/build_info.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"
#include "study_fixtures.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using namespace slipfront::testing;

namespace {

const std::string bin = SLIPFRONT_BINARY;

// mpirun refuses to run as root without these (harmless otherwise).
const std::map<std::string, std::string> mpi_env = {{"OMPI_ALLOW_RUN_AS_ROOT", "1"},
                                                     {"OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1"}};

// Why the MPI tests cannot run here ("" if they can).
std::string mpi_missing() {
  if (!app::build_info::mpi_engine_built) return "slipfront was built without MPI (CMake did not find it)";
  if (find_program("mpirun").empty()) return "mpirun is not installed (Debian: openmpi-bin libopenmpi-dev)";
  return "";
}

bool skip_without_mpi() {
  const std::string why = mpi_missing();
  if (why.empty()) return false;
  std::cout << skip_marker << " " << why << "\n";
  WARN("skipped: " << why);
  return true;
}

std::vector<std::string> mpirun(int ranks, const std::vector<std::string>& args, bool oversubscribe = false) {
  std::vector<std::string> cmd = {"mpirun", "-n", std::to_string(ranks), "--bind-to", "none"};
  if (oversubscribe) cmd.push_back("--oversubscribe");
  cmd.push_back(bin);
  cmd.insert(cmd.end(), args.begin(), args.end());
  return cmd;
}

// The ranks that made the runs (from "[study run 0003, MPI rank 1 of 2]" in /meta command_line).
std::set<int> ranks_used(const fs::path& dir) {
  std::set<int> ranks;
  const std::regex re(R"(MPI rank (\d+) of)");
  for (const auto& f : run_files(dir)) {
    std::smatch m;
    const std::string line = read_h5(f).strings.at("/meta@command_line");
    if (std::regex_search(line, m, re)) ranks.insert(std::stoi(m[1]));
  }
  return ranks;
}

}  // namespace

TEST_CASE("mpi: mpirun -n 2 and -n 3 --oversubscribe give the thread pool's run files bit for bit and the same "
          "study.h5",
          "[study][mpi]") {
  if (skip_without_mpi()) return;
  const TempDir dir("mpi-same");
  const fs::path study = write_front_study(dir.path);
  const Output ref = run({bin, "study", study.string(), "--out", "threads", "-j", "2", "-q"}, dir.path);
  INFO(ref.err);
  REQUIRE(ref.code == 0);
  const auto ref_files = run_files(dir.path / "threads");
  REQUIRE(ref_files.size() == 6);

  for (const auto& [ranks, oversubscribe] : {std::pair{2, false}, std::pair{3, true}}) {
    const std::string out = "mpi" + std::to_string(ranks);
    const Output m = run(mpirun(ranks, {"study", study.string(), "--out", out, "-q"}, oversubscribe), dir.path, mpi_env);
    INFO("mpirun -n " << ranks << "\n" << m.out << m.err);
    REQUIRE(m.code == 0);
    CHECK(m.out.find("on " + std::to_string(ranks) + " MPI ranks") != std::string::npos);
    CHECK(m.out.find("runs: 6 run now, 0 skipped") != std::string::npos);
    const auto files = run_files(dir.path / out);
    REQUIRE(files.size() == ref_files.size());
    for (std::size_t k = 0; k < files.size(); ++k) {
      const auto d = run_file_differences(ref_files[k], files[k]);
      INFO(files[k].string() << (d.empty() ? "" : ": " + d.front()));
      CHECK(d.empty());
    }
    const auto d = study_differences(dir.path / "threads" / "study.h5", dir.path / out / "study.h5");
    for (const auto& x : d) UNSCOPED_INFO(x);
    CHECK(d.empty());
    const H5Content s = read_h5(dir.path / out / "study.h5");
    CHECK(s.strings.at("/study/runs@engine") == "mpi");
    CHECK(s.numbers.at("/study/runs@workers") == ranks);
    // dynamic distribution: more than one rank computed (rank 0 included in the counting)
    CHECK(ranks_used(dir.path / out).size() >= 2);
  }
}

TEST_CASE("mpi: SIGTERM to mpirun stops every rank with run files readable and study.h5 interrupted, and the rerun "
          "completes it",
          "[study][mpi]") {
  if (skip_without_mpi()) return;
  const TempDir dir("mpi-term");
  const fs::path study = write_front_study(dir.path, 150.0);  // ~0.5 s of CPU a run
  const std::vector<std::string> cmd = mpirun(2, {"study", study.string(), "--out", "s", "-q"});
  const Child c = spawn(cmd, dir.path, dir.path / "o.txt", dir.path / "e.txt", mpi_env);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  auto any_complete = [&] {
    if (!fs::exists(dir.path / "s" / "runs")) return false;
    for (const auto& f : run_files(dir.path / "s"))
      if (run_status(f) == "complete") return true;
    return false;
  };
  while (std::chrono::steady_clock::now() < give_up && !any_complete())
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // both ranks are in their next run
  const auto sent = std::chrono::steady_clock::now();
  REQUIRE(::kill(c.pid, SIGTERM) == 0);
  const int code = wait_for(c, 30);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  INFO(slurp(dir.path / "o.txt") << slurp(dir.path / "e.txt"));
  CHECK(code != 0);  // mpirun's own code when it is signalled (1); the status is in study.h5
  CHECK(seconds < 10);
  int complete = 0, interrupted = 0;
  for (const auto& f : run_files(dir.path / "s")) {
    if (!fs::exists(f)) continue;
    const std::string s = run_status(f);
    INFO(f.string());
    CHECK((s == "complete" || s == "interrupted"));  // readable, whole
    complete += s == "complete";
    interrupted += s == "interrupted";
  }
  CHECK(complete >= 1);
  CHECK(interrupted >= 1);
  REQUIRE(fs::exists(dir.path / "s" / "study.h5"));
  const H5Content s = read_h5(dir.path / "s" / "study.h5");
  CHECK(s.strings.at("/meta@status") == "interrupted");
  CHECK(s.strings.at("/meta@message").find("stopped: " + std::to_string(complete) + " of 6 runs complete") == 0);

  const Output again = run(cmd, dir.path, mpi_env);
  INFO(again.out << again.err);
  REQUIRE(again.code == 0);
  CHECK(again.out.find("runs: " + std::to_string(6 - complete) + " run now, " + std::to_string(complete) +
                       " skipped") != std::string::npos);
  CHECK(read_h5(dir.path / "s" / "study.h5").strings.at("/meta@status") == "complete");
}

TEST_CASE("mpi: slipfront does not link libmpi, and without a loadable MPI engine mpirun's ranks refuse, one process "
          "falls back to threads",
          "[study][mpi]") {
  const TempDir dir("mpi-none");
  // the executable itself: no libmpi among its needed libraries (the engine is a dlopen'ed module)
  if (!find_program("readelf").empty()) {
    const Output elf = run({"readelf", "-d", bin}, dir.path);
    REQUIRE(elf.code == 0);
    CHECK(elf.out.find("libxxhash") != std::string::npos);  // the listing is the right one
    CHECK(elf.out.find("libmpi") == std::string::npos);
  } else {
    WARN("readelf not installed: the libmpi check is skipped");
  }
  const fs::path study = write_sweep_study(dir.path);
  // As mpirun would start it (its environment), where the engine cannot be loaded (a machine
  // without libmpi, or a build without MPI): several processes must not each run the whole study.
  const std::map<std::string, std::string> launched = {{"OMPI_COMM_WORLD_SIZE", "2"},
                                                       {"SLIPFRONT_MPI_ENGINE", "/nonexistent/libslipfront_mpi.so"}};
  const Output refused = run({bin, "study", study.string(), "--out", "s", "-q"}, dir.path, launched);
  CHECK(refused.code == 2);
  CHECK(refused.err.find("MPI engine could not be loaded") != std::string::npos);
  CHECK(refused.err.find("/nonexistent/libslipfront_mpi.so") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "s" / "study.h5"));
  const Output alone = run({bin, "study", study.string(), "--out", "s"}, dir.path,
                           {{"OMPI_COMM_WORLD_SIZE", "1"}, {"SLIPFRONT_MPI_ENGINE", "/nonexistent/x.so"}});
  INFO(alone.err);
  CHECK(alone.code == 0);
  CHECK(alone.err.find("using threads") != std::string::npos);
  CHECK(alone.out.find("thread") != std::string::npos);
  // not started by mpirun: no MPI at all, even with a broken engine path
  const Output plain = run({bin, "study", study.string(), "--out", "p", "-q"}, dir.path,
                           {{"SLIPFRONT_MPI_ENGINE", "/nonexistent/x.so"}}, {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"});
  CHECK(plain.code == 0);
  CHECK(plain.err.empty());
  if (mpi_missing().empty()) {  // under a real mpirun too
    auto env = mpi_env;
    env["SLIPFRONT_MPI_ENGINE"] = "/nonexistent/x.so";
    const Output real = run(mpirun(2, {"study", study.string(), "--out", "m", "-q"}), dir.path, env);
    CHECK(real.code == 2);
    CHECK(real.err.find("MPI engine could not be loaded") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.path / "m" / "study.h5"));
  }
}
