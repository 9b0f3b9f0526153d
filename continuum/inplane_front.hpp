#pragma once
// Steady fronts of the in-plane strip (plane strain, docs/model.md §10; issue 39 item 1): the traveling-wave problem
// of docs/fronts.md §1 with the Lamé strip of height H under the interface, u_y = 0 and σ_xy = σ̄ + η v on it, the
// top face loaded by σ_xy = σ_d and σ_yy = −p. Equations, method, far-field conditions and their mode count, order
// and results: docs/fronts.md §11.
//
// In ξ = x − c t (tip at ξ = 0), the strip is cut into the rows of the antiplane front (docs/fronts.md §10.2:
// vertex-centred, graded toward the interface) with two components per row: P1 Galerkin across the height with the
// ξξ terms lumped, which leaves a first-order system of ODEs in ξ for (u_x, u_y, ∂ξu_x, ∂ξu_y) of every row. It is
// the third node block of front_solver::Collocation (after the 1D chain's and the antiplane strip's): c an unknown,
// one Newton iteration, the exact modes ahead of the tip, a projection behind.
//
// The solved front is a StripFront (continuum/strip_front.hpp) whose `bulk.body()` is inplane: u, strain and lift
// are u_x's; uy, uy_strain are u_y's; normal_stress is σ_yy(ξ, 0). The strip's entry points (solve_strip_front,
// solve_strip_saddle_node_front, solve_strip_front_stretched, continue_strip_fronts, estimate_strip_speed_error)
// dispatch on `bulk.body()` to the functions below, so a branch, its error estimate and `slipfront fronts` are
// written once for both strips. Plain structs; nothing here does I/O.
#include "continuum/strip_front.hpp"
#include "core/params.hpp"

namespace slipfront::continuum {

namespace front_solver {
struct Arclength;
}

/// The in-plane strip's material per unit height (docs/model.md §10.2): the scene's μ keeps its 1D meaning
/// (μ = E'H, E' = 2μ'/(1 − ν) the plate modulus), so μ' = μ(1 − ν)/(2H), ρ' = ρ/H, λ' = 2μ'ν/(1 − 2ν); the
/// speeds c_s = sqrt(μ'/ρ'), c_p = sqrt((λ' + 2μ')/ρ'), c_R (the Rayleigh wave of the free top) and the plate
/// speed c_0 = sqrt(μ/ρ) (the 1D sound speed of the thin limit).
struct InPlaneMaterial {
  double mu = 0.0, rho = 0.0, lambda = 0.0, nu = 0.0;
  double shear_speed = 0.0, pressure_speed = 0.0, rayleigh_speed = 0.0, plate_speed = 0.0;
};
InPlaneMaterial inplane_material(const core::BulkParams& bulk);

/// c_R/c_s at Poisson's ratio ν: the root in (0, 1) of (2 − x²)² = 4 sqrt(1 − x²) sqrt(1 − x² c_s²/c_p²).
double rayleigh_ratio(double nu);

/// The in-plane front at σ_d (bulk.body() == inplane, bulk.height > 0). `guess`: an in-plane front (any H, σ_d,
/// mesh); without it, the cold start of docs/fronts.md §10.4 (the 1D front of μ = E'H, the strip grown from
/// options.thin_height at fixed μ).
StripFront solve_inplane_front(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                               const StripFrontOptions& options = {}, const StripFront* guess = nullptr);

/// The limiting in-plane front at σ_c^d (v_b = v_m, the null mode of the saddle-node behind), from `guess`
/// stretched by c_guess/guess.c when c_guess > 0.
StripFront solve_inplane_saddle_node_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                           const StripFrontOptions& options, const StripFront& guess, double c_guess = 0.0);

/// The front at σ_d (σ_c^d with saddle_node) from `from` stretched in ξ and y by c_guess/from.c, Newton starting at
/// c_guess (as solve_strip_front_stretched).
StripFront solve_inplane_front_stretched(const core::InterfaceParams& law, const core::BulkParams& bulk, double sigma_d,
                                         const StripFrontOptions& options, const StripFront& from, double c_guess,
                                         bool saddle_node);

/// One pseudo-arclength corrector of the branch in σ_d (σ_d an unknown, the row `arc`) from the front `from`, at the
/// predicted (σ_p, c_p): the in-plane form of the antiplane continuation's step (continuum/sigma_continuation.hpp).
StripFront correct_inplane_front(const core::InterfaceParams& law, const core::BulkParams& bulk,
                                 const StripFrontOptions& options, double sigma_p, double c_p,
                                 const front_solver::Arclength& arc, const StripFront& from);

/// c_min(H) of the in-plane strip at a fixed material (docs/fronts.md §11.8): continue_strip_height's path in H (the
/// limiting front, or the front at options.sigma_d) with μ' (shear modulus per height), ρ', ν and the top's normal load
/// p held: bulk.mu = E'H with E' = 2μ'/(1 − ν), bulk.rho = ρ'H, bulk.body = inplane. Every solve dispatches to the
/// in-plane solver (solve_strip_front_stretched); steps, predictor, meshes and step control are the antiplane path's.
StripHeightPath continue_inplane_height(const core::InterfaceParams& law, double mu_strip, double rho_strip, double poisson,
                                        double normal_load, const StripHeightOptions& options, double length = 1000.0);

/// The state of a solved in-plane front at node i in the solver's unknowns (docs/fronts.md §11.1): (u_0, d_1 … d_M,
/// w_1 … w_M, p_0 … p_M, q_1 … q_M, A, σ̄), d_j = u_x,j − u_x,0, w_j = u_y,j, p = ∂ξu_x, q = ∂ξu_y; the layout of
/// `ahead_mode`.
std::vector<double> inplane_front_node(const StripFront& front, std::size_t i);

/// The whole in-plane front at positions ξ on its own rows (docs/fronts.md §11.10), the in-plane form of
/// sample_strip_front: `x` holds the interface fields and u_x(ξ, y_j), ∂t u_x = −c ∂ξ u_x of every row (index
/// k·(M + 1) + j, k the position); uy, uy_velocity the same for u_y (0 on the interface row). On [−L, 0] the cubic
/// Hermite of the collocation solution; ahead of the tip the stored modes (→ the stuck state u_x = σ_d/α + σ_d y/μ',
/// u_y = −p y/(λ' + 2μ')); behind −L the sliding state: every row's u_x translating at v_b with the lift it has at −L,
/// u_y at rest at its value there. sample_strip_front and sample_strip_interface return `x` for an in-plane front.
struct InPlaneFrontSample {
  StripFrontSample x;
  std::vector<double> uy, uy_velocity;
};
InPlaneFrontSample sample_inplane_front(const StripFront& front, std::span<const double> xi);

}  // namespace slipfront::continuum
