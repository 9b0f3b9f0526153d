#pragma once
// A test body in one file (issue 37: "a new body is its own files plus <= 3 registration lines"): the 1D chain
// of core/bulk.hpp with a second displacement per node, decoupled from the first. Component 0 is the scene's
// chain (its interface: the law's sites, the drive, σ_d); component 1 is a free elastic chain on the same grid
// (same μ, ρ; no interface, no drive, free ends), started by the lift from the interface's initial state. It
// stands in for the paper's in-plane strip (plane strain: two displacements per node) where the run layer
// is concerned: two components per node, a dof layout of its own (component planes, dof c·n + i), a
// two-component snapshot field. It implements core::Body and core::RunBody; nothing else in the code base knows about it.
#include <cstddef>
#include <span>
#include <vector>

#include "core/body.hpp"
#include "core/bulk.hpp"
#include "core/params.hpp"

namespace slipfront::testing {

class TwinChain {
 public:
  TwinChain(const core::BulkParams& bulk, const core::DriveParams& drive, const core::InterfaceParams& law,
            const core::GridParams& grid)
      : chain_(bulk, drive, law, grid), free_(bulk, free_drive(), law, grid), zeros_(chain_.nodes(), 0.0),
        c0_(chain_.nodes(), 0.0), c1_(chain_.nodes(), 0.0) {}

  // --- core::Body ---------------------------------------------------------------------------------------
  std::size_t sites() const { return chain_.sites(); }
  std::size_t dofs() const { return 2 * chain_.sites(); }
  std::size_t rows() const { return 1; }
  double height() const { return 0.0; }
  double row_height(std::size_t) const { return 0.0; }
  const std::vector<double>& x() const { return chain_.x(); }
  double rho() const { return chain_.rho(); }
  double dx() const { return chain_.dx(); }
  double interface_weight(std::size_t i) const { return chain_.interface_weight(i); }
  double edge_mass() const { return chain_.edge_mass(); }
  double stable_dt() const { return chain_.stable_dt(); }  // the free chain's bound is the larger (no α, no K)
  double uniform_stress() const { return chain_.uniform_stress(); }
  double spring_K() const { return chain_.spring_K(); }
  double driver_velocity() const { return chain_.driver_velocity(); }
  double rear_traction() const { return chain_.rear_traction(); }
  bool has_drive_spring() const { return chain_.has_drive_spring(); }
  double edge_slip(std::span<const double> u) const { return u[0]; }
  double drive_force(double t, std::span<const double> u) const { return chain_.drive_force(t, u[0]); }
  double kinetic_energy(std::span<const double> V) const {
    return chain_.kinetic_energy(first(V)) + free_.kinetic_energy(second(V));
  }
  double elastic_energy(std::span<const double> u) const {
    return chain_.elastic_energy(first(u)) + free_.elastic_energy(second(u));
  }
  double spring_energy(double t, std::span<const double> u) const { return chain_.spring_energy(t, u[0]); }
  double uniform_power(std::span<const double> v) const { return chain_.uniform_power(first(v)); }
  void kick(double dt, double eta, double edge, std::span<const double> u, std::span<const double> sigma_bar,
            std::span<const double> v_old, std::span<double> v_new) const {
    chain_.kick(dt, eta, edge, first(u), sigma_bar, first(v_old), v_new.first(sites()));
    free_.kick(dt, 0.0, 0.0, second(u), zeros_, second(v_old), v_new.subspan(sites()));
  }
  template <class Lin>
  void implicit_solve(const Lin& lin, std::span<const double> w_prev, std::span<double> c0, std::span<double> c1,
                      double t, double dt, double eta, std::span<const double> u, std::span<const double> V,
                      std::span<const double> sigma_bar, std::span<double> W) {
    chain_.implicit_solve(lin, w_prev, c0, c1, t, dt, eta, first(u), first(V), sigma_bar, W.first(sites()));
    const auto none = [](std::size_t, double, double& a, double& b) { a = b = 0.0; };
    free_.implicit_solve(none, zeros_, c0_, c1_, t, dt, 0.0, second(u), second(V), zeros_, W.subspan(sites()));
  }

  // --- core::RunBody --------------------------------------------------------------------------------------
  static core::BodyShape shape(const core::BulkParams& bulk, const core::DriveParams& drive,
                               const core::GridParams& grid) {
    core::BodyShape s = core::Bulk::shape(bulk, drive, grid);
    s.components = 2;
    return s;
  }
  static double stable_time_step(const core::BulkParams& bulk, const core::DriveParams& drive,
                                 const core::InterfaceParams& law, const core::GridParams& grid) {
    return core::Bulk::stable_time_step(bulk, drive, law, grid);
  }
  core::BodyShape shape() const { return {sites(), 1, 2}; }
  std::size_t dof(std::size_t i, std::size_t, std::size_t c) const { return c * sites() + i; }
  /// Both components start from the interface's state.
  template <class Set>
  void lift(std::size_t i, double u, double v, double, Set&& set) const {
    set(dof(i, 0, 0), u, v);
    set(dof(i, 0, 1), u, v);
  }
  template <class Value>
  double edge_slip_of(Value&& value) const {
    return value(std::size_t{0});
  }
  double drive_force_at(double t, double edge_slip) const { return chain_.drive_force(t, edge_slip); }
  /// "u": both displacements of a node.
  static std::span<const core::SnapshotField> snapshot_fields() {
    static constexpr core::SnapshotField fields[] = {{"u", 2}};
    return fields;
  }
  void snapshot_values(std::span<const double> u, std::size_t i, std::size_t, std::span<double> out) const {
    out[0] = u[dof(i, 0, 0)];
    out[1] = u[dof(i, 0, 1)];
  }

 private:
  static core::DriveParams free_drive() {  // homogeneous loading at σ_d = 0: no spring, no stress, no traction
    core::DriveParams d;
    d.loading = core::Loading::homogeneous;
    d.sigma_d = 0.0;
    d.rear_traction = 0.0;
    return d;
  }
  std::span<const double> first(std::span<const double> f) const { return f.first(sites()); }
  std::span<const double> second(std::span<const double> f) const { return f.subspan(sites(), sites()); }

  core::Bulk chain_, free_;
  std::vector<double> zeros_;  ///< the free chain's interface stress and previous rates: none
  std::vector<double> c0_, c1_;  ///< the free chain's (empty) linearisation
};

static_assert(core::Body<TwinChain> && core::RunBody<TwinChain>);

}  // namespace slipfront::testing
