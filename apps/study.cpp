#include "apps/study.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <toml++/toml.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "apps/build_info.hpp"
#include "apps/cli.hpp"
#include "apps/config.hpp"
#include "core/interrupt.hpp"
#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "apps/paths.hpp"
#include "apps/study_mpi.hpp"
#include "compare/pool.hpp"
#include "compare/alongside.hpp"

extern char** environ;

namespace slipfront::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// TOML text of a value given in a study file, as --set understands it.
std::string value_text(const toml::node& n) {
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* f = n.as_floating_point()) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, f->get());
    std::string s(buf, r.ptr);
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // keep it a float
    return s;
  }
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* s = n.as_string()) return "\"" + s->get() + "\"";
  if (const auto* a = n.as_array()) {
    std::string out = "[";
    for (std::size_t k = 0; k < a->size(); ++k) out += (k ? ", " : "") + value_text(*a->get(k));
    return out + "]";
  }
  return "";  // dates and tables: refused by read_vary
}

std::vector<std::pair<std::string, std::vector<std::string>>> read_vary(const toml::table& t, const std::string& file,
                                                                        const std::string& where) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    const auto* arr = v.as_array();
    if (!arr || arr->empty())
      throw ConfigError(file, where + "." + key, "must be a non-empty array of values for the key '" + key + "'");
    std::vector<std::string> values;
    for (const auto& e : *arr) {
      if (!(e.is_number() || e.is_boolean() || e.is_string() || e.is_array()))
        throw ConfigError(file, where + "." + key, "values must be numbers, booleans, strings or arrays");
      values.push_back(value_text(e));
    }
    out.emplace_back(key, values);
  }
  return out;
}

}  // namespace

