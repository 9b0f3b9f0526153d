#include "apps/config.hpp"


#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>
#include <variant>

#include "apps/read_file.hpp"
#include "apps/toml_integer.hpp"

namespace slipfront::app {

ConfigError::ConfigError(std::string f, std::string k, std::string r)
    : std::runtime_error(f + ": " + (k.empty() ? "" : k + ": ") + r),
      file(std::move(f)),
      key(std::move(k)),
      reason(std::move(r)) {}

ConfigError::ConfigError(std::string f, long line, long column, std::string r)
    : std::runtime_error(f + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + r),
      file(std::move(f)),
      reason(std::move(r)) {}

namespace {

using compare::Scene;
using core::Loading;

// ---------------------------------------------------------------------------------------------
// The schema: one row per key. `target` points into the Scene; `used` says whether the run uses
// the key (keys not used are accepted, noted and reset to their defaults); `required` says whether
// the file must give it (nullptr: optional, the struct default applies).
// To add a key: add a member to the param struct and one row below (and a line in docs/cli.md).

using Target = std::variant<double*, int*, long*, std::uint64_t*, bool*, std::string*, std::vector<std::string>*,
                            std::vector<double>*, Loading*, core::Integrator*>;
using Predicate = bool (*)(const Scene&);

struct Field {
  const char* key;               ///< key inside its section
  Target (*target)(Scene&);      ///< where the value lives
  Predicate used;                ///< does this scene use the key?
  const char* used_when;         ///< human version of `used`, for notes
  Predicate required = nullptr;  ///< must the file give it? (nullptr: optional)
  bool scalar_ok = false;        ///< list: a single element is accepted too (v = 1.0, models = "discrete")
};

struct Section {
  const char* name;  ///< "" for the top level
  std::vector<Field> fields;
};

bool always(const Scene&) { return true; }
bool one_d(const Scene& s) { return core::is_one_dimensional(s.drive.loading); }
bool spring_driven(const Scene& s) {
  return s.drive.loading == Loading::edge || s.drive.loading == Loading::spring_block;
}
bool homogeneous(const Scene& s) { return s.drive.loading == Loading::homogeneous; }
bool edge_loaded(const Scene& s) { return s.drive.loading == Loading::edge; }
bool steady_front_start(const Scene& s) { return homogeneous(s) && s.drive.start == "steady_front"; }
bool nucleated(const Scene& s) { return homogeneous(s) && s.drive.start != "steady_front"; }
bool imposed(const Scene& s) { return s.drive.loading == Loading::imposed_rate; }
bool imposed_history(const Scene& s) { return imposed(s) && s.drive.sweep_points == 0; }
bool imposed_sweep(const Scene& s) { return imposed(s) && s.drive.sweep_points != 0; }
bool dt_given(const Scene& s) { return s.time.dt != 0.0; }
bool aging(const Scene& s) { return s.interface.ages_contacts(); }
bool load_profile(const Scene& s) { return s.interface.has_load_profile(); }
bool load_coupled(const Scene& s) { return s.interface.load_coupling != "none"; }  // an unknown value is refused
bool normal_load(const Scene& s) { return s.interface.has_normal_load(); }
bool load_relaxed(const Scene& s) { return s.interface.relaxes_load(); }
bool cfl_used(const Scene& s) { return !imposed(s) && s.time.dt == 0.0; }
bool bulk_scene(const Scene& s) { return !imposed(s); }
// a body of height: the antiplane or the in-plane strip (bulk.height given)
bool strip_given(const Scene& s) { return s.bulk.body() != core::BodyKind::chain; }
// bulk.body, used when given: on a chain or a 0D scene it is refused (BulkParams::validate), not ignored
bool body_given(const Scene& s) { return !s.bulk.body_name.empty(); }
bool inplane(const Scene& s) { return s.bulk.body() == core::BodyKind::inplane; }
bool bulk_snapshots(const Scene& s) { return strip_given(s) && s.bulk_output.dt > 0.0; }
// grid.dy given to a chain is refused (GridParams::validate): it would otherwise be dropped in silence
bool strip_grid(const Scene& s) { return one_d(s) && (strip_given(s) || s.grid.dy != 0.0); }
bool implicit_integrator(const Scene& s) {
  return !imposed(s) && s.time.integrator == core::Integrator::implicit_trapezoidal;
}
bool adaptive(const Scene& s) { return !imposed(s) && s.time.integrator == core::Integrator::adaptive_rosenbrock; }
// the step-controlled integrator of the stochastic and mean-field laws (core/leap.hpp): adaptive with one of them
bool leap_stepped(const Scene& s) { return adaptive(s) && (s.lists("discrete") || s.lists("mean_field")); }
// the implicit step's error control: the implicit integrator, and the step-controlled one built on it
bool linearisation_controlled(const Scene& s) { return implicit_integrator(s) || leap_stepped(s); }
bool discrete_listed(const Scene& s) { return s.lists("discrete"); }
// the threshold law's keys: the discrete model's and the mean-field law's (docs/model.md §2.2)
bool thresholds_used(const Scene& s) { return s.lists("discrete") || s.lists("mean_field"); }
bool contact_statistics(const Scene& s) { return discrete_listed(s) && s.discrete.contact_statistics; }
bool both_models_bulk(const Scene& s) {
  return s.lists("discrete") && (s.lists("continuum") || s.lists("mean_field")) && s.drive.loading != Loading::imposed_rate;
}

// Pointer to member `M` of section `S` of a Scene, as a Target.
template <auto S, auto M>
Target at(Scene& s) {
  return &((s.*S).*M);
}

const std::vector<Section>& schema() {
  using namespace core;
  using D = discrete::DiscreteParams;
  static const std::vector<Section> sections = {
      {"",
       {
           {"scene", [](Scene& s) -> Target { return &s.name; }, always, "always", always},
           {"description", [](Scene& s) -> Target { return &s.description; }, always, "always"},
           {"models", [](Scene& s) -> Target { return &s.models; }, always, "always", nullptr, true},
       }},
      {"interface",
       {
           {"alpha", at<&Scene::interface, &InterfaceParams::alpha>, always, "always", always},
           {"kappa", at<&Scene::interface, &InterfaceParams::kappa>, always, "always", always},
           {"eta", at<&Scene::interface, &InterfaceParams::eta>, always, "always", always},
           // used when not 0 (docs/model.md §11): a scene without aging resolves to today's configuration
           {"aging_b", at<&Scene::interface, &InterfaceParams::aging_b>, aging, "when not 0 (contact aging)"},
           {"aging_tau", at<&Scene::interface, &InterfaceParams::aging_tau>, aging, "with interface.aging_b > 0"},
           // a normal-load profile (docs/model.md §12), used when load_p is given: without it, today's configuration
           {"load_x", at<&Scene::interface, &InterfaceParams::load_x>, load_profile, "with interface.load_p"},
           {"load_p", at<&Scene::interface, &InterfaceParams::load_p>, load_profile, "when given (a normal-load profile)"},
           {"load_exponent", at<&Scene::interface, &InterfaceParams::load_exponent>, normal_load,
            "with interface.load_p or load_coupling"},
           {"load_channel", at<&Scene::interface, &InterfaceParams::load_channel>, normal_load,
            "with interface.load_p or load_coupling"},
           // the in-plane strip's own normal load (docs/model.md §12.5), used when not "none": refused on other bodies
           {"load_coupling", at<&Scene::interface, &InterfaceParams::load_coupling>, load_coupled,
            "when not \"none\" (the in-plane strip's sigma_yy)"},
           // the regularised instantaneous channel (docs/model.md §12.7), used when not 0: refused where it acts on nothing
           {"load_relaxation_length", at<&Scene::interface, &InterfaceParams::load_relaxation_length>, load_relaxed,
            "when not 0 (the regularised instantaneous channel)"},
           {"load_relaxation_speed", at<&Scene::interface, &InterfaceParams::load_relaxation_speed>, load_relaxed,
            "with interface.load_relaxation_length > 0"},
       }},
      {"bulk",
       {
           {"rho", at<&Scene::bulk, &BulkParams::rho>, always, "always", always},
           {"mu", at<&Scene::bulk, &BulkParams::mu>, one_d, "with drive.loading = edge or homogeneous", one_d},
           {"length", at<&Scene::bulk, &BulkParams::length>, one_d, "with drive.loading = edge or homogeneous",
            one_d},
           // used when given: a height given to a 0D scene is refused (BulkParams::validate), not ignored,
           // and the resolved configuration of a chain does not gain the key
           {"height", at<&Scene::bulk, &BulkParams::height>, strip_given, "when given (the strip)"},
           {"body", at<&Scene::bulk, &BulkParams::body_name>, body_given, "when given (with bulk.height)"},
           // the in-plane strip's material and load: given to another body, refused (check_inplane_keys)
           {"poisson", at<&Scene::bulk, &BulkParams::poisson>, inplane, "with bulk.body = \"inplane\""},
           {"normal_load", at<&Scene::bulk, &BulkParams::normal_load>, inplane, "with bulk.body = \"inplane\""},
       }},
      {"drive",
       {
           {"loading", at<&Scene::drive, &DriveParams::loading>, always, "always", always},
           {"K", at<&Scene::drive, &DriveParams::K>, spring_driven, "with drive.loading = edge or spring_block",
            spring_driven},
           {"v_d", at<&Scene::drive, &DriveParams::v_d>, spring_driven,
            "with drive.loading = edge or spring_block", spring_driven},
           {"sigma_d", at<&Scene::drive, &DriveParams::sigma_d>, homogeneous, "with drive.loading = homogeneous",
            homogeneous},
           {"start", at<&Scene::drive, &DriveParams::start>, homogeneous, "with drive.loading = homogeneous"},
           {"front_x", at<&Scene::drive, &DriveParams::front_x>, steady_front_start,
            "with drive.loading = homogeneous and drive.start = steady_front"},
           {"kick_dv", at<&Scene::drive, &DriveParams::kick_dv>, steady_front_start,
            "with drive.loading = homogeneous and drive.start = steady_front"},
           {"kick_length", at<&Scene::drive, &DriveParams::kick_length>, steady_front_start,
            "with drive.loading = homogeneous and drive.start = steady_front"},
           {"nucleation_length", at<&Scene::drive, &DriveParams::nucleation_length>, nucleated,
            "with drive.loading = homogeneous and drive.start = nucleation", nucleated},
           {"v", at<&Scene::drive, &DriveParams::v>, imposed_history,
            "with drive.loading = imposed_rate and no sweep (drive.points)", imposed_history, true},
           {"switch_times", at<&Scene::drive, &DriveParams::v_times>, imposed_history,
            "with drive.loading = imposed_rate and no sweep (drive.points)"},
           {"v_min", at<&Scene::drive, &DriveParams::v_min>, imposed_sweep,
            "for a sweep (drive.loading = imposed_rate with drive.points)"},
           {"v_max", at<&Scene::drive, &DriveParams::v_max>, imposed_sweep,
            "for a sweep (drive.loading = imposed_rate with drive.points)"},
           {"points", at<&Scene::drive, &DriveParams::sweep_points>, imposed_sweep,
            "with drive.loading = imposed_rate"},
       }},
      {"grid",
       {
           {"dx", at<&Scene::grid, &GridParams::dx>, one_d, "with drive.loading = edge or homogeneous", one_d},
           {"dy", at<&Scene::grid, &GridParams::dy>, strip_grid, "with bulk.height (the strip)"},
       }},
      {"time",
       {
           {"t_end", at<&Scene::time, &TimeParams::t_end>, always, "always", always},
           {"dt", at<&Scene::time, &TimeParams::dt>, dt_given, "when not 0"},
           {"cfl", at<&Scene::time, &TimeParams::cfl>, cfl_used,
            "when time.dt is not given and drive.loading is not imposed_rate"},
           {"slip_end", at<&Scene::time, &TimeParams::slip_end>, imposed, "with drive.loading = imposed_rate"},
           {"steps", at<&Scene::time, &TimeParams::steps>, imposed, "with drive.loading = imposed_rate"},
           {"integrator", at<&Scene::time, &TimeParams::integrator>, bulk_scene,
            "with drive.loading = edge, homogeneous or spring_block"},
           {"implicit_tolerance", at<&Scene::time, &TimeParams::implicit_tolerance>, linearisation_controlled,
            "with time.integrator = implicit, or adaptive with the discrete or mean_field model"},
           {"implicit_max_halvings", at<&Scene::time, &TimeParams::implicit_max_halvings>, implicit_integrator,
            "with time.integrator = implicit"},
           {"implicit_resolution_check", at<&Scene::time, &TimeParams::implicit_resolution_check>,
            implicit_integrator, "with time.integrator = implicit"},
           {"rtol", at<&Scene::time, &TimeParams::rtol>, adaptive, "with time.integrator = adaptive"},
           {"atol", at<&Scene::time, &TimeParams::atol>, adaptive, "with time.integrator = adaptive"},
           {"dt_max", at<&Scene::time, &TimeParams::dt_max>, adaptive, "with time.integrator = adaptive"},
           {"group_switchings", at<&Scene::time, &TimeParams::group_switchings>, adaptive,
            "with time.integrator = adaptive"},
           {"leap_epsilon", at<&Scene::time, &TimeParams::leap_epsilon>, leap_stepped,
            "with time.integrator = adaptive and the discrete or mean_field model"},
           {"stop_at_arrest", at<&Scene::time, &TimeParams::stop_at_arrest>, edge_loaded, "with drive.loading = edge"},
       }},
      {"measure",
       {
           {"A_tip", at<&Scene::measure, &MeasureParams::A_tip>, always, "always"},
           {"A_tip_alt", at<&Scene::measure, &MeasureParams::A_tip_alt>, always, "always"},
           {"v_event", at<&Scene::measure, &MeasureParams::v_event>, always, "always"},
           {"sample_dt", at<&Scene::measure, &MeasureParams::sample_dt>, always, "always"},
           {"average_from", at<&Scene::measure, &MeasureParams::average_from>, always, "always"},
           {"batches", at<&Scene::measure, &MeasureParams::batches>, always, "always"},
           {"arrest_fraction", at<&Scene::measure, &MeasureParams::arrest_fraction>, always, "always"},
           {"behind_tip_fraction", at<&Scene::measure, &MeasureParams::behind_tip_fraction>, homogeneous,
            "with drive.loading = homogeneous"},
           {"behind_near", at<&Scene::measure, &MeasureParams::behind_near>, homogeneous,
            "with drive.loading = homogeneous"},
           {"behind_far", at<&Scene::measure, &MeasureParams::behind_far>, homogeneous,
            "with drive.loading = homogeneous"},
           {"settle_window", at<&Scene::measure, &MeasureParams::settle_window>, homogeneous,
            "with drive.loading = homogeneous"},
           {"settle_band", at<&Scene::measure, &MeasureParams::settle_band>, homogeneous,
            "with drive.loading = homogeneous"},
           {"settle_end_zone", at<&Scene::measure, &MeasureParams::settle_end_zone>, homogeneous,
            "with drive.loading = homogeneous"},
           {"tip_band", at<&Scene::measure, &MeasureParams::tip_band>, one_d,
            "with drive.loading = edge or homogeneous"},
       }},
      {"output",
       {
           {"series_dt", at<&Scene::output, &OutputParams::series_dt>, always, "always"},
           {"snapshot_dt", at<&Scene::output, &OutputParams::snapshot_dt>, always, "always"},
           {"energy", at<&Scene::output, &OutputParams::energy>, always, "always"},
           {"ages", at<&Scene::output, &OutputParams::ages>, always, "always"},
           {"sequence", at<&Scene::output, &OutputParams::sequence>, edge_loaded, "with drive.loading = edge"},
           {"deflate", at<&Scene::output, &OutputParams::deflate>, always, "always"},
           {"compare_dt", at<&Scene::output, &OutputParams::compare_dt>, both_models_bulk,
            "when models lists discrete and continuum or mean_field on a bulk scene"},
           {"contact_snapshot_dt", at<&Scene::output, &OutputParams::contact_snapshot_dt>, contact_statistics,
            "with discrete.contact_statistics = true"},
           // the strip's body snapshots (/<model>/bulk/, docs/output.md): a chain has no body to snapshot
           {"bulk_dt", at<&Scene::bulk_output, &compare::BulkOutputParams::dt>, strip_given,
            "with bulk.height (the strip)"},
           {"bulk_stride", at<&Scene::bulk_output, &compare::BulkOutputParams::stride>, bulk_snapshots,
            "with bulk.height (the strip) and output.bulk_dt > 0"},
       }},
      {"discrete",
       {
           {"contacts_per_site", at<&Scene::discrete, &D::contacts_per_site>, discrete_listed,
            "when models lists discrete"},
           {"threshold", at<&Scene::discrete, &D::threshold>, thresholds_used, "when models lists discrete or mean_field"},
           {"width", at<&Scene::discrete, &D::width>, thresholds_used, "when models lists discrete or mean_field"},
           {"renewal", at<&Scene::discrete, &D::renewal>, thresholds_used, "when models lists discrete or mean_field"},
           {"representation", at<&Scene::discrete, &D::representation>, discrete_listed,
            "when models lists discrete"},
           {"noise", at<&Scene::discrete, &D::noise>, discrete_listed, "when models lists discrete"},
           {"seed", at<&Scene::discrete, &D::seed>, discrete_listed, "when models lists discrete"},
           {"bins", at<&Scene::discrete, &D::bins>, thresholds_used, "when models lists discrete or mean_field"},
           {"contact_statistics", at<&Scene::discrete, &D::contact_statistics>, discrete_listed,
            "when models lists discrete"},
           {"threads", at<&Scene::discrete, &D::threads>, discrete_listed, "when models lists discrete"},
       }},
      {"limits",
       {
           {"max_steps", at<&Scene::limits, &compare::LimitParams::max_steps>, always, "always"},
           {"max_memory_gib", at<&Scene::limits, &compare::LimitParams::max_memory_gib>, always, "always"},
           {"max_hours", at<&Scene::limits, &compare::LimitParams::max_hours>, always, "always"},
           {"max_checkpoint_gib", at<&Scene::limits, &compare::LimitParams::max_checkpoint_gib>, bulk_scene,
            "with drive.loading = edge, homogeneous or spring_block"},
           {"min_nodes_per_elastic_length", at<&Scene::limits, &compare::LimitParams::min_nodes_per_elastic_length>,
            one_d, "with drive.loading = edge or homogeneous"},
       }},
  };
  return sections;
}

std::string dotted(const Section& sec, const Field& f) {
  return sec.name[0] == '\0' ? std::string(f.key) : std::string(sec.name) + "." + f.key;
}

const Section* find_section(std::string_view name) {
  for (const auto& s : schema())
    if (name == s.name) return &s;
  return nullptr;
}

const Field* find_field(const Section& sec, std::string_view key) {
  for (const auto& f : sec.fields)
    if (key == f.key) return &f;
  return nullptr;
}

// Edit distance, for "did you mean" hints.
std::size_t distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      const auto ca = static_cast<char>(std::tolower(static_cast<unsigned char>(a[i - 1])));
      const auto cb = static_cast<char>(std::tolower(static_cast<unsigned char>(b[j - 1])));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (ca == cb ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string hint(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates)
    if (const auto d = distance(word, c); d < best_d) best_d = d, best = c;
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

std::string join(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

std::vector<std::string> section_keys(const Section& sec) {
  std::vector<std::string> out;
  for (const auto& f : sec.fields) out.emplace_back(f.key);
  return out;
}

std::vector<std::string> section_names() {
  std::vector<std::string> out;
  for (const auto& s : schema())
    if (s.name[0] != '\0') out.emplace_back(s.name);
  return out;
}

std::string unknown_key_reason(const Section& sec, std::string_view key) {
  const auto keys = section_keys(sec);
  return "unknown key (known keys of [" + std::string(sec.name) + "]: " + join(keys) + ")" + hint(key, keys);
}

std::string unknown_top_level_reason(std::string_view key) {
  const auto& top = *find_section("");
  std::vector<std::string> all = section_keys(top);
  std::vector<std::string> sections;
  for (const auto& n : section_names()) sections.push_back("[" + n + "]"), all.push_back(n);
  return "unknown key or section (known top-level keys: " + join(section_keys(top)) +
         "; sections: " + join(sections) + ")" + hint(key, all);
}

// ---------------------------------------------------------------------------------------------
// Reading values.

std::string describe(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "the string \"" + std::string(*n.as_string()) + "\"";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

// Reports problems of one key; `key` is already in its display form.
struct Reader {
  const std::string& source;
  std::string key;

  [[noreturn]] void fail(const std::string& reason) const { throw ConfigError(source, key, reason); }

  double number(const toml::node& n) const {
    if (const auto* f = n.as_floating_point()) return f->get();
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    fail("expected a number, got " + describe(n));
  }

  void read(const toml::node& n, Target t, bool scalar_ok) const {
    std::visit(
        [&](auto* p) {
          using T = std::remove_pointer_t<decltype(p)>;
          if constexpr (std::is_same_v<T, double>) {
            *p = number(n);
          } else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, long> ||
                               std::is_same_v<T, std::uint64_t>) {
            *p = checked_integer<T>(n, source, key, IntegralFloats::accepted);  // "integer" takes 4e1 (docs/cli.md)
          } else if constexpr (std::is_same_v<T, bool>) {
            if (const auto* b = n.as_boolean()) *p = b->get();
            else fail("expected true or false, got " + describe(n));
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (const auto* s = n.as_string()) *p = s->get();
            else fail("expected a string, got " + describe(n));
          } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
            if (const auto* s = n.as_string(); s && scalar_ok) {
              *p = {s->get()};
              return;
            }
            const auto* a = n.as_array();
            if (!a) fail("expected an array of strings, got " + describe(n));
            p->clear();
            for (const auto& e : *a) {
              if (const auto* s = e.as_string()) p->push_back(s->get());
              else fail("expected an array of strings, got an element that is " + describe(e));
            }
          } else if constexpr (std::is_same_v<T, std::vector<double>>) {
            if (scalar_ok && (n.is_integer() || n.is_floating_point())) {
              *p = {number(n)};
              return;
            }
            const auto* a = n.as_array();
            if (!a)
              fail(std::string("expected ") + (scalar_ok ? "a number or " : "") + "an array of numbers, got " +
                   describe(n));
            p->clear();
            for (const auto& e : *a) {
              if (!e.is_integer() && !e.is_floating_point())
                fail("expected an array of numbers, got an element that is " + describe(e));
              p->push_back(number(e));
            }
          } else if constexpr (std::is_same_v<T, Loading>) {
            const auto* s = n.as_string();
            if (!s) fail("expected a string (edge, homogeneous, imposed_rate or spring_block), got " + describe(n));
            try {
              *p = core::loading_from_string(s->get());
            } catch (const core::ParamError& e) {
              fail(e.reason);
            }
          } else if constexpr (std::is_same_v<T, core::Integrator>) {
            const auto* s = n.as_string();
            if (!s) fail("expected a string (explicit, implicit or adaptive), got " + describe(n));
            try {
              *p = core::integrator_from_string(s->get());
            } catch (const core::ParamError& e) {
              fail(e.reason);
            }
          }
        },
        t);
  }
};

// Copies the value of `f` from `from` into `to` (both scenes).
void copy_field(const Field& f, Scene& to, Scene& from) {
  std::visit(
      [&](auto* p) {
        using P = decltype(p);
        *p = *std::get<P>(f.target(from));
      },
      f.target(to));
}

bool same_field(const Field& f, Scene& a, Scene& b) {
  return std::visit(
      [&](auto* p) {
        using P = decltype(p);
        using T = std::remove_pointer_t<P>;
        const T& x = *p;
        const T& y = *std::get<P>(f.target(b));
        if constexpr (std::is_same_v<T, double>) {
          return x == y || (std::isnan(x) && std::isnan(y));
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          if (x.size() != y.size()) return false;
          for (std::size_t i = 0; i < x.size(); ++i)
            if (!(x[i] == y[i] || (std::isnan(x[i]) && std::isnan(y[i])))) return false;
          return true;
        } else {
          return x == y;
        }
      },
      f.target(a));
}

// ---------------------------------------------------------------------------------------------
// Overrides: "section.key=value" into the parsed document.

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

// Returns the dotted key it set.
std::string apply_override(toml::table& root, const std::string& arg, const std::string& source) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos)
    throw ConfigError(source, "--set " + arg, "expected section.key=value (for example bulk.mu=200)");
  const std::string key = trim(std::string_view(arg).substr(0, eq));
  const std::string text = trim(std::string_view(arg).substr(eq + 1));
  if (key.empty())
    throw ConfigError(source, "--set '" + arg + "'",
                      "the key before '=' is empty: expected section.key=value (for example bulk.mu=200)");
  if (text.empty())
    throw ConfigError(source, "--set " + key,
                      "no value after '=': expected section.key=value (a string value: --set 'key=\"\"')");
  const auto dot = key.find('.');
  const std::string sec_name = dot == std::string::npos ? "" : key.substr(0, dot);
  const std::string field_key = dot == std::string::npos ? key : key.substr(dot + 1);
  const Section* sec = find_section(sec_name);
  if (dot == std::string::npos) {
    if (!find_field(*sec, field_key)) {
      throw ConfigError(source, "--set " + key,
                        find_section(field_key) ? "a whole section cannot be set; use --set " + field_key + ".KEY=VALUE"
                                                : unknown_top_level_reason(field_key));
    }
  } else if (!sec || sec_name.empty()) {
    throw ConfigError(source, "--set " + key,
                      "unknown section '" + sec_name + "' (known sections: " + join(section_names()) + ")" +
                          hint(sec_name, section_names()));
  } else if (!find_field(*sec, field_key)) {
    throw ConfigError(source, "--set " + key, unknown_key_reason(*sec, field_key));
  }

