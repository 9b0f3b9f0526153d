#include "studies/strip_cmin_height.hpp"

#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>

#include "studies/study.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/steady_front.hpp"
#include "core/strip.hpp"

namespace slipfront::studies {
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

double strip_cmin_column_modulus(const StripCminHeightOptions& o) {
  return o.body == core::BodyKind::inplane ? 2.0 * o.mu_strip / (1.0 - o.poisson) : o.mu_strip;
}

core::BulkParams strip_cmin_bulk(const StripCminHeightOptions& o, double H) {
  core::BulkParams b{o.rho_strip * H, strip_cmin_column_modulus(o) * H, 1000.0, H};
  if (o.body == core::BodyKind::inplane) {
    b.body_name = "inplane";
    b.poisson = o.poisson;
    b.normal_load = o.normal_load;
  }
  return b;
}

namespace {

// The path in H at o's material on o's body (continuum::continue_strip_height or its in-plane form, §11.8).
continuum::StripHeightPath continue_path(const StripCminHeightOptions& o, const continuum::StripHeightOptions& po) {
  if (o.body == core::BodyKind::inplane)
    return continuum::continue_inplane_height(o.law, o.mu_strip, o.rho_strip, o.poisson, o.normal_load, po);
  return continuum::continue_strip_height(o.law, o.mu_strip, o.rho_strip, po);
}

// The cost model's unknowns per row (continuum::strip_solve_cost): 2 on the in-plane strip (u_x, u_y).
int components(const StripCminHeightOptions& o) { return o.body == core::BodyKind::inplane ? 2 : 1; }

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
  p.front.stop = o.stop;  // polled inside every solve too (docs/fronts.md §10.20)
  return p;
}

continuum::StripHeightPath strip_cmin_limiting_path(const StripCminHeightOptions& o) {
  const double mu = o.mu_strip, rho = o.rho_strip, ell = strip_cmin_column_modulus(o);
  const auto& law = o.law;
  if (o.body == core::BodyKind::inplane)
    say(o, format("in-plane strip, nu = %g, p = %g: E' = 2 mu'/(1 - nu) = %g", o.poisson, o.normal_load, ell));
  say(o, format("material mu' = %g rho' = %g (c_s = %g), alpha = %g kappa = %g eta = %g: l = %g, l_kappa = %g, s = %g", mu,
                rho, std::sqrt(mu / rho), law.alpha, law.kappa, law.eta, ell, ell * law.kappa / (law.eta * law.alpha),
                ell / law.eta));
  const auto t0 = std::chrono::steady_clock::now();
  auto path = continue_path(o, strip_cmin_path_options(o));
  say(o, format("limiting path: %zu fronts, %zu steps, %.1f s%s%s", path.fronts.size(), path.steps.size(), seconds_since(t0),
                path.complete ? "" : ", incomplete: ", path.reason.c_str()));
  for (const auto& st : path.steps)
    say(o, format("  step H = %-12.6g c = %-12.8g predicted %-12.8g (%+.2e) newton %d rejected %d", st.height, st.c,
                  st.c_predicted, st.c_predicted / st.c - 1.0, st.newton_iterations, st.rejected));
  return path;
}

StripCminHeightOptions strip_cmin_study_defaults() {
  StripCminHeightOptions o;
  o.rtol = 1e-3;
  o.choose_meshes = true;
  o.intervals = 300;  // 64 rows on 400 intervals are above the Newton iteration limit; the ξ part is ~1e-7 of c here
  return o;
}

namespace {

// The meshes chosen by rtol (docs/fronts.md §10.20): what the path has cost in the cost model's CPU seconds
// (continuum::strip_solve_cost of each solve's mesh times its Newton iterations, counted at the stop polls).
struct ChosenPathCost {
  long iterations = 0;        // every Newton iteration so far (the solves poll the stop before each)
  double spent = 0.0;         // their cost
  int components = 1;         // unknowns per row (2: in-plane)
  std::function<bool()> counted;
  // the iterations since `before` charged at the price of `rows` × `intervals`
  void charge(long before, int rows, int intervals) {
    spent += static_cast<double>(iterations - before) *
             continuum::strip_solve_cost(rows, intervals, components).iteration_seconds;
  }
};

// The path's options on `rows` × `intervals`: the first row spacing ℓ_tip/(10 rows/first_rows), so that doubling the
// rows halves every spacing (the grading held, as the estimate's every-other-row re-solve assumes).
continuum::StripHeightOptions chosen_path_options(const StripCminHeightOptions& o, int rows, int intervals,
                                                  const std::function<bool()>& counted) {
  continuum::StripHeightOptions p = strip_cmin_path_options(o);
  p.front.rows = rows;
  p.front.intervals = intervals;
  p.row_resolution = continuum::strip_row_resolution * rows / o.first_rows;
  p.front.stop = counted;
  return p;
}

// The meshes a front of the path was solved on (its tip zone's spacings), for its estimate and its re-solves.
continuum::StripFrontOptions path_front_options(const continuum::StripHeightOptions& po, const continuum::StripFront& f) {
  return continuum::following_tip(po.front, continuum::strip_tip_zone(f.law, f.c, f.v_behind), po.tip_resolution,
                                  po.row_resolution);
}

// A refinement of the choice to `fine` at height index k (of n), or why not ({"", ""}): the mesh limits, the iteration
// limit, and the budget: spent, this height's re-solve and estimate (~26 iterations) and the heights left at the mean
// iterations per height so far, all at `fine`'s price.
std::pair<std::string, std::string> chosen_refusal(const StripCminHeightOptions& o, const continuum::StripFrontOptions& fine,
                                                   const ChosenPathCost& cost, std::size_t k, std::size_t n) {
  const std::string mesh = std::to_string(fine.rows) + " rows, " + std::to_string(fine.intervals) + " intervals";
  if (fine.rows > o.max_rows || fine.intervals > o.max_intervals)
    return {"limit", "limit: max " + std::to_string(o.max_rows) + " rows, " + std::to_string(o.max_intervals) + " intervals"};
  const double price = continuum::strip_solve_cost(fine.rows, fine.intervals, cost.components).iteration_seconds;
  if (price > continuum::strip_max_iteration_seconds) return {"limit", "limit: " + mesh + " exceed the Newton iteration limit"};
  const double per_height = static_cast<double>(cost.iterations) / static_cast<double>(k + 1);
  const double total = cost.spent + (26.0 + static_cast<double>(n - k - 1) * per_height) * price;
  if (total > o.budget_seconds)
    return {"budget", "budget: " + mesh + " predicted at " + core::format_number(total, 3) +
                          " s of CPU in all, over paths.budget " + core::format_number(o.budget_seconds) + " s"};
  return {"", ""};
}

// The front kept at height index k: the path's front re-solved with the rows (and, where the ξ part is ≥ 0.1 rtol·c,
// the intervals) doubled until its estimate is below 0.9 rtol·c; `m` its estimate and how the choice went.
continuum::StripFront refine_height(const StripCminHeightOptions& o, const continuum::StripHeightOptions& po,
                                    continuum::StripFront f, std::size_t k, std::size_t n, ChosenPathCost& cost,
                                    StripCminMesh& m) {
  continuum::StripFrontOptions fo = path_front_options(po, f);
  const double H = f.bulk.height;
  std::string rows = "rows " + std::to_string(fo.rows), intervals = "intervals " + std::to_string(fo.intervals), why;
  for (;;) {
    const long before = cost.iterations;
    m.error = continuum::estimate_strip_speed_error(f, fo);  // on half the rows, then twice the intervals
    cost.charge(before, std::max(1, fo.rows / 2), 2 * fo.intervals);
    const double e = m.error.total, target = o.rtol * f.c;
    if (std::isfinite(e) && e < 0.9 * target) break;
    if (o.stop && o.stop()) {
      m.limited = "stopped";
      break;
    }
    if (!std::isfinite(e)) {
      m.limited = "no estimate", why = "no estimate: " + m.error.note;
      break;
    }
    continuum::StripFrontOptions fine = fo;
    if (m.error.xi >= 0.1 * target) fine.intervals *= 2;
    if (m.error.rows >= 0.8 * target) fine = continuum::with_rows(H, fine, 2 * fine.rows);
    if (const auto [lim, line] = chosen_refusal(o, fine, cost, k, n); !lim.empty()) {
      m.limited = lim, why = line;
      break;
    }
    continuum::StripFrontOptions so = fine;
    so.max_newton = std::max(so.max_newton, 40);  // from other rows: more than a continuation step (the path's 12)
    const long before_solve = cost.iterations;
    continuum::StripFront g = continuum::solve_strip_saddle_node_front(f.law, f.bulk, so, f);
    cost.charge(before_solve, fine.rows, fine.intervals);
    if (g.status != continuum::FrontStatus::converged) {
      m.limited = g.status == continuum::FrontStatus::stopped ? "stopped" : "no convergence";
      why = "no convergence on " + std::to_string(fine.rows) + " rows, " + std::to_string(fine.intervals) + " intervals: " + g.reason;
      break;
    }
    if (fine.rows != fo.rows) rows += " -> " + std::to_string(fine.rows);
    if (fine.intervals != fo.intervals) intervals += " -> " + std::to_string(fine.intervals);
    f = std::move(g);
    fo = fine;
  }
  m.how = rows + ", " + intervals + (why.empty() ? "" : " (" + why + ")");
  return f;
}

}  // namespace

continuum::StripHeightPath strip_cmin_chosen_path(const StripCminHeightOptions& o, std::vector<StripCminMesh>& meshes,
                                                  double& predicted_seconds) {
  const std::vector<double> heights = strip_cmin_heights(o);
  ChosenPathCost cost;
  cost.components = components(o);
  cost.counted = [&cost, stop = o.stop] { return ++cost.iterations, stop && stop(); };
  continuum::StripHeightPath out;
  continuum::StripFront last;
  int rows = o.first_rows, intervals = o.intervals;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < heights.size(); ++k) {
    continuum::StripHeightOptions po = chosen_path_options(o, rows, intervals, cost.counted);
    po.heights = k == 0 ? std::vector<double>{heights[0]} : std::vector<double>{heights[k - 1], heights[k]};
    po.start = k == 0 ? nullptr : &last;
    const long before = cost.iterations;
    continuum::StripHeightPath seg = continue_path(o, po);
    cost.charge(before, rows, intervals);
    // the steps of the segment (its first, the start re-solved on the path's meshes, is the last height's)
    out.steps.insert(out.steps.end(), seg.steps.begin() + (k == 0 || seg.steps.empty() ? 0 : 1), seg.steps.end());
    if (!seg.complete || seg.fronts.size() < po.heights.size()) {
      out.reason = seg.reason;
      break;
    }
    StripCminMesh m;
    last = refine_height(o, po, std::move(seg.fronts.back()), k, heights.size(), cost, m);
    const bool within = m.error.total <= o.rtol * last.c;  // the verdict's test (the choice aims at 0.9 rtol)
    say(o, format("  H = %-10.6g c_min = %-12.8g +- %.2e (%.2e of c): %s%s%s", heights[k], last.c, m.error.total,
                  m.error.total / last.c, m.how.c_str(), within ? "" : ", NOT met: ", within ? "" : m.limited.c_str()));
    rows = last.rows();
    intervals = static_cast<int>(last.xi.size()) - 1;
    out.fronts.push_back(last);
    meshes.push_back(std::move(m));
    if (meshes.back().limited == "stopped") {
      out.reason = "stopped on request at H = " + core::format_number(heights[k]);
      break;
    }
  }
  out.complete = out.fronts.size() == heights.size() && out.reason.empty();
  predicted_seconds = cost.spent;
  say(o, format("limiting path (meshes chosen by rtol %g): %zu fronts, %zu steps, %.1f s, %.1f s of CPU predicted%s%s", o.rtol,
                out.fronts.size(), out.steps.size(), seconds_since(t0), cost.spent, out.complete ? "" : ", incomplete: ",
                out.reason.c_str()));
  return out;
}

