#pragma once
// The body seam (docs/model.md §1.2, §9): what a stepper sees of the elastic body under the interface.
// Two models: the 1D chain (core::Bulk, core/bulk.hpp) and the antiplane strip of height H
// (core::Strip, core/strip.hpp). Each holds its grid, its loading and its elastic operator; the steppers
// (core/stepper.hpp, core/implicit.hpp) hold the state and call the body for every term that depends
// on its geometry, so the interface laws (core/law.hpp) run on either body unchanged.
//
// Degrees of freedom: dofs() bulk displacements, of which the first sites() are the interface (the
// law's sites, in order; the chain's every node is one). Slip and slip rate are the interface's.
#include <concepts>
#include <cstddef>
#include <span>
#include <vector>

#include "core/params.hpp"

namespace slipfront::core {

/// A stand-in for an interface law's linearisation in the Body concept (core/law.hpp).
struct NoLinearisation {
  void operator()(std::size_t, double, double&, double&) const {}
};

/// What a stepper needs of a body:
///   sites(), dofs(), x()              interface sites (x() their positions), all degrees of freedom
///   rows(), height(), row_height(j)   rows of sites.size() dofs each, row j at y = row_height(j) (chain: one, y = 0)
///   rho(), dx(), interface_weight(i)  the scene's inertia, the grid spacing, the interface length of site i
///   edge_mass()                       the inertia the drive spring pulls (implicit_resolution)
///   stable_dt()                       the explicit scheme's stability limit
///   uniform_stress(), spring_K(), driver_velocity(), rear_traction(), has_drive_spring()   the loading
///   edge_slip(u)                      the slip the drive spring sees (chain: u_0; strip: the edge mean ū₀)
///   drive_force(t, u)                 F = K (v_d t − edge_slip(u)) + F_r
///   kinetic_energy(V), elastic_energy(u), spring_energy(t, u)   energies of the whole body
///   uniform_power(v)                  the power of the uniform stress σ_d (on the loaded face)
///   kick(dt, η, F, u, σ̄, v_old, v_new)   the explicit scheme's kick v^{n−1/2} → v^{n+1/2}, all dofs
///   implicit_solve(lin, …, W)         the implicit step's linear system for W (core/implicit.hpp)
template <class B>
concept Body = requires(const B& b, B& mb, std::size_t i, double d, std::span<const double> c, std::span<double> m) {
  { b.sites() } -> std::convertible_to<std::size_t>;
  { b.dofs() } -> std::convertible_to<std::size_t>;
  { b.rows() } -> std::convertible_to<std::size_t>;
  { b.height() } -> std::convertible_to<double>;
  { b.row_height(i) } -> std::convertible_to<double>;
  { b.x() } -> std::convertible_to<const std::vector<double>&>;
  { b.rho() } -> std::convertible_to<double>;
  { b.dx() } -> std::convertible_to<double>;
  { b.interface_weight(i) } -> std::convertible_to<double>;
  { b.edge_mass() } -> std::convertible_to<double>;
  { b.stable_dt() } -> std::convertible_to<double>;
  { b.uniform_stress() } -> std::convertible_to<double>;
  { b.spring_K() } -> std::convertible_to<double>;
  { b.driver_velocity() } -> std::convertible_to<double>;
  { b.rear_traction() } -> std::convertible_to<double>;
  { b.has_drive_spring() } -> std::convertible_to<bool>;
  { b.edge_slip(c) } -> std::convertible_to<double>;
  { b.drive_force(d, c) } -> std::convertible_to<double>;
  { b.kinetic_energy(c) } -> std::convertible_to<double>;
  { b.elastic_energy(c) } -> std::convertible_to<double>;
  { b.spring_energy(d, c) } -> std::convertible_to<double>;
  { b.uniform_power(c) } -> std::convertible_to<double>;
  b.kick(d, d, d, c, c, c, m);
  mb.implicit_solve(NoLinearisation{}, c, m, m, d, d, d, c, c, c, m);
};

// ---------------------------------------------------------------------------------------------
// What the run layer asks of a body beyond the steppers (issue 37): its shape from the parameters (no grid
// built), its stable step, the layout of its fields, the lift of an interface state into the body, the edge
// slip of any field and its snapshot fields. The run layer (compare/dispatch.hpp, initial.hpp, record.hpp,
// estimate.cpp) asks these and never tests which body it has.

/// The grid of a body: `sites` interface sites per row, `rows` rows (row 0 the interface), `components`
/// displacements per node (the antiplane bodies: one; an in-plane body: two).
struct BodyShape {
  std::size_t sites = 1, rows = 1, components = 1;
  std::size_t nodes() const { return sites * rows; }
  std::size_t dofs() const { return nodes() * components; }
};

/// One field of a body's snapshots (docs/output.md /<model>/bulk/): its name and its values per node (a
/// displacement of an in-plane body: two). The writer describes it (apps/h5out.cpp).
struct SnapshotField {
  const char* name;
  std::size_t components;
};

/// Stand-ins for the callbacks of the RunBody concept.
struct NoDofSetter {
  void operator()(std::size_t, double, double) const {}
};
struct NoDofValue {
  double operator()(std::size_t) const { return 0.0; }
};

/// A body the run layer can run:
///   B(bulk, drive, law, grid)          built from the scene's parameters
///   B::shape(bulk, drive, grid)        its BodyShape, without building the grid (the law's size, the estimate)
///   B::stable_time_step(bulk, drive, law, grid)   stable_dt() of the body those parameters build
///   shape(), dof(i, j, c)              the grid; the dof index of component c of node (site i, row j)
///   lift(i, u, v, σ_d, set)            an interface state (u, v at site i) lifted into the body under the
///                                      uniform stress σ_d: set(dof, u, v) for every dof of column i
///   edge_slip_of(value)                the edge slip (the drive's) of any field given as value(dof)
///   drive_force_at(t, edge_slip)       F = K (v_d t − edge_slip) + F_r
///   snapshot_fields(), snapshot_values(u, i, j, out)   the body's snapshot fields and their values at a
///                                      node, components inner, in the order of snapshot_fields()
template <class B>
concept RunBody =
    Body<B> && requires(const B& b, const BulkParams& bp, const DriveParams& dp, const InterfaceParams& ip,
                        const GridParams& gp, std::size_t i, double d, std::span<const double> c, std::span<double> m) {
      B(bp, dp, ip, gp);
      { B::shape(bp, dp, gp) } -> std::same_as<BodyShape>;
      { B::stable_time_step(bp, dp, ip, gp) } -> std::convertible_to<double>;
      { b.shape() } -> std::same_as<BodyShape>;
      { b.dof(i, i, i) } -> std::convertible_to<std::size_t>;
      b.lift(i, d, d, d, NoDofSetter{});
      { b.edge_slip_of(NoDofValue{}) } -> std::convertible_to<double>;
      { b.drive_force_at(d, d) } -> std::convertible_to<double>;
      { B::snapshot_fields() } -> std::convertible_to<std::span<const SnapshotField>>;
      b.snapshot_values(c, i, i, m);
    };

}  // namespace slipfront::core

