#include "apps/stability.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>
#include <stdexcept>

#include "apps/cli.hpp"
#include "apps/config.hpp"
#include "apps/h5out.hpp"
#include "apps/paths.hpp"
#include "continuum/friction_law.hpp"
#include "core/interrupt.hpp"

namespace slipfront::app {

namespace fs = std::filesystem;
using Complex = std::complex<double>;

namespace {

// Every mode: leading_growth_rate's frequency bound that no eigenvalue exceeds.
constexpr double all_modes = std::numeric_limits<double>::max();

std::string number(double x) { return core::format_number(x, 6); }

// The verb's own options (the scene's keys are the scene's): false, the reason printed, when one is out of range.
bool check_options(const StabilityOptions& o, std::ostream& err) {
  std::string problem;
  if (!std::isfinite(o.v0)) problem = "--v0: must be a finite number, got " + number(o.v0);
  for (const double k : o.kh)
    if (problem.empty() && !(k > 0.0 && std::isfinite(k))) problem = "--kh: every kH must be > 0 and finite, got " + number(k);
  if (problem.empty() && o.kh.empty() && !(o.kh_min > 0.0 && o.kh_max >= o.kh_min && std::isfinite(o.kh_max)))
    problem = "--kh-min, --kh-max: need 0 < kh-min <= kh-max, got " + number(o.kh_min) + ", " + number(o.kh_max);
  if (problem.empty() && o.kh.empty() && o.points > 1 && !(o.kh_max > o.kh_min))
    problem = "--points: more than one point needs kh-min < kh-max";
  if (problem.empty() && !(o.relaxation_length > 0.0 && std::isfinite(o.relaxation_length)))
    problem = "--relaxation-length: must be > 0 and finite, got " + number(o.relaxation_length);
  if (problem.empty()) return true;
  err << "slipfront: error: stability: " << problem << "\n";
  return false;
}

// One channel over the kH grid; false when stopped (the rates so far kept).
bool channel_rates(StabilityChannel& c, const std::vector<double>& kh, double max_frequency,
                   const std::function<bool()>& stop) {
  for (const double x : kh) {
    if (stop()) return false;
    const double k = x / c.params.height;
    c.resolved.push_back(continuum::leading_growth_rate(c.params, k, max_frequency));
    c.fastest.push_back(continuum::leading_growth_rate(c.params, k, all_modes));
    double scale = 0.0;
    for (const Complex z : continuum::inplane_growth_rates(c.params, k)) scale = std::max(scale, std::abs(z));
    c.roundoff.push_back(1e-8 * scale);
  }
  return true;
}

// The fastest mode at the channel's fastest kH on 1, 2, 4 times its rows; false when stopped.
bool row_check(StabilityChannel& c, const std::vector<double>& kh, double frequency_scale,
               const std::function<bool()>& stop) {
  std::size_t best = 0;
  for (std::size_t a = 1; a < c.fastest.size(); ++a)
    if (c.fastest[a].real() > c.fastest[best].real()) best = a;
  c.check_kh = kh[best];
  for (const int m : {1, 2, 4}) {
    if (stop()) return false;
    continuum::InPlaneStabilityParams p = c.params;
    p.elements = m * c.params.elements;
    c.check_rows.push_back(p.elements);
    c.check_fastest.push_back(m == 1 ? c.fastest[best] : continuum::leading_growth_rate(p, c.check_kh / p.height, all_modes));
  }
  c.converged = stability_converged(c.check_fastest, frequency_scale);
  return true;
}

// The four channels of the scene's material: uncoupled, re-attachment, instantaneous, regularised instantaneous.
std::vector<StabilityChannel> channels_of(const continuum::InPlaneStabilityParams& scene, double regularised_length) {
  std::vector<StabilityChannel> out(4);
  for (auto& c : out) c.params = scene;
  out[0].group = out[0].label = "uncoupled";
  out[0].params.coupled = false;
  out[1].group = out[1].label = "reattachment";
  out[2].group = out[2].label = "instantaneous";
  out[3].group = "regularised";
  for (std::size_t a = 0; a < out.size(); ++a) {
    out[a].params.instantaneous = a >= 2;
    out[a].params.relaxation_length = a == 3 ? (scene.relaxation_length > 0.0 ? scene.relaxation_length : regularised_length) : 0.0;
    out[a].params.relaxation_speed = a == 3 && scene.relaxation_length > 0.0 ? scene.relaxation_speed : 0.0;
  }
  out[3].label = "instantaneous L=" + number(out[3].params.relaxation_length);
  const std::size_t own = !scene.instantaneous ? 1 : scene.relaxation_length > 0.0 ? 3 : 2;
  out[own].scene = true;
  return out;
}

// The summary on stdout: each channel's largest Re s over the grid, and its row check.
void print_summary(std::ostream& out, const compare::Scene& scene, const StabilityResult& r, double seconds,
                   const fs::path& dir) {
  const auto& p = r.params;
  const double A0 = 1.0 / (1.0 + p.kappa * p.v0), f = p.exponent * p.alpha * A0 / p.p0;
  out << scene.name << ": growth rates " << compare::to_string(r.status) << " in " << seconds << " s -> "
      << (dir / "stability.h5").string() << (r.status == compare::RunStatus::complete ? ", growth_rates.csv" : "") << "\n"
      << "  v0 = " << number(p.v0) << " (v_m = " << number(continuum::steady_minimum_velocity(scene.interface))
      << "), p_0 = " << number(p.p0) << ", m = " << number(p.exponent) << ": coupling coefficient m sigma_bar0/p_0 = "
      << number(f) << "; " << p.elements << " rows; kH " << number(r.kh.front()) << " .. " << number(r.kh.back())
      << " (" << r.kh.size() << " values)\n";
  for (const auto& c : r.channels) {
    if (c.fastest.empty()) continue;
    const auto top = std::max_element(c.fastest.begin(), c.fastest.end(),
                                      [](Complex a, Complex b) { return a.real() < b.real(); });
    out << "  " << c.label << (c.scene ? " (the scene's)" : "") << ": largest Re s " << number(top->real()) << " at kH = "
        << number(r.kh[static_cast<std::size_t>(top - c.fastest.begin())]) << " (omega H/c_p "
        << number(top->imag() / r.max_frequency * 4.0) << ")";
    bool grows = false;
    for (std::size_t a = 0; a < c.fastest.size(); ++a) grows = grows || c.fastest[a].real() > c.roundoff[a];
    if (!grows) {
      out << ": stable (Re s below the eigensolver's round-off at every kH)\n";
      continue;
    }
    if (!c.check_fastest.empty()) {
      out << "; on " << c.check_rows[0] << ", " << c.check_rows[1] << ", " << c.check_rows[2] << " rows";
      for (const Complex s : c.check_fastest) out << " " << number(s.real());
      out << (c.converged ? ": converged" : ": NOT converged");
    }
    out << "\n";
  }
}

}  // namespace

continuum::InPlaneStabilityParams stability_params_of(const compare::Scene& scene, const std::string& file, double v0,
                                                      int rows) {
  if (scene.bulk.body() != core::BodyKind::inplane)
    throw ConfigError(file, "bulk.body",
                      "the growth rates are those of the in-plane strip (docs/model.md §12.6): needs bulk.body = "
                      "\"inplane\" with bulk.height, got " +
                          std::string(scene.bulk.body() == core::BodyKind::chain ? "the chain (no bulk.height)"
                                                                                : "the antiplane strip"));
  if (!scene.interface.couples_load())
    throw ConfigError(file, "interface.load_coupling",
                      "the growth rates are those of the normal-load coupling (docs/model.md §12.5): needs "
                      "\"sigma_yy\", got \"" + scene.interface.load_coupling + "\"");
  continuum::InPlaneStabilityParams p;
  const double H = scene.bulk.height, nu = scene.bulk.poisson;
  p.height = H;
  p.mu_p = scene.bulk.mu * (1.0 - nu) / (2.0 * H);  // docs/model.md §10.2: μ = E'H
  p.lambda_p = 2.0 * p.mu_p * nu / (1.0 - 2.0 * nu);
  p.rho_p = scene.bulk.rho / H;
  p.alpha = scene.interface.alpha;
  p.kappa = scene.interface.kappa;
  p.eta = scene.interface.eta;
  p.v0 = v0;
  p.p0 = scene.bulk.normal_load;
  p.exponent = scene.interface.load_exponent;
  p.instantaneous = scene.interface.instantaneous_load();
  p.relaxation_length = scene.interface.load_relaxation_length;
  p.relaxation_speed = scene.interface.load_relaxation_speed;
  p.elements = rows > 0 ? rows : std::max(2, static_cast<int>(std::lround(H / scene.grid.row_spacing())));
  return p;
}

std::vector<double> stability_kh(const StabilityOptions& opts) {
  if (!opts.kh.empty()) return opts.kh;
  std::vector<double> kh;
  for (int a = 0; a < opts.points; ++a)
    kh.push_back(opts.points == 1 ? opts.kh_min
                                  : opts.kh_min * std::pow(opts.kh_max / opts.kh_min, double(a) / (opts.points - 1)));
  return kh;
}

bool stability_converged(const std::vector<Complex>& s, double frequency_scale) {
  if (s.size() < 3) return false;
  const double dr1 = std::abs(s[1].real() - s[0].real()), dr2 = std::abs(s[2].real() - s[1].real());
  const double dw1 = std::abs(s[1].imag() - s[0].imag()), dw2 = std::abs(s[2].imag() - s[1].imag());
  const bool rate = dr2 <= 0.05 * std::abs(s[2].real()) + 1e-3 && (dr2 < dr1 || dr2 <= 1e-12);
  const bool frequency = dw2 <= 0.05 * std::abs(s[2].imag()) + 1e-3 * frequency_scale && (dw2 < dw1 || dw2 <= 1e-12);
  return rate && frequency;
}

StabilityResult compute_stability(const continuum::InPlaneStabilityParams& scene_params, double regularised_length,
                                  const std::vector<double>& kh, const std::function<bool()>& stop) {
  StabilityResult r;
  r.params = scene_params;
  r.kh = kh;
  const double cp = std::sqrt((scene_params.lambda_p + 2.0 * scene_params.mu_p) / scene_params.rho_p);
  r.max_frequency = 4.0 * cp / scene_params.height;  // ωH/c_p ≤ 4, as docs/model.md §12.6's resolved modes
  r.channels = channels_of(scene_params, regularised_length);
  for (auto& c : r.channels)
    if (!channel_rates(c, kh, r.max_frequency, stop) || !row_check(c, kh, cp / scene_params.height, stop)) {
      r.status = compare::RunStatus::interrupted;
      r.message = "stopped by a signal at channel " + c.label;
      break;
    }
  return r;
}

std::string growth_rates_csv(const StabilityResult& r) {
  std::string out = "channel,kH,kind,re_s,im_s\n";
  char line[256];
  for (const auto& c : r.channels)
    for (std::size_t a = 0; a < c.fastest.size(); ++a)
      for (const auto& [kind, s] : {std::pair{"theory_resolved", c.resolved[a]}, std::pair{"theory_max", c.fastest[a]}}) {
        std::snprintf(line, sizeof line, "%s,%.17g,%s,%.17g,%.17g\n", c.label.c_str(), r.kh[a], kind, s.real(), s.imag());
        out += line;
      }
  return out;
}

int stability_command(const StabilityOptions& opts, std::ostream& out, std::ostream& err) {
  const auto wall0 = std::chrono::steady_clock::now();
  if (!check_options(opts, err)) return exit_code::usage;
  compare::Scene scene;
  continuum::InPlaneStabilityParams params;
  try {
    scene = load_scene(opts.config, opts.overrides);
    params = stability_params_of(scene, opts.config.string(), opts.v0, opts.rows);
  } catch (const ConfigError& e) {
    err << "slipfront: error: " << e.what() << "\n";
    return exit_code::usage;
  }
  if (const double vm = continuum::steady_minimum_velocity(scene.interface); !(opts.v0 > vm)) {
    err << "slipfront: error: stability: --v0: must lie on the strengthening branch v0 > v_m = " << number(vm)
        << " (docs/model.md §1: homogeneous sliding below v_m is on the weakening branch), got " << number(opts.v0) << "\n";
    return exit_code::usage;
  }
  const fs::path dir = opts.out.empty() ? fs::path("out") / scene.name : opts.out;
  const fs::path file = dir / "stability.h5", csv = dir / "growth_rates.csv";
  OutputLock lock;
  std::string problem = create_and_lock(dir, lock);
  std::error_code ec;
  if (problem.empty() && fs::exists(fs::symlink_status(file, ec)) && !opts.force)
    problem = "'" + file.string() + "' already exists (use --force to overwrite it)";
  if (!problem.empty()) {
    err << "slipfront: error: " << problem << "\n";
    return exit_code::usage;
  }
  fs::remove(csv, ec);  // a stale table never sits beside a new file

  StabilityResult r;
  try {
    r = compute_stability(params, opts.relaxation_length, stability_kh(opts),
                          [] { return core::stop_flag().load(std::memory_order_relaxed); });
  } catch (const std::exception& e) {
    r = StabilityResult();  // nothing of the channels kept: the file says why
    r.params = params;
    r.kh = stability_kh(opts);
    r.status = compare::RunStatus::failed;
    r.message = std::string("the linearisation stopped with an error: ") + e.what();
  }
  RunMeta meta;
  meta.command_line = opts.command_line;
  meta.status = r.status;
  meta.message = r.message;
  meta.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  try {
    if (r.status == compare::RunStatus::complete) write_text_file(csv, growth_rates_csv(r));
    write_stability(file, scene, to_toml(scene), r, meta);
  } catch (const std::exception& e) {
    err << "slipfront: error: cannot write " << file.string() << ": " << e.what() << "\n";
    return exit_code::failed;
  }
  if (!opts.quiet) print_summary(out, scene, r, meta.wall_seconds, dir);
  if (r.status == compare::RunStatus::failed) err << "slipfront: error: stability failed: " << r.message << "\n";
  if (r.status == compare::RunStatus::interrupted) err << "slipfront: interrupted; partial rates written to " << file.string() << "\n";
  return r.status == compare::RunStatus::complete ? exit_code::ok
         : r.status == compare::RunStatus::interrupted ? exit_code::interrupted : exit_code::failed;
}

CLI::App* add_stability_verb(CLI::App& app, StabilityOptions& opts) {
  auto* v = app.add_subcommand("stability", "Growth rates of homogeneous sliding on the in-plane strip under the "
                                            "normal-load coupling: DIR/stability.h5, DIR/growth_rates.csv");
  v->add_option("config", opts.config, "Scene (TOML): bulk.body = \"inplane\", interface.load_coupling = \"sigma_yy\"")
      ->required();
  v->add_option("--v0", opts.v0, "The homogeneous sliding rate, on the strengthening branch (v0 > v_m)")->required();
  v->add_option("-o,--out", opts.out, "Output directory DIR (default: out/<scene name>)");
  v->add_option("-s,--set", opts.overrides, "Override one key, as for run; repeatable")
      ->allow_extra_args(false)
      ->type_name("SECTION.KEY=VALUE");
  auto* kh = v->add_option("--kh", opts.kh, "The kH values (comma-separated), in place of the grid below")->delimiter(',');
  v->add_option("--kh-min", opts.kh_min, "Smallest kH of the geometric grid (default 0.1)")->excludes(kh);
  v->add_option("--kh-max", opts.kh_max, "Largest kH of the geometric grid (default 8)")->excludes(kh);
  v->add_option("--points", opts.points, "kH values of the geometric grid (default 41)")
      ->check(CLI::Range(1, 10000))
      ->excludes(kh);
  v->add_option("--rows", opts.rows, "Linear elements over the height (default: the scene's rows, round(H/dy))")
      ->check(CLI::Range(2, 256));
  v->add_option("--relaxation-length", opts.relaxation_length,
                "L of the regularised instantaneous channel when the scene has none (default 0.03; docs/model.md §12.7)");
  v->add_flag("-f,--force", opts.force, "Overwrite an existing DIR/stability.h5");
  v->add_flag("-q,--quiet", opts.quiet, "No summary on stdout");
  v->footer(
      "The linearisation of docs/model.md §12.6-§12.7 (continuum::leading_growth_rate) with the scene's material, law,\n"
      "p_0 = bulk.normal_load and m: for the uncoupled strip, the re-attachment channel, the instantaneous one and the\n"
      "regularised instantaneous one (the scene's interface.load_relaxation_length, else --relaxation-length), the\n"
      "least-damped resolved mode (omega H/c_p <= 4) and the fastest mode of all at every kH; at each channel's fastest\n"
      "kH the fastest mode on 2 and 4 times the rows (converged or not). Takes seconds. Layout: docs/output.md.");
  return v;
}

}  // namespace slipfront::app