compare::StudySpec load_study(const fs::path& file) {
  const std::string name = file.string();
  toml::table t;
  try {
    t = toml::parse_file(name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    if (!fs::exists(file)) throw ConfigError(name, "", "cannot open the file: no such file");
    throw ConfigError(name, static_cast<long>(b.line), static_cast<long>(b.column), std::string(e.description()));
  }
  static const std::set<std::string> known{"study", "kind", "description", "scene", "set", "seeds", "vary", "group",
                                           "fit_from"};
  for (const auto& [k, v] : t)
    if (!known.count(std::string(k.str())))
      throw ConfigError(name, std::string(k.str()),
                        "unknown key (known: study, kind, description, scene, set, seeds, fit_from, vary, group)");
  compare::StudySpec s;
  auto need_string = [&](const char* key, bool required) -> std::string {
    const auto* n = t.get(key);
    if (!n) {
      if (required) throw ConfigError(name, key, "required key is missing");
      return "";
    }
    if (!n->is_string()) throw ConfigError(name, key, "expected a string");
    return n->as_string()->get();
  };
  s.name = need_string("study", true);
  s.kind = need_string("kind", true);
  s.description = need_string("description", false);
  const std::string scene = need_string("scene", true);
  s.scene_file = (fs::path(scene).is_absolute() ? fs::path(scene) : file.parent_path() / scene).lexically_normal().string();
  if (!compare::find_study_kind(s.kind)) {
    std::string list;
    for (const compare::StudyKind& k : compare::study_kinds()) list += (list.empty() ? "" : ", ") + std::string(k.name);
    throw ConfigError(name, "kind", "unknown study kind '" + s.kind + "' (known: " + list + ")");
  }
  if (const auto* n = t.get("seeds")) {
    if (!n->is_integer() || n->as_integer()->get() < 1) throw ConfigError(name, "seeds", "must be an integer >= 1");
    s.seeds = static_cast<int>(n->as_integer()->get());
  }
  if (const auto* n = t.get("fit_from")) {
    if (!n->is_number() || n->value<double>().value_or(-1) < 0) throw ConfigError(name, "fit_from", "must be a number >= 0");
    s.fit_from = n->value<double>().value_or(0.0);
  }
  if (const auto* n = t.get("set")) {
    const auto* a = n->as_array();
    if (!a) throw ConfigError(name, "set", "must be an array of \"section.key=value\" strings");
    for (const auto& e : *a) {
      if (!e.is_string()) throw ConfigError(name, "set", "must be an array of \"section.key=value\" strings");
      s.common.push_back(e.as_string()->get());
    }
  }
  if (const auto* n = t.get("vary")) {
    if (!n->is_table()) throw ConfigError(name, "vary", "must be a table of key = [values]");
    s.groups.push_back({"", read_vary(*n->as_table(), name, "vary")});
  }
  if (const auto* n = t.get("group")) {
    const auto* a = n->as_array();
    if (!a || !a->is_array_of_tables()) throw ConfigError(name, "group", "must be an array of tables ([[group]])");
    for (std::size_t k = 0; k < a->size(); ++k) {
      const auto& g = *a->get(k)->as_table();
      const std::string where = "group[" + std::to_string(k) + "]";
      compare::StudyGroup grp;
      for (const auto& [gk, gv] : g) {
        const std::string key(gk.str());
        if (key == "name") {
          if (!gv.is_string()) throw ConfigError(name, where + ".name", "expected a string");
          grp.name = gv.as_string()->get();
        } else if (key == "vary") {
          if (!gv.is_table()) throw ConfigError(name, where + ".vary", "must be a table of key = [values]");
          grp.vary = read_vary(*gv.as_table(), name, where + ".vary");
        } else {
          throw ConfigError(name, where + "." + key, "unknown key (known: name, vary)");
        }
      }
      if (grp.name.empty()) grp.name = "group" + std::to_string(k);
      s.groups.push_back(std::move(grp));
    }
  }
  return s;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Stop requests: SIGINT/SIGTERM set a flag that every run polls (RunControl::stop). Every signal
// only sets the flag (no abort on a second one: under mpirun, Ctrl-C reaches the ranks as SIGTERM
// from mpirun, and mpirun ends them itself if they take too long).

std::atomic<bool> stop_signal{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_study_signal(int) {
  stop_signal.store(true);
  core::stop_flag().store(true);  // set-up loops (core/interrupt.hpp)
}

class StudySignals {
 public:
  StudySignals() {
    stop_signal.store(false);
    core::stop_flag().store(false);
    struct sigaction sa {};
    sa.sa_handler = on_study_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StudySignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StudySignals(const StudySignals&) = delete;
  StudySignals& operator=(const StudySignals&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// ---------------------------------------------------------------------------------------------
// Resume: what an existing run file holds, compared with the run about to be made.

enum class RunFile { missing, complete, partial, unreadable, unverified, other_config };

struct RunFileCheck {
  RunFile state = RunFile::missing;
  std::string detail;  ///< status of a partial file, the error of an unreadable one, the first difference
};

// "line 12: `mu = 300.0` in the file, `mu = 200.0` now" (or the lengths, if one is a prefix).
std::string first_difference(const std::string& stored, const std::string& now) {
  std::istringstream a(stored), b(now);
  std::string la, lb;
  for (int line = 1;; ++line) {
    const bool ga = static_cast<bool>(std::getline(a, la)), gb = static_cast<bool>(std::getline(b, lb));
    if (!ga && !gb) return "same text";
    if (!ga) la = "(end of file)";
    if (!gb) lb = "(end of file)";
    if (la != lb || !ga || !gb) return "line " + std::to_string(line) + ": `" + la + "` in the file, `" + lb + "` now";
  }
}

RunFileCheck check_run_file(const fs::path& file, const std::string& resolved, const std::string& hash) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return {RunFile::missing, ""};
  ResultsHeader h;
  try {
    h = read_results_header(file);
  } catch (const InputError& e) {
    return {RunFile::unreadable, e.what()};
  }
  if (h.resolved_toml != resolved || (!h.config_hash.empty() && h.config_hash != hash))
    return {RunFile::other_config, first_difference(h.resolved_toml, resolved)};
  if (h.config_hash.empty()) return {RunFile::unverified, "no /meta config_hash (written by an older slipfront)"};
  if (h.status != compare::RunStatus::complete) return {RunFile::partial, compare::to_string(h.status)};
  return {RunFile::complete, ""};
}

// Temporaries left by a killed writer (h5out's ".results.h5.tmp.<pid>").
void remove_stale_temporaries(const fs::path& run_dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(run_dir, ec))
    if (e.path().filename().string().rfind(".results.h5.tmp.", 0) == 0) fs::remove(e.path(), ec);
}

std::string plural(long long n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

struct RunPlan {
  int code = 0;            ///< 0: go on; else the exit code (the reason was printed)
  std::vector<char> skip;  ///< per run: 1 if its results file is complete for the same configuration
  long long rerun = 0;     ///< runs with a partial, failed, unreadable or unverified file: made again
  long long fresh = 0;     ///< runs with no file yet (every run with --force)
};

// Creates DIR/runs/<id>/, checks the files already there (the table in docs/studies.md, "Resuming")
// and removes the temporaries of killed writers. Nothing is touched when it refuses.
RunPlan plan_runs(const fs::path& dir, const compare::StudySpec& spec, const std::vector<compare::StudyRun>& runs,
                  const std::vector<std::string>& resolved, bool force, std::ostream& err) {
  RunPlan p;
  p.skip.assign(runs.size(), 0);
  const auto refuse = [] {
    RunPlan r;
    r.code = exit_code::usage;
    return r;
  };
  std::error_code ec;
  fs::create_directories(dir / "runs", ec);
  if (ec) {
    err << "slipfront: error: cannot create the output directory '" << dir.string() << "': " << ec.message() << "\n";
    return refuse();
  }
  if (fs::exists(dir / "study.h5") && !force) {
    std::string other;
    try {
      other = read_study_name(dir / "study.h5");
    } catch (const InputError&) {
      other = "";
    }
    if (other != spec.name) {
      err << "slipfront: error: '" << (dir / "study.h5").string() << "' belongs to "
          << (other.empty() ? std::string("no readable study") : "the study '" + other + "'") << ", not to '"
          << spec.name << "' (use --force to replace it, or --out for another directory)\n";
      return refuse();
    }
  }
  std::vector<std::string> other_config;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const fs::path run_dir = dir / "runs" / runs[i].id;
    fs::create_directories(run_dir, ec);
    if (ec) {
      err << "slipfront: error: cannot create '" << run_dir.string() << "': " << ec.message() << "\n";
      return refuse();
    }
    if (force) {
      ++p.fresh;
      continue;
    }
    const RunFileCheck c = check_run_file(run_dir / "results.h5", resolved[i], config_hash(resolved[i]));
    switch (c.state) {
      case RunFile::complete: p.skip[i] = 1; break;
      case RunFile::missing: ++p.fresh; break;
      case RunFile::other_config: other_config.push_back("runs/" + runs[i].id + "/results.h5: " + c.detail); break;
      default: ++p.rerun; break;  // partial, unreadable or unverified: made again
    }
  }
  if (!other_config.empty()) {
    err << "slipfront: error: " << other_config.size() << " of " << runs.size() << " run files in '" << dir.string()
        << "' were made with another configuration (the study file, its scene or --set changed since):\n";
    for (std::size_t k = 0; k < other_config.size() && k < 5; ++k) err << "  " << other_config[k] << "\n";
    if (other_config.size() > 5) err << "  ... and " << other_config.size() - 5 << " more\n";
    err << "slipfront: nothing was run; use --force to rerun every run, or --out for another directory\n";
    return refuse();
  }
  for (const auto& r : runs) remove_stale_temporaries(dir / "runs" / r.id);
  return p;
}

// The counters every rank reports at the end (summed over the ranks under MPI).
enum Count : std::size_t { n_complete, n_interrupted, n_failed, n_write_failures, n_stopped, n_counts };

}  // namespace

int study_command(const StudyOptions& opts, std::ostream& out_all, std::ostream& err_all) {
  const auto wall0 = Clock::now();

  // (a) The engine: the thread pool, or MPI when mpirun started this process (then every rank runs
  // this function; rank 0 prints, plans, analyses and writes study.h5).
  std::unique_ptr<MpiEngine> mpi;
  if (const int launched = mpirun_size(); launched > 0) {
    std::string why;
    mpi = MpiEngine::load(why);
    if (!mpi && !build_info::mpi_engine_built) why = "this slipfront was built without MPI; " + why;
    if (!mpi && launched > 1) {
      err_all << "slipfront: error: started by mpirun as one of " << launched
              << " processes, but the MPI engine could not be loaded (" << why
              << "); without it every process would run the whole study. Run `slipfront study` without mpirun "
                 "(it uses threads), or build slipfront where MPI is installed (docs/studies.md)\n";
      return exit_code::usage;
    }
    if (!mpi && !opts.quiet)
      err_all << "slipfront: note: started by mpirun with one process and no MPI engine (" << why
              << "): using threads\n";
  }
  const bool root = !mpi || mpi->rank() == 0;
  std::ostream quiet_stream(nullptr);  // discards: only rank 0 speaks for the study
  std::ostream& out = root ? out_all : quiet_stream;
  std::ostream& err = root ? err_all : quiet_stream;

  // (b) Everything is read and every run validated before any work (every rank does the same).
  compare::StudySpec spec;
  std::vector<compare::StudyRun> runs;
  std::vector<compare::Scene> scenes;
  std::vector<std::string> resolved;
  try {
    spec = load_study(opts.study);
    runs = compare::expand(spec);
    for (auto& r : runs) {
      r.overrides.insert(r.overrides.end(), opts.overrides.begin(), opts.overrides.end());
      scenes.push_back(load_scene(spec.scene_file, r.overrides));
      resolved.push_back(to_toml(scenes.back()));
    }
  } catch (const ConfigError& e) {
    err << "slipfront: error: " << e.what() << "\n";
    return exit_code::usage;
  }
  std::string spec_toml;
  {
    std::ifstream in(opts.study);
    std::ostringstream ss;
    ss << in.rdbuf();
    spec_toml = ss.str();
  }
  const fs::path dir = opts.out.empty() ? fs::path("out") / "studies" / spec.name : opts.out;
  const std::size_t n = runs.size();
  auto run_file = [&](std::size_t i) { return dir / "runs" / runs[i].id / "results.h5"; };

  // (c) The plan (rank 0, then sent to every rank): which runs are complete already (resume).
  // plan[0]: 0 to go on, else the exit code; plan[1 + i]: 1 if run i is skipped.
  std::vector<char> plan(1 + n, 0);
  RunPlan p;
  if (root) {
    p = plan_runs(dir, spec, runs, resolved, opts.force, err);
    plan[0] = static_cast<char>(p.code);
    std::copy(p.skip.begin(), p.skip.end(), plan.begin() + 1);
  }
  if (mpi) mpi->broadcast(plan.data(), plan.size(), -1);
  if (plan[0] != 0) return plan[0];
  const long long n_rerun = p.rerun, n_new = p.fresh;
  std::vector<std::size_t> todo;
  std::vector<int> skipped(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (plan[1 + i]) skipped[i] = 1;
    else todo.push_back(i);
  }
  const long long n_skipped = static_cast<long long>(n - todo.size());

  // (d) The runs: on `threads` threads, or on every MPI rank (each taking the next run from the
  // counter at rank 0), `threads` per rank (default 1).
  unsigned threads = opts.threads ? opts.threads : std::max(1u, std::thread::hardware_concurrency());
  if (mpi) {
    threads = opts.threads ? opts.threads : 1u;
    if (threads > 1 && !mpi->serialized()) {
      err << "slipfront: note: this MPI library gives no MPI_THREAD_SERIALIZED: one run at a time per rank\n";
      threads = 1;
    }
  }
  const std::string engine = mpi ? "mpi" : "threads";
  const int workers = static_cast<int>(threads) * (mpi ? mpi->size() : 1);
  const std::string where = mpi ? plural(mpi->size(), "MPI rank", "MPI ranks") +
                                      (threads > 1 ? " x " + plural(threads, "thread", "threads") : "")
                                : plural(threads, "thread", "threads");
  if (!opts.quiet) {
    err << "slipfront: study " << spec.name << " (" << spec.kind << "): " << plural(static_cast<long long>(n), "run", "runs");
    if (n_skipped > 0 || n_rerun > 0)
      err << ", " << n_skipped << " complete already (skipped), " << todo.size() << " to run (" << n_rerun
          << " partial, failed or unverified, " << n_new << " new)";
    err << " on " << where << " -> " << dir.string() << "\n";
  }

  const StudySignals signals;
  std::atomic<bool> remote_stop{false}, stop_sent{false};
  std::atomic<std::int64_t> last_remote_check{0};
  // Under MPI a stop anywhere stops every rank: the rank that sees a signal raises the stop counter
  // at rank 0, the others look at it every 50 ms.
  auto stop_requested = [&]() -> bool {
    if (stop_signal.load(std::memory_order_relaxed)) {
      if (mpi && !stop_sent.exchange(true)) {
        try {
          mpi->fetch_add(slipfront_mpi_stop, 1);
        } catch (const std::exception&) {
        }
      }
      return true;
    }
    if (!mpi || remote_stop.load(std::memory_order_relaxed)) return remote_stop.load();
    const auto now = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch()).count();
    auto last = last_remote_check.load();
    if (now - last >= 50 && last_remote_check.compare_exchange_strong(last, now)) {
      mpi->progress();
      if (mpi->try_read(slipfront_mpi_stop) > 0) remote_stop = true;
    }
    return remote_stop.load();
  };

  std::vector<std::vector<compare::ModelResult>> results(n);
  std::vector<char> in_memory(n, 0);
  std::vector<long long> counts(n_counts, 0);
  std::mutex io;
  std::size_t done = 0;
  const bool tty = root && !opts.quiet && ::isatty(STDERR_FILENO);
  auto job = [&](std::size_t i) {
    const auto t0 = Clock::now();
    compare::RunControl ctl;
    ctl.stop = stop_requested;
    std::vector<compare::ModelResult> r;
    compare::Comparison cmp;
    RunMeta meta;
    meta.command_line = opts.command_line + "  [study run " + runs[i].id +
                        (mpi ? ", MPI rank " + std::to_string(mpi->rank()) + " of " + std::to_string(mpi->size()) : "") +
                        "]";
    try {
      compare::SceneResult sr = compare::run_scene_alongside(scenes[i], ctl);
      r = std::move(sr.models);
      cmp = std::move(sr.comparison);
    } catch (const core::Interrupted& e) {
      meta.status = compare::RunStatus::interrupted;
      meta.message = e.what();
    } catch (const std::exception& e) {
      meta.status = compare::RunStatus::failed;
      meta.message = e.what();
    }
    meta.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const compare::RunStatus status = overall_status(r, meta.status);
    bool written = true;
    try {
      write_results(run_file(i), scenes[i], resolved[i], r, meta, &cmp);
    } catch (const std::exception& e) {
      written = false;
      std::lock_guard lock(io);
      err_all << "slipfront: error: run " << runs[i].id << (mpi ? " (rank " + std::to_string(mpi->rank()) + ")" : "")
              << ": " << e.what() << "\n";
    }
    for (auto& m : r) {  // the analysis needs events, series and tables, not the fields
      m.snapshots.clear();
      m.snapshot_t.clear();
      m.contacts.clear();
      m.contacts_2d.clear();
    }
    results[i] = std::move(r);
    std::lock_guard lock(io);
    in_memory[i] = 1;
    ++counts[status == compare::RunStatus::complete ? n_complete : status == compare::RunStatus::interrupted ? n_interrupted : n_failed];
    if (!written) ++counts[n_write_failures];
    std::size_t finished = ++done;
    if (mpi) finished = static_cast<std::size_t>(mpi->fetch_add(slipfront_mpi_finished, 1) + 1);
    const double el = std::chrono::duration<double>(Clock::now() - wall0).count();
    if (tty)
      err << "\r[study " << spec.name << "] " << finished << "/" << todo.size() << " runs, elapsed "
          << static_cast<int>(el) << " s, eta "
          << static_cast<int>(el * static_cast<double>(todo.size() - std::min(finished, todo.size())) /
                              static_cast<double>(finished))
          << " s   " << std::flush;
  };
  std::atomic<std::size_t> next_local{0};
  compare::run_workers(
      std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(todo.size(), 1)))),
      [&]() -> std::optional<std::size_t> {
        if (stop_requested()) return std::nullopt;
        const auto k = mpi ? static_cast<std::size_t>(mpi->fetch_add(slipfront_mpi_next, 1)) : next_local.fetch_add(1);
        if (k >= todo.size()) return std::nullopt;
        return todo[k];
      },
      job);
  if (tty) err << "\n";
  counts[n_stopped] = stop_requested() ? 1 : 0;

  // (e) Every rank done: the counters summed (under MPI, also the sign that every run file is
  // written; after a stop, ranks that do not answer within 0.5 s are not waited for).
  bool all_reported = true;
  std::size_t handed_out = todo.size();
  if (mpi) {
    const bool stopped_here = counts[n_stopped] != 0;
    all_reported = mpi->sum(counts, stopped_here ? 0.5 : -1.0);
    if (root && (stopped_here || counts[n_stopped] != 0))
      handed_out = std::min<std::size_t>(todo.size(), static_cast<std::size_t>(mpi->try_read(slipfront_mpi_next)));
  } else if (counts[n_stopped]) {
    handed_out = std::min(todo.size(), next_local.load());
  }
  const bool stopped = counts[n_stopped] != 0 || stop_signal.load();

  int code = exit_code::ok;
  if (root) {
    // (f) The analysis (rank 0): results in memory, or read back from the run files of skipped runs
    // and of runs made by other ranks. Runs never started have no results.
    std::vector<char> started(n, 0);
    for (std::size_t k = 0; k < handed_out; ++k) started[todo[k]] = 1;
    std::vector<std::string> read_problems;
    std::vector<char> lost(n, 0);  // started, but no readable results file (its process died, or writing failed)
    for (std::size_t i = 0; i < n; ++i) {
      if (in_memory[i] || !(skipped[i] || started[i])) continue;
      std::error_code ec;
      if (!fs::exists(run_file(i), ec)) {
        lost[i] = 1;
        read_problems.push_back("run " + runs[i].id + ": no results file (its process stopped before writing it)");
        continue;
      }
      try {
        results[i] = read_results(run_file(i), {.fields = false}).models;
      } catch (const InputError& e) {
        lost[i] = 1;
        read_problems.push_back("run " + runs[i].id + ": cannot read back its results: " + e.what());
      }
    }
    long long complete = 0, interrupted = 0, failed = 0, n_lost = 0, not_started = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!skipped[i] && !started[i]) ++not_started;
      else if (lost[i]) ++n_lost;
      else {
        const compare::RunStatus s = results[i].empty() ? compare::RunStatus::failed : overall_status(results[i]);
        ++(s == compare::RunStatus::complete ? complete : s == compare::RunStatus::interrupted ? interrupted : failed);
      }
    }
    const long long computed = static_cast<long long>(handed_out);
    RunMeta meta;
    meta.command_line = opts.command_line;
    if (stopped && complete == static_cast<long long>(n)) {
      meta.message = "a stop was requested after every run had finished";  // nothing was lost: complete
    } else if (stopped) {
      meta.status = compare::RunStatus::interrupted;
      meta.message = "stopped: " + std::to_string(complete) + " of " + std::to_string(n) + " runs complete (" +
                     std::to_string(n_skipped) + " of them from an earlier invocation), " +
                     std::to_string(interrupted) + " interrupted, " + std::to_string(failed) + " failed, " +
                     (n_lost ? std::to_string(n_lost) + " without a results file, " : "") +
                     std::to_string(not_started) + " not started; run the same command again to resume";
      if (!all_reported) meta.message += " (some MPI ranks did not report after the stop)";
    }
    compare::StudyReport report;
    try {
      report = compare::analyse_study(spec, runs, scenes, results);
    } catch (const std::exception& e) {
      meta.status = compare::RunStatus::failed;
      meta.message = std::string("analysis: ") + e.what();
    }
    report.notes.insert(report.notes.end(), read_problems.begin(), read_problems.end());
    meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
    const StudyExecution exec{engine, workers, computed, skipped};
    try {
      write_study(dir / "study.h5", spec, spec_toml, runs, report, meta, exec);
    } catch (const std::exception& e) {
      err << "slipfront: error: cannot write " << (dir / "study.h5").string() << ": " << e.what() << "\n";
      code = exit_code::failed;
    }
    if (code == exit_code::ok) {
      out << spec.name << " (" << spec.kind << "): " << compare::to_string(meta.status) << ", " << n << " runs in "
          << static_cast<int>(meta.wall_seconds * 10) / 10.0 << " s on " << where << " -> "
          << (dir / "study.h5").string() << "\n";
      out << "  runs: " << computed << " run now, " << n_skipped << " skipped (complete from an earlier invocation)";
      if (interrupted || failed || n_lost || not_started)
        out << "; " << complete << " complete, " << interrupted << " interrupted, " << failed << " failed, "
            << (n_lost ? std::to_string(n_lost) + " without a results file, " : "") << not_started << " not started";
      out << "\n";
      for (const auto& [k, v] : report.scalars)
        if (k.find("_ci_") == std::string::npos && k.find("_points") == std::string::npos) {
          out << "  " << k << " = " << v;
          const auto lo = report.scalars.find(k + "_ci_low"), hi = report.scalars.find(k + "_ci_high");
          if (lo != report.scalars.end() && hi != report.scalars.end())
            out << "  (95% CI " << lo->second << " .. " << hi->second << ")";
          out << "\n";
        }
      for (const auto& note : report.notes) out << "  note: " << note << "\n";
      if (meta.status == compare::RunStatus::interrupted) err << "slipfront: " << meta.message << "\n";
      if (meta.status == compare::RunStatus::interrupted) code = exit_code::interrupted;
      else if (meta.status != compare::RunStatus::complete || counts[n_write_failures] != 0 || !read_problems.empty())
        code = exit_code::failed;
    }
  }
  if (mpi) {
    // Every rank exits with rank 0's code (mpirun reports the first non-zero one), and not before
    // rank 0 is done: a rank ending early with a non-zero code makes mpirun abort the others.
    int shared = code;
    if (mpi->broadcast(&shared, sizeof shared, root && stopped ? 0.5 : -1.0)) code = shared;
    mpi->finalize();
  }
  return code;
}

