// The body seam of the run layer (issue 37 item 1): a body is decided once (core::BulkParams::body,
// core::with_body) and supplies what the run layer used to re-derive — sites, stable step, the lift of the
// initial state, the edge slip, its snapshot fields with their components. A test body in one file
// (tests/bodies/twin_chain.hpp: the chain with a second, decoupled displacement per node) runs through the real
// dispatch (with_integrator_on), the run (DynamicRun, run_loop), the recorder and the writer, and needs no change
// outside its own file.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <numeric>
#include <vector>

#include "apps/config.hpp"
#include "apps/h5in.hpp"
#include "apps/h5out.hpp"
#include "bodies/twin_chain.hpp"
#include "compare/dispatch.hpp"
#include "compare/dynamic_run.hpp"
#include "compare/estimate.hpp"
#include "compare/runner.hpp"
#include "continuum/friction_law.hpp"
#include "core/bodies.hpp"
#include "h5content.hpp"
#include "process.hpp"
#include "scenes.hpp"

namespace fs = std::filesystem;
using namespace slipfront;
using testing::TwinChain;

namespace {

// A short homogeneous run with a nucleation patch (L = 60, dx = 1): the interface slides behind a front while
// the twin's free chain carries the patch's momentum; snapshots of both every 0.5.
compare::Scene twin_scene(core::Integrator integrator) {
  compare::Scene s = testing::short_front_scene(integrator);
  s.bulk_output.dt = 0.5;
  s.bulk_output.stride = 1;
  s.validate();
  return s;
}

// The continuum model on body B through the dispatch of the scene's integrator (the fixed-step ones: the
// adaptive integrator is not on the body concept yet).
template <class B>
compare::ModelResult run_on(const compare::Scene& s) {
  using Law = continuum::FrictionLaw;
  const std::size_t sites = B::shape(s.bulk, s.drive, s.grid).sites;
  return compare::with_integrator_on<B>(s, [&](auto tag) {
    using Tag = decltype(tag);
    if constexpr (compare::is_adaptive<Tag>) {
      FAIL("the test body runs on the fixed-step integrators");
      return compare::ModelResult{};
    } else {
      using Stepper = typename Tag::template stepper<Law>;
      return compare::run_dynamic<Law, Stepper>(s, Law(s.interface, sites), "continuum", compare::RunControl{});
    }
  });
}

// Σ_i w_i f_i over the nodes of a chain of spacing dx (half weights at the ends).
double weighted_sum(const std::vector<double>& f, double dx) {
  double s = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) s += (i == 0 || i + 1 == f.size() ? 0.5 * dx : dx) * f[i];
  return s;
}

}  // namespace

TEST_CASE("body seam: the body kind is decided by bulk.height alone and maps to its class", "[body]") {
  compare::Scene s = testing::fig1_scene();
  CHECK(s.bulk.body() == core::BodyKind::chain);
  CHECK(core::with_body(s.bulk.body(), []<class B>(std::type_identity<B>) { return std::is_same_v<B, core::Bulk>; }));
  s.bulk.height = 4.0;
  CHECK(s.bulk.body() == core::BodyKind::strip);
  CHECK(core::with_body(s.bulk.body(), []<class B>(std::type_identity<B>) { return std::is_same_v<B, core::Strip>; }));
}