// --- The adaptive integrator's body (core/adaptive.hpp, docs/numerics.md §8.8) ----------------------------------
namespace slipfront::core {

/// The Rosenbrock stage's right-hand side of the dofs beyond the interface sites, for a body whose stage solve takes
/// it apart (the strip's rows j ≥ 1, fused into its sweeps): b_u = bu − sub_u, b_v = bv − sub_v + (the drive's
/// ∂f/∂t, hdT at the edge site, spread over the body's loaded dofs); after the solve x_u += add_u, x_v += add_v
/// (sub_*, add_* may be null). The sites' entries are the integrator's (it forms them before, adds back after).
/// guess_scale · guess_u − guess_sub_u (guess_sub_u may be null; guess_u null: none): a guess of the solve's x_u over all
/// dofs (before add_u), for a body whose stage solve iterates (the in-plane strip; docs/numerics.md §8.9).
struct BulkStage {
  const double* bu;
  const double* bv;
  const double* sub_u = nullptr;
  const double* sub_v = nullptr;
  const double* add_u = nullptr;
  const double* add_v = nullptr;
  double hdT = 0.0;
  const double* guess_u = nullptr;
  const double* guess_sub_u = nullptr;
  double guess_scale = 1.0;
};

/// The local error of one block (u or v) of a Rosenbrock step, as the `field` norm weighs it: scale = the largest
/// |y| the block shows (start and trial end), emax = the largest |e| (e = k1 − 2 k2 + k3 in node values, or a bound
/// never below it), probe = a sum that is finite iff every error is.
struct StageError {
  double scale = 0.0, emax = 0.0, probe = 0.0;
};

/// Stand-ins for the adaptive integrator's per-site callbacks in the AdaptiveBody concept.
struct NoSiteCoefficient {
  double operator()(std::size_t) const { return 0.0; }
};
struct NoSiteBack {
  void operator()(std::size_t, double) const {}
};

/// What the adaptive integrator (core/adaptive.hpp) asks of a body beyond Body: the bulk's part of the stage right-
/// hand side and of the W solve, in the body's own **stage representation** of u and v (all dofs, components()
/// displacement components per node: dofs() = nodes × components()). The first sites() entries of a stage field are
/// the interface sites' slip (rate) as node values — the law acts there, site by site; the rest is the body's (the
/// chain: node values; the strip: cosine modes of the rows j ≥ 1, docs/numerics.md §8.6).
///   components()                        displacement components per node (chain, strip: 1; an in-plane body: 2)
///   stage_is_nodes                      the stage representation is node values (no transforms; checkpoints hold
///                                       the node values only)
///   stage_archive_tag()                 the checkpoint's tag of the adaptive integrator on this body
///   to_stage(nodes, z), from_stage(z, nodes)   node values ↔ stage representation, all dofs (may alias)
///   stage_value(z, i)                   the node value of dof i of the stage field z (dense output of one dof)
///   stage_drive_force(t, u)             F(t) the drive applies, from the stage field u
///   stage_accelerations(t, u, v, σ̄, η, a)   v' of every dof (stage representation): elastic forces, loading, and
///                                       the interface traction σ̄_i + η v_i on the sites
///   set_stage_tolerance(rtol)           the integrator's rtol, for a body whose stage solve iterates
///   stage_factor(c, η, q_σ)             W = I − c J: the u system's factors; q_σ(i) the law's per-site coefficient
///                                       (x_σ = p_σ + q_σ x_v of site i), called once per site in order
///   stage_solve(in, p_σ, back, xu, xv)  W⁻¹ in place on the u, v blocks (xu, xv: the sites' right-hand side on entry,
///                                       the rest from in): p_σ(i) eliminates site i's A and σ̄ rows and returns its p_σ
///                                       (once per site, in order); back(i, x_v,i) completes them after the solve
///   stage_scale(y)                      the scale of a u or v block of the state beyond its sites' values (field norm)
///   stage_error(y, ynew, k1, k2, k3)    the block's StageError (the field norm, docs/performance.md §2)
template <class B>
concept AdaptiveBody = Body<B> && requires(const B& b, B& mb, double d, std::size_t i, const double* p, double* q,
                                           std::span<const double> c, std::span<double> m, const BulkStage& in) {
  { b.components() } -> std::convertible_to<std::size_t>;
  { B::stage_is_nodes } -> std::convertible_to<bool>;
  { b.stage_archive_tag() } -> std::convertible_to<const char*>;
  b.to_stage(c, m);
  b.from_stage(c, m);
  { b.stage_value(p, i) } -> std::convertible_to<double>;
  { b.stage_drive_force(d, c) } -> std::convertible_to<double>;
  mb.stage_accelerations(d, c, p, p, d, m);
  mb.set_stage_tolerance(d);
  mb.stage_factor(d, d, NoSiteCoefficient{});
  mb.stage_solve(in, NoSiteCoefficient{}, NoSiteBack{}, q, q);
  { b.stage_scale(p) } -> std::convertible_to<double>;
  { b.stage_error(p, p, p, p, p) } -> std::convertible_to<StageError>;
};

}  // namespace slipfront::core
