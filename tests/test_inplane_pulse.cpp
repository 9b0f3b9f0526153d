// The in-plane strip in time (core/inplane.hpp, docs/model.md §10.3; ~2 s): a pulse on the free top travels at
// the Rayleigh speed c_R.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

#include "core/inplane.hpp"
#include "inplane_fixtures.hpp"

namespace core = slipfront::core;

namespace {

// Position of the largest |f| on the grid x (step h) for x > from, refined by the parabola through its neighbours.
double peak(const std::vector<double>& f, double h, double from) {
  std::size_t best = 0;
  for (std::size_t i = 1; i + 1 < f.size(); ++i)
    if (static_cast<double>(i) * h > from && std::abs(f[i]) > std::abs(f[best])) best = i;
  const double a = std::abs(f[best - 1]), b = std::abs(f[best]), c = std::abs(f[best + 1]);
  return (static_cast<double>(best) + 0.5 * (a - c) / (a - 2.0 * b + c)) * h;
}

}  // namespace

TEST_CASE("inplane pulse: a pulse on the free top travels at the Rayleigh speed", "[inplane]") {
  // A deep strip (H = 40, L = 200, dx = dy = 0.5; c_s = 1: ρ = 1, μ = 2/(1 − ν) = 3, ν = 1/3, c_p = 2,
  // c_R = 0.93253) on a frictionless base, at rest, the top displaced by a Gaussian bump u_y = e^{−r²/4} around
  // (50, H). The right-going surface pulse (the Rayleigh wave: it keeps its shape, the body waves along the surface
  // decay) is tracked by its largest |u_y| at t = 50 and t = 110 (the base's reflections come back weaker; the far
  // end is reached at t ≈ 160). Its speed against c_R within 1 % (the grid's dispersion at k dx ≈ 0.25: ~0.3 %).
  slipfront::testing::InPlaneSetup st = slipfront::testing::fig1_inplane(200.0, 40.0, 0.5, 0.5, false);
  st.bulk.rho = 1.0;
  st.bulk.mu = 3.0;
  st.drive.sigma_d = 0.0;
  st.law.alpha = 0.0;
  const core::InPlane b = st.make();
  REQUIRE(b.shear_speed() == Approx(1.0).epsilon(1e-14));
  const std::size_t nx = b.sites(), P = b.plane(), top = (b.rows() - 1) * nx;
  std::vector<double> u(b.dofs(), 0.0), v(b.dofs(), 0.0), vn(b.dofs()), sb(nx, 0.0);
  for (std::size_t j = 0; j < b.rows(); ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const double dx = b.x()[i] - 50.0, dy = b.row_height(j) - b.height();
      if (j > 0) u[P + j * nx + i] = std::exp(-(dx * dx + dy * dy) / 4.0);
    }
  const double dt = b.stable_dt();
  auto surface_peak = [&](double t_at, double& t) {
    while (t < t_at - 1e-9) {
      const double h = std::min(dt, t_at - t);
      b.kick(h, 0.0, 0.0, u, sb, v, vn);  // a shorter last step: v is then v^{n+1/2} of that step (central in u)
      v.swap(vn);
      for (std::size_t k = 0; k < u.size(); ++k) u[k] += h * v[k];
      t += h;
    }
    std::vector<double> uy(u.begin() + static_cast<std::ptrdiff_t>(P + top),
                           u.begin() + static_cast<std::ptrdiff_t>(P + top + nx));
    return peak(uy, b.dx(), 60.0);
  };
  double t = 0.0;
  const double x1 = surface_peak(50.0, t), x2 = surface_peak(110.0, t);
  const double c = (x2 - x1) / 60.0;
  std::printf("inplane Rayleigh pulse: peak at %.3f (t = 50), %.3f (t = 110): speed %.5f c_s (c_R = 0.93253)\n", x1, x2, c);
  CHECK(c == Approx(0.93253).epsilon(0.01));
}
