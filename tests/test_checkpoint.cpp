// Checkpoint and restart (issue 10): a run continued from any checkpoint gives the uninterrupted run's
// results bit for bit — every integrator (explicit, implicit, adaptive with the discrete model after it),
// every representation (count, agent with contact statistics, naive), lockstep and sequential runs,
// energy budgets, a steady-front start, a stop request; and through the program, a run killed with
// SIGKILL resumes from its last checkpoint file (verified: tests/test_checkpoint_hostile.cpp).
#include <catch2/catch.hpp>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "apps/checkpoint.hpp"
#include "compare/alongside.hpp"
#include "identical.hpp"
#include "scenes.hpp"

using namespace slipfront;
namespace fs = std::filesystem;

namespace {

using testing::require_identical;
using testing::same;


struct Saved {
  double t;
  std::string state;
};

// Runs s with checkpoints every `every` and returns the result and the checkpoints it wrote.
compare::SceneResult run_checkpointed(const compare::Scene& s, double every, std::vector<Saved>& saved) {
  compare::RunControl ctl;
  ctl.checkpoint_every = every;
  ctl.checkpoint = [&](const std::string& state, double t) { saved.push_back({t, state}); };
  return compare::run_scene_alongside(s, ctl);
}

compare::SceneResult restarted(const compare::Scene& s, const std::string& state) {
  compare::RunControl ctl;
  ctl.restart = state;
  return compare::run_scene_alongside(s, ctl);
}

// fig1 on L = 60, dx = 1 to t = 60 (through first yield and the slow front), both models.
compare::Scene small(core::Integrator integ, const std::string& representation) {
  compare::Scene s = testing::small_fig1_scene(integ);
  s.models = {"continuum", "discrete"};
  s.output.sequence = true;
  s.discrete.representation = representation;
  s.discrete.contacts_per_site = 50;
  s.discrete.contact_statistics = representation != "count";
  s.output.ages = representation != "count";  // the mean contact age (docs/model.md §7): the count representation has none
  s.discrete.seed = 3;
  s.validate();
  return s;
}

}  // namespace

TEST_CASE("checkpoint: a restarted run is the uninterrupted run bit for bit, every integrator and representation",
          "[checkpoint]") {
  using core::Integrator;
  for (const auto integ : {Integrator::central_difference, Integrator::implicit_trapezoidal, Integrator::adaptive_rosenbrock})
    for (const char* rep : {"count", "agent", "naive"}) {
      const compare::Scene s = small(integ, rep);
      INFO(core::to_string(integ) << ", " << rep);
      const auto whole = compare::run_scene_alongside(s, {});
      if (std::string(rep) != "count") {
        // the state of docs/model.md §7 is in the run: both models' ages, the agent's classed statistics,
        // and on the fixed-step integrators the continuum's prediction of them
        CHECK(whole.models[0].snapshots.count("age") == 1);
        CHECK(whole.models[1].snapshots.count("age") == (std::string(rep) == "agent" ? 1u : 0u));  // naive: no ages
        CHECK(whole.models[1].contacts_2d.count("class_lifetime_counts") == 1);
        if (integ != Integrator::adaptive_rosenbrock) CHECK(whole.models[0].contacts_2d.count("class_lifetime_counts") == 1);
      }
      std::vector<Saved> saved;
      const auto with = run_checkpointed(s, 12.0, saved);
      require_identical(whole, with);  // checkpointing itself changes nothing
      // lockstep: 4 checkpoints (t = 12 .. 48); adaptive: the models one after the other, 4 each
      REQUIRE(saved.size() >= 4);
      for (const std::size_t k : {std::size_t{0}, saved.size() / 2, saved.size() - 1}) {
        INFO("restarted from the checkpoint at t = " << saved[k].t << " (" << k + 1 << " of " << saved.size() << ")");
        require_identical(whole, restarted(s, saved[k].state));
      }
    }
}

