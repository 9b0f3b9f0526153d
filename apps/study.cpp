#include "apps/study.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <toml++/toml.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <thread>

#include "apps/build_info.hpp"
#include "apps/cli.hpp"
#include "apps/config.hpp"
#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "apps/json_progress.hpp"
#include "apps/paths.hpp"
#include "apps/study_mpi.hpp"
#include "apps/toml_integer.hpp"
#include "compare/alongside.hpp"
#include "compare/runner.hpp"
#include "compare/estimate.hpp"
#include "compare/pool.hpp"
#include "core/interrupt.hpp"
#include "studies/resolution.hpp"
#include "studies/strip_cmin_height.hpp"

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

// What makes two values of a varied key the same point: their TOML text, with numbers compared by value
// (100, 100.0 and 1e2 are one point; integers beyond 2^53 stay exact).
std::string point_identity(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) {
    const double x = f->get();
    if (std::isfinite(x) && x == std::trunc(x) && std::abs(x) < 9007199254740992.0)
      return std::to_string(static_cast<std::int64_t>(x));
  }
  return value_text(n);
}

// One [vary] table: key -> its values. A value repeated in a list is one point, not two (they would be
// pooled as extra seeds): it is kept once, with a note.
std::vector<std::pair<std::string, std::vector<std::string>>> read_vary(const toml::table& t, const std::string& file,
                                                                        const std::string& where,
                                                                        std::vector<std::string>& notes) {
  std::vector<std::pair<std::string, std::vector<std::string>>> out;
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    const auto* arr = v.as_array();
    if (!arr || arr->empty())
      throw ConfigError(file, where + "." + key, "must be a non-empty array of values for the key '" + key + "'");
    std::vector<std::string> values;
    std::map<std::string, std::string> seen;  // identity -> the text kept
    for (const auto& e : *arr) {
      if (!(e.is_number() || e.is_boolean() || e.is_string() || e.is_array()))
        throw ConfigError(file, where + "." + key, "values must be numbers, booleans, strings or arrays");
      const std::string text = value_text(e);
      const auto [it, fresh] = seen.emplace(point_identity(e), text);
      if (fresh) {
        values.push_back(text);
      } else {
        notes.push_back(file + ": " + where + "." + key + ": the value " + text +
                        (text == it->second ? "" : " (the same point as " + it->second + ")") +
                        " is repeated: it is run once (a repeated value is one point, not extra seeds)");
      }
    }
    out.emplace_back(key, values);
  }
  return out;
}

// The study file's text parsed (errors: ConfigError naming the file, and the line and column of a syntax error).
toml::table parse_study_file(const fs::path& file, const std::string& text) {
  const std::string name = file.string();
  try {
    return toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw ConfigError(name, static_cast<long>(b.line), static_cast<long>(b.column), std::string(e.description()));
  }
}

// A string key of the study file ("" when absent and not required).
std::string read_string(const toml::table& t, const std::string& file, const char* key, bool required) {
  const auto* n = t.get(key);
  if (!n) {
    if (required) throw ConfigError(file, key, "required key is missing");
    return "";
  }
  if (!n->is_string()) throw ConfigError(file, key, "expected a string");
  return n->as_string()->get();
}

// The kind must be a row of studies::study_kinds(); the refusal lists them all.
void check_kind(const std::string& file, const std::string& kind) {
  if (studies::find_study_kind(kind)) return;
  std::string list;
  for (const studies::StudyKind& k : studies::study_kinds()) list += (list.empty() ? "" : ", ") + std::string(k.name);
  throw ConfigError(file, "kind", "unknown study kind '" + kind + "' (known: " + list + ")");
}

// `set`: the overrides common to every run.
std::vector<std::string> read_common(const toml::node& n, const std::string& file) {
  const auto* a = n.as_array();
  if (!a) throw ConfigError(file, "set", "must be an array of \"section.key=value\" strings");
  std::vector<std::string> common;
  for (const auto& e : *a) {
    if (!e.is_string()) throw ConfigError(file, "set", "must be an array of \"section.key=value\" strings");
    common.push_back(e.as_string()->get());
  }
  return common;
}

// One [[group]] (the k-th): its name (default "group<k>") and its [vary] table.
compare::StudyGroup read_group(const toml::table& g, const std::string& file, std::size_t k,
                               std::vector<std::string>& notes) {
  const std::string where = "group[" + std::to_string(k) + "]";
  compare::StudyGroup grp;
  for (const auto& [gk, gv] : g) {
    const std::string key(gk.str());
    if (key == "name") {
      if (!gv.is_string()) throw ConfigError(file, where + ".name", "expected a string");
      grp.name = gv.as_string()->get();
    } else if (key == "vary") {
      if (!gv.is_table()) throw ConfigError(file, where + ".vary", "must be a table of key = [values]");
      grp.vary = read_vary(*gv.as_table(), file, where + ".vary", notes);
    } else {
      throw ConfigError(file, where + "." + key, "unknown key (known: name, vary)");
    }
  }
  if (grp.name.empty()) grp.name = "group" + std::to_string(k);
  return grp;
}

// The varied keys: one unnamed group from [vary], then every [[group]].
std::vector<compare::StudyGroup> read_groups(const toml::table& t, const std::string& file,
                                             std::vector<std::string>& notes) {
  std::vector<compare::StudyGroup> groups;
  if (const auto* n = t.get("vary")) {
    if (!n->is_table()) throw ConfigError(file, "vary", "must be a table of key = [values]");
    groups.push_back({"", read_vary(*n->as_table(), file, "vary", notes)});
  }
  if (const auto* n = t.get("group")) {
    const auto* a = n->as_array();
    if (!a || !a->is_array_of_tables()) throw ConfigError(file, "group", "must be an array of tables ([[group]])");
    for (std::size_t k = 0; k < a->size(); ++k) groups.push_back(read_group(*a->get(k)->as_table(), file, k, notes));
  }
  return groups;
}

// A number of the study file, checked against its row of compare::study_key_domains().
double in_study_domain(const std::string& file, const std::string& key, double value) {
  try {
    core::check_in_domain(*core::find_key_domain(compare::study_key_domains(), key), value);
  } catch (const core::ParamError& e) {
    throw ConfigError(file, key, e.reason);
  }
  return value;
}

// A number key of the study file (integers accepted), checked against its domain.
double read_number(const toml::node& n, const std::string& file, const std::string& key) {
  if (!n.is_number()) throw ConfigError(file, key, "expected a number, got " + value_text(n));
  return in_study_domain(file, key, n.value<double>().value_or(0.0));
}

// An integer key of the study file: a TOML integer (not a float, not even 1e9), in the range of T, in
// its domain.
template <class T>
T read_integer(const toml::node& n, const std::string& file, const std::string& key) {
  in_study_domain(file, key, static_cast<double>(checked_integer<std::int64_t>(n, file, key, IntegralFloats::refused)));
  return checked_integer<T>(n, file, key, IntegralFloats::refused);  // (within the domain: fits T; checked all the same)
}

// [limits]: what the study may cost in its own process (docs/studies.md).
compare::StudyLimits read_limits(const toml::node& n, const std::string& file) {
  const auto* t = n.as_table();
  if (!t) throw ConfigError(file, "limits", "must be a table [limits] (keys: max_runs, max_memory_gib)");
  compare::StudyLimits lim;
  for (const auto& [k, v] : *t) {
    const std::string key = "limits." + std::string(k.str());
    if (k.str() == "max_runs") lim.max_runs = static_cast<double>(read_integer<std::int64_t>(v, file, key));
    else if (k.str() == "max_memory_gib") lim.max_memory_gib = read_number(v, file, key);
    else throw ConfigError(file, key, "unknown key (known keys of [limits]: max_runs, max_memory_gib)");
  }
  return lim;
}