  // The value: a TOML value if it parses as one, else the bare text as a string. Text that can only
  // have been meant as a number, array, table or quoted string is refused with TOML's reason.
  toml::table value_doc;
  bool parsed = false;
  try {
    value_doc = toml::parse("value = " + text + "\n");
    parsed = value_doc.contains("value");
  } catch (const toml::parse_error& e) {
    parsed = false;
    const char c = text.front();
    const std::string_view unsigned_part = std::string_view(text).substr(c == '+' || c == '-' ? 1 : 0);
    if (unsigned_part.size() > 18 && unsigned_part.find_first_not_of("0123456789") == std::string_view::npos)
      throw ConfigError(source, "--set " + key,
                        "the integer " + text + " is out of range (TOML integers are 64-bit: -2^63 ... 2^63 - 1 = "
                        "9223372036854775807)");
    if (c == '[' || c == '{' || c == '"' || c == '\'')  // (a scene named 2024run stays a bare string)
      throw ConfigError(source, "--set " + key, "not a valid TOML value: " + std::string(e.description()));
  }
  toml::table* target = &root;
  if (!sec_name.empty()) {
    target = root.get_as<toml::table>(sec_name);
    if (!target) {
      root.insert_or_assign(sec_name, toml::table{});
      target = root.get_as<toml::table>(sec_name);
    }
  }
  if (parsed) {
    value_doc.get("value")->visit([&](auto& v) { target->insert_or_assign(field_key, v); });
  } else {
    target->insert_or_assign(field_key, text);
  }
  return key;
}

// ---------------------------------------------------------------------------------------------

// The document being read: its source name and the keys set by --set (named "--set <key>" in messages).
struct Document {
  const toml::table& root;
  const std::string& source;
  std::set<std::string> overridden;

