// Steady fronts of the in-plane strip (continuum/inplane_front.hpp, docs/fronts.md §11): the solved front against an
// independent transcription of its discrete equations (element by element here, node by node in the solver), the
// order in ξ and across the rows, the thin limit H → 0 against the 1D solver with μ = E'H on the branch and at its end (c_min → 11.281),
// and the end of the subsonic fronts at c_s. Paper parameters, μ and ρ integrated over the height, ν = 1/3
// (docs/model.md §10.2). Default tier: a few seconds in all (the branch, the rows' order at H = 10 and the error
// estimate against a fine mesh: tests/test_slow_inplane_front.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "compare/fit.hpp"
#include "continuum/inplane_front.hpp"
#include "continuum/steady_front.hpp"
#include "front_checks.hpp"
#include "front_defect.hpp"

namespace continuum = slipfront::continuum;
namespace core = slipfront::core;
namespace testing = slipfront::testing;
using continuum::FrontStatus;
using continuum::StripFront;
using continuum::StripFrontOptions;

namespace {

const core::InterfaceParams paper{1.05, 8.0, 0.1};
core::BulkParams inplane(double H, double normal_load = 0.0) {
  core::BulkParams b{0.01, 300.0, 300.0, H};
  b.body_name = "inplane";
  b.normal_load = normal_load;
  return b;
}

// The rows' traveling-wave equations written out again from docs/model.md §10 (plane strain, μ' = μ(1 − ν)/(2H),
// ρ' = ρ/H, λ' = 2μ'ν/(1 − 2ν)) by elements: P1 across the height (rows y_j, spacing k_e of element e = [y_j, y_j+1],
// dual widths W_j), the ξξ terms lumped. Per element the mean stresses
//   s_xy,e = μ' ((u_{j+1} − u_j)/k_e + (q_j + q_{j+1})/2),   s_yy,e = λ' (p_j + p_{j+1})/2 + (λ' + 2μ')(w_{j+1} − w_j)/k_e
// and the weak equations at row a (φ_a' k_e = −1 at the element's lower row, +1 at its upper):
//   (λ' + 2μ' − ρ'c²) W_a p_a' = Σ_e [−λ' (q_{j+1} − q_j)/2 + φ_a'k_e s_xy,e] + τ δ_a0 − σ_d δ_aM
//   (μ' − ρ'c²) W_a q_a'        = Σ_e [−μ' (p_{j+1} − p_j)/2 + φ_a'k_e s_yy,e] + p δ_aM            (a ≥ 1; w_0 = q_0 = 0)
template <class T>
struct RowState {
  std::vector<T> u, w, p, q;  // u: u_0 and the lifts u_j − u_0 (u_0 does not enter the fluxes)
};
struct Transcription {
  const StripFront& f;
  std::vector<double> k, W;
  double mu, lam, rho;
  explicit Transcription(const StripFront& front) : f(front) {
    const std::size_t M = f.y.size() - 1;
    k.resize(M);
    W.assign(M + 1, 0.0);
    for (std::size_t j = 0; j < M; ++j) {
      k[j] = f.y[j + 1] - f.y[j];
      W[j] += k[j] / 2;
      W[j + 1] += k[j] / 2;
    }
    const double nu = f.bulk.poisson, H = f.bulk.height;
    mu = f.bulk.mu * (1.0 - nu) / (2.0 * H);
    rho = f.bulk.rho / H;
    lam = 2.0 * mu * nu / (1.0 - 2.0 * nu);
  }
  // (p', q') of every row for the bulk state s, interface traction tau, top loads (sd, pl); with `size`, also the
  // sum of the magnitudes of the terms each balances (their round-off scale: q' is a small difference of large terms).
  template <class T>
  void bulk(const RowState<T>& s, T tau, double sd, double pl, std::vector<T>& dp, std::vector<T>& dq,
            std::vector<double>* size = nullptr) const {
    const std::size_t n = f.y.size(), M = n - 1;
    std::vector<T> rx(n, T(0)), ry(n, T(0));
    std::vector<double> mx(n, 0.0), my(n, 0.0);
    auto lift = [&](std::size_t j) { return j == 0 ? T(0) : s.u[j]; };
    for (std::size_t e = 0; e < M; ++e) {
      const std::size_t lo = e, hi = e + 1;
      const T sxy = mu * ((lift(hi) - lift(lo)) / k[e] + (s.q[lo] + s.q[hi]) / 2.0);
      const T syy = lam * (s.p[lo] + s.p[hi]) / 2.0 + (lam + 2 * mu) * (s.w[hi] - s.w[lo]) / k[e];
      for (std::size_t a : {lo, hi}) {
        const double sign = a == lo ? -1.0 : 1.0;
        rx[a] += -lam * (s.q[hi] - s.q[lo]) / 2.0 + sign * sxy;
        ry[a] += -mu * (s.p[hi] - s.p[lo]) / 2.0 + sign * syy;
        mx[a] += std::abs(lam * (s.q[hi] - s.q[lo]) / 2.0) + std::abs(sxy);
        my[a] += std::abs(mu * (s.p[hi] - s.p[lo]) / 2.0) + std::abs(syy);
      }
    }
    rx[0] += tau;
    rx[M] -= sd;
    ry[M] += pl;
    mx[0] += std::abs(tau);
    mx[M] += std::abs(sd);
    my[M] += std::abs(pl);
    const double c2 = rho * f.c * f.c;
    dp.assign(n, T(0));
    dq.assign(n, T(0));
    if (size) size->assign(2 * n, 0.0);
    for (std::size_t a = 0; a < n; ++a) {
      dp[a] = rx[a] / ((lam + 2 * mu - c2) * W[a]);
      if (a > 0) dq[a] = ry[a] / ((mu - c2) * W[a]);
      if (!size) continue;
      (*size)[a] = mx[a] / std::abs((lam + 2 * mu - c2) * W[a]);
      (*size)[n + a] = my[a] / std::abs((mu - c2) * W[a]);
    }
  }
  // The whole state at node i: (u, w, p, q) of every row (w_0 = q_0 = 0 kept as entries), A, σ̄.
  std::vector<double> node(std::size_t i) const {
    const std::size_t n = f.y.size();
    std::vector<double> s(4 * n + 2);
    for (std::size_t j = 0; j < n; ++j) {
      s[j] = j == 0 ? f.u[i * n] : f.lift[i * n + j];
      s[n + j] = f.uy[i * n + j];
      s[2 * n + j] = f.strain[i * n + j];
      s[3 * n + j] = f.uy_strain[i * n + j];
    }
    s[4 * n] = f.area[i];
    s[4 * n + 1] = f.sigma_bar[i];
    return s;
  }
  // dy/dξ of the whole state; `size`: the magnitude of each component's terms (|f| where f is not a balance).
  std::vector<double> rhs(const std::vector<double>& s, std::vector<double>* size = nullptr) const {
    const std::size_t n = f.y.size();
    RowState<double> r{{s.begin(), s.begin() + n}, {s.begin() + n, s.begin() + 2 * n},
                       {s.begin() + 2 * n, s.begin() + 3 * n}, {s.begin() + 3 * n, s.begin() + 4 * n}};
    const double v = -f.c * r.p[0], A = s[4 * n], sb = s[4 * n + 1];
    std::vector<double> dp, dq, out(4 * n + 2, 0.0), balance;
    bulk(r, sb + f.law.eta * v, f.sigma_d, f.bulk.normal_load, dp, dq, &balance);
    for (std::size_t j = 0; j < n; ++j) {
      out[j] = j == 0 ? r.p[0] : r.p[j] - r.p[0];
      out[n + j] = r.q[j];
      out[2 * n + j] = dp[j];
      out[3 * n + j] = dq[j];
    }
    out[4 * n] = (f.law.kappa * A * std::abs(v) - (1.0 - A)) / f.c;
    out[4 * n + 1] = (sb * std::abs(v) - f.law.alpha * A * v) / f.c;
    if (size) {
      size->resize(out.size());
      for (std::size_t idx = 0; idx < out.size(); ++idx) (*size)[idx] = std::abs(out[idx]);
      for (std::size_t j = 0; j < 2 * n; ++j) (*size)[2 * n + j] = balance[j];
    }
    return out;
  }
  // The collocation defect relative to the terms it balances (for the rows' p', q': the terms of (P2), not their sum).
  double scaled_defect() const {
    return slipfront::testing::scaled_collocation_defect(
        f.xi, 4 * f.y.size() + 2, [this](std::size_t i) { return node(i); },
        [this](const std::vector<double>& s, std::vector<double>* size) { return rhs(s, size); });
  }
};

}  // namespace

