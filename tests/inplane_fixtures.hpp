#pragma once
// Shared by the in-plane strip's tests (tests/test_inplane_*.cpp): a strip's parameters, fig1's material on it, a
// bisection for the closed forms' roots, random vectors.
#include <catch2/catch.hpp>

#include <random>
#include <vector>

#include "core/inplane.hpp"

namespace slipfront::testing {

struct InPlaneSetup {
  core::BulkParams bulk;
  core::DriveParams drive;
  core::InterfaceParams law;
  core::InPlaneParams material;
  double dx = 1.0, dy = 1.0;
  core::InPlane make() const { return core::InPlane(bulk, drive, law, material, dx, dy); }
};

/// fig1's parameters (ρ = 0.01, μ = 300, α = 1.05, κ = 8, η = 0.1; edge: K = 2.5, v_d = 0.3; homogeneous: σ_d = 0.5,
/// no rear traction) on length L, height H, ν = 1/3, no normal load.
inline InPlaneSetup fig1_inplane(double L, double H, double dx, double dy, bool edge = true) {
  InPlaneSetup s;
  s.dx = dx;
  s.dy = dy;
  s.bulk.rho = 0.01;
  s.bulk.mu = 300.0;
  s.bulk.length = L;
  s.bulk.height = H;
  s.drive.loading = edge ? core::Loading::edge : core::Loading::homogeneous;
  s.drive.K = 2.5;
  s.drive.v_d = 0.3;
  s.drive.sigma_d = 0.5;
  s.drive.rear_traction = 0.0;
  s.law.alpha = 1.05;
  s.law.kappa = 8.0;
  s.law.eta = 0.1;
  return s;
}

/// A root of f in [lo, hi] (f changes sign there) by bisection to 1e-15 relative.
template <class F>
double bisect(F&& f, double lo, double hi) {
  double flo = f(lo);
  REQUIRE(flo * f(hi) < 0.0);
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm < 0.0) == (flo < 0.0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

inline std::vector<double> uniform_vector(std::size_t n, std::mt19937& g, double lo = -1.0, double hi = 1.0) {
  std::uniform_real_distribution<double> d(lo, hi);
  std::vector<double> v(n);
  for (auto& x : v) x = d(g);
  return v;
}

}  // namespace slipfront::testing