  std::string shown(const std::string& key) const { return overridden.count(key) ? "--set " + key : key; }

  // The value of a key in the document, or nullptr.
  const toml::node* lookup(const Section& sec, const Field& f) const {
    if (sec.name[0] == '\0') return root.get(f.key);
    const auto* tbl = root.get_as<toml::table>(sec.name);
    return tbl ? tbl->get(f.key) : nullptr;
  }
};

// Unknown sections and keys.
void refuse_unknown_keys(const Document& doc) {
  const Section& top = *find_section("");
  for (const auto& [k, node] : doc.root) {
    const std::string key(k.str());
    if (find_field(top, key)) continue;
    const Section* sec = find_section(key);
    if (!sec) throw ConfigError(doc.source, key, unknown_top_level_reason(key));
    const auto* tbl = node.as_table();
    if (!tbl) throw ConfigError(doc.source, key, "expected a section [" + key + "], got " + describe(node));
    for (const auto& [sk, snode] : *tbl) {
      const std::string skey(sk.str());
      if (!find_field(*sec, skey))
        throw ConfigError(doc.source, doc.shown(key + "." + skey), unknown_key_reason(*sec, skey));
    }
  }
}

// Values present in the file (drive.loading first: what is required depends on it).
Scene read_values(const Document& doc) {
  Scene s;
  const Section& drive = *find_section("drive");
  if (!doc.lookup(drive, *find_field(drive, "loading")))
    throw ConfigError(doc.source, "drive.loading",
                      "required key is missing (one of edge, homogeneous, imposed_rate, spring_block)");
  for (const auto& sec : schema())
    for (const auto& f : sec.fields)
      if (const toml::node* n = doc.lookup(sec, f))
        Reader{doc.source, doc.shown(dotted(sec, f))}.read(*n, f.target(s), f.scalar_ok);
  return s;
}

// Required keys, which depend on the values read.
void refuse_missing_keys(const Document& doc, const Scene& s) {
  for (const auto& sec : schema())
    for (const auto& f : sec.fields)
      if (f.required && f.required(s) && !doc.lookup(sec, f)) {
        std::string reason = "required key is missing";
        if (std::string_view(f.key) == "v")
          reason += " (with drive.loading = imposed_rate give drive.v, or a sweep: drive.points with drive.v_min, "
                    "drive.v_max)";
        else if (f.required != always)
          reason += std::string(" (required ") + f.used_when + ")";
        throw ConfigError(doc.source, dotted(sec, f), reason);
      }
}

// The rules between the keys of an imposed rate: a sweep of at least 2 points; a history of one rate
// starts at 0 without drive.switch_times, of several needs them.
void check_imposed_rate(const Document& doc, Scene& s) {
  const Section& drive = *find_section("drive");
  if (imposed(s) && doc.lookup(drive, *find_field(drive, "points")) && s.drive.sweep_points < 2)
    throw ConfigError(doc.source, doc.shown("drive.points"),
                      "a sweep needs at least 2 points, got " + std::to_string(s.drive.sweep_points));
  if (imposed_history(s) && !doc.lookup(drive, *find_field(drive, "switch_times"))) {
    if (s.drive.v.size() > 1)
      throw ConfigError(doc.source, "drive.switch_times",
                        "required key is missing (drive.v has " + std::to_string(s.drive.v.size()) +
                            " values: give the time at which each starts, the first 0)");
    s.drive.v_times = {0.0};
  }
}

// The keys that choose and describe the body (docs/model.md §10): bulk.body given must name one; bulk.poisson and
// bulk.normal_load belong to the in-plane strip, and given to another body they are refused, not ignored.
void check_inplane_keys(const Document& doc, const Scene& s) {
  const Section& bulk = *find_section("bulk");
  if (doc.lookup(bulk, *find_field(bulk, "body")) && s.bulk.body_name.empty())
    throw ConfigError(doc.source, doc.shown("bulk.body"), "must be one of antiplane, inplane, got \"\"");
  if (inplane(s)) return;
  const char* body = s.bulk.body() == core::BodyKind::strip ? "the antiplane strip" : "the 1D chain";
  for (const char* key : {"poisson", "normal_load"})
    if (doc.lookup(bulk, *find_field(bulk, key)))
      throw ConfigError(doc.source, doc.shown(std::string("bulk.") + key),
                        std::string("belongs to the in-plane strip (bulk.body = \"inplane\" with bulk.height); this "
                                    "scene's body is ") + body);
}

// The scene's name (it names the output directory out/<scene>) and its list of models.
void check_names(const Document& doc, const Scene& s) {
  check_directory_name(s.name, doc.source, doc.shown("scene"), "out/<scene>");
  for (std::size_t i = 0; i < s.models.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (s.models[i] == s.models[j])
        throw ConfigError(doc.source, doc.shown("models"), "lists '" + s.models[i] + "' twice");
}

// Keys this scene does not use: noted, and reset to their defaults (canonical form).
void reset_unused_keys(const Document& doc, Scene& s, std::vector<std::string>* notes) {
  Scene defaults;
  std::vector<const Field*> unused;
  for (const auto& sec : schema())
    for (const auto& f : sec.fields)
      if (!f.used(s)) {
        if (doc.lookup(sec, f) && notes)
          notes->push_back(dotted(sec, f) + " is ignored: it is used only " + f.used_when);
        unused.push_back(&f);
      }
  for (const Field* f : unused) copy_field(*f, s, defaults);
}

// Scene::validate(), its refusals as ConfigErrors naming the key as the document gave it.
void validate_scene(const Document& doc, const Scene& s) {
  try {
    s.validate();
  } catch (const core::ParamError& e) {
    throw ConfigError(doc.source, doc.shown(e.key), e.reason);
  } catch (const std::exception& e) {  // a check outside the parameter structs (e.g. building the grid)
    throw ConfigError(doc.source, "", e.what());
  }
}

Scene scene_from_table(toml::table& root, const std::string& source, const std::vector<std::string>& overrides,
                       std::vector<std::string>* notes) {
  std::set<std::string> overridden;
  for (const auto& o : overrides) overridden.insert(apply_override(root, o, source));
  const Document doc{root, source, std::move(overridden)};
  refuse_unknown_keys(doc);
  Scene s = read_values(doc);
  refuse_missing_keys(doc, s);
  check_imposed_rate(doc, s);
  check_names(doc, s);
  check_inplane_keys(doc, s);
  reset_unused_keys(doc, s, notes);
  validate_scene(doc, s);
  if (strip_given(s) && s.grid.dy == 0.0) s.grid.dy = s.grid.dx;  // the effective value, resolved
  return s;
}

// ---------------------------------------------------------------------------------------------
// Writing.

std::string format_double(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, x);  // shortest round-trip form
  std::string s(buf, res.ptr);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

std::string format_string(const std::string& v) {
  std::string out = "\"";
  for (const char c : v) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\t': out += "\\t"; break;
      case '\n': out += "\\n"; break;
      case '\f': out += "\\f"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04X", static_cast<unsigned>(static_cast<unsigned char>(c)));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string format_value(Target t) {
  return std::visit(
      [](auto* p) -> std::string {
        using T = std::remove_pointer_t<decltype(p)>;
        if constexpr (std::is_same_v<T, double>) {
          return format_double(*p);
        } else if constexpr (std::is_same_v<T, bool>) {
          return *p ? "true" : "false";
        } else if constexpr (std::is_same_v<T, std::string>) {
          return format_string(*p);
        } else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
          std::vector<std::string> items;
          for (const auto& e : *p) items.push_back(format_string(e));
          std::string text = "[";  // (appends: GCC 12 warns falsely on "[" + std::string)
          text += join(items);
          text += "]";
          return text;
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          std::vector<std::string> items;
          for (const double e : *p) items.push_back(format_double(e));
          std::string text = "[";  // (appends: GCC 12 warns falsely on "[" + std::string)
          text += join(items);
          text += "]";
          return text;
        } else if constexpr (std::is_same_v<T, Loading> || std::is_same_v<T, core::Integrator>) {
          return format_string(core::to_string(*p));
        } else {
          return std::to_string(*p);  // integers (a seed above 2^63 - 1 cannot be written in TOML)
        }
      },
      t);
}

}  // namespace