TEST_CASE("checkpoint: energy budgets, the spring block, a steady-front start and a stop request", "[checkpoint]") {
  std::vector<compare::Scene> scenes;
  for (const auto integ : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal}) {
    compare::Scene b = testing::spring_block_scene(80.0);
    b.models = {"continuum", "discrete"};
    b.drive.K = 0.25;
    b.discrete.contacts_per_site = 200;
    b.output.energy = true;
    b.output.series_dt = 0.1;
    b.time.integrator = integ;
    if (integ == core::Integrator::implicit_trapezoidal) b.time.dt = 0.01;
    scenes.push_back(b);
  }
  compare::Scene h = testing::homogeneous_scene(0.3, 0.0, 6.0);
  h.models = {"continuum", "discrete"};
  h.bulk.length = 300.0;
  h.grid.dx = 1.0;
  h.drive.start = "steady_front";
  h.drive.front_x = 50.0;
  h.discrete.contacts_per_site = 1000;
  h.output.energy = true;
  h.output.snapshot_dt = 1.0;
  scenes.push_back(h);
  for (auto& s : scenes) {
    s.validate();
    INFO(s.name << ", " << core::to_string(s.time.integrator));
    const auto whole = compare::run_scene_alongside(s, {});
    std::vector<Saved> saved;
    run_checkpointed(s, s.time.t_end / 4.0, saved);
    REQUIRE(saved.size() >= 2);
    require_identical(whole, restarted(s, saved[1].state));
  }
  // A stop request writes a last checkpoint; continued from it, the run completes as if never stopped.
  const compare::Scene s = small(core::Integrator::central_difference, "count");
  const auto whole = compare::run_scene_alongside(s, {});
  compare::RunControl ctl;
  std::vector<Saved> saved;
  int calls = 0;
  ctl.stop = [&] { return ++calls == 20000; };
  ctl.checkpoint_every = 1000.0;  // none due: the only checkpoint is the stop's
  ctl.checkpoint = [&](const std::string& state, double t) { saved.push_back({t, state}); };
  const auto stopped = compare::run_scene_alongside(s, ctl);
  CHECK(stopped.models[0].status == slipfront::compare::RunStatus::interrupted);
  REQUIRE(saved.size() == 1);
  require_identical(whole, restarted(s, saved[0].state));
}

TEST_CASE("checkpoint: a run killed with SIGKILL resumes from its checkpoint file", "[checkpoint][cli]") {
  // The program on fig1 (both models, ~1 s), checkpoints every 5 time units; SIGKILL once a checkpoint
  // exists; `--restart` completes it: every dataset of results.h5 equals the uninterrupted run's exactly.
  testing::TempDir tmp("checkpoint");
  const std::string cfg = std::string(SLIPFRONT_SOURCE_DIR) + "/configs/fig1.toml";
  const std::string bin = SLIPFRONT_BINARY;
  const fs::path a = tmp.path / "whole", b = tmp.path / "killed";
  REQUIRE(std::system((bin + " run " + cfg + " --out " + a.string() + " --quiet > /dev/null").c_str()) == 0);
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    execl(bin.c_str(), bin.c_str(), "run", cfg.c_str(), "--out", b.c_str(), "--quiet", "--checkpoint-every", "5",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  const fs::path ck = b / "checkpoint.bin";
  for (int k = 0; k < 2000 && !fs::exists(ck); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  std::this_thread::sleep_for(std::chrono::milliseconds(150));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  REQUIRE(WIFSIGNALED(status));  // killed, not finished
  REQUIRE(fs::exists(ck));
  CHECK_FALSE(fs::exists(b / "results.h5"));
  fs::copy_file(ck, tmp.path / "copy.bin");
  const auto saved = app::read_checkpoint(ck);
  CHECK(saved.time > 0.0);
  CHECK(saved.time < 140.0);
  REQUIRE(std::system((bin + " run " + cfg + " --out " + b.string() + " --quiet --checkpoint-every 5 --restart " + ck.string() +
                       " > /dev/null").c_str()) == 0);
  CHECK_FALSE(fs::exists(ck));  // removed once the run is complete
  for (const auto& e : fs::directory_iterator(b))  // no lock file, no temporary of the killed run left
    CHECK(e.path().filename() == "results.h5");
  auto read = [](const fs::path& f, const char* path) {
    const hid_t file = H5Fopen(f.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(file, path, H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(sp);
    H5Dclose(d);
    H5Fclose(file);
    return v;
  };
  for (const char* p : {"/continuum/series/drive_force", "/continuum/series/tip_x", "/continuum/snapshots/A",
                        "/discrete/series/max_v", "/discrete/snapshots/sigma_bar", "/compare/fields/A_distance"}) {
    INFO(p);
    const auto x = read(a / "results.h5", p), y = read(b / "results.h5", p);
    REQUIRE(x.size() > 10);
    CHECK(same(x, y));
  }
  // a checkpoint of another configuration is refused, before any work
  CHECK(WEXITSTATUS(std::system((bin + " run " + cfg + " --out " + (tmp.path / "other").string() +
                                 " --quiet --set interface.kappa=9 --restart " + (tmp.path / "copy.bin").string() +
                                 " > /dev/null 2>&1").c_str())) == 2);
}
