#include "compare/strip_cmin_height.hpp"

#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "continuum/steady_front.hpp"

namespace slipfront::compare {
namespace {

namespace continuum = slipfront::continuum;

// printf into a string (the table's and the log's formats are the bench's, kept byte for byte).
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  va_list a, b;
  va_start(a, fmt);
  va_copy(b, a);
  const int n = std::vsnprintf(nullptr, 0, fmt, a);
  va_end(a);
  std::string s(static_cast<std::size_t>(n > 0 ? n : 0), '\0');
  if (n > 0) std::vsnprintf(s.data(), s.size() + 1, fmt, b);
  va_end(b);
  return s;
}

void say(const StripCminHeightOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::vector<double> strip_cmin_heights(const StripCminHeightOptions& o) {
  std::vector<double> H;
  const int n = static_cast<int>(std::lround(o.per_decade * std::log10(o.hmax / o.hmin)));
  for (int k = 0; k <= n; ++k) H.push_back(o.hmin * std::pow(o.hmax / o.hmin, static_cast<double>(k) / n));
  return H;
}

continuum::StripHeightOptions strip_cmin_path_options(const StripCminHeightOptions& o) {
  continuum::StripHeightOptions p;
  p.heights = strip_cmin_heights(o);
  p.front.rows = o.rows;
  p.front.intervals = o.intervals;
  p.front.max_newton = 12;
  p.front.tolerance = o.tolerance;
  p.max_factor = o.max_factor;
  p.stop = o.stop;
  return p;
}

continuum::StripHeightPath strip_cmin_limiting_path(const StripCminHeightOptions& o) {
  const double mu = o.mu_strip, rho = o.rho_strip;
  const auto& law = o.law;
  say(o, format("material mu' = %g rho' = %g (c_s = %g), alpha = %g kappa = %g eta = %g: l = %g, l_kappa = %g, s = %g", mu,
                rho, std::sqrt(mu / rho), law.alpha, law.kappa, law.eta, mu, mu * law.kappa / (law.eta * law.alpha),
                mu / law.eta));
  const auto t0 = std::chrono::steady_clock::now();
  auto path = continuum::continue_strip_height(law, mu, rho, strip_cmin_path_options(o));
  say(o, format("limiting path: %zu fronts, %zu steps, %.1f s%s%s", path.fronts.size(), path.steps.size(), seconds_since(t0),
                path.complete ? "" : ", incomplete: ", path.reason.c_str()));
  for (const auto& st : path.steps)
    say(o, format("  step H = %-12.6g c = %-12.8g predicted %-12.8g (%+.2e) newton %d rejected %d", st.height, st.c,
                  st.c_predicted, st.c_predicted / st.c - 1.0, st.newton_iterations, st.rejected));
  return path;
}

std::vector<StripCminRow> strip_cmin_rows(const StripCminHeightOptions& o, const continuum::StripHeightPath& path) {
  const double mu = o.mu_strip, rho = o.rho_strip;
  const auto& law = o.law;
  const double ell = mu, ell_kappa = mu * law.kappa / (law.eta * law.alpha), s = mu / law.eta, cs = std::sqrt(mu / rho);
  const continuum::StripHeightOptions po = strip_cmin_path_options(o);
  continuum::StripHeightPath start_path;
  if (o.branches) {
    continuum::StripHeightOptions os = po;
    os.limiting = false;
    os.sigma_d = 0.8;
    os.front.rows = o.branch_rows;
    os.front.intervals = o.branch_intervals;
    start_path = continuum::continue_strip_height(law, mu, rho, os);
    say(o, format("sigma_d = 0.8 path: %zu fronts%s%s", start_path.fronts.size(), start_path.complete ? "" : ", incomplete: ",
                  start_path.reason.c_str()));
  }
  std::vector<StripCminRow> rows;
  for (std::size_t k = 0; k < path.fronts.size(); ++k) {
    const auto& fr = path.fronts[k];
    const double h = fr.bulk.height;
    const auto b1 = continuum::continue_steady_fronts(law, {rho * h, mu * h, 1000.0, 0.0});
    StripCminRow r;
    r.H = h;
    r.H_over_l = h / ell;
    r.H_over_l_kappa = h / ell_kappa;
    r.c_min = fr.c;
    r.c_min_over_s = fr.c / s;
    r.c_min_over_cs = fr.c / cs;
    r.c_min_1d = b1.c_min;
    r.ratio_to_1d = fr.c / b1.c_min;
    r.local_exponent = std::nan("");
    if (k + 1 < path.fronts.size())
      r.local_exponent = std::log(path.fronts[k + 1].c / fr.c) / std::log(path.fronts[k + 1].bulk.height / h);
    r.branch_c_min = r.branch_sigma_d_at_c_min = std::nan("");
    if (o.branches && k < start_path.fronts.size()) {
      continuum::StripContinuationOptions co;
      co.sigma_start = 0.8;
      co.front = po.front;
      co.front.rows = o.branch_rows;
      co.front.intervals = o.branch_intervals;
      co.front.max_newton = 12;
      const double lt = continuum::strip_tip_zone(law, start_path.fronts[k].c, start_path.fronts[k].v_behind);
      co.front = continuum::following_tip(co.front, lt, po.tip_resolution, po.row_resolution);
      co.start = &start_path.fronts[k];
      co.stop = o.stop;
      const auto tb = std::chrono::steady_clock::now();
      const auto br = continuum::continue_strip_fronts(law, {rho * h, mu * h, 1000.0, h}, co);
      r.branch_seconds = seconds_since(tb);
      r.branch_c_min = br.c_min;
      r.branch_sigma_d_at_c_min = br.sigma_d_at_c_min;
      r.branch_c_min_at_end = br.c_min_at_end ? 1 : 0;
      r.branch_points = static_cast<int>(br.points.size());
      r.branch_folds = static_cast<int>(br.folds.size());
      r.branch_end = continuum::to_string(br.end);
      say(o, format("  branch H = %g: %d points, end %s, c_min %.8g (path %.8g, %+.2e), %.1f s: %s", h, r.branch_points,
                    r.branch_end.c_str(), r.branch_c_min, fr.c, r.branch_c_min / fr.c - 1.0, r.branch_seconds,
                    br.reason.c_str()));
    }
    r.rows = fr.rows();
    r.intervals = static_cast<int>(fr.xi.size()) - 1;
    r.domain_length = fr.domain_length;
    r.tip_zone = continuum::strip_tip_zone(law, fr.c, fr.v_behind);
    rows.push_back(std::move(r));
  }
  return rows;
}

StripCminHeight strip_cmin_height(const StripCminHeightOptions& o) {
  StripCminHeight out;
  out.path = strip_cmin_limiting_path(o);
  out.rows = strip_cmin_rows(o, out.path);
  return out;
}

std::string strip_cmin_csv(const std::vector<StripCminRow>& rows) {
  std::string out =
      "H,H_over_l,H_over_l_kappa,c_min,c_min_over_s,c_min_over_cs,c_min_1d,ratio_to_1d,local_exponent,"
      "branch_c_min,branch_sigma_d_at_c_min,branch_c_min_at_end,branch_points,branch_folds,branch_end,"
      "branch_seconds,rows,intervals,domain_length,tip_zone\n";
  for (const auto& r : rows)
    out += format("%.9g,%.6g,%.6g,%.10g,%.6g,%.6g,%.10g,%.8g,%.6g,%.10g,%.8g,%d,%d,%d,%s,%.2f,%d,%d,%.6g,%.6g\n", r.H,
                  r.H_over_l, r.H_over_l_kappa, r.c_min, r.c_min_over_s, r.c_min_over_cs, r.c_min_1d, r.ratio_to_1d,
                  r.local_exponent, r.branch_c_min, r.branch_sigma_d_at_c_min, r.branch_c_min_at_end, r.branch_points,
                  r.branch_folds, r.branch_end.c_str(), r.branch_seconds, r.rows, r.intervals, r.domain_length, r.tip_zone);
  return out;
}

}  // namespace slipfront::compare
