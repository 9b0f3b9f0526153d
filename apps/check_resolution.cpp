#include "apps/check_resolution.hpp"

#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <ostream>
#include <sstream>

#include "apps/cli.hpp"
#include "apps/config.hpp"
#include "apps/study.hpp"

namespace slipfront::app {

namespace fs = std::filesystem;

namespace {

// Each option in its domain (studies::resolution_key_domains()), the message naming the option; then the rules
// between them. False (the reason printed) if not.
bool check_options(const studies::ResolutionOptions& o, std::ostream& err) {
  const std::pair<const char*, double> given[] = {{"levels", o.levels},       {"coarser", o.coarser},
                                                  {"ratio", o.ratio},         {"tolerance", o.tolerance},
                                                  {"tolerance_order", o.tolerance_order}, {"seeds", o.seeds}};
  try {
    for (const auto& [name, value] : given) {
      const std::string key = "resolution." + std::string(name);
      try {
        core::check_in_domain(*core::find_key_domain(studies::resolution_key_domains(), key), value);
      } catch (const core::ParamError& e) {
        std::string option = name;
        for (char& c : option) c = c == '_' ? '-' : c;
        throw core::ParamError("--" + option, e.reason);
      }
    }
    studies::check_resolution_options(o);
  } catch (const core::ParamError& e) {
    const std::string key = e.key == "resolution.levels" ? "--levels" : e.key;
    err << "slipfront: error: check-resolution: " << key << ": " << e.reason << "\n";
    return false;
  }
  return true;
}

}  // namespace

std::string resolution_study_text(const std::string& scene_name, const fs::path& config,
                                  const studies::ResolutionOptions& o) {
  toml::table resolution{{"levels", o.levels},
                         {"coarser", o.coarser},
                         {"ratio", o.ratio},
                         {"tolerance", o.tolerance},
                         {"tolerance_order", o.tolerance_order},
                         {"seeds", o.seeds}};
  toml::table t{{"study", "resolution_" + scene_name},
                {"kind", "resolution"},
                {"description", "slipfront check-resolution of the scene " + scene_name},
                {"scene", fs::absolute(config).lexically_normal().string()},
                {"resolution", resolution}};
  std::ostringstream s;
  s << "# written by slipfront check-resolution (docs/cli.md); `slipfront study` on this file runs the same check\n"
    << t << "\n";
  return s.str();
}

int check_resolution_command(const ResolutionCheckOptions& opts, std::ostream& out, std::ostream& err) {
  if (!check_options(opts.check, err)) return exit_code::usage;
  std::string name;
  try {
    name = parse_scene(read_config_file(opts.config), opts.config.string(), opts.overrides).name;
  } catch (const ConfigError& e) {
    err << "slipfront: error: " << e.what() << "\n";
    return exit_code::usage;
  }
  StudyOptions so;
  so.study = opts.config;
  so.study_text = resolution_study_text(name, opts.config, opts.check);
  so.overrides = opts.overrides;
  so.out = opts.out.empty() ? fs::path("out") / "resolution" / name : opts.out;
  so.threads = opts.threads;
  so.force = opts.force;
  so.quiet = opts.quiet;
  so.command_line = opts.command_line;
  return study_command(so, out, err);
}

CLI::App* add_check_resolution_verb(CLI::App& app, ResolutionCheckOptions& opts) {
  auto* v = app.add_subcommand("check-resolution",
                               "Run a scene at its own resolution and refined ones: each event's error and order");
  const studies::ResolutionOptions d;
  v->add_option("config", opts.config, "Scene configuration file (TOML)")->required();
  v->add_option("-o,--out", opts.out, "Output directory (default: out/resolution/<scene name>)");
  v->add_option("-s,--set", opts.overrides, "Override one scene key before the levels are made; repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  v->add_option("--levels", opts.check.levels, "Refined levels beyond the scene's own: h/r, h/r^2, ... (default " +
                                                   std::to_string(d.levels) + ")");
  v->add_option("--coarser", opts.check.coarser,
                "Coarser levels h r, ... (default 0): an order for a scene too costly to refine twice");
  v->add_option("--ratio", opts.check.ratio, "Refinement ratio r between levels (default 2)");
  v->add_option("--tolerance", opts.check.tolerance,
                "Relative error each event must meet at the scene's own resolution (default 0.01)");
  v->add_option("--tolerance-order", opts.check.tolerance_order,
                "Integrator tolerances (rtol, atol, leap_epsilon, implicit_tolerance) are divided by r^q per level "
                "(default 2)");
  v->add_option("--seeds", opts.check.seeds,
                "A stochastic model (discrete, noise on): seeds at the scene's own level for its sampling part "
                "(default 4; 0: none)");
  v->add_option("-j,--threads", opts.threads, "Runs at once (default: all cores), as for study");
  v->add_flag("-f,--force", opts.force, "Rerun every run and replace DIR/study.h5");
  v->add_flag("-q,--quiet", opts.quiet, "No progress line and no start line");
  v->footer(
      "Levels k = -coarser .. levels at h = r^-k of the scene's: grid.dx (and grid.dy on the strip) divided by r^k, a\n"
      "fixed time.dt with them (time.cfl: the step follows dx), the adaptive or implicit tolerances by r^(q k).\n"
      "Each event's error at the scene's own level: Richardson from the finest three levels, with the observed order;\n"
      "a stochastic model is judged on its noise-off skeleton, its seeds give the sampling part (docs/studies.md).\n"
      "Runs on the study engine: DIR/runs/<id>/results.h5 and DIR/study.h5 (docs/output.md), resumed by the same\n"
      "command, Ctrl-C writes study.h5 with status interrupted (exit 130).");
  return v;
}

}  // namespace slipfront::app