// [paths]: the path in H of a kind without scene runs (strip_cmin_height; docs/studies.md), each key checked
// against its row of studies::strip_cmin_path_domains(), then the rules between keys.
studies::StripCminHeightOptions read_paths(const toml::node& n, const std::string& file) {
  std::string names;
  for (const core::KeyDomain& d : studies::strip_cmin_path_domains())
    names += (names.empty() ? "" : ", ") + std::string(d.key).substr(6);
  const auto* t = n.as_table();
  if (!t) throw ConfigError(file, "paths", "must be a table [paths] (keys: " + names + ")");
  studies::StripCminHeightOptions o = studies::strip_cmin_study_defaults();
  bool rows_given = false, rtol_given = false;
  for (const auto& [k, v] : *t) {
    const std::string key = "paths." + std::string(k.str());
    const core::KeyDomain* d = core::find_key_domain(studies::strip_cmin_path_domains(), key);
    if (!d) throw ConfigError(file, key, "unknown key (known keys of [paths]: " + names + ")");
    if (d->kind == core::KeyKind::boolean) {
      if (!v.is_boolean()) throw ConfigError(file, key, "expected true or false, got " + value_text(v));
      o.branches = v.as_boolean()->get();
      continue;
    }
    double x = 0.0;
    if (d->kind == core::KeyKind::integer) {
      x = static_cast<double>(checked_integer<std::int64_t>(v, file, key, IntegralFloats::refused));
    } else {
      if (!v.is_number()) throw ConfigError(file, key, "expected a number, got " + value_text(v));
      x = v.value<double>().value_or(0.0);
    }
    try {
      core::check_in_domain(*d, x);
    } catch (const core::ParamError& e) {
      throw ConfigError(file, key, e.reason);
    }
    const std::string_view name = k.str();
    if (name == "hmin") o.hmin = x;
    else if (name == "hmax") o.hmax = x;
    else if (name == "per_decade") o.per_decade = x;
    else if (name == "rows") o.rows = static_cast<int>(x), rows_given = true;
    else if (name == "intervals") o.intervals = static_cast<int>(x);
    else if (name == "branch_rows") o.branch_rows = static_cast<int>(x);
    else if (name == "branch_intervals") o.branch_intervals = static_cast<int>(x);
    else if (name == "tolerance") o.tolerance = x;
    else if (name == "max_factor") o.max_factor = x;
    else if (name == "rtol") o.rtol = x, rtol_given = true;
    else if (name == "budget") o.budget_seconds = x;
  }
  // an explicit rows fixes the mesh (as before paths.rtol); rtol, when given too, only judges each height
  o.choose_meshes = !rows_given;
  if (rows_given && !rtol_given) o.rtol = 0.0;
  try {
    studies::check_strip_cmin_paths(o);
  } catch (const core::ParamError& e) {
    throw ConfigError(file, e.key, e.reason);
  }
  return o;
}

// [resolution]: the levels and the tolerance of the kind resolution (docs/studies.md), each key checked against its
// row of studies::resolution_key_domains(), then the rules between keys.
studies::ResolutionOptions read_resolution(const toml::node& n, const std::string& file) {
  const auto* t = n.as_table();
  if (!t) throw ConfigError(file, "resolution", "must be a table [resolution] (keys: levels, coarser, ratio, tolerance, "
                                                "tolerance_order, seeds)");
  studies::ResolutionOptions o;
  for (const auto& [k, v] : *t) {
    const std::string key = "resolution." + std::string(k.str());
    const core::KeyDomain* d = core::find_key_domain(studies::resolution_key_domains(), key);
    if (!d) throw ConfigError(file, key, "unknown key (known keys of [resolution]: levels, coarser, ratio, tolerance, "
                                         "tolerance_order, seeds)");
    const bool integer = d->kind == core::KeyKind::integer;
    if (!integer && !v.is_number()) throw ConfigError(file, key, "expected a number, got " + value_text(v));
    const double x = integer ? static_cast<double>(checked_integer<std::int64_t>(v, file, key, IntegralFloats::refused))
                             : v.value<double>().value_or(0.0);
    try {
      core::check_in_domain(*d, x);
    } catch (const core::ParamError& e) {
      throw ConfigError(file, key, e.reason);
    }
    const std::string_view name = k.str();
    if (name == "levels") o.levels = static_cast<int>(x);
    else if (name == "coarser") o.coarser = static_cast<int>(x);
    else if (name == "ratio") o.ratio = x;
    else if (name == "tolerance") o.tolerance = x;
    else if (name == "tolerance_order") o.tolerance_order = x;
    else if (name == "seeds") o.seeds = static_cast<int>(x);
  }
  try {
    studies::check_resolution_options(o);
  } catch (const core::ParamError& e) {
    throw ConfigError(file, e.key, e.reason);
  }
  return o;
}

// The keys of a study that runs scenes, refused in one that runs none (StudyKind::compute), and why.
void refuse_run_keys(const toml::table& t, const std::string& file, const std::string& kind) {
  static const std::pair<const char*, const char*> run_keys[] = {
      {"group", "[[group]] varies the runs of a study"},
      {"vary", "[vary] varies the runs of a study"},
      {"seeds", "seeds multiply the runs of a study"},
      {"fit_from", "fit_from bounds fits over runs"},
      {"share_references", "share_references shares the continuum and mean_field among runs"},
      {"share_continuum", "share_continuum shares the continuum and mean_field among runs"},
      {"limits", "[limits] bounds the runs of a study ([paths] bounds this one: at most 1000 target heights)"}};
  for (const auto& [key, why] : run_keys)
    if (t.get(key))
      throw ConfigError(file, key,
                        std::string(why) + ", and the kind '" + kind +
                            "' makes no runs: it computes from the base scene (with `set`) and [paths] only; remove it "
                            "(vary the material with another study file or --set)");
}

}  // namespace

compare::StudySpec load_study(const fs::path& file, std::string* text) {
  std::string file_text = read_config_file(file);
  compare::StudySpec s = load_study_text(file, file_text);
  if (text) *text = std::move(file_text);
  return s;
}

