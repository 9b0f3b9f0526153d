#pragma once
// Scenes built in code for the tests (docs/model.md §4), so that a test states every parameter it relies on
// and does not depend on configs/ (which other people edit). Plus small helpers to read results, a
// scratch directory and the minimal TOML configuration of the apps/ tests. bench/scenes.hpp uses it too.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "compare/result.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "continuum/friction_law.hpp"
#include "core/params.hpp"

namespace slipfront::testing {

/// The paper's interface parameters (docs/model.md §1): α = 1.05, κ = 8, η = 0.1.
inline core::InterfaceParams paper_interface() {
  core::InterfaceParams p;
  p.alpha = 1.05;
  p.kappa = 8.0;
  p.eta = 0.1;
  return p;
}

/// fig1 (docs/model.md §4): edge loading, paper parameters ρ = 0.01, μ = 300, κ = 8, α = 1.05, η = 0.1,
/// K = 2.5, v_d = 0.3, L = 300, dx = 0.5, cfl = 0.5, t_end = 140.
inline compare::Scene fig1_scene() {
  compare::Scene s;
  s.name = "fig1";
  s.interface = paper_interface();
  s.bulk.rho = 0.01;
  s.bulk.mu = 300.0;
  s.bulk.length = 300.0;
  s.drive.loading = core::Loading::edge;
  s.drive.K = 2.5;
  s.drive.v_d = 0.3;
  s.grid.dx = 0.5;
  s.time.t_end = 140.0;
  s.time.dt = 0.0;
  s.time.cfl = 0.5;
  s.output.series_dt = 0.05;
  s.output.snapshot_dt = 1.0;
  return s;
}

/// fig1 made small: L = 60, dx = 1, to t = 60 (first yield, t* = 26.5, and the slow front) on `integrator` (implicit:
/// dt = 0.01), series every 0.5, field snapshots and field comparisons every 5. On the chain; a test adds a height
/// (small_strip_scene) and its keys; not validated.
inline compare::Scene small_fig1_scene(core::Integrator integrator) {
  compare::Scene s = fig1_scene();
  s.bulk.length = 60.0;
  s.grid.dx = 1.0;
  s.time.t_end = 60.0;
  s.time.integrator = integrator;
  if (integrator == core::Integrator::implicit_trapezoidal) s.time.dt = 0.01;
  s.output.series_dt = 0.5;
  s.output.snapshot_dt = 5.0;
  s.output.compare_dt = 5.0;
  return s;
}

/// small_fig1_scene on a strip of height 4, dy = 1 (61 × 5 nodes): the antiplane strip, or with `body` = "inplane"
/// the in-plane strip (ν = 1/3); named `name`.
inline compare::Scene small_strip_scene(core::Integrator integrator, const std::string& name,
                                        const std::string& body = "") {
  compare::Scene s = small_fig1_scene(integrator);
  s.name = name;
  s.bulk.height = 4.0;
  s.bulk.body_name = body;
  s.grid.dy = 1.0;
  return s;
}

/// Homogeneous loading (docs/model.md §1): uniform σ_d, free ends, nucleation patch 0 ≤ x < ℓ_n
/// (ℓ_n = 0: no patch, the stuck state everywhere). Paper bulk and interface parameters.
inline compare::Scene homogeneous_scene(double sigma_d, double nucleation_length, double t_end) {
  compare::Scene s = fig1_scene();
  s.name = "homogeneous_front";
  s.drive.loading = core::Loading::homogeneous;
  s.drive.sigma_d = sigma_d;
  s.drive.nucleation_length = nucleation_length;
  s.time.t_end = t_end;
  return s;
}

/// Homogeneous loading at σ_d on a strip of height H (the paper's column μ = 300, ρ = 0.01 integrated over the height;
/// body "inplane": the in-plane strip, ν = 1/3, μ = E'H; else the antiplane strip), grid dx, dy, started from the solved
/// strip front with its tip at 100 on [0, 400], continuum alone, explicit, c_front fitted over the last 0.7 of the run,
/// series every 0.05, no snapshots; t_end is the caller's (docs/fronts.md §10.15, §11.10).
inline compare::Scene strip_front_start_scene(double H, double sigma_d, double dx, double dy, const std::string& body = "") {
  compare::Scene s = homogeneous_scene(sigma_d, 0.0, 1.0);
  s.models = {"continuum"};
  s.bulk.height = H;
  s.bulk.body_name = body;
  s.bulk.length = 400.0;
  s.grid.dx = dx;
  s.grid.dy = dy;
  s.drive.start = "steady_front";
  s.drive.front_x = 100.0;
  s.measure.behind_tip_fraction = 0.7;
  s.output.snapshot_dt = 0.0;
  s.output.series_dt = 0.05;
  return s;
}

/// A short homogeneous run on a small chain (L = 60, dx = 1, σ_d = 0.55, a nucleation patch ℓ_n = 20, t_end = 3) on
/// `integrator` (implicit: dt = 0.005): series every 0.1, snapshots every 0.5; not validated (a test adds its keys).
inline compare::Scene short_front_scene(core::Integrator integrator) {
  compare::Scene s = homogeneous_scene(0.55, 20.0, 3.0);
  s.bulk.length = 60.0;
  s.grid.dx = 1.0;
  s.time.integrator = integrator;
  if (integrator == core::Integrator::implicit_trapezoidal) s.time.dt = 0.005;
  s.output.series_dt = 0.1;
  s.output.snapshot_dt = 0.5;
  return s;
}

/// 0D spring block (docs/model.md §1): ρ v̇ = K (v_d t − u) − σ̄ − η v, paper parameters K = 2.5, v_d = 0.3,
/// ρ = 0.01.
inline compare::Scene spring_block_scene(double t_end) {
  compare::Scene s = fig1_scene();
  s.name = "spring_block";
  s.drive.loading = core::Loading::spring_block;
  s.time.t_end = t_end;
  s.output.series_dt = 0.0;  // every step
  s.output.snapshot_dt = 0.0;
  return s;
}

/// 0D imposed slip rate (docs/model.md §4 friction_law): one site, v imposed; steady_point() runs
/// t_end + slip_end/|v| in `steps` exact steps.
inline compare::Scene imposed_rate_scene() {
  compare::Scene s;
  s.name = "friction_law";
  s.interface = paper_interface();
  s.drive.loading = core::Loading::imposed_rate;
  s.time.t_end = 100.0;
  s.time.slip_end = 50.0;
  s.time.steps = 4000;
  return s;
}

/// Scratch directory <temp>/slipfront-test-<tag>-<pid>: emptied when made, removed (with its
/// contents) when it goes out of scope.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() / ("slipfront-test-" + tag + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

/// The smallest valid configuration (docs/model.md §5, docs/cli.md): edge loading with every required key
/// and nothing else; paper parameters, L = 20, dx = 2, t_end = 2 (a few hundred steps).
/// The paper's [interface] (α = 1.05, κ = 8, η = 0.1) and the bulk's ρ = 0.01, the lines every scene file of the
/// tests begins with (a [bulk] section follows on: its other keys come next).
inline std::string paper_interface_toml() {
  return R"([interface]
alpha = 1.05
kappa = 8
eta = 0.1
[bulk]
rho = 0.01
)";
}