std::string quoted_string(const std::string& s) { return format_string(s); }

Scene parse_scene(const std::string& toml_text, const std::string& source_name,
                  const std::vector<std::string>& overrides, std::vector<std::string>* notes) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw ConfigError(source_name, static_cast<long>(e.source().begin.line),
                      static_cast<long>(e.source().begin.column), std::string(e.description()));
  }
  return scene_from_table(root, source_name, overrides, notes);
}

Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                 std::vector<std::string>* notes) {
  return parse_scene(read_config_file(file), file.string(), overrides, notes);
}

std::string read_config_file(const std::filesystem::path& file, std::size_t limit) {
  try {
    return read_regular_file(file, limit);
  } catch (const UnreadableFile& e) {
    std::string why = e.what();
    if (e.why == UnreadableFile::Why::not_regular) why += " (a configuration is read from a file)";
    if (e.why == UnreadableFile::Why::too_large) why += " for a configuration file (is it the right file?)";
    throw ConfigError(file.string(), "", why);
  }
}

void check_directory_name(const std::string& name, const std::string& file, const std::string& key,
                          const std::string& names) {
  if (name.empty()) throw ConfigError(file, key, "must not be empty (it names the output directory " + names + ")");
  if (name.front() == '/' || name.find("..") != std::string::npos)
    throw ConfigError(file, key, "must be a relative name without '..' (it names " + names + ")");
  if (std::any_of(name.begin(), name.end(), [](char ch) { return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f; }))
    throw ConfigError(file, key, "must not contain control characters (it names the directory " + names + ")");
}