TEST_CASE("inplane front: the solution satisfies its discrete equations", "[inplane][front]") {
  // H = 2, σ_d = 0.5, 8 graded rows, 200 intervals.
  StripFrontOptions o;
  o.rows = 8;
  o.intervals = 200;
  o.row_spacing = 0.1;
  const StripFront f = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o);
  REQUIRE(f.status == FrontStatus::converged);
  CHECK(f.residual_norm < 1e-11);
  // The defect from the transcription, relative to the terms: 0.8–1.5e−10 at Newton tolerances 1e−11 … 1e−13 (the
  // round-off floor of u_y and ∂ξu_y, ~1e−5 of u_x's size; a wrong term in either transcription leaves a defect of its size).
  const Transcription t(f);
  CHECK(t.scaled_defect() < 1e-9);

  // The tip: A = 1, σ̄ = α u_x(0, 0), τ = 1.
  const std::size_t N = f.xi.size() - 1, n = f.y.size(), M = n - 1;
  CHECK(std::abs(f.area[N] - 1.0) < 1e-12);
  CHECK(std::abs(f.sigma_bar[N] - paper.alpha * f.u[N * n]) < 1e-12);
  CHECK(std::abs(f.sigma_bar[N] + paper.eta * f.slip_rate[N] - 1.0) < 1e-12);

  // Ahead: the tip state minus the stuck state (u_x = σ_d/α + σ_d y/μ', u_y = 0) is the sum of the 2M + 1 stored
  // decaying modes, each an eigenvector of the linear stuck system as transcribed here (τ = α u_0 − η c p_0, no loads).
  // Mode layout (continuum::inplane_front_node): u_0, lifts 1..M, w 1..M, p 0..M, q 1..M.
  REQUIRE(f.ahead_rate.size() == 2 * M + 1);
  using C = std::complex<double>;
  std::vector<C> sum(4 * M + 2, 0.0);
  for (std::size_t m = 0; m < f.ahead_rate.size(); ++m) {
    const C lam = f.ahead_rate[m];
    CHECK(lam.real() < 0.0);
    const auto& r = f.ahead_mode[m];
    RowState<C> s;
    s.u.assign(r.begin(), r.begin() + static_cast<long>(n));
    s.w = {C(0)};
    s.w.insert(s.w.end(), r.begin() + static_cast<long>(n), r.begin() + static_cast<long>(n + M));
    s.p.assign(r.begin() + static_cast<long>(n + M), r.begin() + static_cast<long>(2 * n + M));
    s.q = {C(0)};
    s.q.insert(s.q.end(), r.begin() + static_cast<long>(2 * n + M), r.end());
    std::vector<C> dp, dq;
    t.bulk(s, paper.alpha * s.u[0] - paper.eta * f.c * s.p[0], 0.0, 0.0, dp, dq);
    double worst = 0.0, size = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      const C du = j == 0 ? s.p[0] : s.p[j] - s.p[0];
      worst = std::max({worst, std::abs(du - lam * s.u[j]), std::abs(s.q[j] - lam * s.w[j]), std::abs(dp[j] - lam * s.p[j]),
                        std::abs(dq[j] - lam * s.q[j])});
      size = std::max({size, std::abs(lam * s.u[j]), std::abs(lam * s.p[j]), std::abs(lam * s.q[j])});
    }
    CHECK(worst <= 1e-8 * size);
    for (std::size_t q = 0; q < sum.size(); ++q) sum[q] += r[q];
  }
  const auto tip = continuum::inplane_front_node(f, N);
  const double mu_s = t.mu;
  for (std::size_t j = 0; j < n; ++j) {
    const double stuck = j == 0 ? 0.5 / paper.alpha : 0.5 * f.y[j] / mu_s;
    CHECK(std::abs(sum[j].real() - (tip[j] - stuck)) < 1e-10);
  }
  for (std::size_t q = n; q < sum.size(); ++q) CHECK(std::abs(sum[q].real() - tip[q]) < 1e-10);

  // Behind: steady sliding at v_b, ∂ξu_x = −v_b/c on every row, τ = σ_d, σ_yy(ξ, 0) → −p = 0.
  CHECK(std::abs(f.slip_rate[0] / f.v_behind - 1.0) < 1e-6);
  CHECK(std::abs(f.area[0] / f.area_behind - 1.0) < 1e-6);
  for (std::size_t j = 0; j < n; ++j) CHECK(std::abs(-f.strain[j] * f.c / f.v_behind - 1.0) < 1e-6);
  CHECK(std::abs(f.traction[0] - 0.5) < 1e-6);
  CHECK(std::abs(f.normal_stress[0]) < 1e-6);
  CHECK(std::abs(f.normal_stress[N]) > 1e-3);  // the slip's normal stress at the tip (no reflection symmetry)
  CHECK(f.stable_eigenvalue < 0.0);
  CHECK(f.overstress_margin > 0.0);
  CHECK(f.min_slip_rate > 0.0);

  // A normal load p on the top adds the uniform compression and nothing else (the law does not see σ_yy): the
  // same c, σ_yy(ξ, 0) shifted by −p (both solved from f on its own mesh: L fixed).
  o.domain_length = f.domain_length;
  const StripFront same = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o, &f);
  const StripFront loaded = continuum::solve_inplane_front(paper, inplane(2.0, 0.5), 0.5, o, &f);
  REQUIRE(same.status == FrontStatus::converged);
  REQUIRE(loaded.status == FrontStatus::converged);
  CHECK(std::abs(loaded.c - same.c) < 1e-10 * f.c);
  for (std::size_t i = 0; i <= N; ++i) REQUIRE(std::abs(loaded.normal_stress[i] - same.normal_stress[i] + 0.5) < 1e-8);
  CHECK(Transcription(loaded).scaled_defect() < 1e-9);
}