/// The 0D imposed-rate sweep (docs/model.md §4 friction_law) of both models as a scene file: 5 rates, `steps` steps
/// each to t_end = 5.
inline std::string sweep_config(int steps) {
  return R"(scene = "sweep"
models = ["continuum", "discrete"]
)" + paper_interface_toml() +
         R"([drive]
loading = "imposed_rate"
points = 5
[time]
t_end = 5
steps = )" + std::to_string(steps) + "\n";
}

inline std::string minimal_config() {
  return R"(scene = "tiny"
)" + paper_interface_toml() + R"(mu = 300
length = 20
[drive]
loading = "edge"
K = 2.5
v_d = 0.3
[grid]
dx = 2
[time]
t_end = 2
)";
}

/// Run the continuum model on a scene (validated first: a test must not run an invalid scene).
inline compare::ModelResult run_continuum(const compare::Scene& s, bool validate = true) {
  if (validate) s.validate();
  auto make = [&](std::size_t n) { return continuum::FrictionLaw(s.interface, n); };
  return compare::run_model<continuum::FrictionLaw>(s, make, "continuum", compare::RunControl{});
}

/// Row k of a snapshot field ([ns, nx] row-major).
inline std::span<const double> snapshot_row(const compare::ModelResult& r, const std::string& field, std::size_t k) {
  const auto& d = r.snapshots.at(field);
  const std::size_t nx = r.x.size();
  if ((k + 1) * nx > d.size()) throw std::out_of_range("snapshot_row: no snapshot " + std::to_string(k));
  return std::span<const double>(d).subspan(k * nx, nx);
}