TEST_CASE("body seam: each body's shape and stable step from the parameters are those of the body built", "[body]") {
  compare::Scene s = testing::homogeneous_scene(0.5, 20.0, 1.0);
  s.bulk.length = 40.0;
  s.grid.dx = 2.0;
  for (const double H : {0.0, 4.0}) {
    s.bulk.height = H;
    s.grid.dy = H > 0.0 ? 1.0 : 0.0;
    s.validate();
    INFO("H = " << H);
    core::with_body(s.bulk.body(), [&]<class B>(std::type_identity<B>) {
      const B body = compare::make_body<B>(s, s.drive);
      const core::BodyShape shape = B::shape(s.bulk, s.drive, s.grid);
      CHECK(shape.sites == body.sites());
      CHECK(shape.rows == body.rows());
      CHECK(shape.dofs() == body.dofs());
      CHECK(compare::body_shape(s).dofs() == body.dofs());
      CHECK(B::stable_time_step(s.bulk, s.drive, s.interface, s.grid) == body.stable_dt());  // the same bits
      CHECK(compare::explicit_stable_dt(s) == body.stable_dt());
      // the layout: every dof once
      std::vector<int> seen(body.dofs(), 0);
      for (std::size_t j = 0; j < body.rows(); ++j)
        for (std::size_t i = 0; i < body.sites(); ++i) ++seen[body.dof(i, j, 0)];
      CHECK(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
    });
  }
  // The 0D spring block is the chain's one-node case.
  const compare::Scene block = testing::spring_block_scene(1.0);
  CHECK(compare::body_shape(block).sites == 1);
  CHECK(compare::explicit_stable_dt(block) == core::Bulk(block.bulk, block.drive, block.interface, block.grid).stable_dt());
}

TEST_CASE("body seam: the strip's lift puts the uniform shear sigma_d y / mu' in every row", "[body][strip]") {
  compare::Scene s = testing::homogeneous_scene(0.5, 0.0, 1.0);
  s.bulk.length = 20.0;
  s.grid.dx = 2.0;
  s.bulk.height = 4.0;
  s.grid.dy = 1.0;
  const auto strip = compare::make_body<core::Strip>(s, s.drive);
  std::vector<double> u(strip.dofs(), -1.0), v(strip.dofs(), -1.0);
  for (std::size_t i = 0; i < strip.sites(); ++i)
    strip.lift(i, 0.25, 0.5, 0.5, [&](std::size_t k, double a, double b) { u[k] = a, v[k] = b; });
  const double mu_p = s.bulk.mu / s.bulk.height;
  for (std::size_t j = 0; j < strip.rows(); ++j)
    for (std::size_t i = 0; i < strip.sites(); ++i) {
      CHECK(u[strip.dof(i, j, 0)] == Approx(0.25 + 0.5 * static_cast<double>(j) / mu_p).epsilon(1e-15));
      CHECK(v[strip.dof(i, j, 0)] == 0.5);
    }
  // the edge slip of a field: the edge column's weighted mean, from the dofs it needs
  CHECK(strip.edge_slip_of([&](std::size_t k) { return u[k]; }) == strip.edge_slip(u));
}

TEST_CASE("body seam: a two-component test body runs through the dispatch, the run, the recorder and the writer",
          "[body]") {
  for (const auto integrator : {core::Integrator::central_difference, core::Integrator::implicit_trapezoidal}) {
    INFO(core::to_string(integrator));
    const compare::Scene s = twin_scene(integrator);
    const compare::ModelResult chain = testing::run_continuum(s);
    const compare::ModelResult twin = run_on<TwinChain>(s);
    REQUIRE(twin.status == compare::RunStatus::complete);

    // Component 0 is the chain: the interface's records are the chain's, bit for bit.
    CHECK(testing::same(twin.series, chain.series));
    CHECK(testing::same(twin.snapshots, chain.snapshots));
    CHECK(twin.snapshot_t == chain.snapshot_t);
    CHECK(testing::same(twin.events.t_hat, chain.events.t_hat));
    CHECK(chain.bulk_t.empty());  // the chain has no snapshot fields: nothing recorded

    // The body's snapshot field u carries both components per node: [nb, 1 row, nx, 2].
    const std::size_t nx = chain.x.size(), nb = twin.bulk_t.size();
    REQUIRE(nb == chain.snapshot_t.size());
    REQUIRE(twin.bulk_x == chain.x);
    REQUIRE(twin.bulk_y == std::vector<double>{0.0});
    REQUIRE(twin.bulk.size() == 1);
    const auto& bu = twin.bulk.at("u");
    REQUIRE(bu.size() == nb * nx * 2);
    std::vector<double> u0(nx), u1(nx);
    const auto& su = chain.snapshots.at("u");
    double p0 = 0.0, m0 = 0.0;  // the free chain's momentum (per ρ) and Σ w u at t = 0
    for (std::size_t k = 0; k < nb; ++k) {
      for (std::size_t i = 0; i < nx; ++i) {
        u0[i] = bu[(k * nx + i) * 2];
        u1[i] = bu[(k * nx + i) * 2 + 1];
      }
      // component 0: the interface slip of the same snapshot
      CHECK(std::equal(u0.begin(), u0.end(), su.begin() + static_cast<std::ptrdiff_t>(k * nx)));
      // component 1: a free chain started from the lift (u = sigma_d/alpha, v = v_s on the patch) keeps its
      // momentum, so its mean displacement moves at the patch's momentum over the length
      if (k == 0) {
        std::vector<double> v0(nx);
        const auto& sv = chain.snapshots.at("v");
        std::copy(sv.begin(), sv.begin() + static_cast<std::ptrdiff_t>(nx), v0.begin());
        p0 = weighted_sum(v0, s.grid.dx);
        m0 = weighted_sum(u1, s.grid.dx);
        CHECK(p0 > 0.0);
        CHECK(u1 == u0);  // the lift sets both components alike
      } else {
        INFO("t = " << twin.bulk_t[k]);
        CHECK(weighted_sum(u1, s.grid.dx) == Approx(m0 + twin.bulk_t[k] * p0).epsilon(1e-10));
      }
    }
    CHECK(u1 != u0);  // the interface's friction acts on component 0 only

    // The writer lays the field out from its length: [nb, nyk, nxk, 2], read back bit for bit.
    testing::TempDir dir("body_seam");
    const fs::path file = dir.path / "results.h5";
    app::write_results(file, s, app::to_toml(s), {twin}, app::RunMeta{});
    CHECK(testing::dataset_shape(file, "/continuum/bulk/u") == std::vector<hsize_t>{nb, 1, nx, 2});
    const app::ResultsFile back = app::read_results(file);
    REQUIRE(back.models.size() == 1);
    CHECK(back.models[0].bulk.at("u") == bu);
  }
}