compare::StudySpec load_study_text(const fs::path& file, const std::string& text) {
  const std::string name = file.string();
  const toml::table t = parse_study_file(file, text);
  static const std::set<std::string> known{"study", "kind",   "description", "scene",  "set",   "seeds",
                                           "vary",  "group",  "fit_from",    "limits", "paths", "share_references",
                                           "share_continuum", "resolution"};
  for (const auto& [k, v] : t)
    if (!known.count(std::string(k.str())))
      throw ConfigError(name, std::string(k.str()),
                        "unknown key (known: study, kind, description, scene, set, seeds, fit_from, vary, group, "
                        "limits, paths, share_references, resolution)");
  compare::StudySpec s;
  s.name = read_string(t, name, "study", true);
  check_directory_name(s.name, name, "study", "out/studies/<study>");
  s.kind = read_string(t, name, "kind", true);
  s.description = read_string(t, name, "description", false);
  const std::string scene = read_string(t, name, "scene", true);
  s.scene_file = (fs::path(scene).is_absolute() ? fs::path(scene) : file.parent_path() / scene).lexically_normal().string();
  check_kind(name, s.kind);
  if (studies::find_study_kind(s.kind)->compute) {  // a kind without scene runs: [paths], no runs
    refuse_run_keys(t, name, s.kind);
    if (const auto* n = t.get("set")) s.common = read_common(*n, name);
    if (const auto* n = t.get("paths")) s.kind_options = read_paths(*n, name);
    return s;
  }
  if (const auto* n = t.get("resolution")) {
    if (!studies::find_study_kind(s.kind)->plan)
      throw ConfigError(name, "resolution", "only the kind resolution has [resolution]; the kind '" + s.kind + "' has none");
    s.kind_options = read_resolution(*n, name);
  }
  if (studies::find_study_kind(s.kind)->plan)  // the kind plans its runs from the base scene
    for (const char* key : {"group", "vary", "seeds"})
      if (t.get(key))
        throw ConfigError(name, key, std::string("the kind '") + s.kind + "' plans its runs from the base scene and " +
                                         "[resolution] (levels, seeds): remove `" + key + "`");
  if (t.get("paths"))
    throw ConfigError(name, "paths",
                      "only a kind without scene runs (strip_cmin_height) has [paths]; the kind '" + s.kind + "' runs scenes");
  if (const auto* n = t.get("seeds")) s.seeds = read_integer<int>(*n, name, "seeds");
  if (const auto* n = t.get("fit_from")) s.fit_from = read_number(*n, name, "fit_from");
  if (t.get("share_references") && t.get("share_continuum"))
    throw ConfigError(name, "share_continuum",
                      "is the earlier name of share_references, and both are given: keep share_references");
  for (const char* key : {"share_references", "share_continuum"})  // (share_continuum: the earlier name)
    if (const auto* n = t.get(key)) {
      const auto* b = n->as_boolean();
      if (!b) throw ConfigError(name, key, "must be true or false (a TOML boolean, not a string or number)");
      s.share_references = b->get();
    }
  if (const auto* n = t.get("limits")) s.limits = read_limits(*n, name);
  if (const auto* n = t.get("set")) s.common = read_common(*n, name);
  s.groups = read_groups(t, name, s.notes);
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

enum class RunFile { missing, complete, partial, unreadable, unverified, corrupt, other_config };

struct RunFileCheck {
  RunFile state = RunFile::missing;
  std::string detail;  ///< status of a partial file, the error of an unreadable one, why a checksum fails, the first difference
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

// What a run file is worth, its checksum first: a file that is not what was written is made again,
// whatever its content says (a flipped byte in /config would otherwise read as another configuration,
// one in a dataset as a complete run).
RunFileCheck check_run_file(const fs::path& file, const std::string& resolved, const std::string& hash) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return {RunFile::missing, ""};
  ChecksumCheck sum;
  ResultsHeader h;
  try {
    sum = verify_checksum(file);
    if (sum.state == Checksum::failed) return {RunFile::corrupt, sum.detail};
    h = read_results_header(file);
  } catch (const InputError& e) {
    return {RunFile::unreadable, e.what()};
  }
  if (h.resolved_toml != resolved || (!h.config_hash.empty() && h.config_hash != hash))
    return {RunFile::other_config, first_difference(h.resolved_toml, resolved)};
  if (h.config_hash.empty()) return {RunFile::unverified, "no /meta config_hash (written by an older slipfront)"};
  if (sum.state == Checksum::absent) return {RunFile::unverified, sum.detail};
  if (h.status != compare::RunStatus::complete) return {RunFile::partial, compare::to_string(h.status)};
  return {RunFile::complete, ""};
}

// Temporaries left by a killed writer (h5out's ".results.h5.tmp.<pid>").
std::string plural(long long n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

struct RunPlan {
  int code = 0;            ///< 0: go on; else the exit code (the reason was printed)
  std::vector<char> skip;  ///< per run: 1 if its results file is complete for the same configuration
  long long rerun = 0;     ///< runs with a partial, failed, unreadable, unverified or corrupt file: made again
  long long fresh = 0;     ///< runs with no file yet (every run with --force)
  std::vector<std::string> untrusted;  ///< run files made again because their checksum fails, and why
};

// DIR/study.h5 is this study's (or absent, or --force): else refused, the reason printed. Another study's
// name is refused. A kind without scene runs (strip_cmin_height) has no run files whose configurations
// would tell another study of the same name (plan_runs): its study.h5 and files are recomputed whole, so
// where either study is of such a kind, a study.h5 of another kind or another study file (`spec_toml`, the
// text study.h5 keeps) is refused too.
bool owns_study_file(const fs::path& dir, const compare::StudySpec& spec, const std::string& spec_toml, bool force,
                     std::ostream& err) {
  if (!fs::exists(dir / "study.h5") || force) return true;
  StudyHeader other;
  try {
    other = read_study_header(dir / "study.h5");
  } catch (const InputError&) {
    other = {};
  }
  const auto refuse = [&](const std::string& why) {
    err << "slipfront: error: '" << (dir / "study.h5").string() << "' belongs to " << why
        << " (use --force to replace it, or --out for another directory)\n";
    return false;
  };
  if (other.name != spec.name)
    return refuse((other.name.empty() ? std::string("no readable study") : "the study '" + other.name + "'") +
                  ", not to '" + spec.name + "'");
  const auto computed = [](const std::string& kind) {
    const studies::StudyKind* k = studies::find_study_kind(kind);
    return k != nullptr && k->compute != nullptr;
  };
  if (!computed(spec.kind) && !computed(other.kind)) return true;  // the run files are checked one by one
  if (other.kind != spec.kind)
    return refuse("the study '" + other.name + "' of kind '" + other.kind + "', not '" + spec.kind + "'");
  if (other.toml != spec_toml)
    return refuse("the study '" + other.name + "' made from another study file (" + first_difference(other.toml, spec_toml) + ")");
  return true;
}

// Creates DIR/runs/ (each run's directory is created when the run starts: make_run), checks the files
// already there (the table in docs/studies.md, "Resuming") and removes the temporaries of killed
// writers. Nothing is touched when it refuses.
RunPlan plan_runs(const fs::path& dir, const compare::StudySpec& spec, const std::string& spec_toml,
                  const std::vector<compare::StudyRun>& runs, const std::vector<std::string>& resolved, bool force,
                  std::ostream& err) {
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
  if (!owns_study_file(dir, spec, spec_toml, force, err)) return refuse();
  std::vector<std::string> other_config;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const fs::path run_dir = dir / "runs" / runs[i].id;
    if (force) {
      ++p.fresh;
      continue;
    }
    const RunFileCheck c = check_run_file(run_dir / "results.h5", resolved[i], config_hash(resolved[i]));
    switch (c.state) {
      case RunFile::complete: p.skip[i] = 1; break;
      case RunFile::missing: ++p.fresh; break;
      case RunFile::other_config: other_config.push_back("runs/" + runs[i].id + "/results.h5: " + c.detail); break;
      case RunFile::corrupt:
        p.untrusted.push_back("runs/" + runs[i].id + "/results.h5: " + c.detail);
        ++p.rerun;
        break;
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
  // temporaries of dead writers only (apps/h5out.hpp): a run file being written by a live process stays
  for (const auto& r : runs) remove_stale_temporaries(dir / "runs" / r.id, ".results.h5.tmp.");
  return p;
}

// The counters every rank reports at the end (summed over the ranks under MPI).
enum Count : std::size_t { n_complete, n_interrupted, n_failed, n_write_failures, n_stopped, n_counts };

// ---------------------------------------------------------------------------------------------
// The stages of `slipfront study`, in order; study_command lists them.

// The study as read: its runs with their scenes and resolved configurations, and where it goes.
struct Study {
  compare::StudySpec spec;
  std::string spec_toml;  ///< the study file's text (kept in study.h5)
  std::vector<compare::StudyRun> runs;
  std::vector<compare::Scene> scenes;  ///< per run
  std::vector<std::string> resolved;   ///< per run: the scene's resolved TOML
  compare::StudyEstimate estimate;     ///< what the study holds in its own process (checked against its [limits])
  compare::Scene base;                 ///< a kind without scene runs: the base scene (with `set` and --set)
  fs::path dir;
  fs::path run_file(std::size_t i) const { return dir / "runs" / runs[i].id / "results.h5"; }
};

// Where the runs go: the threads of this process, on one process or on every MPI rank.
struct Engine {
  std::unique_ptr<MpiEngine> mpi;  ///< null: the thread pool of one process
  bool root = true;                ///< rank 0 (or no MPI): prints, plans, analyses and writes study.h5
  unsigned threads = 1;            ///< runs at once in this process
  std::string name() const { return mpi ? "mpi" : "threads"; }
  int workers() const { return static_cast<int>(threads) * (mpi ? mpi->size() : 1); }
  std::string where() const {
    return mpi ? plural(mpi->size(), "MPI rank", "MPI ranks") + (threads > 1 ? " x " + plural(threads, "thread", "threads") : "")
               : plural(threads, "thread", "threads");
  }
};

// Which runs this invocation makes (the plan of rank 0, known to every rank).
struct Schedule {
  int code = 0;                   ///< 0: go on; else the exit code (rank 0 printed why)
  std::vector<std::size_t> todo;  ///< the runs to make, in order
  std::vector<int> skipped;       ///< per run: 1 if its results file is complete already
  long long rerun = 0, fresh = 0; ///< rank 0 only: runs made again, runs with no file yet
  std::vector<std::string> untrusted; ///< rank 0 only: run files made again because their checksum fails
  long long n_skipped() const { return static_cast<long long>(skipped.size() - todo.size()); }
};

// What the runs of this process left.
struct RunsMade {
  explicit RunsMade(std::size_t n) : results(n), in_memory(n, 0) {}
  std::vector<std::vector<compare::ModelResult>> results;  ///< per run, without the fields
  std::vector<char> in_memory;                              ///< per run: 1 if made by this process
  std::vector<long long> counts = std::vector<long long>(n_counts, 0);  ///< by Count (summed by end_runs)
  std::size_t taken = 0;  ///< without MPI: the indices the workers took from the local counter
};

// How the runs ended, over every rank.
struct RunsEnd {
  bool all_reported = true;    ///< every MPI rank answered
  std::size_t handed_out = 0;  ///< runs of the schedule started (all of them unless stopped)
  bool stopped = false;        ///< a stop was requested here or on another rank
};

// What rank 0 knows of every run at the end.
struct Tally {
  long long complete = 0, interrupted = 0, failed = 0, lost = 0, not_started = 0;
  std::vector<std::string> read_problems;  ///< runs started without a readable results file
};

// (a) The engine: the thread pool, or MPI when mpirun started this process (then every rank runs
// study_command). False (the reason printed) when mpirun started several processes and no MPI.
bool load_engine(bool quiet, Engine& engine, std::ostream& err) {
  if (const int launched = mpirun_size(); launched > 0) {
    std::string why;
    engine.mpi = MpiEngine::load(why);
    if (!engine.mpi && !build_info::mpi_engine_built) why = "this slipfront was built without MPI; " + why;
    if (!engine.mpi && launched > 1) {
      err << "slipfront: error: started by mpirun as one of " << launched
          << " processes, but the MPI engine could not be loaded (" << why
          << "); without it every process would run the whole study. Run `slipfront study` without mpirun "
             "(it uses threads), or build slipfront where MPI is installed (docs/studies.md)\n";
      return false;
    }
    if (!engine.mpi && !quiet)
      err << "slipfront: note: started by mpirun with one process and no MPI engine (" << why << "): using threads\n";
  }
  engine.root = !engine.mpi || engine.mpi->rank() == 0;
  return true;
}

// The base scene's text, read once for every run. A `scene` that is not a readable configuration file
// is refused naming the study's key.
std::string read_scene_text(const compare::StudySpec& spec, const std::string& study_file) {
  try {
    return read_config_file(spec.scene_file);
  } catch (const ConfigError& e) {
    throw ConfigError(study_file, "scene", spec.scene_file + ": " + e.reason);
  }
}

// The study's size (compare::estimate_study) against its [limits], before any run is expanded: the
// count of runs first (from the file alone), then the memory, from one sample run per group.
compare::StudyEstimate check_study_size(const compare::StudySpec& spec, const std::string& study_file,
                                        const std::string& scene_text, const std::vector<std::string>& extra) {
  try {
    compare::StudyEstimate runs_only;
    runs_only.runs = compare::count_runs(spec);
    compare::check_study_limits(spec, runs_only);
    std::vector<compare::StudyRun> samples = compare::sample_runs(spec);
    std::vector<compare::Scene> scenes;
    std::vector<std::size_t> resolved;
    for (auto& r : samples) {
      r.overrides.insert(r.overrides.end(), extra.begin(), extra.end());
      scenes.push_back(parse_scene(scene_text, spec.scene_file, r.overrides));
      resolved.push_back(to_toml(scenes.back()).size());
    }
    const compare::StudyEstimate e = compare::estimate_study(spec, samples, scenes, resolved);
    compare::check_study_limits(spec, e);
    return e;
  } catch (const core::ParamError& e) {
    throw ConfigError(study_file, e.key, e.reason);
  }
}

// The kind's analysis needs its models in every run (studies::StudyKind::needs).
// (`what`: "run 0000", or "the base scene" of a kind without scene runs.)
void check_models(const compare::StudySpec& spec, const std::string& study_file, const std::string& what,
                  const compare::Scene& scene) {
  const studies::StudyKind& kind = *studies::find_study_kind(spec.kind);
  const std::string missing = studies::missing_models(kind, scene);
  if (missing.empty()) return;
  std::string listed;
  for (const auto& m : scene.models) listed += (listed.empty() ? "\"" : ", \"") + m + "\"";
  throw ConfigError(study_file, "kind",
                    "the analysis of kind '" + spec.kind + "' needs " + studies::describe(kind.needs) + ", but " + what +
                        " has models = [" + listed + "] (no " + missing +
                        "): list the models it needs in the scene, or in the study's `set` (for example 'models=[\"continuum\",\"discrete\"]')");
}

// A kind that plans its runs (resolution): its checks of the base scene (with `set` and --set), then its groups;
// --set joins the study's `set`: it makes the base scene the levels refine.
void plan_groups(compare::StudySpec& spec, const std::string& scene_text, const std::vector<std::string>& extra,
                 const std::string& study_file) {
  spec.common.insert(spec.common.end(), extra.begin(), extra.end());
  const compare::Scene base = parse_scene(scene_text, spec.scene_file, spec.common);
  const studies::StudyKind& kind = *studies::find_study_kind(spec.kind);
  try {
    if (kind.check) kind.check(spec, base);
    spec.groups = kind.plan(spec, base);
  } catch (const core::ParamError& e) {
    throw ConfigError(study_file, e.key, e.reason);
  }
}

// (b) The study read and every run validated before any work (every rank does the same): its size
// within the study's [limits] before any run is expanded, then every run's scene and the models its
// kind needs. Nothing (the reason printed) on a configuration error.
std::optional<Study> read_study(const StudyOptions& opts, std::ostream& err) {
  Study study;
  const std::string file = opts.study.string();
  try {
    if (opts.study_text.empty()) {
      study.spec = load_study(opts.study, &study.spec_toml);
    } else {
      study.spec = load_study_text(opts.study, opts.study_text);
      study.spec_toml = opts.study_text;
    }
    const std::string scene_text = read_scene_text(study.spec, file);
    std::vector<std::string> extra = opts.overrides;  // --set, after the study's own overrides in every run
    if (studies::find_study_kind(study.spec.kind)->plan) {  // ... but before the levels a kind plans from the base scene
      plan_groups(study.spec, scene_text, extra, file);
      extra.clear();
    }
    if (const studies::StudyKind& kind = *studies::find_study_kind(study.spec.kind); kind.compute) {
      // no runs: the base scene with the study's `set` and --set, checked for the kind's computation
      std::vector<std::string> overrides = study.spec.common;
      overrides.insert(overrides.end(), opts.overrides.begin(), opts.overrides.end());
      study.base = parse_scene(scene_text, study.spec.scene_file, overrides);
      check_models(study.spec, file, "the base scene", study.base);
      if (kind.check) {
        try {
          kind.check(study.spec, study.base);
        } catch (const core::ParamError& e) {
          throw ConfigError(file, e.key, e.reason);
        }
      }
      study.dir = opts.out.empty() ? fs::path("out") / "studies" / study.spec.name : opts.out;
      return study;
    }
    study.estimate = check_study_size(study.spec, file, scene_text, extra);
    study.runs = compare::expand(study.spec);
    for (auto& r : study.runs) {
      r.overrides.insert(r.overrides.end(), extra.begin(), extra.end());
      study.scenes.push_back(parse_scene(scene_text, study.spec.scene_file, r.overrides));
      check_models(study.spec, file, "run " + r.id, study.scenes.back());
      study.resolved.push_back(to_toml(study.scenes.back()));
    }
  } catch (const ConfigError& e) {
    err << "slipfront: error: " << e.what() << "\n";
    return std::nullopt;
  }
  if (!opts.quiet)
    for (const auto& note : study.spec.notes) err << "slipfront: note: " << note << "\n";
  study.dir = opts.out.empty() ? fs::path("out") / "studies" / study.spec.name : opts.out;
  return study;
}

// (c) The plan (rank 0, then sent to every rank): DIR held by rank 0 (`lock`, until study.h5 is in place: one
// writer at a time, apps/paths.hpp), then which runs are complete already (resume).
Schedule share_plan(const Study& study, bool force, const Engine& engine, OutputLock& lock, std::ostream& err) {
  const std::size_t n = study.runs.size();
  // plan[0]: 0 to go on, else the exit code; plan[1 + i]: 1 if run i is skipped.
  std::vector<char> plan(1 + n, 0);
  Schedule s;
  if (engine.root) {
    RunPlan p;
    if (const std::string problem = create_and_lock(study.dir, lock); !problem.empty()) {
      err << "slipfront: error: " << problem << "\n";
      p.code = exit_code::usage;
    } else {
      p = plan_runs(study.dir, study.spec, study.spec_toml, study.runs, study.resolved, force, err);
    }
    plan[0] = static_cast<char>(p.code);
    std::copy(p.skip.begin(), p.skip.end(), plan.begin() + 1);
    s.rerun = p.rerun;
    s.fresh = p.fresh;
    s.untrusted = p.untrusted;
  }
  if (engine.mpi) engine.mpi->broadcast(plan.data(), plan.size(), -1);
  s.code = plan[0];
  if (s.code != 0) return s;
  s.skipped.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (plan[1 + i]) s.skipped[i] = 1;
    else s.todo.push_back(i);
  }
  return s;
}

// (d) Runs at once in this process: `threads` (default: every core), under MPI `threads` per rank
// (default 1; 1 when the MPI library cannot serialise calls from several threads).
unsigned threads_per_process(unsigned threads, const MpiEngine* mpi, std::ostream& err) {
  if (!mpi) return threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  if (threads > 1 && !mpi->serialized()) {
    err << "slipfront: note: this MPI library gives no MPI_THREAD_SERIALIZED: one run at a time per rank\n";
    return 1;
  }
  return threads ? threads : 1u;
}

// The start line: the runs, those complete already and those made again, on what, to where.
void print_start(std::ostream& err, const Study& study, const Schedule& s, const Engine& engine) {
  err << "slipfront: study " << study.spec.name << " (" << study.spec.kind
      << "): " << plural(static_cast<long long>(study.runs.size()), "run", "runs") << " ("
      << compare::describe(study.estimate) << ")";
  if (s.n_skipped() > 0 || s.rerun > 0)
    err << ", " << s.n_skipped() << " complete already (skipped), " << s.todo.size() << " to run (" << s.rerun
        << " partial, failed or unverified, " << s.fresh << " new)";
  err << " on " << engine.where() << " -> " << study.dir.string() << "\n";
  if (!s.untrusted.empty())
    err << "slipfront: note: " << plural(static_cast<long long>(s.untrusted.size()), "run file is", "run files are")
        << " not trusted (the checksum fails: not what was written) and made again:\n";
  for (std::size_t k = 0; k < s.untrusted.size() && k < 5; ++k) err << "  " << s.untrusted[k] << "\n";
  if (s.untrusted.size() > 5) err << "  ... and " << s.untrusted.size() - 5 << " more (all in study.h5, /study/runs@untrusted)\n";
}

// Stop requests: a signal to this process, or under MPI a stop anywhere (the rank that sees a signal
// raises the stop counter at rank 0, the others look at it every 50 ms). Called from every worker.
class StopRequests {
 public:
  explicit StopRequests(MpiEngine* mpi) : mpi_(mpi) {}
  bool operator()() {
    if (stop_signal.load(std::memory_order_relaxed)) {
      if (mpi_ && !stop_sent_.exchange(true)) {
        try {
          mpi_->fetch_add(slipfront_mpi_stop, 1);
        } catch (const std::exception&) {
        }
      }
      return true;
    }
    if (!mpi_ || remote_stop_.load(std::memory_order_relaxed)) return remote_stop_.load();
    const auto now = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now().time_since_epoch()).count();
    auto last = last_remote_check_.load();
    if (now - last >= 50 && last_remote_check_.compare_exchange_strong(last, now)) {
      mpi_->progress();
      if (mpi_->try_read(slipfront_mpi_stop) > 0) remote_stop_ = true;
    }
    return remote_stop_.load();
  }

 private:
  MpiEngine* mpi_;
  std::atomic<bool> remote_stop_{false}, stop_sent_{false};
  std::atomic<std::int64_t> last_remote_check_{0};
};

// The progress line: on rank 0's terminal only, the runs finished of this invocation's, elapsed, eta.
struct StudyProgress {
  std::ostream& err;
  bool on;
  std::string name;
  std::size_t total;
  Clock::time_point start;
  JsonProgress* json = nullptr;  // --progress json (rank 0)

  void update(std::size_t finished) const {
    if (json) json->study(name, finished, total);
    if (!on) return;
    const double el = std::chrono::duration<double>(Clock::now() - start).count();
    err << "\r[study " << name << "] " << finished << "/" << total << " runs, elapsed " << static_cast<int>(el)
        << " s, eta "
        << static_cast<int>(el * static_cast<double>(total - std::min(finished, total)) / static_cast<double>(finished))
        << " s   " << std::flush;
  }
  void end() const {
    if (on) err << "\n";
  }
};

// The shared references (docs/studies.md): for each model of compare::shareable_references of a run's scene (the
// continuum, mean_field), the model is run once per distinct scene of that model — the run's group and its
// overrides without the keys the model does not read (compare::reference_ignores: the seed, N, ...) — by the first
// run that needs it, while the other runs of this process that need it wait; every run's file holds a copy (label
// shared_from_run: the study's first run, in its order, that shares it — not the run that happened to compute it,
// which depends on the workers' timing: the files are then the same whatever the scheduling, -j and resumes
// included). Under MPI each rank computes its own. A model that fails or is
// interrupted is handed to its runs as it is, as each run's own would have been (both are deterministic).
class SharedReferences {
 public:
  using Result = std::shared_ptr<const compare::ModelResult>;
  Result get(const Study& study, std::size_t i, const std::string& model, const compare::RunControl& ctl) {
    const std::string key = key_of(study, i, model);
    std::promise<Result> mine;
    std::shared_future<Result> f;
    bool compute = false;
    {
      std::lock_guard lock(m_);
      const auto it = cache_.find(key);
      if (it != cache_.end()) {
        f = it->second;
      } else {
        f = mine.get_future().share();
        cache_.emplace(key, f);
        compute = true;
      }
    }
    if (compute) {
      try {
        compare::Scene alone = study.scenes[i];
        alone.models = {model};
        auto r = compare::run_scene(alone, ctl);
        std::size_t first = 0;  // the first run sharing it (i at the latest)
        while (first < i && key_of(study, first, model) != key) ++first;
        r.at(0).labels["shared_from_run"] = study.runs[first].id;
        mine.set_value(std::make_shared<const compare::ModelResult>(std::move(r.at(0))));
      } catch (...) {
        mine.set_exception(std::current_exception());
      }
    }
    return f.get();
  }

 private:
  // The model's scene in run i: its group and its overrides without the keys the model does not read.
  static std::string key_of(const Study& study, std::size_t i, const std::string& model) {
    std::string key = model + "\n" + study.runs[i].group;
    for (const auto& o : study.runs[i].overrides)
      if (!compare::reference_ignores(model, o.substr(0, o.find('=')))) key += "\n" + o;
    return key;
  }
  std::mutex m_;
  std::map<std::string, std::shared_future<Result>> cache_;
};

// One run made and written to its file (a write error is reported on `err_all`, under `io`); its
// results come back without the fields: the analysis needs events, series and tables.
struct MadeRun {
  std::vector<compare::ModelResult> models;
  compare::RunStatus status = compare::RunStatus::complete;
  bool written = true;
};

MadeRun make_run(const Study& study, std::size_t i, StopRequests& stop, const std::string& command_line,
                 const MpiEngine* mpi, std::mutex& io, std::ostream& err_all, SharedReferences* shared) {
  const auto t0 = Clock::now();
  compare::RunControl ctl;
  ctl.stop = [&stop] { return stop(); };
  MadeRun made;
  compare::Comparison cmp;
  RunMeta meta;
  meta.command_line = command_line + "  [study run " + study.runs[i].id +
                      (mpi ? ", MPI rank " + std::to_string(mpi->rank()) + " of " + std::to_string(mpi->size()) : "") +
                      "]";
  try {
    const compare::Scene& scene = study.scenes[i];
    std::vector<SharedReferences::Result> held;
    std::map<std::string, const compare::ModelResult*> given;
    if (shared && study.spec.share_references)
      for (const auto& m : compare::shareable_references(scene)) given[m] = held.emplace_back(shared->get(study, i, m, ctl)).get();
    compare::SceneResult sr =
        given.empty() ? compare::run_scene_alongside(scene, ctl) : compare::run_scene_with_references(scene, given, ctl);
    made.models = std::move(sr.models);
    cmp = std::move(sr.comparison);
  } catch (const core::Interrupted& e) {
    meta.status = compare::RunStatus::interrupted;
    meta.message = e.what();
  } catch (const std::exception& e) {
    meta.status = compare::RunStatus::failed;
    meta.message = e.what();
  }
  meta.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  made.status = overall_status(made.models, meta.status);
  try {
    std::error_code ec;
    fs::create_directories(study.run_file(i).parent_path(), ec);  // (created when the run is made: a
    if (ec)                                                        // stopped study leaves no empty ones)
      throw OutputError("cannot create '" + study.run_file(i).parent_path().string() + "': " + ec.message());
    write_results(study.run_file(i), study.scenes[i], study.resolved[i], made.models, meta, &cmp);
  } catch (const std::exception& e) {
    made.written = false;
    std::lock_guard lock(io);
    err_all << "slipfront: error: run " << study.runs[i].id
            << (mpi ? " (rank " + std::to_string(mpi->rank()) + ")" : "") << ": " << e.what() << "\n";
  }
  for (auto& m : made.models) {
    m.snapshots.clear();
    m.snapshot_t.clear();
    m.contacts.clear();
    m.contacts_2d.clear();
  }
  return made;
}

// (d) The runs: on the threads of this process, each taking the next run of the schedule (under MPI
// from the counter at rank 0, so every rank shares one schedule).
RunsMade run_points(const Study& study, const std::vector<std::size_t>& todo, const Engine& engine,
                    StopRequests& stop, const std::string& command_line, const StudyProgress& progress,
                    std::ostream& err_all) {
  MpiEngine* const mpi = engine.mpi.get();
  RunsMade made(study.runs.size());
  SharedReferences shared;
  std::mutex io;
  std::size_t done = 0;
  auto job = [&](std::size_t i) {
    MadeRun run = make_run(study, i, stop, command_line, mpi, io, err_all, &shared);
    made.results[i] = std::move(run.models);
    std::lock_guard lock(io);
    made.in_memory[i] = 1;
    ++made.counts[run.status == compare::RunStatus::complete      ? n_complete
                  : run.status == compare::RunStatus::interrupted ? n_interrupted
                                                                  : n_failed];
    if (!run.written) ++made.counts[n_write_failures];
    std::size_t finished = ++done;
    if (mpi) finished = static_cast<std::size_t>(mpi->fetch_add(slipfront_mpi_finished, 1) + 1);
    progress.update(finished);
  };
  std::atomic<std::size_t> next_local{0};
  compare::run_workers(
      std::max(1u, std::min<unsigned>(engine.threads, static_cast<unsigned>(std::max<std::size_t>(todo.size(), 1)))),
      [&]() -> std::optional<std::size_t> {
        if (stop()) return std::nullopt;
        const auto k = mpi ? static_cast<std::size_t>(mpi->fetch_add(slipfront_mpi_next, 1)) : next_local.fetch_add(1);
        if (k >= todo.size()) return std::nullopt;
        return todo[k];
      },
      job);
  progress.end();
  made.counts[n_stopped] = stop() ? 1 : 0;
  made.taken = next_local.load();
  return made;
}

// (e) Every rank done: the counters summed (under MPI, also the sign that every run file is
// written; after a stop, ranks that do not answer within 0.5 s are not waited for).
RunsEnd end_runs(RunsMade& made, std::size_t scheduled, const Engine& engine) {
  RunsEnd end;
  end.handed_out = scheduled;
  std::vector<long long>& counts = made.counts;
  if (engine.mpi) {
    const bool stopped_here = counts[n_stopped] != 0;
    end.all_reported = engine.mpi->sum(counts, stopped_here ? 0.5 : -1.0);
    if (engine.root && (stopped_here || counts[n_stopped] != 0))
      end.handed_out =
          std::min<std::size_t>(scheduled, static_cast<std::size_t>(engine.mpi->try_read(slipfront_mpi_next)));
  } else if (counts[n_stopped]) {
    end.handed_out = std::min(scheduled, made.taken);
  }
  end.stopped = counts[n_stopped] != 0 || stop_signal.load();
  return end;
}

// (f) Rank 0: results in memory, or read back from the run files of skipped runs and of runs made
// by other ranks (runs never started have none); every run counted by how it ended.
Tally read_back(const Study& study, const Schedule& schedule, std::size_t handed_out, RunsMade& made) {
  const std::size_t n = study.runs.size();
  std::vector<char> started(n, 0);
  for (std::size_t k = 0; k < handed_out; ++k) started[schedule.todo[k]] = 1;
  Tally tally;
  std::vector<char> lost(n, 0);  // started, but no readable results file (its process died, or writing failed)
  for (std::size_t i = 0; i < n; ++i) {
    if (made.in_memory[i] || !(schedule.skipped[i] || started[i])) continue;
    std::error_code ec;
    if (!fs::exists(study.run_file(i), ec)) {
      lost[i] = 1;
      tally.read_problems.push_back("run " + study.runs[i].id + ": no results file (its process stopped before writing it)");
      continue;
    }
    try {
      made.results[i] = read_results(study.run_file(i), {.fields = false, .verified = true}).models;
    } catch (const InputError& e) {
      lost[i] = 1;
      tally.read_problems.push_back("run " + study.runs[i].id + ": cannot read back its results: " + e.what());
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!schedule.skipped[i] && !started[i]) ++tally.not_started;
    else if (lost[i]) ++tally.lost;
    else {
      const std::vector<compare::ModelResult>& r = made.results[i];
      const compare::RunStatus s = r.empty() ? compare::RunStatus::failed : overall_status(r);
      ++(s == compare::RunStatus::complete ? tally.complete
         : s == compare::RunStatus::interrupted ? tally.interrupted
                                                : tally.failed);
    }
  }
  return tally;
}

// The status and message of the study as a whole: interrupted when a stop left runs undone.
RunMeta study_meta(const std::string& command_line, const Tally& t, std::size_t n, long long n_skipped,
                   const RunsEnd& end) {
  RunMeta meta;
  meta.command_line = command_line;
  if (end.stopped && t.complete == static_cast<long long>(n)) {
    meta.message = "a stop was requested after every run had finished";  // nothing was lost: complete
  } else if (end.stopped) {
    meta.status = compare::RunStatus::interrupted;
    meta.message = "stopped: " + std::to_string(t.complete) + " of " + std::to_string(n) + " runs complete (" +
                   std::to_string(n_skipped) + " of them from an earlier invocation), " +
                   std::to_string(t.interrupted) + " interrupted, " + std::to_string(t.failed) + " failed, " +
                   (t.lost ? std::to_string(t.lost) + " without a results file, " : "") +
                   std::to_string(t.not_started) + " not started; run the same command again to resume";
    if (!end.all_reported) meta.message += " (some MPI ranks did not report after the stop)";
  }
  return meta;
}

// The analysis of the study kind (a failed analysis fails the study); the runs that could not be
// read back are notes.
studies::StudyReport analyse(const Study& study, const RunsMade& made, const Tally& tally, RunMeta& meta) {
  studies::StudyReport report;
  try {
    report = studies::analyse_study(study.spec, study.runs, study.scenes, made.results);
  } catch (const std::exception& e) {
    meta.status = compare::RunStatus::failed;
    meta.message = std::string("analysis: ") + e.what();
    report.notes = study.spec.notes;
  }
  report.notes.insert(report.notes.end(), tally.read_problems.begin(), tally.read_problems.end());
  return report;
}

// The summary on stdout: the status, the runs, the scalars with their intervals, the notes.
void print_summary(std::ostream& out, const Study& study, const RunMeta& meta, const Engine& engine, long long computed,
                   long long n_skipped, std::size_t n_untrusted, const Tally& t, const studies::StudyReport& report) {
  out << study.spec.name << " (" << study.spec.kind << "): " << compare::to_string(meta.status) << ", "
      << study.runs.size() << " runs in " << static_cast<int>(meta.wall_seconds * 10) / 10.0 << " s on "
      << engine.where() << " -> " << (study.dir / "study.h5").string() << "\n";
  out << "  runs: " << computed << " run now, " << n_skipped << " skipped (complete from an earlier invocation)";
  if (n_untrusted > 0) out << ", " << n_untrusted << " made again because their file failed its checksum";
  if (t.interrupted || t.failed || t.lost || t.not_started)
    out << "; " << t.complete << " complete, " << t.interrupted << " interrupted, " << t.failed << " failed, "
        << (t.lost ? std::to_string(t.lost) + " without a results file, " : "") << t.not_started << " not started";
  out << "\n";
  for (const auto& line : report.summary) out << line << "\n";
  for (const auto& [k, v] : report.scalars)
    if (report.summary.empty() && k.find("_ci_") == std::string::npos && k.find("_points") == std::string::npos) {
      out << "  " << k << " = " << v;
      const auto lo = report.scalars.find(k + "_ci_low"), hi = report.scalars.find(k + "_ci_high");
      if (lo != report.scalars.end() && hi != report.scalars.end())
        out << "  (95% CI " << lo->second << " .. " << hi->second << ")";
      out << "\n";
    }
  for (const auto& note : report.notes) out << "  note: " << note << "\n";
}

// (f) Rank 0 concludes: reads back, analyses, writes study.h5, prints the summary; the exit code.
int conclude(const StudyOptions& opts, const Study& study, const Schedule& schedule, const Engine& engine,
             RunsMade& made, const RunsEnd& end, Clock::time_point wall0, std::ostream& out, std::ostream& err) {
  const Tally tally = read_back(study, schedule, end.handed_out, made);
  RunMeta meta = study_meta(opts.command_line, tally, study.runs.size(), schedule.n_skipped(), end);
  const studies::StudyReport report = analyse(study, made, tally, meta);
  meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  const auto computed = static_cast<long long>(end.handed_out);
  const StudyExecution exec{engine.name(), engine.workers(), computed, schedule.skipped, schedule.untrusted};
  try {
    write_study(study.dir / "study.h5", study.spec, study.spec_toml, study.runs, report, meta, exec);
  } catch (const std::exception& e) {
    err << "slipfront: error: cannot write " << (study.dir / "study.h5").string() << ": " << e.what() << "\n";
    return exit_code::failed;
  }
  print_summary(out, study, meta, engine, computed, schedule.n_skipped(), schedule.untrusted.size(), tally, report);
  if (meta.status == compare::RunStatus::interrupted) {
    err << "slipfront: " << meta.message << "\n";
    return exit_code::interrupted;
  }
  if (meta.status != compare::RunStatus::complete || made.counts[n_write_failures] != 0 || !tally.read_problems.empty())
    return exit_code::failed;
  return exit_code::ok;
}

// (g) Under MPI every rank exits with rank 0's code (mpirun reports the first non-zero one), and not
// before rank 0 is done: a rank ending early with a non-zero code makes mpirun abort the others.
int share_exit_code(MpiEngine& mpi, int code, bool root_stopped) {
  int shared = code;
  if (mpi.broadcast(&shared, sizeof shared, root_stopped ? 0.5 : -1.0)) code = shared;
  mpi.finalize();
  return code;
}

// A kind without scene runs (studies::StudyKind::compute), on rank 0: its computation from the base scene, stoppable
// by SIGINT/SIGTERM, its files and DIR/study.h5 written (as a study's: temporary and rename, /meta status complete,
// interrupted or failed), the summary printed; the exit code.
int compute_study(const StudyOptions& opts, const Study& study, const Engine& engine, Clock::time_point wall0,
                  std::ostream& out, std::ostream& err) {
  const studies::StudyKind& kind = *studies::find_study_kind(study.spec.kind);
  OutputLock lock;  // DIR held until study.h5 is in place (apps/paths.hpp)
  if (const std::string problem = create_and_lock(study.dir, lock); !problem.empty()) {
    err << "slipfront: error: " << problem << "\n";
    return exit_code::usage;
  }
  if (!owns_study_file(study.dir, study.spec, study.spec_toml, opts.force, err)) return exit_code::usage;
  const std::string tag = "[study " + study.spec.name + "] ";
  if (!opts.quiet)
    err << "slipfront: study " << study.spec.name << " (" << study.spec.kind << "): no runs, computed from "
        << study.spec.scene_file << " and [paths] -> " << study.dir.string() << "\n";
  const StudySignals signals;
  // Progress: the kind's lines as they come; on a terminal also the solves so far and the elapsed time.
  const bool tty = !opts.quiet && ::isatty(STDERR_FILENO);
  long long solves = 0;
  double shown = -1.0;
  bool open_line = false;
  studies::StudyWork work;
  work.stop = [&] {
    ++solves;
    const double el = std::chrono::duration<double>(Clock::now() - wall0).count();
    if (tty && el - shown >= 0.25) {
      err << "\r" << tag << solves << " solves, elapsed " << static_cast<int>(el) << " s   " << std::flush;
      shown = el;
      open_line = true;
    }
    return stop_signal.load();
  };
  work.log = [&](const std::string& line) {
    if (opts.quiet) return;
    if (open_line) err << "\n";
    open_line = false;
    err << tag << line << "\n";
  };
  studies::StudyReport report;
  report.notes = study.spec.notes;
  RunMeta meta;
  meta.command_line = opts.command_line;
  try {
    const studies::StudyOutcome o = kind.compute(report, study.spec, study.base, work);
    meta.status = o.status;
    meta.message = o.message;
  } catch (const std::exception& e) {
    meta.status = compare::RunStatus::failed;
    meta.message = std::string("computation: ") + e.what();
  }
  if (open_line) err << "\n";
  meta.wall_seconds = std::chrono::duration<double>(Clock::now() - wall0).count();
  try {
    for (const auto& [name, text] : report.files) write_text_file(study.dir / name, text);
    const StudyExecution exec{engine.name(), 1, 0, {}, {}};
    write_study(study.dir / "study.h5", study.spec, study.spec_toml, {}, report, meta, exec);
  } catch (const std::exception& e) {
    err << "slipfront: error: cannot write the results of " << study.spec.name << " in " << study.dir.string() << ": "
        << e.what() << "\n";
    return exit_code::failed;
  }
  out << study.spec.name << " (" << study.spec.kind << "): " << compare::to_string(meta.status) << ", no runs, "
      << static_cast<int>(meta.wall_seconds * 10) / 10.0 << " s -> " << (study.dir / "study.h5").string();
  for (const auto& [name, text] : report.files) out << ", " << (study.dir / name).string();
  out << "\n";
  for (const auto& [k, v] : report.scalars) out << "  " << k << " = " << v << "\n";
  for (const auto& note : report.notes) out << "  note: " << note << "\n";
  if (meta.status == compare::RunStatus::interrupted) {
    err << "slipfront: " << meta.message << "\n";
    return exit_code::interrupted;
  }
  if (meta.status != compare::RunStatus::complete) {
    err << "slipfront: error: " << study.spec.name << ": " << meta.message << "\n";
    return exit_code::failed;
  }
  return exit_code::ok;
}

}  // namespace