TEST_CASE("inplane front: the speed converges at 4th order in xi and about 2nd across the rows", "[inplane][front]") {
  // Fixed rows (4), H = 2, L = 330, mesh map β = 6; N = 100 … 800. Lobatto IIIA: 4 (docs/fronts.md §11.4).
  // Observed: differences 1.49e-6, 9.33e-8, 5.83e-9 (ratios 16.0, 16.0).
  StripFrontOptions o;
  o.rows = 4;
  o.domain_length = 330.0;
  o.grading = 6.0;
  const StripFront g = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o);
  REQUIRE(g.status == FrontStatus::converged);
  std::vector<double> c;
  for (int N : {100, 200, 400, 800}) {
    o.intervals = N;
    const StripFront f = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o, &g);
    REQUIRE(f.status == FrontStatus::converged);
    c.push_back(f.c);
  }
  const std::vector<double> h{1.0, 0.5, 0.25}, diff{std::abs(c[1] - c[0]), std::abs(c[2] - c[1]), std::abs(c[3] - c[2])};
  const auto fit = slipfront::compare::fit_power_law(h, diff);
  WARN("inplane xi: observed order " << fit.slope);
  CHECK(std::abs(fit.slope - 4.0) < 0.1);

  // Rows: H = 2, graded with fixed γ = 4, M = 4 … 32, 150 intervals. P1 across the height is 2nd order, less the tip
  // corner's log (docs/fronts.md §10.5, §11.4): observed successive orders 1.67, 1.85 (differences 6.95e-3, 2.18e-3,
  // 6.05e-4); at H = 10, 1.60, 1.77 (tests/test_slow_inplane_front.cpp).
  o.intervals = 150;
  o.row_grading = 4.0;
  c.clear();
  for (int M : {4, 8, 16, 32}) {
    o.rows = M;
    const StripFront f = continuum::solve_inplane_front(paper, inplane(2.0), 0.5, o, &g);
    REQUIRE(f.status == FrontStatus::converged);
    c.push_back(f.c);
  }
  const auto [o1, o2] = testing::successive_orders(c);
  WARN("inplane rows: successive orders " << o1 << ", " << o2);
  CHECK(o2 > o1);
  CHECK(o2 > 1.7);
  CHECK(o2 < 2.1);
}