namespace {

// The σ_d = 0.8 path whose fronts start each height's whole branch (only with o.branches).
continuum::StripHeightPath strip_cmin_start_path(const StripCminHeightOptions& o, const continuum::StripHeightOptions& po) {
  continuum::StripHeightOptions os = po;
  os.limiting = false;
  os.sigma_d = 0.8;
  os.front.rows = o.branch_rows;
  os.front.intervals = o.branch_intervals;
  auto start_path = continue_path(o, os);
  say(o, format("sigma_d = 0.8 path: %zu fronts%s%s", start_path.fronts.size(), start_path.complete ? "" : ", incomplete: ",
                start_path.reason.c_str()));
  return start_path;
}

// The 1D chain's c_min at the same material (μ = μ'H, in-plane E'H; ρ = ρ'H) and its estimate; a note where it is not
// computed.
continuum::FrontBranch strip_cmin_1d_pass(const StripCminHeightOptions& o, double h, StripCminRow& r) {
  const double mu = strip_cmin_column_modulus(o), rho = o.rho_strip;
  continuum::ContinuationOptions c1;
  c1.stop = o.stop;  // the 1D pass stops with the study (it took ~60 s per height unpolled)
  auto b1 = continuum::continue_steady_fronts(o.law, {rho * h, mu * h, 1000.0, 0.0}, c1);
  if (!std::isfinite(b1.c_min))
    r.note = "c_min_1d and ratio_to_1d not computed at H = " + format("%g", h) + ": the 1D branch (mu = " +
             format("%g", mu * h) + ", rho = " + format("%g", rho * h) + ") ended " + continuum::to_string(b1.end) + ": " +
             b1.reason;
  r.c_min_1d_error = std::nan("");
  for (const auto& q : b1.points)
    if (std::isfinite(b1.c_min) && q.c == b1.c_min) r.c_min_1d_error = q.speed_error;
  return b1;
}

// The path front's own error estimate (every other row, twice the intervals; docs/fronts.md §10.20).
void strip_cmin_front_error(const StripCminHeightOptions& o, const continuum::StripHeightOptions& po,
                            const continuum::StripFront& fr, StripCminRow& r) {
  continuum::StripFrontOptions eo = po.front;
  eo.stop = o.stop;
  eo = continuum::following_tip(eo, continuum::strip_tip_zone(o.law, fr.c, fr.v_behind), po.tip_resolution,
                                po.row_resolution);
  const auto err = continuum::estimate_strip_speed_error(fr, eo);
  r.c_min_error = err.total;
  if (!err.note.empty() && !std::isfinite(err.total))
    r.note += std::string(r.note.empty() ? "" : "; ") + "c_min_error not estimated at H = " + format("%g", fr.bulk.height) +
              ": " + err.note;
}

// The whole branch at height h from the σ_d = 0.8 path's front: its c_min against the limiting path's.
void strip_cmin_branch(const StripCminHeightOptions& o, const continuum::StripHeightOptions& po,
                       const continuum::StripFront& start, const continuum::StripFront& fr, StripCminRow& r) {
  const double h = fr.bulk.height;
  continuum::StripContinuationOptions co;
  co.sigma_start = 0.8;
  co.front = po.front;
  co.front.rows = o.branch_rows;
  co.front.intervals = o.branch_intervals;
  co.front.max_newton = 12;
  const double lt = continuum::strip_tip_zone(o.law, start.c, start.v_behind);
  co.front = continuum::following_tip(co.front, lt, po.tip_resolution, po.row_resolution);
  co.start = &start;
  co.stop = o.stop;
  const auto tb = std::chrono::steady_clock::now();
  const auto br = continuum::continue_strip_fronts(o.law, strip_cmin_bulk(o, h), co);
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

// The verdict on rtol (o.rtol > 0): met when c_min's estimate is below rtol·c_min, else NOT met with why (the choice's
// `limited`, or the meshes given) in the row's verdict. NaN when not judged.
void judge_height(const StripCminHeightOptions& o, const StripCminMesh* m, StripCminRow& r) {
  r.rtol_met = std::nan("");
  if (!(o.rtol > 0.0)) return;
  const bool met = std::isfinite(r.c_min_error) && r.c_min_error <= o.rtol * r.c_min;
  r.rtol_met = met ? 1.0 : 0.0;
  if (met) return;
  const std::string limited = m ? m->limited : std::string();
  r.verdict = "NOT met" + (limited.empty() ? std::string() : " (" + limited + ")") + " at H = " + format("%g", r.H) +
              ": c_min = " + format("%.8g", r.c_min) +
              (std::isfinite(r.c_min_error) ? " +- " + format("%.3g", r.c_min_error) + " (" +
                                                  format("%.3g", 100.0 * r.c_min_error / r.c_min) + " % of c"
                                            : std::string(" (no estimate")) +
              ", rtol " + format("%g", 100.0 * o.rtol) + " %); " +
              (m ? m->how : "rows " + std::to_string(r.rows) + ", intervals " + std::to_string(r.intervals) + " given");
}

}  // namespace

std::vector<StripCminRow> strip_cmin_rows(const StripCminHeightOptions& o, const continuum::StripHeightPath& path,
                                          const std::vector<StripCminMesh>* meshes) {
  const double ell = strip_cmin_column_modulus(o), cs = std::sqrt(o.mu_strip / o.rho_strip);
  const auto& law = o.law;
  const double ell_kappa = ell * law.kappa / (law.eta * law.alpha), s = ell / law.eta;
  const continuum::StripHeightOptions po = strip_cmin_path_options(o);
  const continuum::StripHeightPath start_path = o.branches ? strip_cmin_start_path(o, po) : continuum::StripHeightPath{};
  std::vector<StripCminRow> rows;
  for (std::size_t k = 0; k < path.fronts.size(); ++k) {
    if (o.stop && o.stop()) break;
    const auto& fr = path.fronts[k];
    const double h = fr.bulk.height;
    StripCminRow r;
    const auto b1 = strip_cmin_1d_pass(o, h, r);
    const StripCminMesh* m = meshes && k < meshes->size() ? &(*meshes)[k] : nullptr;
    if (m) {
      r.c_min_error = m->error.total;
      if (!std::isfinite(r.c_min_error))
        r.note += std::string(r.note.empty() ? "" : "; ") + "c_min_error not estimated at H = " + format("%g", h) + ": " + m->error.note;
    } else {
      strip_cmin_front_error(o, po, fr, r);
    }
    r.H = h;
    r.H_over_l = h / ell;
    r.H_over_l_kappa = h / ell_kappa;
    r.c_min = fr.c;
    r.c_min_over_s = fr.c / s;
    r.c_min_over_cs = fr.c / cs;
    r.c_min_1d = b1.c_min;
    r.ratio_to_1d = fr.c / b1.c_min;
    r.ratio_to_1d_error = r.ratio_to_1d * (r.c_min_error / fr.c + r.c_min_1d_error / b1.c_min);
    r.local_exponent = std::nan("");
    if (k + 1 < path.fronts.size())
      r.local_exponent = std::log(path.fronts[k + 1].c / fr.c) / std::log(path.fronts[k + 1].bulk.height / h);
    r.branch_c_min = r.branch_sigma_d_at_c_min = std::nan("");
    if (o.branches && k < start_path.fronts.size()) strip_cmin_branch(o, po, start_path.fronts[k], fr, r);
    r.rows = fr.rows();
    r.intervals = static_cast<int>(fr.xi.size()) - 1;
    r.domain_length = fr.domain_length;
    r.tip_zone = continuum::strip_tip_zone(law, fr.c, fr.v_behind);
    judge_height(o, m, r);
    rows.push_back(std::move(r));
  }
  return rows;
}

StripCminHeight strip_cmin_height(const StripCminHeightOptions& o) {
  StripCminHeight out;
  if (o.choose_meshes && o.rtol > 0.0) {
    out.path = strip_cmin_chosen_path(o, out.meshes, out.predicted_seconds);
    out.rows = strip_cmin_rows(o, out.path, &out.meshes);
  } else {
    out.predicted_seconds = std::nan("");
    out.path = strip_cmin_limiting_path(o);
    out.rows = strip_cmin_rows(o, out.path);
  }
  return out;
}

std::string strip_cmin_csv(const std::vector<StripCminRow>& rows) {
  std::string out =
      "H,H_over_l,H_over_l_kappa,c_min,c_min_over_s,c_min_over_cs,c_min_1d,ratio_to_1d,local_exponent,"
      "branch_c_min,branch_sigma_d_at_c_min,branch_c_min_at_end,branch_points,branch_folds,branch_end,"
      "branch_seconds,rows,intervals,domain_length,tip_zone,c_min_error,c_min_1d_error,ratio_to_1d_error,rtol_met\n";
  for (const auto& r : rows)
    out += format("%.9g,%.6g,%.6g,%.10g,%.6g,%.6g,%.10g,%.8g,%.6g,%.10g,%.8g,%d,%d,%d,%s,%.2f,%d,%d,%.6g,%.6g,%.3g,%.3g,%.3g,%g\n",
                  r.H, r.H_over_l, r.H_over_l_kappa, r.c_min, r.c_min_over_s, r.c_min_over_cs, r.c_min_1d, r.ratio_to_1d,
                  r.local_exponent, r.branch_c_min, r.branch_sigma_d_at_c_min, r.branch_c_min_at_end, r.branch_points,
                  r.branch_folds, r.branch_end.c_str(), r.branch_seconds, r.rows, r.intervals, r.domain_length, r.tip_zone,
                  r.c_min_error, r.c_min_1d_error, r.ratio_to_1d_error, r.rtol_met);
  return out;
}

namespace {

using core::KeyDomain;
using K = core::KeyKind;
constexpr KeyDomain path_domains[] = {
    {"paths.hmin", K::number, 0.0, core::parameter_cap, true, false, false, "", "(the first target height)"},
    {"paths.hmax", K::number, 0.0, core::parameter_cap, true, false, false, "", "(the last target height)"},
    {"paths.per_decade", K::number, 0.0, 100.0, true, false, false, "", "(target heights per decade)"},
    {"paths.rows", K::integer, 1.0, 256.0, false, false, false, "", "(as slipfront fronts --rows)"},
    {"paths.intervals", K::integer, 8.0, 100000.0, false, false, false, "", "(as slipfront fronts --intervals)"},
    {"paths.branches", K::boolean},
    {"paths.branch_rows", K::integer, 1.0, 256.0, false, false, false, "", "(as slipfront fronts --rows)"},
    {"paths.branch_intervals", K::integer, 8.0, 100000.0, false, false, false, "", "(as slipfront fronts --intervals)"},
    {"paths.tolerance", K::number, 1e-15, 1e-3, false, false, false, "", "(Newton tolerance of every solve)"},
    {"paths.max_factor", K::number, 1.01, 10.0, false, false, false, "", "(largest step H_{n+1}/H_n of the path)"},
    {"paths.rtol", K::number, 1e-8, 0.5, false, false, false, "", "(the target on c_min, as slipfront fronts --rtol)"},
    {"paths.budget", K::number, 1.0, 1e7, false, false, false, "", "(CPU seconds of the mesh choice, as slipfront fronts --budget)"},
};

// A numeric column of the rows.
template <class T>
std::vector<double> column(const std::vector<StripCminRow>& rows, T StripCminRow::*field) {
  std::vector<double> v;
  for (const auto& r : rows) v.push_back(static_cast<double>(r.*field));
  return v;
}

// Every row's note (why a number is NaN) into the notes, the largest relative c_min estimate as a scalar; a
// message counting the rows with a NaN ("" when none).
std::string note_errors(const std::vector<StripCminRow>& rows, StudyReport& rep) {
  int without = 0;
  double worst = 0.0;
  for (const auto& row : rows) {
    if (!row.note.empty()) rep.notes.push_back(row.note), ++without;
    if (std::isfinite(row.c_min_error)) worst = std::max(worst, row.c_min_error / row.c_min);
  }
  rep.scalars["c_min_largest_relative_error"] = worst;
  rep.definitions["c_min_largest_relative_error"] = "largest c_min_error/c_min over the table (docs/fronts.md §10.20)";
  int unmet = 0;
  for (const auto& row : rows)
    if (!row.verdict.empty()) rep.notes.push_back(row.verdict), ++unmet;
  rep.scalars["heights_rtol_unmet"] = unmet;
  rep.definitions["heights_rtol_unmet"] = "heights whose c_min_error is not below rtol c_min (rtol_met = 0; each in the notes)";
  std::string message;
  if (without > 0)
    message = std::to_string(without) + " of " + std::to_string(rows.size()) +
              " heights have a NaN (c_min_1d, ratio_to_1d or an error estimate): see the notes";
  if (unmet > 0)
    message += (message.empty() ? "" : "; ") + std::to_string(unmet) + " of " + std::to_string(rows.size()) +
               " heights NOT met (c_min not within its rtol): see the notes";
  return message;
}

}  // namespace

std::span<const core::KeyDomain> strip_cmin_path_domains() { return path_domains; }

void check_strip_cmin_paths(const StripCminHeightOptions& o) {
  if (!(o.hmax > o.hmin))
    throw core::ParamError("paths.hmax", "must be > paths.hmin = " + core::format_number(o.hmin) + ", got " +
                                             core::format_number(o.hmax));
  const double steps = std::round(o.per_decade * std::log10(o.hmax / o.hmin));
  if (steps < 1.0)
    throw core::ParamError("paths.per_decade",
                           "gives one target height only: round(per_decade log10(hmax/hmin)) = round(" +
                               core::format_number(o.per_decade) + " x " + core::format_number(std::log10(o.hmax / o.hmin), 4) +
                               ") = 0; raise paths.per_decade or widen paths.hmin .. paths.hmax");
  if (steps + 1.0 > strip_cmin_max_heights)
    throw core::ParamError("paths.per_decade", "gives " + core::format_number(steps + 1.0) + " target heights, more than " +
                                                   std::to_string(strip_cmin_max_heights) +
                                                   "; lower paths.per_decade or narrow paths.hmin .. paths.hmax");
}

StripCminHeightOptions strip_cmin_study_options(const StudySpec& spec, const Scene& base) {
  if (base.bulk.body() == core::BodyKind::chain)
    throw core::ParamError("scene", "the kind strip_cmin_height needs a strip scene (bulk.height > 0): its material is "
                                    "mu' = bulk.mu/bulk.height, rho' = bulk.rho/bulk.height; " + spec.scene_file +
                                    " is the 1D chain (bulk.height = 0)");
  StripCminHeightOptions o = spec.kind_options.has_value() ? kind_options<StripCminHeightOptions>(spec)
                                                           : strip_cmin_study_defaults();
  o.law = base.interface;
  o.body = base.bulk.body();
  o.poisson = base.bulk.poisson;
  o.normal_load = base.bulk.normal_load;
  o.mu_strip = o.body == core::BodyKind::inplane ? continuum::inplane_material(base.bulk).mu : core::Strip::modulus(base.bulk);
  o.rho_strip = base.bulk.rho / base.bulk.height;
  check_strip_cmin_paths(o);
  return o;
}

void check_strip_cmin_study(const StudySpec& spec, const Scene& base) { (void)strip_cmin_study_options(spec, base); }

namespace {

// The study's scalars: the material, the law and the lengths and speeds of docs/fronts.md §10.12.
void put_strip_cmin_scalars(StudyReport& rep, const StripCminHeightOptions& o, const StripCminHeight& r) {
  const double ell = strip_cmin_column_modulus(o), ell_kappa = ell * o.law.kappa / (o.law.eta * o.law.alpha);
  const bool inplane = o.body == core::BodyKind::inplane;
  rep.scalars["inplane"] = inplane ? 1.0 : 0.0;
  rep.scalars["mu_column"] = ell;
  rep.scalars["poisson"] = inplane ? o.poisson : std::nan("");
  rep.scalars["c_R"] = inplane ? continuum::rayleigh_ratio(o.poisson) * std::sqrt(o.mu_strip / o.rho_strip) : std::nan("");
  rep.definitions["inplane"] = "1: the in-plane strip (bulk.body = \"inplane\", docs/fronts.md §11.8); 0: the antiplane strip";
  rep.definitions["mu_column"] = "the column stiffness per height mu/H: mu' (antiplane), E' = 2 mu'/(1 - nu) (in-plane); the 1D "
                                 "c_min compared with is that of mu = mu_column H";
  rep.definitions["poisson"] = "nu of the in-plane strip (bulk.poisson); NaN on the antiplane strip";
  rep.definitions["c_R"] = "Rayleigh speed of the in-plane strip's material c_R(nu) c_s; NaN on the antiplane strip";
  rep.scalars["mu_strip"] = o.mu_strip;
  rep.scalars["rho_strip"] = o.rho_strip;
  rep.scalars["alpha"] = o.law.alpha;
  rep.scalars["kappa"] = o.law.kappa;
  rep.scalars["eta"] = o.law.eta;
  rep.scalars["ell"] = ell;
  rep.scalars["ell_kappa"] = ell_kappa;
  rep.scalars["s"] = ell / o.law.eta;
  rep.scalars["c_s"] = std::sqrt(o.mu_strip / o.rho_strip);
  rep.scalars["heights_target"] = static_cast<double>(strip_cmin_heights(o).size());
  rep.scalars["heights_reached"] = static_cast<double>(r.rows.size());
  rep.scalars["path_steps"] = static_cast<double>(r.path.steps.size());
  rep.definitions["mu_strip"] = "the strip's shear modulus per height mu' of the base scene, held along the path in H: "
                                "bulk.mu/bulk.height (antiplane), bulk.mu (1 - nu)/(2 bulk.height) (in-plane)";
  rep.definitions["rho_strip"] = "rho' = bulk.rho/bulk.height of the base scene, held along the path";
  rep.definitions["alpha"] = "interface.alpha of the base scene";
  rep.definitions["kappa"] = "interface.kappa of the base scene";
  rep.definitions["eta"] = "interface.eta of the base scene";
  rep.definitions["ell"] = "the paper's elastic length of the strip, l = mu_column (mu' antiplane, docs/fronts.md §10.12; "
                           "E' in-plane, §11.8)";
  rep.definitions["ell_kappa"] = "l_kappa = l kappa/(eta alpha)";
  rep.definitions["s"] = "the paper's speed s = l/eta";
  rep.definitions["c_s"] = "shear wave speed sqrt(mu'/rho')";
  rep.definitions["heights_target"] = "target heights of [paths]: round(per_decade log10(hmax/hmin)) + 1";
  rep.definitions["heights_reached"] = "target heights the limiting path reached (the table's rows)";
  rep.definitions["path_steps"] = "accepted steps of the limiting path in H";
  rep.scalars["rtol"] = o.rtol;
  rep.scalars["meshes_chosen"] = o.choose_meshes && o.rtol > 0.0 ? 1.0 : 0.0;
  rep.scalars["budget_seconds"] = o.budget_seconds;
  rep.scalars["predicted_seconds"] = r.predicted_seconds;
  rep.definitions["rtol"] = "paths.rtol: the target on every c_min (its estimate below rtol c_min); 0: not judged";
  rep.definitions["meshes_chosen"] = "1: each height's rows and intervals chosen by rtol (no paths.rows); 0: paths.rows, "
                                     "paths.intervals as given (docs/fronts.md §10.20)";
  rep.definitions["budget_seconds"] = "paths.budget: CPU seconds (continuum::strip_solve_cost) the mesh choice may predict";
  rep.definitions["predicted_seconds"] = "the cost model's CPU seconds of the path with its re-solves and estimates "
                                         "(NaN: meshes given)";
}

// The table strip_cmin_height, one row per target height reached, and its definitions (a table: one line a column).
void put_strip_cmin_table(StudyReport& rep, const StripCminHeight& r) {
  Columns t;
  t["H"] = column(r.rows, &StripCminRow::H);
  t["H_over_l"] = column(r.rows, &StripCminRow::H_over_l);
  t["H_over_l_kappa"] = column(r.rows, &StripCminRow::H_over_l_kappa);
  t["c_min"] = column(r.rows, &StripCminRow::c_min);
  t["c_min_over_s"] = column(r.rows, &StripCminRow::c_min_over_s);
  t["c_min_over_cs"] = column(r.rows, &StripCminRow::c_min_over_cs);
  t["c_min_1d"] = column(r.rows, &StripCminRow::c_min_1d);
  t["ratio_to_1d"] = column(r.rows, &StripCminRow::ratio_to_1d);
  t["local_exponent"] = column(r.rows, &StripCminRow::local_exponent);
  t["branch_c_min"] = column(r.rows, &StripCminRow::branch_c_min);
  t["branch_sigma_d_at_c_min"] = column(r.rows, &StripCminRow::branch_sigma_d_at_c_min);
  t["branch_c_min_at_end"] = column(r.rows, &StripCminRow::branch_c_min_at_end);
  t["branch_points"] = column(r.rows, &StripCminRow::branch_points);
  t["branch_folds"] = column(r.rows, &StripCminRow::branch_folds);
  t["branch_seconds"] = column(r.rows, &StripCminRow::branch_seconds);
  t["rows"] = column(r.rows, &StripCminRow::rows);
  t["intervals"] = column(r.rows, &StripCminRow::intervals);
  t["domain_length"] = column(r.rows, &StripCminRow::domain_length);
  t["tip_zone"] = column(r.rows, &StripCminRow::tip_zone);
  t["c_min_error"] = column(r.rows, &StripCminRow::c_min_error);
  t["c_min_1d_error"] = column(r.rows, &StripCminRow::c_min_1d_error);
  t["ratio_to_1d_error"] = column(r.rows, &StripCminRow::ratio_to_1d_error);
  t["rtol_met"] = column(r.rows, &StripCminRow::rtol_met);
  rep.tables["strip_cmin_height"] = t;
  const std::map<std::string, std::string> defs = {
      {"H", "strip height (a target height of [paths] the limiting path reached)"},
      {"H_over_l", "H/l, l = mu_column (mu' antiplane, E' in-plane)"},
      {"H_over_l_kappa", "H/l_kappa, l_kappa = l kappa/(eta alpha)"},
      {"c_min", "speed of the limiting front at sigma_c^d (the strip's c_min), continued in H at fixed mu', rho'"},
      {"c_min_over_s", "c_min/s, s = l/eta"},
      {"c_min_over_cs", "c_min/c_s, c_s = sqrt(mu'/rho')"},
      {"c_min_1d", "c_min of the 1D chain of the same column stiffness mu = mu_column H, rho = rho' H (end of its branch)"},
      {"ratio_to_1d", "c_min/c_min_1d"},
      {"local_exponent", "d ln c_min/d ln H to the next height (NaN at the last)"},
      {"branch_c_min", "paths.branches: c_min of the branch c(sigma_d) from sigma_d = 0.8 to its end (NaN without)"},
      {"branch_sigma_d_at_c_min", "paths.branches: sigma_d where the branch's c is least (NaN without)"},
      {"branch_c_min_at_end", "paths.branches: 1 when the branch's c is monotone and least at its end (0 without)"},
      {"branch_points", "paths.branches: continuation points of the branch (0 without)"},
      {"branch_folds", "paths.branches: turning points of the branch (0 without)"},
      {"branch_seconds", "paths.branches: wall time of the branch in s (0 without): the table's only timing column"},
      {"rows", "row intervals across the height of the limiting front (chosen per height by rtol, or paths.rows)"},
      {"intervals", "xi intervals of the limiting front's collocation mesh (chosen per height by rtol from paths.intervals, or as given)"},
      {"domain_length", "length L of the limiting front's xi domain"},
      {"tip_zone", "the front's tip zone c/(1 + kappa v_behind)"},
      {"c_min_error", "estimated error of c_min (docs/fronts.md §10.20): re-solved on every other row (order 1.5 "
                      "assumed) plus the xi part; NaN: not estimated (see the notes)"},
      {"c_min_1d_error", "estimated error of c_min_1d (the 1D solver's Richardson in xi); NaN: no c_min_1d (see the notes)"},
      {"ratio_to_1d_error", "estimated error of ratio_to_1d: ratio x (both relative errors summed)"},
      {"rtol_met", "1: c_min_error below rtol c_min; 0: NOT met (why: the notes); NaN: not judged (rtol = 0)"}};
  for (const auto& [k, v] : defs) rep.definitions["strip_cmin_height/" + k] = v;
}

// complete, failed (the limiting path fell short) or interrupted, with the reason as a note.
StudyOutcome strip_cmin_outcome(StudyReport& rep, const StripCminHeightOptions& o, const StripCminHeight& r,
                                const StudyWork& work) {
  StudyOutcome out;
  out.message = note_errors(r.rows, rep);
  const bool stopped = work.stop && work.stop();
  if (!r.path.complete) {
    out.status = stopped ? RunStatus::interrupted : RunStatus::failed;
    out.message = "the limiting path reached " + std::to_string(r.rows.size()) + " of " +
                  std::to_string(strip_cmin_heights(o).size()) + " target heights: " + r.path.reason;
    rep.notes.push_back(out.message);
  } else if (stopped) {
    out.status = RunStatus::interrupted;
    out.message = "stopped while the branches were continued: the limiting path is complete, the branches are not";
    rep.notes.push_back(out.message);
  }
  return out;
}

}  // namespace

StudyOutcome strip_cmin_height_study(StudyReport& rep, const StudySpec& spec, const Scene& base, const StudyWork& work) {
  StripCminHeightOptions o = strip_cmin_study_options(spec, base);
  o.stop = work.stop;
  o.log = work.log;
  const StripCminHeight r = strip_cmin_height(o);
  put_strip_cmin_scalars(rep, o, r);
  put_strip_cmin_table(rep, r);
  rep.files["strip_cmin_height.csv"] = strip_cmin_csv(r.rows);
  return strip_cmin_outcome(rep, o, r, work);
}

}  // namespace slipfront::studies
