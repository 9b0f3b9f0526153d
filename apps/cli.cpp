#include "apps/cli.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <sstream>

#include "apps/build_info.hpp"
#include "apps/check_resolution.hpp"
#include "apps/checkpoint.hpp"
#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "apps/json_progress.hpp"
#include "apps/paths.hpp"
#include "apps/stability.hpp"
#include "apps/study.hpp"
#include "compare/alongside.hpp"
#include "compare/estimate.hpp"
#include "compare/fronts.hpp"
#include "core/archive.hpp"
#include "core/interrupt.hpp"

namespace slipfront::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------------------------------------
// Stop requests: SIGINT/SIGTERM set a flag that the runner polls between steps (RunControl::stop).
// A second signal while stopping kills the program at once (default action).

std::atomic<int> stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void on_stop_signal(int sig) {
  core::stop_flag().store(true);  // set-up loops (core/interrupt.hpp)
  if (stop_signal.exchange(sig) != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  static const char msg[] =
      "\nslipfront: stopping at the next check (signal again to abort); the partial results will be written\n";
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
}

class StopSignals {
 public:
  StopSignals() {
    stop_signal.store(0);
    core::stop_flag().store(false);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  static bool requested() { return stop_signal.load(std::memory_order_relaxed) != 0; }

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// ---------------------------------------------------------------------------------------------
// The progress line: stderr, only on a terminal, only once the run has lasted a second, at most
// five refreshes a second, erased at the end.

class Progress {
 public:
  Progress(std::ostream& err, std::string scene, bool enabled) : err_(err), scene_(std::move(scene)), on_(enabled) {}
  ~Progress() { clear(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(const std::string& model, double t, double t_end) {
    const auto now = Clock::now();
    if (model != model_) model_ = model, model_start_ = now;
    if (!on_) return;
    const double elapsed = seconds(start_, now);
    if (elapsed < 1.0 || (width_ > 0 && seconds(last_, now) < 0.2)) return;
    last_ = now;
    const double in_model = seconds(model_start_, now);
    char line[256];
    const double pct = t_end > 0 ? 100.0 * t / t_end : 0.0;
    int n = std::snprintf(line, sizeof line, "[%s %s] t = %.2f / %g (%.0f%%)  elapsed %.1f s", scene_.c_str(),
                          model.c_str(), t, t_end, pct, elapsed);
    if (t > 0 && t < t_end && n > 0 && n < static_cast<int>(sizeof line))
      n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "  eta %.1f s",
                         in_model * (t_end - t) / t);
    std::string text(line);
    const std::size_t len = text.size();
    if (len < width_) text.append(width_ - len, ' ');
    width_ = std::max(width_, len);
    err_ << '\r' << text << std::flush;
  }

  void clear() {
    if (width_ == 0) return;
    err_ << '\r' << std::string(width_, ' ') << '\r' << std::flush;
    width_ = 0;
  }

 private:
  static double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }
  std::ostream& err_;
  std::string scene_, model_;
  bool on_;
  Clock::time_point start_ = Clock::now(), last_ = start_, model_start_ = start_;
  std::size_t width_ = 0;  // length of the longest line shown (0: nothing on screen)
};

// ---------------------------------------------------------------------------------------------

void print_error(std::ostream& err, const std::string& message) { err << "slipfront: error: " << message << "\n"; }

// (c) The output directory: created and locked, free of results.h5 (unless --force) and writable, before any
// work; the temporaries of killed runs removed (results, checkpoints, probes). Returns an error message,
// or "" if the directory is usable (and `lock` holds it).
std::string prepare_output_dir(const fs::path& dir, bool force, OutputLock& lock) {
  if (std::string problem = create_and_lock(dir, lock); !problem.empty()) return problem;
  std::error_code ec;
  const fs::path file = dir / "results.h5";
  if (fs::exists(fs::symlink_status(file, ec))) {
    if (!force) return "'" + file.string() + "' already exists (use --force to overwrite it)";
    if (fs::is_directory(file, ec)) return "'" + file.string() + "' is a directory";
  }
  for (const char* prefix : {".slipfront-probe.", ".results.h5.tmp.", ".checkpoint.bin.tmp."})
    remove_stale_temporaries(dir, prefix);
  const fs::path probe = dir / (".slipfront-probe." + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) return "the output directory '" + dir.string() + "' is not writable: " + std::strerror(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

// Numbers in the summary: 6 significant digits.
std::string format_number(double x) { return core::format_number(x, 6); }

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f s", s);
  return buf;
}

// The events that are not NaN; with `primary`, only those that differ from it.
std::string format_events(const compare::Events& e, const compare::Events* primary = nullptr) {
  std::string out;
  for (const auto& [name, member] : compare::event_fields) {
    const double value = e.*member;
    if (std::isnan(value) || (primary && value == primary->*member)) continue;
    out += std::string(out.empty() ? "" : "  ") + name + " = " + format_number(value);
  }
  return out;
}

// Why events are NaN (only those the run could have been expected to have), events with the same
// reason on one line.
std::string format_reasons(const compare::Events& e) {
  std::vector<std::pair<std::string, std::string>> grouped;  // reason, names
  for (const auto& [name, why] : e.reasons) {
    auto it = std::find_if(grouped.begin(), grouped.end(), [&](const auto& g) { return g.first == why; });
    if (it == grouped.end()) grouped.emplace_back(why, name);
    else it->second += ", " + name;
  }
  std::string out;
  for (const auto& [why, names] : grouped) out += "      " + names + ": " + why + "\n";
  return out;
}

void print_summary(std::ostream& out, const compare::Scene& scene, const std::vector<compare::ModelResult>& results,
                   compare::RunStatus status, double wall, const fs::path& file) {
  out << scene.name << ": " << compare::to_string(status) << " in " << format_seconds(wall) << " -> " << file.string() << "\n";
  for (const auto& r : results) {
    out << "  " << r.model << ": " << compare::to_string(r.status) << ", " << format_seconds(r.wall_seconds);
    if (const auto it = r.scalars.find("steps"); it != r.scalars.end())
      out << ", " << format_number(it->second) << " steps";
    out << "\n";
    if (!r.message.empty()) out << "    message: " << r.message << "\n";
    if (const auto ev = format_events(r.events); !ev.empty()) out << "    events: " << ev << "\n";
    if (const auto why = format_reasons(r.events); !why.empty()) out << "    events not measured (NaN):\n" << why;
    if (const auto ev = format_events(r.events_alt, &r.events); !ev.empty())
      out << "    events on the A_tip_alt front (where different): " << ev << "\n";
    if (const auto it = r.cycles.find("t_start"); it != r.cycles.end())
      out << "    stick-slip cycles: " << it->second.size() << "\n";
    const auto vn = r.scalars.find("v_m_numeric"), sn = r.scalars.find("sigma_c_numeric");
    const auto vm = r.scalars.find("v_m_fit"), sc = r.scalars.find("sigma_c_fit");
    if (vn != r.scalars.end() && sn != r.scalars.end()) {
      out << "    friction law minimum (golden section): sigma_c = " << format_number(sn->second)
          << " at v_m = " << format_number(vn->second) << "\n";
    } else if (vm != r.scalars.end() && sc != r.scalars.end()) {
      out << "    friction law minimum (fit): sigma_c = " << format_number(sc->second)
          << " at v_m = " << format_number(vm->second) << "\n";
    } else if (const auto s = r.friction_law.find("sigma"); s != r.friction_law.end() && !s->second.empty()) {
      const auto k = static_cast<std::size_t>(std::min_element(s->second.begin(), s->second.end()) - s->second.begin());
      out << "    friction law minimum (tabulated): sigma = " << format_number(s->second[k]);
      if (const auto v = r.friction_law.find("v"); v != r.friction_law.end() && k < v->second.size())
        out << " at v = " << format_number(v->second[k]);
      out << "\n";
    }
  }
}

int exit_code_of(compare::RunStatus status) {
  if (status == compare::RunStatus::complete) return exit_code::ok;
  if (status == compare::RunStatus::interrupted) return exit_code::interrupted;
  return exit_code::failed;
}

std::string shell_quote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                            "-_./=:,+@%") == std::string::npos)
    return arg;
  std::string q = "'";
  for (const char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// ---------------------------------------------------------------------------------------------
// The stages of `slipfront run`, in order; run_command lists them.

// What a run left: the models' results and their comparison, the run's status and message.
struct RunOutcome {
  std::vector<compare::ModelResult> results;
  compare::Comparison comparison;
  RunMeta meta;
  std::string checkpoint_error;  ///< the first checkpoint that could not be written ("" if none)
  std::string restart_error;     ///< the checkpoint's state does not fit this run ("" if it does; nothing ran)
};

// (a) The configuration, and on stderr its notes and the estimate of a long or large run. Nothing
// (the reason printed) when it is invalid.
std::optional<compare::Scene> load_run_scene(const RunOptions& opts, std::ostream& err) {
  compare::Scene scene;
  std::vector<std::string> notes;
  try {
    scene = load_scene(opts.config, opts.overrides, &notes);
  } catch (const ConfigError& e) {
    print_error(err, e.what());
    return std::nullopt;
  }
  if (!opts.quiet) {
    for (const auto& n : notes) err << "slipfront: note: " << n << "\n";
    const compare::Estimate estimate = compare::estimate(scene);
    for (const auto& n : estimate.notes) err << "slipfront: note: " << n << "\n";
    if (estimate.seconds >= 10.0 || estimate.memory_bytes >= 1024.0 * 1024.0 * 1024.0)
      for (const auto& line : compare::describe(estimate))
        if (line.rfind("note: ", 0) != 0) err << "slipfront: estimate: " << line << "\n";
  }
  return scene;
}

// (b) The checkpoint options, before any work: a finite cadence >= 0, bulk scenes only, and what the
// checkpoints cost (compare::estimate_checkpoints) within [limits]. False (the reason printed) when
// they cannot be used.
bool check_checkpoint_options(const RunOptions& opts, const compare::Scene& scene, std::ostream& err) {
  if (!(opts.checkpoint_every >= 0.0) || !std::isfinite(opts.checkpoint_every)) {
    print_error(err, "--checkpoint-every: must be a finite time >= 0, got " + format_number(opts.checkpoint_every));
    return false;
  }
  if ((opts.checkpoint_every > 0.0 || !opts.restart.empty()) && scene.drive.loading == core::Loading::imposed_rate) {
    print_error(err, opts.config.string() + ": drive.loading: checkpoints are for bulk scenes (an imposed-rate scene "
                                             "runs one site in seconds and has none)");
    return false;
  }
  if (opts.checkpoint_every == 0.0) return true;
  const compare::Estimate estimate = compare::estimate(scene);
  const compare::CheckpointEstimate checkpoints = compare::estimate_checkpoints(scene, estimate, opts.checkpoint_every);
  try {
    compare::check_checkpoint_limits(scene, estimate, checkpoints);
  } catch (const core::ParamError& e) {
    print_error(err, opts.config.string() + ": " + e.what());
    return false;
  }
  if (!opts.quiet && (estimate.seconds + checkpoints.seconds >= 10.0 || checkpoints.bytes >= 1024.0 * 1024.0 * 1024.0))
    err << "slipfront: estimate: " << compare::describe(checkpoints) << "\n";
  return true;
}

// The first key whose value differs between two resolved configurations (app::to_toml: "[section]"
// headers, "key = value" lines), as "section.key: the checkpoint has V, this run W".
std::string first_differing_key(const std::string& checkpoint, const std::string& run) {
  using Keys = std::vector<std::pair<std::string, std::string>>;
  auto keys_of = [](const std::string& text) {
    Keys keys;
    std::istringstream in(text);
    std::string line, section;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      if (line.front() == '[' && line.back() == ']') {
        section = line.substr(1, line.size() - 2) + ".";
        continue;
      }
      const std::size_t eq = line.find(" = ");
      if (eq == std::string::npos) keys.emplace_back(section + line, "");
      else keys.emplace_back(section + line.substr(0, eq), line.substr(eq + 3));
    }
    return keys;
  };
  const Keys a = keys_of(checkpoint), b = keys_of(run);
  auto find = [](const Keys& keys, const std::string& key) {
    return std::find_if(keys.begin(), keys.end(), [&](const auto& kv) { return kv.first == key; });
  };
  for (const auto& [key, value] : a) {
    const auto it = find(b, key);
    if (it == b.end()) return key + ": the checkpoint has " + value + ", this run none (the key is not used)";
    if (it->second != value) return key + ": the checkpoint has " + value + ", this run " + it->second;
  }
  for (const auto& [key, value] : b)
    if (find(a, key) == a.end()) return key + ": the checkpoint has none (the key is not used), this run " + value;
  return "the configuration texts differ outside their keys";
}

// (d) The checkpoint to continue from (its state; "" without --restart), verified (apps/checkpoint.hpp:
// a regular file within limits.max_memory_gib, checksum, this build's commit, sizes) and of this very
// configuration: a checkpoint of another one is refused, naming the first key that differs, so the run
// computes and records the configuration the checkpoint was made with. Nothing (the reason printed)
// when it cannot be used.
std::optional<std::string> read_restart(const RunOptions& opts, const compare::Scene& scene, const std::string& resolved,
                                        std::ostream& err) {
  if (opts.restart.empty()) return std::string();
  // (a checkpoint is read whole: one larger than the run's memory limit, at most 1e6 GiB, is not this run's)
  const auto max_bytes = static_cast<std::uint64_t>(scene.limits.max_memory_gib * 1024.0 * 1024.0 * 1024.0);
  Checkpoint restart;
  try {
    restart = read_checkpoint(opts.restart, max_bytes);
  } catch (const CheckpointError& e) {
    print_error(err, e.what());
    return std::nullopt;
  }
  if (restart.resolved_toml != resolved) {
    print_error(err, opts.restart.string() + ": the checkpoint belongs to another configuration: " +
                         first_differing_key(restart.resolved_toml, resolved) +
                         " (restart with the configuration and --set options it was made with)");
    return std::nullopt;
  }
  return std::move(restart.state);
}

// (e) The run, polling the stop requests, with a progress line on a terminal and a checkpoint every
// --checkpoint-every (a checkpoint that cannot be written is reported, the run goes on; the exit code
// says it). A restart state that does not fit the run is reported before anything ran.
RunOutcome run_scene_stoppable(const RunOptions& opts, const compare::Scene& scene, const std::string& resolved,
                               const fs::path& checkpoint_file, std::string restart_state, std::ostream& err) {
  RunOutcome run;
  run.meta.command_line = opts.command_line;
  const bool json = opts.progress == "json";
  Progress progress(err, scene.name, !json && !opts.quiet && ::isatty(STDERR_FILENO));
  JsonProgress json_progress(err, json);
  compare::RunControl control;
  control.stop = [] { return StopSignals::requested(); };
  control.progress = [&](const std::string& model, double t, double t_end) {
    progress.update(model, t, t_end);
    json_progress.run(scene.name, model, t, t_end);
  };
  control.checkpoint_every = opts.checkpoint_every;
  if (opts.checkpoint_every > 0.0)
    control.checkpoint = [&](const std::string& state, double t) {
      try {
        write_checkpoint(checkpoint_file, resolved, t, state);
      } catch (const CheckpointError& e) {  // a failed checkpoint does not stop the run; it is reported
        if (run.checkpoint_error.empty()) run.checkpoint_error = e.what();
      }
    };
  const bool restarting = !restart_state.empty();
  control.restart = std::move(restart_state);
  try {
    compare::SceneResult sr = compare::run_scene_alongside(scene, control);
    run.results = std::move(sr.models);
    run.comparison = std::move(sr.comparison);
  } catch (const core::ArchiveError& e) {
    if (restarting) {  // a state is read back at the start only: the checkpoint, not the run, is at fault
      run.restart_error = e.what();
    } else {
      run.meta.status = compare::RunStatus::failed;
      run.meta.message = std::string("the run stopped with an error: ") + e.what();
    }
  } catch (const core::Interrupted& e) {
    run.meta.status = compare::RunStatus::interrupted;
    run.meta.message = e.what();
  } catch (const std::exception& e) {
    run.meta.status = compare::RunStatus::failed;
    run.meta.message = std::string("the run stopped with an error: ") + e.what();
  }
  progress.clear();
  if (StopSignals::requested() && run.meta.status == compare::RunStatus::complete &&
      overall_status(run.results) == compare::RunStatus::complete) {
    // The signal came after the last poll: the results are complete; say so in the message only.
    run.meta.message = "a stop was requested after the run had finished";
  }
  return run;
}

// (f) What went wrong on stderr (a run that threw, a checkpoint not written: also in /meta message); a
// restarted run says where it came from.
void report_run_problems(const RunOptions& opts, RunOutcome& run, std::ostream& err) {
  if (run.meta.status == compare::RunStatus::failed) print_error(err, run.meta.message);
  if (!opts.restart.empty() && run.meta.message.empty())
    run.meta.message = "continued from the checkpoint " + opts.restart.string();
  if (!run.checkpoint_error.empty()) {
    const std::string problem = "a checkpoint could not be written: " + run.checkpoint_error;
    print_error(err, problem);
    run.meta.message += (run.meta.message.empty() ? "" : "; ") + problem;
  }
}

// (h) The end on stderr: how to continue an unfinished run from its checkpoint, an interruption,
// each failed model.
void print_run_end(const RunOptions& opts, const RunOutcome& run, compare::RunStatus status, const fs::path& dir,
                   const fs::path& file, const fs::path& checkpoint_file, std::ostream& err) {
  if (status != compare::RunStatus::complete && opts.checkpoint_every > 0.0 && fs::exists(checkpoint_file))
    err << "slipfront: continue with: slipfront run " << shell_quote(opts.config.string()) << " --out "
        << shell_quote(dir.string()) << " --restart " << shell_quote(checkpoint_file.string()) << " --force\n";
  if (status == compare::RunStatus::interrupted) err << "slipfront: interrupted; partial results written to " << file.string() << "\n";
  for (const auto& r : run.results)
    if (r.status == compare::RunStatus::failed) print_error(err, r.model + " failed: " + r.message + " (results written to " + file.string() + ")");
}

}  // namespace

std::string version_string() {
  return std::string("slipfront ") + build_info::version + " (git " + build_info::git_commit + ")";
}

int check_command(const fs::path& config, const std::vector<std::string>& overrides, std::ostream& out,
                  std::ostream& err) {
  try {
    std::vector<std::string> notes;
    const compare::Scene scene = load_scene(config, overrides, &notes);
    for (const auto& n : notes) err << "slipfront: note: " << n << "\n";
    out << to_toml(scene);
    // The estimate as TOML comments (the output still parses back to the same scene).
    out << "\n# estimate (compare::estimate; limits in [limits], basis in docs/robustness.md):\n";
    for (const auto& line : compare::describe(compare::estimate(scene))) out << "#   " << line << "\n";
    return exit_code::ok;
  } catch (const ConfigError& e) {
    print_error(err, e.what());
    return exit_code::usage;
  }
}

int run_command(const RunOptions& opts, std::ostream& out, std::ostream& err) {
  const auto wall0 = Clock::now();
  // (a) the configuration
  const std::optional<compare::Scene> scene = load_run_scene(opts, err);
  if (!scene) return exit_code::usage;
  const std::string resolved = to_toml(*scene);

  // (b) the checkpoint options, (c) the output directory, held by this run until the results are in
  // place, (d) the checkpoint to continue from: all before any work
  if (!check_checkpoint_options(opts, *scene, err)) return exit_code::usage;
  const fs::path dir = opts.out.empty() ? fs::path("out") / scene->name : opts.out;
  OutputLock lock;
  if (const std::string problem = prepare_output_dir(dir, opts.force, lock); !problem.empty()) {
    print_error(err, problem);
    return exit_code::usage;
  }
  const fs::path file = dir / "results.h5", checkpoint_file = dir / "checkpoint.bin";
  std::optional<std::string> restart_state = read_restart(opts, *scene, resolved, err);
  if (!restart_state) return exit_code::usage;

  // (e) the run, stoppable by SIGINT/SIGTERM (the handler stays until the file is written: a first
  // signal while writing does not lose the results)
  const StopSignals signals;
  RunOutcome run = run_scene_stoppable(opts, *scene, resolved, checkpoint_file, std::move(*restart_state), err);
  if (!run.restart_error.empty()) {
    print_error(err, opts.restart.string() + ": the checkpoint's state does not fit this run (" + run.restart_error + ")");
    return exit_code::usage;
  }
  report_run_problems(opts, run, err);

  // (g) the file, whatever the status
  run.meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  const compare::RunStatus status = overall_status(run.results, run.meta.status);
  try {
    write_results(file, *scene, resolved, run.results, run.meta, &run.comparison);
  } catch (const std::exception& e) {
    print_error(err, "cannot write " + file.string() + ": " + e.what());
    return exit_code::failed;
  }

  // (h) the summary; a complete run needs its checkpoint no more; a checkpoint that could not be
  // written fails the run (exit code 1: it could not have been continued), its results written
  if (status == compare::RunStatus::complete && opts.checkpoint_every > 0.0) {
    std::error_code ec;
    fs::remove(checkpoint_file, ec);
  }
  print_summary(out, *scene, run.results, status, run.meta.wall_seconds, file);
  print_run_end(opts, run, status, dir, file, checkpoint_file, err);
  return run.checkpoint_error.empty() ? exit_code_of(status) : exit_code::failed;
}

namespace {

// ---------------------------------------------------------------------------------------------
// The stages of `slipfront fronts`, in order; fronts_command lists them.

// (a) The scene, which must be under homogeneous loading. Nothing (the reason printed) when it is invalid.
std::optional<compare::Scene> load_fronts_scene(const FrontsOptions& opts, std::ostream& err) {
  try {
    compare::Scene scene = load_scene(opts.config, opts.overrides);
    if (scene.drive.loading != core::Loading::homogeneous)
      throw ConfigError(opts.config.string(), "drive.loading",
                        "steady fronts are solved for homogeneous loading (docs/model.md §6), got " +
                            std::string(core::to_string(scene.drive.loading)));
    return scene;
  } catch (const ConfigError& e) {
    print_error(err, e.what());
    return std::nullopt;
  }
}

// (b) DIR/fronts.h5: the directory created and locked (as `run`'s: one writer at a time, apps/paths.hpp), an
// existing file refused unless --force. "" when usable (and `lock` holds DIR).
std::string prepare_fronts_file(const fs::path& dir, const fs::path& file, bool force, OutputLock& lock) {
  if (std::string problem = create_and_lock(dir, lock); !problem.empty()) return problem;
  std::error_code ec;
  if (fs::exists(fs::symlink_status(file, ec)) && !force)
    return "'" + file.string() + "' already exists (use --force to overwrite it)";
  return "";
}

// The scaling study's line: the pooled prefactor with the points it fitted, those without a c_min by name
// and value, and the largest deviation over the fitted points only; or why no fit was made.
std::string scaling_line(const compare::FrontsResult& fr) {
  const auto& fits = fr.scaling_fits;
  if (!fits.count("parameter_index") || fits.at("parameter_index").empty()) return "  scaling: not run\n";
  const std::size_t all = fits.at("parameter_index").size() - 1;  // the pooled fit comes last
  const int fitted = static_cast<int>(fits.at("points")[all]), tried = static_cast<int>(fits.at("tried")[all]);
  std::string without;
  const auto& pts = fr.scaling_points;
  // A study stopped before its first point has fits (refused) but no points.
  const std::size_t points = pts.count("c_min") ? pts.at("c_min").size() : 0;
  for (std::size_t k = 0; k < points; ++k)
    if (!(pts.at("c_min")[k] > 0.0))
      without += (without.empty() ? "" : ", ") + fr.scaling_parameters[static_cast<std::size_t>(pts.at("parameter_index")[k])] +
                 " = " + format_number(pts.at("value")[k]);
  if (!fr.scaling_refused[all].empty()) return "  scaling: no fit: " + fr.scaling_refused[all] + "\n";
  return "  scaling: c_min = " + format_number(fits.at("prefactor")[all]) + " sqrt(mu alpha/(eta kappa)), fitted to " +
         std::to_string(fitted) + " of " + std::to_string(tried) + " points" +
         (without.empty() ? std::string() : " (no c_min for " + without + ")") + "; largest deviation " +
         core::format_number(100.0 * fits.at("spread")[all], 3) + " % over those " + std::to_string(fitted) + " points\n";
}

// The strip's collapse line: the pooled prefactor and spread, and each parameter's exponent d ln c_min/d ln p.
std::string strip_scaling_line(const compare::FrontsResult& fr) {
  const auto& fits = fr.scaling_fits;
  if (!fits.count("parameter_index") || fits.at("parameter_index").empty()) return "  scaling: not run\n";
  const int fitted = static_cast<int>(fits.at("points").back()), tried = static_cast<int>(fits.at("tried").back());
  std::string dropped = fr.labels.count("scaling_dropped") ? fr.labels.at("scaling_dropped") : std::string();
  while (!dropped.empty() && dropped.back() == '\n') dropped.pop_back();
  for (auto& ch : dropped)
    if (ch == '\n') ch = ';';
  const bool inplane = fr.scalars.count("shear_speed") > 0;  // the 1D scale of mu = E'H (docs/fronts.md §11.6)
  std::string line = "  scaling (strip): c_min = " + format_number(fits.at("prefactor").back()) +
                     (inplane ? " sqrt(mu alpha/(eta kappa)), mu = E'H" : " sqrt(mu' H alpha/(eta kappa))") + ", fitted to " + std::to_string(fitted) + " of " + std::to_string(tried) +
                     " points" + (dropped.empty() ? std::string() : " (dropped: " + dropped + ")") + "; largest deviation " +
                     core::format_number(100.0 * fits.at("spread").back(), 3) + " % over those " + std::to_string(fitted) +
                     " points; exponents";
  for (std::size_t k = 0; k + 1 < fits.at("parameter_index").size(); ++k)
    line += " " + fr.scaling_parameters[static_cast<std::size_t>(fits.at("parameter_index")[k])] + " " +
            format_number(fits.at("exponent")[k]);
  return line + " (1D: 0.5, 0.5, -0.5, -0.5)\n";
}

// (e) The summary on stdout, whatever the status: the branch, c_min (nan: not computed), the front at the
// scene's σ_d and, with --scaling, the fit.
void print_fronts_summary(std::ostream& out, const compare::Scene& scene, const compare::FrontsResult& fr,
                          const RunMeta& meta, bool scaling, const fs::path& file) {
  auto get = [&](const char* k) { return fr.scalars.count(k) ? fr.scalars.at(k) : std::nan(""); };
  auto label = [&](const char* k) { return fr.labels.count(k) ? fr.labels.at(k) : std::string(); };
  auto with_error = [&](const std::string& k) {  // "value ± error", or "value (no error estimate)"
    const double v = get(k.c_str()), e = get((k + "_error").c_str());
    if (!std::isfinite(v)) return format_number(v);
    return format_number(v) + (std::isfinite(e) ? " ± " + core::format_number(e, 2) : std::string(" (no error estimate)"));
  };
  const auto sd = fr.branch.find("sigma_d");
  const std::size_t n = sd == fr.branch.end() ? 0 : sd->second.size();
  out << scene.name << ": steady fronts " << compare::to_string(meta.status) << " in " << format_seconds(meta.wall_seconds)
      << " -> " << file.string() << "\n"
      << "  branch: " << n << " fronts, ends at sigma_d = " << format_number(n ? sd->second.back() : std::nan("")) << " ("
      << label("end") << ": " << label("reason") << ")\n"
      << "  c_min = " << with_error("c_min") << " at sigma_d = " << format_number(get("sigma_d_at_c_min"))
      << " (sigma_c^d = " << format_number(get("sigma_c_d")) << "); c_min / sqrt(mu alpha/(eta kappa)) = "
      << with_error("c_min_over_scale") << "\n"
      << "  at the scene's sigma_d = " << format_number(get("scene_sigma_d")) << ": "
      << (std::isfinite(get("c_at_scene_sigma_d")) ? "c = " + with_error("c_at_scene_sigma_d") + " (profile 0)"
                                                    : "no steady front (" + label("scene_front") + ")")
      << "\n";
  if (!label("accuracy").empty())
    out << "  accuracy (estimated errors, docs/fronts.md §10.20): rtol " << label("accuracy") << "; resolution "
        << label("resolution") << "\n";
  if (!label("profiles_failed").empty())  // a profile without a front: no speed, counted above without an estimate
    out << "  profiles NOT solved: " << label("profiles_failed") << "\n";
  if (get("height") > 0.0)
    out << "  strip H = " << format_number(get("height")) << " (mu' = " << format_number(get("mu_strip")) << ", l_kappa = "
        << format_number(get("ell_kappa")) << ", s = " << format_number(get("s")) << "): c_min / c_min(1D, mu = "
        << (std::isfinite(get("shear_speed")) ? "E'H" : "mu' H") << ") = "
        << with_error("c_min_over_1d") << " (1D: " << with_error("c_min_1d")
        << (label("c_min_1d").empty() ? "" : ", " + label("c_min_1d")) << "); "
        << format_number(get("rows")) << " rows, " << format_number(get("intervals")) << " intervals\n";
  if (std::isfinite(get("shear_speed")))  // the in-plane strip (docs/fronts.md §11.6)
    out << "  in-plane: nu = " << format_number(get("poisson")) << ", c_R = " << format_number(get("rayleigh_speed"))
        << ", c_s = " << format_number(get("shear_speed")) << ", c_p = " << format_number(get("pressure_speed"))
        << ", plate speed c_0 = " << format_number(get("plate_speed")) << " (fronts above c_s are not solved)\n";
  if (scaling && get("height") > 0.0) out << strip_scaling_line(fr);
  else if (scaling) out << scaling_line(fr);
}

}  // namespace

int fronts_command(const FrontsOptions& opts, std::ostream& out, std::ostream& err) {
  const auto wall0 = Clock::now();
  // (a) the scene
  const std::optional<compare::Scene> scene = load_fronts_scene(opts, err);
  if (!scene) return exit_code::usage;

  // (b) the mesh refused before any work when it cannot fit; the output file, DIR held by this process until
  //     fronts.h5 is in place
  compare::StripFrontsSettings strip{opts.rows, opts.intervals, opts.rtol};
  if (opts.budget > 0.0) strip.budget_seconds = opts.budget;
  if (scene->bulk.body() == core::BodyKind::inplane) strip.components = 2;  // u_x, u_y per row (docs/fronts.md §11.6)
  if (scene->bulk.body() != core::BodyKind::chain)
    if (const std::string refused = compare::strip_fronts_refusal(strip, scene->limits.max_memory_gib); !refused.empty()) {
      print_error(err, opts.config.string() + ": " + refused);
      return exit_code::usage;
    }
  const fs::path dir = opts.out.empty() ? fs::path("out") / scene->name : opts.out;
  const fs::path file = dir / "fronts.h5";
  OutputLock lock;
  if (const std::string problem = prepare_fronts_file(dir, file, opts.force, lock); !problem.empty()) {
    print_error(err, problem);
    return exit_code::usage;
  }

  // (c) the branch (and the scaling study), stoppable by SIGINT/SIGTERM as `run` is (the handler stays until
  // the file is written); failed when no front is found, the solver fails or the fit is refused
  const StopSignals signals;
  RunMeta meta;
  meta.command_line = opts.command_line;
  compare::FrontsResult fr;
  try {
    fr = compare::compute_fronts(*scene, opts.scaling, [] { return StopSignals::requested(); }, strip);
    meta.status = fr.status;
    meta.message = fr.message;
  } catch (const std::exception& e) {
    meta.status = compare::RunStatus::failed;
    meta.message = std::string("the solver stopped with an error: ") + e.what();
  }

  // (d) the file, whatever the status
  meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  try {
    write_fronts(file, *scene, to_toml(*scene), fr, meta);
  } catch (const std::exception& e) {
    print_error(err, "cannot write " + file.string() + ": " + e.what());
    return exit_code::failed;
  }

  // (e) the summary, and on stderr why it is not complete
  print_fronts_summary(out, *scene, fr, meta, opts.scaling, file);
  if (meta.status == compare::RunStatus::failed)
    print_error(err, "fronts failed: " + meta.message + " (results written to " + file.string() + ")");
  else if (meta.status == compare::RunStatus::interrupted)
    err << "slipfront: interrupted (" << meta.message << "); partial results written to " << file.string() << "\n";
  return exit_code_of(meta.status);
}

namespace {

// ---------------------------------------------------------------------------------------------
// The command line: each verb declared with its options, then main_cli parses and dispatches.

// What the parser fills: every verb's options.
struct Verbs {
  RunOptions run;
  fs::path check_config;
  std::vector<std::string> check_overrides;
  StudyOptions study;
  FrontsOptions fronts;
  ResolutionCheckOptions resolution;
  StabilityOptions stability;
  fs::path report_dir;
  std::string python = "/usr/bin/python3";
};

CLI::App* add_run_verb(CLI::App& app, RunOptions& opts) {
  auto* run = app.add_subcommand("run", "Run one scene and write DIR/results.h5");
  run->add_option("config", opts.config, "Scene configuration file (TOML)")->required();
  run->add_option("-o,--out", opts.out, "Output directory DIR (default: out/<scene name>); created if missing");
  run->add_option("-s,--set", opts.overrides,
                  "Override one key before validation, e.g. --set bulk.mu=200, --set 'drive.v=[0.1,1.0]', "
                  "--set discrete.threshold=uniform (the value is read as TOML, else as a bare string); "
                  "repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  run->add_flag("-f,--force", opts.force, "Overwrite an existing DIR/results.h5");
  run->add_flag("-q,--quiet", opts.quiet, "No progress line and no notes on stderr (errors still shown)");
  run->add_option("--progress", opts.progress,
                  "line: a progress line when stderr is a terminal (the default); json: one JSON object per line on "
                  "stderr, at most 10 a second, for a program driving slipfront (docs/cli.md)")
      ->check(CLI::IsMember({"line", "json"}))
      ->type_name("line|json");
  run->add_option("--checkpoint-every", opts.checkpoint_every,
                  "Write DIR/checkpoint.bin (atomically) every T of simulated time and when stopped (bulk scenes); "
                  "removed when the run completes")
      ->type_name("T");
  run->add_option("--restart", opts.restart,
                  "Continue from a checkpoint written by --checkpoint-every of this build (same configuration; verified: "
                  "checksum, commit, sizes); the result is the uninterrupted run's, bit for bit")
      ->type_name("FILE");
  run->footer(
      "The configuration is validated and DIR is created and checked (results.h5 absent unless --force,\n"
      "writable) before any simulation work. Ctrl-C (SIGINT) or SIGTERM stops the run at the next check and\n"
      "writes the partial results with /meta status = interrupted (exit code 130); a second signal aborts.\n"
      "A failed model (non-finite state) still writes the file, with status = failed (exit code 1).\n"
      "The results are written to a temporary file in DIR and renamed to results.h5 when complete.\n"
      "DIR is held by one run at a time (DIR/.slipfront.lock): a second run into it is refused (exit code 2).\n"
      "A checkpoint that cannot be written is reported and the run goes on; its exit code is then 1.");
  return run;
}

CLI::App* add_check_verb(CLI::App& app, fs::path& config, std::vector<std::string>& overrides) {
  auto* check = app.add_subcommand("check", "Validate a scene and print its fully resolved configuration (TOML)");
  check->add_option("config", config, "Scene configuration file (TOML)")->required();
  check->add_option("-s,--set", overrides, "Override one key, as for run; repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  return check;
}

CLI::App* add_study_verb(CLI::App& app, StudyOptions& opts) {
  auto* study = app.add_subcommand("study", "Run a convergence study (many runs on threads or MPI ranks) and analyse it");
  study->add_option("study", opts.study, "Study file (TOML; see docs/studies.md); required unless --list-kinds");
  study->add_option("-o,--out", opts.out, "Output directory (default: out/studies/<study name>)");
  study->add_option("-s,--set", opts.overrides, "Override one scene key in every run; repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  study->add_option("-j,--threads", opts.threads,
                    "Runs at once (default: all cores; under mpirun: per rank, default 1); results do not depend on it");
  study->add_flag("-f,--force", opts.force,
                  "Rerun every run, even those already complete in DIR, and replace study.h5 whatever it holds");
  study->add_flag("-q,--quiet", opts.quiet, "No progress line and no start line");
  study->add_option("--progress", opts.progress,
                    "line: a progress line on a terminal (the default); json: one JSON object per line on stderr "
                    "(runs done of this invocation's), for a program driving slipfront (docs/cli.md)")
      ->check(CLI::IsMember({"line", "json"}))
      ->type_name("line|json");
  auto* list = study->add_flag("--list-kinds", opts.list_kinds,
                               "Print the study kinds (name, models, what it runs, description), then exit");
  study->add_flag("--json", opts.json, "With --list-kinds: the kinds as one JSON object (docs/cli.md)")->needs(list);
  study->footer(
      "Every run is validated before any work. Each run writes DIR/runs/<id>/results.h5; the analysis\n"
      "(tables, fitted rates with 95% intervals, each with its definition) goes to DIR/study.h5.\n"
      "Resuming: the same command again skips the runs whose results file is complete and was made with\n"
      "the same configuration (/meta config_hash and /config toml), reruns partial ones, and refuses (exit 2)\n"
      "files made with another configuration unless --force. Ctrl-C stops every run (status interrupted).\n"
      "DIR is held by one invocation at a time (DIR/.slipfront.lock, as for run and fronts): a second one\n"
      "into it is refused (exit code 2) before any work.\n"
      "MPI: `mpirun -n K slipfront study STUDY.toml` spreads the runs over K processes, rank 0 included;\n"
      "the results are the same bit for bit (docs/studies.md).");
  return study;
}

CLI::App* add_fronts_verb(CLI::App& app, FrontsOptions& opts) {
  auto* fronts = app.add_subcommand("fronts", "Solve the steady fronts of a homogeneous scene and write DIR/fronts.h5");
  fronts->add_option("config", opts.config, "Scene configuration file (TOML) with drive.loading = homogeneous")
      ->required();
  fronts->add_option("-o,--out", opts.out, "Output directory DIR (default: out/<scene name>)");
  fronts->add_option("-s,--set", opts.overrides, "Override one key, as for run; repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  fronts->add_flag("--scaling", opts.scaling,
                   "Also the minimal-speed scaling study: c_min varying each of mu, alpha, eta, kappa (4 values each)");
  fronts->add_flag("-f,--force", opts.force, "Overwrite an existing DIR/fronts.h5");
  fronts->add_option("--rows", opts.rows,
                     "Strip scenes (bulk.height): row intervals across the height (default: chosen by --rtol from 8)")
      ->check(CLI::Range(1, 256));
  fronts->add_option("--intervals", opts.intervals,
                     "Strip scenes: xi intervals of the collocation mesh (default: chosen by --rtol from 300)")
      ->check(CLI::Range(8, 100000));
  fronts->add_option("--rtol", opts.rtol,
                     "Target relative error of every speed reported (estimated, stored beside it; default 1e-3): "
                     "the strip's rows and intervals are refined until the estimate meets it")
      ->check(CLI::Range(1e-8, 0.5));
  fronts->add_option("--budget", opts.budget,
                     "Strip scenes: the CPU seconds the mesh choice may spend on the whole branch (default 300); a "
                     "finer mesh predicted above it is not tried and the verdict says 'NOT met (budget)'")
      ->check(CLI::Range(1.0, 1e7));
  fronts->footer(
      "The traveling waves of docs/model.md §6 solved directly (collocation + Newton, docs/fronts.md): the\n"
      "branch c(sigma_d) continued down to where it ends (and why), c_min, profiles A, sigma_bar, v, u along it.\n"
      "Layout of fronts.h5: docs/output.md. Takes seconds (the scaling study: 16 more continuations).\n"
      "DIR is held by one invocation at a time (DIR/.slipfront.lock, as for run and study): a second one\n"
      "into it is refused (exit code 2) before any work.");
  return fronts;
}

CLI::App* add_report_verb(CLI::App& app, fs::path& dir, std::string& python) {
  auto* report = app.add_subcommand("report", "Write DIR/report.md with plots from the results and studies under DIR");
  report->add_option("dir", dir, "Directory holding results.h5 and study.h5 files (searched recursively)")->required();
  report->add_option("--python", python,
                     "Python with numpy, h5py and matplotlib (default /usr/bin/python3; a bare name is looked up on PATH)");
  report->footer(
      "report.py is looked for in $SLIPFRONT_DATA_DIR, then in <prefix>/share/slipfront beside an installed\n"
      "<prefix>/bin/slipfront, then in the source tree's scripts/.");
  return report;
}

// How the program was invoked, as a shell would read it back (recorded in /meta).
std::string command_line_of(int argc, char** argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) line += (i ? " " : "") + shell_quote(argv[i]);
  return line;
}

}  // namespace

int main_cli(int argc, char** argv) {
  CLI::App app{"slipfront: the onset of frictional sliding, continuum and discrete microcontact models.\n"
               "Runs one scene (a TOML file) and writes DIR/results.h5 (layout: docs/output.md).",
               "slipfront"};
  app.set_version_flag("--version", version_string(), "Print the version and the git commit, then exit");
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success; 1 a model failed or the results could not be written;\n"
      "            2 bad command line, configuration or output directory; 130 interrupted (partial results "
      "written).\n"
      "Configuration keys, types, defaults and ranges: docs/cli.md (`slipfront check CONFIG` prints them resolved).");
  Verbs v;
  CLI::App* const run = add_run_verb(app, v.run);
  add_check_verb(app, v.check_config, v.check_overrides);
  CLI::App* const study = add_study_verb(app, v.study);
  CLI::App* const fronts = add_fronts_verb(app, v.fronts);
  CLI::App* const report = add_report_verb(app, v.report_dir, v.python);
  CLI::App* const check_resolution = add_check_resolution_verb(app, v.resolution);
  CLI::App* const stability = add_stability_verb(app, v.stability);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    print_error(std::cerr, std::string(e.what()) + " (see slipfront --help)");
    return exit_code::usage;
  }
  // An empty --out would silently mean the default directory: refuse it.
  for (const auto& [sub, dir] : {std::pair{run, &v.run.out}, std::pair{study, &v.study.out},
                                  std::pair{check_resolution, &v.resolution.out}, std::pair{stability, &v.stability.out}})
    if (*sub && sub->count("--out") > 0 && dir->empty()) {
      print_error(std::cerr, std::string(sub->get_name()) +
                                 ": --out: the output directory is empty; give a directory, or omit --out for the "
                                 "default out/<name>");
      return exit_code::usage;
    }
  // A file-size limit (RLIMIT_FSIZE) then fails the write with EFBIG, reported like a full disk
  // (exit code 1), instead of killing the program with SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);

  if (*run) {
    v.run.command_line = command_line_of(argc, argv);
    return run_command(v.run, std::cout, std::cerr);
  }
  if (*study) {
    v.study.command_line = command_line_of(argc, argv);
    return study_command(v.study, std::cout, std::cerr);
  }
  if (*report) return report_command(v.report_dir, v.python, std::cerr);
  if (*check_resolution) {
    v.resolution.command_line = command_line_of(argc, argv);
    return check_resolution_command(v.resolution, std::cout, std::cerr);
  }
  if (*stability) {  // stoppable as `fronts` is: the handler stays until stability.h5 is written
    v.stability.command_line = command_line_of(argc, argv);
    const StopSignals signals;
    return stability_command(v.stability, std::cout, std::cerr);
  }
  if (*fronts) {
    v.fronts.command_line = command_line_of(argc, argv);
    return fronts_command(v.fronts, std::cout, std::cerr);
  }
  return check_command(v.check_config, v.check_overrides, std::cout, std::cerr);
}

}  // namespace slipfront::app