TEST_CASE("inplane front: H -> 0 recovers the 1D fronts of mu = E'H at second order in H", "[inplane][front][thin]") {
  // μ, ρ fixed (μ' = μ(1 − ν)/(2H)): the strip tends to the 1D chain with the plate modulus (docs/model.md §10.2).
  // Observed (4 rows, 600 intervals): c(H) − c_1D ≈ −7.2e−3 H² at σ_d = 0.3, −3.9e−2 H² at 0.5.
  for (double sigma_d : {0.3, 0.5}) {
    const double c_1d = testing::one_dimensional_speed(paper, sigma_d);
    StripFrontOptions o;
    o.rows = 4;
    std::vector<double> H{0.1, 0.2, 0.4}, c;
    for (double h : H) {
      const StripFront f = continuum::solve_inplane_front(paper, inplane(h), sigma_d, o);
      REQUIRE(f.status == FrontStatus::converged);
      c.push_back(f.c);
    }
    const auto lim = testing::thin_limit(H, c, c_1d);
    WARN("inplane sigma_d = " << sigma_d << ": |c - c_1D| ~ H^" << lim.order << ", Richardson limit/c_1D - 1 = "
                              << lim.limit / c_1d - 1.0);
    CHECK(std::abs(lim.order - 2.0) < 0.05);
    CHECK(std::abs(lim.limit / c_1d - 1.0) < 1e-7);
    CHECK(c[0] < c_1d);
  }
}