namespace {

// What a kind runs: "scenes" (the study file's groups x seeds), "planned" (runs planned from the base scene), "none"
// (a computation from the base scene, no scene runs).
const char* runs_of(const studies::StudyKind& k) { return k.compute ? "none" : k.plan ? "planned" : "scenes"; }

// `slipfront study --list-kinds [--json]`: the table, as text (one paragraph a kind) or JSON.
int list_kinds(const StudyOptions& opts, std::ostream& out) {
  if (opts.json) {
    out << study_kinds_json() << "\n";
    return exit_code::ok;
  }
  for (const studies::StudyKind& k : studies::study_kinds())
    out << k.name << " (" << studies::describe(k.needs) << "; runs: " << runs_of(k) << ")\n  " << k.description << "\n";
  return exit_code::ok;
}

}  // namespace

std::string study_kinds_json() {
  std::string json = "{\"kinds\": [";
  for (const studies::StudyKind& k : studies::study_kinds()) {
    json += (json.back() == '[' ? "\n  " : ",\n  ");
    json += "{\"name\": " + quoted_string(std::string(k.name)) + ", \"description\": " +
            quoted_string(std::string(k.description)) + ", \"models\": " + quoted_string(studies::describe(k.needs)) +
            ", \"runs\": \"" + runs_of(k) + "\", \"analysis\": " + (k.analyse || k.compute ? "true" : "false") + "}";
  }
  return json + "\n]}";
}

