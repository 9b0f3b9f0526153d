// c_min(H) of the antiplane strip at a fixed strip material (issue 20 items 1, 2; docs/fronts.md §10.11–§10.13):
// the limiting front at σ_c^d continued in H (continuum::continue_strip_height), at every target H the branch
// c(σ_d) from σ_d = 0.8 to its end (started from a second path at σ_d = 0.8), the 1D c_min of the same column
// stiffness μ = μ'H, and the paper's lengths ℓ = μ', ℓ_κ = μ'κ/(ηα), s = μ'/η. Not a Google benchmark: a study
// driver whose table (CSV on stdout, or the file given) is the data of docs/fronts.md §10.12.
//
//   strip_cmin_height [--mu 300] [--rho 1e-9] [--alpha 1.05] [--kappa 8] [--eta 0.1] [--hmin 1] [--hmax 1e6]
//                     [--per-decade 2] [--rows 16] [--intervals 400] [--branch-rows 8] [--branch-intervals 300]
//                     [--no-branches] [--out file.csv]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "continuum/friction_law.hpp"
#include "continuum/steady_front.hpp"
#include "continuum/strip_front.hpp"

namespace continuum = slipfront::continuum;
namespace core = slipfront::core;

int main(int argc, char** argv) {
  double mu = 300.0, rho = 1e-9, alpha = 1.05, kappa = 8.0, eta = 0.1, hmin = 1.0, hmax = 1e6, per_decade = 2.0;
  int rows = 16, intervals = 400, branch_rows = 8, branch_intervals = 300;
  bool branches = true, check = false;
  double tol = 1e-11, max_factor = 2.0;
  std::string out;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--mu") mu = next();
    else if (a == "--rho") rho = next();
    else if (a == "--alpha") alpha = next();
    else if (a == "--kappa") kappa = next();
    else if (a == "--eta") eta = next();
    else if (a == "--hmin") hmin = next();
    else if (a == "--hmax") hmax = next();
    else if (a == "--per-decade") per_decade = next();
    else if (a == "--rows") rows = static_cast<int>(next());
    else if (a == "--intervals") intervals = static_cast<int>(next());
    else if (a == "--branch-rows") branch_rows = static_cast<int>(next());
    else if (a == "--branch-intervals") branch_intervals = static_cast<int>(next());
    else if (a == "--no-branches") branches = false;
    else if (a == "--check") check = true;
    else if (a == "--tol") tol = next();
    else if (a == "--max-factor") max_factor = next();
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else {
      std::fprintf(stderr, "unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  const core::InterfaceParams law{alpha, kappa, eta};
  const double ell = mu, ell_kappa = mu * kappa / (eta * alpha), s = mu / eta, cs = std::sqrt(mu / rho);
  std::vector<double> H;
  const int n = static_cast<int>(std::lround(per_decade * std::log10(hmax / hmin)));
  for (int k = 0; k <= n; ++k) H.push_back(hmin * std::pow(hmax / hmin, static_cast<double>(k) / n));
  std::FILE* f = out.empty() ? stdout : std::fopen(out.c_str(), "w");
  if (f == nullptr) {
    std::fprintf(stderr, "strip_cmin_height: cannot write %s\n", out.c_str());
    return 2;
  }
  std::fprintf(stderr, "material mu' = %g rho' = %g (c_s = %g), alpha = %g kappa = %g eta = %g: l = %g, l_kappa = %g, s = %g\n",
               mu, rho, cs, alpha, kappa, eta, ell, ell_kappa, s);

  const auto t0 = std::chrono::steady_clock::now();
  continuum::StripHeightOptions o;
  o.heights = H;
  o.front.rows = rows;
  o.front.intervals = intervals;
  o.front.max_newton = 12;
  o.front.tolerance = tol;
  o.max_factor = max_factor;
  const auto path = continuum::continue_strip_height(law, mu, rho, o);
  const double t_path = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "limiting path: %zu fronts, %zu steps, %.1f s%s%s\n", path.fronts.size(), path.steps.size(), t_path,
               path.complete ? "" : ", incomplete: ", path.reason.c_str());
  for (const auto& st : path.steps)
    std::fprintf(stderr, "  step H = %-12.6g c = %-12.8g predicted %-12.8g (%+.2e) newton %d rejected %d\n", st.height, st.c,
                 st.c_predicted, st.c_predicted / st.c - 1.0, st.newton_iterations, st.rejected);

  // Mesh convergence at the largest H: each variant re-solved from the path's last front.
  if (check && !path.fronts.empty()) {
    const auto& last = path.fronts.back();
    const double h = last.bulk.height, lt = continuum::strip_tip_zone(law, last.c, last.v_behind);
    struct Variant {
      const char* what;
      int rows, intervals;
      double tip_res, row_res, decay, rho_factor;
    };
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
      for (const auto& f : solved)
        if (f.status == continuum::FrontStatus::converged && f.rows() <= v.rows && f.rows() > from->rows()) from = &f;
      continuum::StripFrontOptions fo = continuum::following_tip(o.front, lt, v.tip_res, v.row_res);
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

  continuum::StripHeightPath start_path;
  if (branches) {
    continuum::StripHeightOptions os = o;
    os.limiting = false;
    os.sigma_d = 0.8;
    os.front.rows = branch_rows;
    os.front.intervals = branch_intervals;
    start_path = continuum::continue_strip_height(law, mu, rho, os);
    std::fprintf(stderr, "sigma_d = 0.8 path: %zu fronts%s%s\n", start_path.fronts.size(), start_path.complete ? "" : ", incomplete: ",
                 start_path.reason.c_str());
  }
  std::fprintf(f, "H,H_over_l,H_over_l_kappa,c_min,c_min_over_s,c_min_over_cs,c_min_1d,ratio_to_1d,local_exponent,"
                  "branch_c_min,branch_sigma_d_at_c_min,branch_c_min_at_end,branch_points,branch_folds,branch_end,"
                  "branch_seconds,rows,intervals,domain_length,tip_zone\n");
  for (std::size_t k = 0; k < path.fronts.size(); ++k) {
    const auto& fr = path.fronts[k];
    const double h = fr.bulk.height;
    const auto b1 = continuum::continue_steady_fronts(law, {rho * h, mu * h, 1000.0, 0.0});
    double expo = std::nan("");
    if (k + 1 < path.fronts.size())
      expo = std::log(path.fronts[k + 1].c / fr.c) / std::log(path.fronts[k + 1].bulk.height / h);
    double bc = std::nan(""), bs = std::nan(""), bsec = 0.0;
    int bend = 0, bpts = 0, bfolds = 0;
    std::string bendname = "none";
    if (branches && k < start_path.fronts.size()) {
      continuum::StripContinuationOptions co;
      co.sigma_start = 0.8;
      co.front = o.front;
      co.front.rows = branch_rows;
      co.front.intervals = branch_intervals;
      co.front.max_newton = 12;
      const double lt = continuum::strip_tip_zone(law, start_path.fronts[k].c, start_path.fronts[k].v_behind);
      co.front = continuum::following_tip(co.front, lt, o.tip_resolution, o.row_resolution);
      co.start = &start_path.fronts[k];
      const auto tb = std::chrono::steady_clock::now();
      const auto br = continuum::continue_strip_fronts(law, {rho * h, mu * h, 1000.0, h}, co);
      bsec = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb).count();
      bc = br.c_min;
      bs = br.sigma_d_at_c_min;
      bend = br.c_min_at_end ? 1 : 0;
      bpts = static_cast<int>(br.points.size());
      bfolds = static_cast<int>(br.folds.size());
      bendname = continuum::to_string(br.end);
      std::fprintf(stderr, "  branch H = %g: %d points, end %s, c_min %.8g (path %.8g, %+.2e), %.1f s: %s\n", h, bpts,
                   bendname.c_str(), bc, fr.c, bc / fr.c - 1.0, bsec, br.reason.c_str());
    }
    std::fprintf(f, "%.9g,%.6g,%.6g,%.10g,%.6g,%.6g,%.10g,%.8g,%.6g,%.10g,%.8g,%d,%d,%d,%s,%.2f,%d,%d,%.6g,%.6g\n", h, h / ell,
                 h / ell_kappa, fr.c, fr.c / s, fr.c / cs, b1.c_min, fr.c / b1.c_min, expo, bc, bs, bend, bpts, bfolds,
                 bendname.c_str(), bsec, fr.rows(), static_cast<int>(fr.xi.size()) - 1, fr.domain_length,
                 continuum::strip_tip_zone(law, fr.c, fr.v_behind));
    std::fflush(f);
  }
  if (f != stdout) std::fclose(f);
  return path.complete ? 0 : 1;
}