// `slipfront report DIR`: scripts/report.py run directly (fork/exec with an argument vector, no
// shell), found beside an installed program or in the source tree (apps/paths.hpp).
int report_command(const fs::path& dir, const std::string& python, std::ostream& err) {
  if (!fs::is_directory(dir)) {
    err << "slipfront: error: '" << dir.string() << "' is not a directory\n";
    return 2;
  }
  const fs::path script = find_data_file("report.py");
  if (script.empty()) {
    err << "slipfront: error: the report script report.py is missing; looked for:";
    for (const auto& c : data_file_candidates("report.py")) err << "\n  " << c.string();
    err << "\n(set SLIPFRONT_DATA_DIR to the directory that holds report.py and plot.py)\n";
    return 1;
  }
  const std::vector<std::string> args = {python, script.string(), dir.string()};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  // posix_spawnp: PYTHON may be a bare name looked up on PATH, or a path.
  if (const int rc = ::posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ); rc != 0) {
    err << "slipfront: error: cannot run '" << python << "': " << std::strerror(rc) << "\n";
    return 1;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      err << "slipfront: error: waiting for the report script: " << std::strerror(errno) << "\n";
      return 1;
    }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return 0;
  if (WIFSIGNALED(status)) err << "slipfront: error: the report script was killed by signal " << WTERMSIG(status) << "\n";
  else err << "slipfront: error: the report script " << script.string() << " exited with " << WEXITSTATUS(status) << "\n";
  return 1;
}

}  // namespace slipfront::app