int study_command(const StudyOptions& opts, std::ostream& out_all, std::ostream& err_all) {
  if (opts.list_kinds) return list_kinds(opts, out_all);
  if (opts.study.empty()) {
    err_all << "slipfront: error: study: the study file is required (or --list-kinds: the study kinds)\n";
    return exit_code::usage;
  }
  const auto wall0 = Clock::now();
  // (a) the engine
  Engine engine;
  if (!load_engine(opts.quiet, engine, err_all)) return exit_code::usage;
  std::ostream quiet_stream(nullptr);  // discards: only rank 0 speaks for the study
  std::ostream& out = engine.root ? out_all : quiet_stream;
  std::ostream& err = engine.root ? err_all : quiet_stream;

  // (b)–(c) the study read, every run validated, the plan shared, before any work
  const std::optional<Study> study = read_study(opts, err);
  if (!study) return exit_code::usage;
  if (studies::find_study_kind(study->spec.kind)->compute) {  // no runs: rank 0 computes, the others wait for its code
    int code = engine.root ? compute_study(opts, *study, engine, wall0, out, err) : exit_code::ok;
    if (engine.mpi) code = share_exit_code(*engine.mpi, code, false);
    return code;
  }
  OutputLock lock;  // rank 0: DIR held from the plan until study.h5 is in place
  const Schedule schedule = share_plan(*study, opts.force, engine, lock, err);
  if (schedule.code != 0) return schedule.code;
  engine.threads = threads_per_process(opts.threads, engine.mpi.get(), err);
  if (!opts.quiet) print_start(err, *study, schedule, engine);

  // (d)–(e) the runs, stoppable by SIGINT/SIGTERM (the handlers stay until study.h5 is written)
  const StudySignals signals;
  StopRequests stop(engine.mpi.get());
  const bool json = opts.progress == "json";
  JsonProgress json_progress(err, json && engine.root);
  const StudyProgress progress{err, !json && engine.root && !opts.quiet && ::isatty(STDERR_FILENO), study->spec.name,
                               schedule.todo.size(), wall0, json ? &json_progress : nullptr};
  RunsMade made = run_points(*study, schedule.todo, engine, stop, opts.command_line, progress, err_all);
  const RunsEnd end = end_runs(made, schedule.todo.size(), engine);

  // (f)–(g) rank 0 analyses, writes study.h5 and prints; every rank exits with its code
  int code = exit_code::ok;
  if (engine.root) code = conclude(opts, *study, schedule, engine, made, end, wall0, out, err);
  if (engine.mpi) code = share_exit_code(*engine.mpi, code, engine.root && end.stopped);
  return code;
}