TEST_CASE("inplane front: the limiting front at sigma_c^d tends to the 1D c_min = 11.281 at second order in H",
          "[inplane][front][thin]") {
  // c_min(H) − 11.28108382 = 1.17e−5, 4.77e−5, 1.965e−4 at H = 0.125, 0.25, 0.5 (4 rows, 600 intervals): +7.6e−4 H².
  const auto f1 = continuum::solve_steady_front(paper, core::BulkParams{0.01, 300.0, 300.0}, 0.22);
  const auto end_1d = continuum::solve_saddle_node_front(paper, core::BulkParams{0.01, 300.0, 300.0}, {}, &f1);
  REQUIRE(end_1d.status == FrontStatus::converged);
  CHECK(end_1d.c == Approx(11.28108382).epsilon(1e-9));
  StripFrontOptions o;
  o.rows = 4;
  std::vector<double> H{0.125, 0.25, 0.5}, c;
  for (double h : H) {
    const StripFront near = continuum::solve_inplane_front(paper, inplane(h), 0.22, o);
    REQUIRE(near.status == FrontStatus::converged);
    const StripFront end = continuum::solve_inplane_saddle_node_front(paper, inplane(h), o, near);
    REQUIRE(end.status == FrontStatus::converged);
    CHECK(end.saddle_node_limit);
    CHECK(std::abs(end.stable_eigenvalue) < 1e-8);
    CHECK(std::abs(end.v_behind - continuum::steady_minimum_velocity(paper)) < 1e-12);
    c.push_back(end.c);
  }
  const auto lim = testing::thin_limit(H, c, end_1d.c);
  WARN("inplane c_min(H) - c_min(1D) ~ H^" << lim.order << ", Richardson limit/c_min(1D) - 1 = " << lim.limit / end_1d.c - 1.0);
  CHECK(std::abs(lim.order - 2.0) < 0.1);
  CHECK(std::abs(lim.limit / end_1d.c - 1.0) < 1e-7);
  CHECK(c[0] > end_1d.c);
}

TEST_CASE("inplane front: subsonic fronts end at c_s, where the far field's mode count changes", "[inplane][front]") {
  // H = 1 (c_s = 100, c_R = 93.25, c_p = 200, the plate speed 173.2): the front at σ_d = 0.72 runs between c_R and c_s
  // (96.43); at σ_d = 0.76 the 1D front of μ = E'H (102.44) is above c_s and the rows' shear coefficient μ' − ρ'c² < 0:
  // the sliding state behind has fewer than 2M + 1 modes decaying in forward ξ, refused (status sonic) with the count.
  const auto m = continuum::inplane_material(inplane(1.0));
  CHECK(m.shear_speed == Approx(100.0).epsilon(1e-12));
  CHECK(m.pressure_speed == Approx(200.0).epsilon(1e-12));
  CHECK(m.rayleigh_speed / m.shear_speed == Approx(0.93253).epsilon(2e-5));  // docs/model.md §10 at ν = 1/3
  CHECK(continuum::rayleigh_ratio(0.25) == Approx(0.91940).epsilon(2e-5));
  StripFrontOptions o;
  o.rows = 4;
  o.intervals = 300;
  const StripFront between = continuum::solve_inplane_front(paper, inplane(1.0), 0.72, o);
  REQUIRE(between.status == FrontStatus::converged);
  CHECK(between.c > m.rayleigh_speed);
  CHECK(between.c < m.shear_speed);
  const StripFront above = continuum::solve_inplane_front(paper, inplane(1.0), 0.76, o);
  CHECK(above.status == FrontStatus::sonic);
  CHECK(above.reason.find("modes of each sign") != std::string::npos);
  // No front outside (σ_c^d, 1); the in-plane front needs the in-plane body.
  CHECK(continuum::solve_inplane_front(paper, inplane(1.0), 0.2).status == FrontStatus::no_front_state);
  const StripFront antiplane = continuum::solve_inplane_front(paper, core::BulkParams{0.01, 300.0, 300.0, 1.0}, 0.5);
  CHECK(antiplane.status != FrontStatus::converged);
  CHECK(antiplane.reason.find("inplane") != std::string::npos);
}