/// Index of the snapshot taken closest to time t.
inline std::size_t snapshot_index(const compare::ModelResult& r, double t) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < r.snapshot_t.size(); ++k)
    if (std::abs(r.snapshot_t[k] - t) < std::abs(r.snapshot_t[best] - t)) best = k;
  return best;
}

/// Largest |a_i − b_i| over the nodes of the coarse grid xa that also belong to grid xb (positions
/// equal to 1e-9 dx): the error of a coarse field against a finer reference at shared nodes.
inline double max_diff_shared(std::span<const double> xa, std::span<const double> a, std::span<const double> xb,
                              std::span<const double> b) {
  if (xa.size() < 2 || xb.size() < 2) throw std::invalid_argument("max_diff_shared: grids too small");
  const double dxb = xb[1] - xb[0];
  double err = 0.0;
  std::size_t matched = 0;
  for (std::size_t i = 0; i < xa.size(); ++i) {
    const double j = xa[i] / dxb;
    const auto jr = static_cast<std::size_t>(std::llround(j));
    if (std::abs(j - static_cast<double>(jr)) > 1e-9 || jr >= xb.size()) continue;
    err = std::max(err, std::abs(a[i] - b[jr]));
    ++matched;
  }
  if (matched != xa.size()) throw std::invalid_argument("max_diff_shared: coarse nodes missing in the fine grid");
  return err;
}

/// Bit-for-bit equality, NaN equal to NaN (restart and identity tests).
inline bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }
inline bool same(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same(a[i], b[i])) return false;
  return true;
}
inline bool same(const compare::Columns& a, const compare::Columns& b) {
  if (a.size() != b.size()) return false;
  for (const auto& [k, v] : a)
    if (!b.count(k) || !same(v, b.at(k))) return false;
  return true;
}

/// Largest |a_i − b_i| relative to the largest |a_i|, |b_i| (0 when both fields vanish).
inline double max_relative_difference(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) throw std::invalid_argument("max_relative_difference: sizes differ");
  double scale = 0.0, diff = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    scale = std::max({scale, std::abs(a[i]), std::abs(b[i])});
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  return scale > 0.0 ? diff / scale : diff;
}

/// max_k |energy residual| / max_k drive work of a run with output.energy (throws without drive work).
inline double worst_energy_residual(const compare::ModelResult& r) {
  const auto& res = r.series.at("energy_residual");
  const auto& work = r.series.at("energy_drive_work");
  const double scale = *std::max_element(work.begin(), work.end());
  if (!(scale > 0.0)) throw std::invalid_argument("worst_energy_residual: no drive work");
  double worst = 0.0;
  for (double x : res) worst = std::max(worst, std::abs(x));
  return worst / scale;
}

/// Observed order of convergence from two errors at refinement ratio `ratio`.
inline double observed_order(double e_coarse, double e_fine, double ratio = 2.0) {
  return std::log(e_coarse / e_fine) / std::log(ratio);
}

/// The scene's models made continuum + discrete, the discrete one the count law with every contact at the one
/// threshold (w = 0) and no count noise: the law that is the continuum's bit for bit (docs/model.md §2, hierarchy
/// item 1; tests/test_discrete_identity.cpp, the strips' identity tests).
inline compare::Scene noise_off_count(compare::Scene s) {
  s.models = {"continuum", "discrete"};
  s.discrete.contacts_per_site = 1000;
  s.discrete.threshold = "delta";
  s.discrete.width = 0.0;
  s.discrete.representation = "count";
  s.discrete.noise = false;
  return s;
}

}  // namespace slipfront::testing