// `slipfront report DIR`: scripts/report.py run directly (fork/exec with an argument vector, no
// shell), found beside an installed program or in the source tree (apps/paths.hpp).
int report_command(const fs::path& dir, const std::string& python, std::ostream& err) {
  if (!fs::is_directory(dir)) {
    err << "slipfront: error: '" << dir.string() << "' is not a directory\n";
    return exit_code::usage;
  }
  const fs::path script = find_data_file("report.py");
  if (script.empty()) {
    err << "slipfront: error: the report script report.py is missing; looked for:";
    for (const auto& c : data_file_candidates("report.py")) err << "\n  " << c.string();
    err << "\n(set SLIPFRONT_DATA_DIR to the directory that holds report.py and plot.py)\n";
    return exit_code::failed;
  }
  const std::vector<std::string> args = {python, script.string(), dir.string()};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  // posix_spawnp: PYTHON may be a bare name looked up on PATH, or a path.
  if (const int rc = ::posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ); rc != 0) {
    err << "slipfront: error: cannot run '" << python << "': " << std::strerror(rc) << "\n";
    return exit_code::failed;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      err << "slipfront: error: waiting for the report script: " << std::strerror(errno) << "\n";
      return exit_code::failed;
    }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return exit_code::ok;
  if (WIFSIGNALED(status)) err << "slipfront: error: the report script was killed by signal " << WTERMSIG(status) << "\n";
  else err << "slipfront: error: the report script " << script.string() << " exited with " << WEXITSTATUS(status) << "\n";
  return exit_code::failed;
}

}  // namespace slipfront::app
