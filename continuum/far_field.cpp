#include "continuum/far_field.hpp"

#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "core/params.hpp"

namespace slipfront::continuum::far_field {

using Mat = Eigen::MatrixXd;
using CVec = Eigen::VectorXcd;

double row_grading_of(double H, int M, double first, double grading) {
  if (grading > 0.0) return grading;
  if (!(first > 0.0) || !(H / M > first)) return 0.0;
  auto spacing = [&](double gm) { return std::log(H * std::expm1(gm / M) / std::expm1(gm)) - std::log(first); };
  double hi = 1.0;
  while (spacing(hi) > 0.0) hi *= 2.0;
  std::uintmax_t iters = 200;
  const auto br = boost::math::tools::toms748_solve(spacing, 1e-9, hi, boost::math::tools::eps_tolerance<double>(50), iters);
  return 0.5 * (br.first + br.second);
}

std::vector<double> make_rows(double H, int M, double g) {
  std::vector<double> y(static_cast<std::size_t>(M) + 1);
  for (int j = 0; j <= M; ++j) {
    const double s = static_cast<double>(j) / M;
    y[static_cast<std::size_t>(j)] = g > 0.0 ? H * std::expm1(g * s) / std::expm1(g) : H * s;
  }
  y.back() = H;
  return y;
}

Subspace left_subspace(const Mat& Jr, int count, bool lowest, bool allow_null) {
  Subspace out;
  const Eigen::EigenSolver<Mat> es(Jr.transpose(), true);
  if (es.info() != Eigen::Success) {
    out.why = "eigenproblem of the far field failed";
    return out;
  }
  const int n = static_cast<int>(Jr.rows());
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const CVec ev = es.eigenvalues();
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return lowest ? ev[a].real() < ev[b].real() : ev[a].real() > ev[b].real();
  });
  const double scale = std::max(1.0, Jr.cwiseAbs().maxCoeff());
  const double last = ev[order[static_cast<std::size_t>(count) - 1]].real(), next = ev[order[static_cast<std::size_t>(count)]].real();
  const double sgn = lowest ? 1.0 : -1.0;  // excluded: sgn·Re < 0
  const bool gap = sgn * next > 0.0 && (sgn * last < 0.0 || (allow_null && std::abs(last) <= 1e-8 * scale));
  for (int r = 0; r < n; ++r) (r < count ? out.excluded : out.kept).push_back(ev[order[static_cast<std::size_t>(r)]]);
  if (!gap) {
    const auto negative = std::count_if(out.excluded.begin(), out.excluded.end(), [](auto l) { return l.real() < 0.0; }) +
                          std::count_if(out.kept.begin(), out.kept.end(), [](auto l) { return l.real() < 0.0; });
    out.why = "the far field has not " + std::to_string(count) + " modes of each sign (the " + std::to_string(count) +
              "th and next real parts: " + core::format_number(last) + ", " + core::format_number(next) + "; " +
              std::to_string(negative) + " of " + std::to_string(n) + " with a negative real part)";
    return out;
  }
  Mat W(n, count);
  int col = 0;
  for (int r = 0; r < count; ++r) {
    const int k = order[static_cast<std::size_t>(r)];
    const CVec l = es.eigenvectors().col(k);
    if (std::abs(ev[k].imag()) <= 1e-12 * scale) {
      W.col(col++) = l.real();
    } else if (ev[k].imag() > 0.0) {
      if (col + 2 > count) break;
      W.col(col++) = l.real();
      W.col(col++) = l.imag();
    }
  }
  if (col != count) {
    out.why = "a complex pair of far-field modes is split by the count";
    return out;
  }
  const Eigen::HouseholderQR<Mat> qr(W);
  out.Q = qr.householderQ() * Mat::Identity(n, count);
  out.ok = true;
  return out;
}

double interp_rows(const std::vector<double>& yo, const double* col, double yy, double top_slope) {
  const std::size_t n = yo.size();
  if (yy >= yo.back()) return col[n - 1] + top_slope * (yy - yo.back());
  const auto it = std::upper_bound(yo.begin(), yo.end(), yy);
  const std::size_t b = std::max<std::size_t>(1, static_cast<std::size_t>(it - yo.begin())), a = b - 1;
  const double t = (yy - yo[a]) / (yo[b] - yo[a]);
  return (1.0 - t) * col[a] + t * col[b];
}

void row_widths(const std::vector<double>& y, std::vector<double>& k, std::vector<double>& w) {
  const std::size_t M = y.size() - 1;
  k.resize(M);
  w.assign(M + 1, 0.0);
  for (std::size_t a = 0; a < M; ++a) {
    k[a] = y[a + 1] - y[a];
    w[a] += 0.5 * k[a];
    w[a + 1] += 0.5 * k[a];
  }
}

Mat translation_free(int n) {
  Mat T = Mat::Zero(n - 1, n);
  for (int r = 1; r < n; ++r) T(r - 1, r) = 1.0;
  return T;
}

void tip_law_rows(const Eigen::VectorXd& yN, int r2, int base, double c, const core::InterfaceParams& law,
                  InterfaceIndex ix, front_solver::Rows& rows, front_solver::ScalarColumns col) {
  rows.F[r2] = yN[ix.A] - 1.0;
  rows.F[r2 + 1] = yN[ix.S] - law.alpha * yN[ix.u0];
  rows.F[r2 + 2] = yN[ix.S] - law.eta * c * yN[ix.p0] - 1.0;
  if (!rows.jacobian()) return;
  rows.entry(r2, base + ix.A, 1.0);
  rows.entry(r2 + 1, base + ix.S, 1.0);
  rows.entry(r2 + 1, base + ix.u0, -law.alpha);
  rows.entry(r2 + 2, base + ix.S, 1.0);
  rows.entry(r2 + 2, base + ix.p0, -law.eta * c);
  rows.entry(r2 + 2, col.c, -law.eta * yN[ix.p0]);
}

}  // namespace slipfront::continuum::far_field
