#include "apps/study.hpp"

#include <csignal>
#include <unistd.h>

#include <toml++/toml.h>

#include <atomic>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "compare/pool.hpp"
#include "compare/runner.hpp"

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
  bool kind_ok = false;
  for (const auto& [k, what] : compare::study_kinds()) kind_ok |= k == s.kind;
  if (!kind_ok) {
    std::string list;
    for (const auto& [k, what] : compare::study_kinds()) list += (list.empty() ? "" : ", ") + k;
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

int study_command(const StudyOptions& opts, std::ostream& out, std::ostream& err) {
  const auto wall0 = Clock::now();
  compare::StudySpec spec;
  std::vector<compare::StudyRun> runs;
  std::vector<compare::Scene> scenes;
  // Everything is read and every run validated before any work.
  try {
    spec = load_study(opts.study);
    runs = compare::expand(spec);
    for (auto& r : runs) {
      r.overrides.insert(r.overrides.end(), opts.overrides.begin(), opts.overrides.end());
      scenes.push_back(load_scene(spec.scene_file, r.overrides));
    }
  } catch (const ConfigError& e) {
    err << "slipfront: error: " << e.what() << "\n";
    return 2;
  }
  std::string spec_toml;
  {
    std::ifstream in(opts.study);
    std::ostringstream ss;
    ss << in.rdbuf();
    spec_toml = ss.str();
  }
  const fs::path dir = opts.out.empty() ? fs::path("out") / "studies" / spec.name : opts.out;
  std::error_code ec;
  fs::create_directories(dir / "runs", ec);
  if (ec) {
    err << "slipfront: error: cannot create the output directory '" << dir.string() << "': " << ec.message() << "\n";
    return 2;
  }
  if (fs::exists(dir / "study.h5") && !opts.force) {
    err << "slipfront: error: '" << (dir / "study.h5").string() << "' already exists (use --force to overwrite it)\n";
    return 2;
  }
  for (const auto& r : runs) {
    fs::create_directories(dir / "runs" / r.id, ec);
    if (ec) {
      err << "slipfront: error: cannot create '" << (dir / "runs" / r.id).string() << "': " << ec.message() << "\n";
      return 2;
    }
  }

  const unsigned threads = opts.threads ? opts.threads : std::max(1u, std::thread::hardware_concurrency());
  static std::atomic<bool> stop{false};
  stop = false;
  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = [](int) { stop = true; };
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);

  std::vector<std::vector<compare::ModelResult>> results(runs.size());
  std::mutex io;
  std::size_t done = 0;
  const bool tty = !opts.quiet && ::isatty(STDERR_FILENO);
  if (!opts.quiet)
    err << "slipfront: study " << spec.name << " (" << spec.kind << "): " << runs.size() << " runs on " << threads
        << " thread(s) -> " << dir.string() << "\n";
  int write_failures = 0;
  compare::run_pool(
      runs.size(), threads,
      [&](std::size_t i) {
        const auto t0 = Clock::now();
        compare::RunControl ctl;
        ctl.stop = [] { return stop.load(); };
        std::vector<compare::ModelResult> r;
        compare::Comparison cmp;
        RunMeta meta;
        meta.command_line = opts.command_line + "  [study run " + runs[i].id + "]";
        try {
          compare::SceneResult sr = compare::run_scene_alongside(scenes[i], ctl);
          r = std::move(sr.models);
          cmp = std::move(sr.comparison);
        } catch (const std::exception& e) {
          meta.status = "failed";
          meta.message = e.what();
        }
        meta.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        try {
          write_results(dir / "runs" / runs[i].id / "results.h5", scenes[i], to_toml(scenes[i]), r, meta, &cmp);
        } catch (const std::exception& e) {
          std::lock_guard lock(io);
          err << "slipfront: error: run " << runs[i].id << ": " << e.what() << "\n";
          ++write_failures;
        }
        for (auto& m : r) {  // the analysis needs events, series and tables, not the fields
          m.snapshots.clear();
          m.snapshot_t.clear();
          m.contacts.clear();
          m.contacts_2d.clear();
        }
        results[i] = std::move(r);
        std::lock_guard lock(io);
        ++done;
        const double el = std::chrono::duration<double>(Clock::now() - wall0).count();
        if (tty)
          err << "\r[study " << spec.name << "] " << done << "/" << runs.size() << " runs, elapsed " << static_cast<int>(el)
              << " s, eta " << static_cast<int>(el * static_cast<double>(runs.size() - done) / static_cast<double>(done))
              << " s   " << std::flush;
      },
      [] { return stop.load(); });
  if (tty) err << "\n";
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);

  RunMeta meta;
  meta.command_line = opts.command_line;
  if (stop) {
    meta.status = "interrupted";
    meta.message = std::to_string(done) + " of " + std::to_string(runs.size()) + " runs finished before the stop";
  }
  compare::StudyReport report;
  try {
    report = compare::analyse_study(spec, runs, scenes, results);
  } catch (const std::exception& e) {
    meta.status = "failed";
    meta.message = std::string("analysis: ") + e.what();
  }
  meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  try {
    write_study(dir / "study.h5", spec, spec_toml, runs, report, meta);
  } catch (const std::exception& e) {
    err << "slipfront: error: cannot write " << (dir / "study.h5").string() << ": " << e.what() << "\n";
    return 1;
  }
  out << spec.name << " (" << spec.kind << "): " << meta.status << ", " << runs.size() << " runs in "
      << static_cast<int>(meta.wall_seconds * 10) / 10.0 << " s on " << threads << " thread(s) -> "
      << (dir / "study.h5").string() << "\n";
  for (const auto& [k, v] : report.scalars)
    if (k.find("_ci_") == std::string::npos && k.find("_points") == std::string::npos) {
      out << "  " << k << " = " << v;
      const auto lo = report.scalars.find(k + "_ci_low"), hi = report.scalars.find(k + "_ci_high");
      if (lo != report.scalars.end() && hi != report.scalars.end())
        out << "  (95% CI " << lo->second << " .. " << hi->second << ")";
      out << "\n";
    }
  for (const auto& n : report.notes) out << "  note: " << n << "\n";
  if (meta.status == "interrupted") return 130;
  return meta.status == "complete" && write_failures == 0 ? 0 : 1;
}

int report_command(const fs::path& dir, const std::string& python, std::ostream& err) {
  const fs::path script = fs::path(SLIPFRONT_SOURCE_DIR) / "scripts" / "report.py";
  if (!fs::is_directory(dir)) {
    err << "slipfront: error: '" << dir.string() << "' is not a directory\n";
    return 2;
  }
  if (!fs::exists(script)) {
    err << "slipfront: error: the report script " << script.string() << " is missing\n";
    return 1;
  }
  const std::string cmd = "'" + python + "' '" + script.string() + "' '" + dir.string() + "'";
  const int rc = std::system(cmd.c_str());
  return rc == 0 ? 0 : 1;
}

}  // namespace slipfront::app
