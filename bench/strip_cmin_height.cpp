// c_min(H) of the antiplane strip at a fixed strip material (issue 20 items 1, 2; docs/fronts.md §10.11–§10.13):
// the limiting front at σ_c^d continued in H (continuum::continue_strip_height), at every target H the branch
// c(σ_d) from σ_d = 0.8 to its end (started from a second path at σ_d = 0.8), the 1D c_min of the same column
// stiffness μ = μ'H, and the paper's lengths ℓ = μ', ℓ_κ = μ'κ/(ηα), s = μ'/η. Not a Google benchmark: the
// command line of studies::strip_cmin_height (studies/strip_cmin_height.hpp; the main job runs the same
// computation as the study configs/studies/strip_cmin_height.toml, docs/studies.md), whose table (CSV on stdout,
// or the file given) is the data of docs/fronts.md §10.12; --check adds the mesh variants at the largest H (§10.13).
//
//   strip_cmin_height [--mu 300] [--rho 1e-9] [--alpha 1.05] [--kappa 8] [--eta 0.1] [--hmin 1] [--hmax 1e6]
//                     [--per-decade 2] [--rows 16] [--intervals 400] [--branch-rows 8] [--branch-intervals 300]
//                     [--no-branches] [--out file.csv]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "studies/strip_cmin_height.hpp"
#include "continuum/strip_front.hpp"

namespace compare = slipfront::compare;
namespace continuum = slipfront::continuum;
namespace studies = slipfront::studies;

// --check: mesh convergence at the largest H, each variant re-solved from the path's last front (printed to stderr).
static void check_meshes_at_largest_height(const studies::StripCminHeightOptions& o, const continuum::StripHeightPath& path) {
  const double mu = o.mu_strip, rho = o.rho_strip;
  const auto& law = o.law;
  const continuum::StripHeightOptions po = studies::strip_cmin_path_options(o);
  const auto& last = path.fronts.back();
  const double h = last.bulk.height, lt = continuum::strip_tip_zone(law, last.c, last.v_behind);
  struct Variant {
    const char* what;
    int rows, intervals;
    double tip_res, row_res, decay, rho_factor;
  };
  const int rows = o.rows, intervals = o.intervals;
  const std::vector<Variant> variants{{"base", rows, intervals, 30, 10, 20, 1},
                                      {"2x rows", 2 * rows, intervals, 30, 10, 20, 1},
                                      {"4x rows", 4 * rows, intervals, 30, 10, 20, 1},
                                      {"2x intervals", rows, 2 * intervals, 30, 10, 20, 1},
                                      {"tip, first row /2", rows, intervals, 60, 20, 20, 1},
                                      {"2x rows, first row /2", 2 * rows, intervals, 30, 20, 20, 1},
                                      {"L: 30 e-folds", rows, intervals, 30, 10, 30, 1},
                                      {"rho' / 100", rows, intervals, 30, 10, 20, 0.01}};
  // Each variant starts from the converged variant with the most rows not above its own (the path's front
  // for the 12-row ones): 48 rows started from the 12-row front did not converge in 40 Newton iterations,
  // from the converged 24-row front it does (docs/fronts.md §10.13).
  std::vector<continuum::StripFront> solved;
  double base = 0.0;
  for (const auto& v : variants) {
    const continuum::StripFront* from = &last;
    for (const auto& s : solved)
      if (s.status == continuum::FrontStatus::converged && s.rows() <= v.rows && s.rows() > from->rows()) from = &s;
    continuum::StripFrontOptions fo = continuum::following_tip(po.front, lt, v.tip_res, v.row_res);
    fo.rows = v.rows;
    fo.intervals = v.intervals;
    fo.decay_lengths = v.decay;
    fo.max_newton = 40;
    const auto tv = std::chrono::steady_clock::now();
    const auto fr = continuum::solve_strip_saddle_node_front(law, {rho * v.rho_factor * h, mu * h, 1000.0, h}, fo, *from);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - tv).count();
    if (base == 0.0) base = fr.c;
    std::fprintf(stderr, "check H = %g %-24s rows %3d intervals %4d: c = %.10g (%+.2e vs base) %s, newton %d, residual %.1e, L = %.4g, %.1f s (from %d rows)\n",
                 h, v.what, v.rows, v.intervals, fr.c, fr.c / base - 1.0, continuum::to_string(fr.status), fr.newton_iterations,
                 fr.residual_norm, fr.domain_length, sec, from->rows());
    solved.push_back(fr);
  }
}

int main(int argc, char** argv) {
  studies::StripCminHeightOptions o;
  bool check = false;
  std::string out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--mu") o.mu_strip = next();
    else if (a == "--rho") o.rho_strip = next();
    else if (a == "--alpha") o.law.alpha = next();
    else if (a == "--kappa") o.law.kappa = next();
    else if (a == "--eta") o.law.eta = next();
    else if (a == "--hmin") o.hmin = next();
    else if (a == "--hmax") o.hmax = next();
    else if (a == "--per-decade") o.per_decade = next();
    else if (a == "--rows") o.rows = static_cast<int>(next());
    else if (a == "--intervals") o.intervals = static_cast<int>(next());
    else if (a == "--branch-rows") o.branch_rows = static_cast<int>(next());
    else if (a == "--branch-intervals") o.branch_intervals = static_cast<int>(next());
    else if (a == "--no-branches") o.branches = false;
    else if (a == "--check") check = true;
    else if (a == "--tol") o.tolerance = next();
    else if (a == "--max-factor") o.max_factor = next();
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  std::FILE* f = out.empty() ? stdout : std::fopen(out.c_str(), "w");
  if (f == nullptr) {
    std::fprintf(stderr, "strip_cmin_height: cannot write %s\n", out.c_str());
    return 2;
  }
  o.log = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const auto path = studies::strip_cmin_limiting_path(o);

  if (check && !path.fronts.empty()) check_meshes_at_largest_height(o, path);

  const std::string csv = studies::strip_cmin_csv(studies::strip_cmin_rows(o, path));
  std::fwrite(csv.data(), 1, csv.size(), f);
  if (f != stdout) std::fclose(f);
  return path.complete ? 0 : 1;
}