std::int64_t toml_integer(const toml::node& n, const std::string& file, const std::string& key, IntegralFloats floats) {
  if (const auto* i = n.as_integer()) return i->get();
  std::string got = describe(n);
  if (const auto* f = n.as_floating_point()) {
    const double x = f->get();
    const bool integral = std::isfinite(x) && x == std::trunc(x) && std::abs(x) < 9.0e18;
    if (integral && floats == IntegralFloats::accepted) return static_cast<std::int64_t>(x);
    got += " (" + format_double(x) + ")";
    if (integral) got += "; write it as the integer " + std::to_string(static_cast<std::int64_t>(x));
  }
  throw ConfigError(file, key, "expected an integer, got " + got);
}

void refuse_integer_range(const std::string& file, const std::string& key, std::int64_t v, const std::string& lo,
                          const std::string& hi) {
  throw ConfigError(file, key, "the integer " + std::to_string(v) + " is out of range (" + lo + " .. " + hi + ")");
}

std::vector<std::string> schema_keys() {
  std::vector<std::string> out;
  for (const auto& sec : schema())
    for (const auto& f : sec.fields) out.push_back(dotted(sec, f));
  return out;
}

bool uses_key(const Scene& scene, std::string_view key) {
  for (const auto& sec : schema())
    for (const auto& f : sec.fields)
      if (dotted(sec, f) == key) return f.used(scene);
  return false;
}

std::string to_toml(const Scene& scene) {
  Scene s = scene;  // targets point into a mutable scene; nothing is modified
  std::ostringstream out;
  out << "# slipfront resolved configuration: every key this scene uses, with its effective value\n";
  for (const auto& sec : schema()) {
    bool header = sec.name[0] == '\0';
    for (const auto& f : sec.fields) {
      if (!f.used(s)) continue;
      if (!header) {
        out << "\n[" << sec.name << "]\n";
        header = true;
      }
      out << f.key << " = " << format_value(f.target(s)) << "\n";
    }
  }
  return out.str();
}

bool same_scene(const Scene& a, const Scene& b) {
  Scene x = a, y = b;
  for (const auto& sec : schema())
    for (const auto& f : sec.fields)
      if (!same_field(f, x, y)) return false;
  return true;
}

}  // namespace slipfront::app
