#pragma once
// The models of a scene in lockstep (docs/architecture.md "The run loop"): every model the scene lists, any number,
// each a DynamicRun of its own law on the scene's fixed-step integrator, advanced together one step at a time in one
// process. The models are read from a set of the model table (compare/laws.hpp: ModelSet; the program's is
// ShippedModels), in the order of its rows; a model whose row names references (compare/models.hpp) has its fields
// compared online with the first of them that runs.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "compare/dispatch.hpp"
#include "compare/dynamic_run.hpp"
#include "compare/laws.hpp"
#include "compare/models.hpp"
#include "compare/result.hpp"
#include "compare/run_control.hpp"
#include "compare/runner.hpp"
#include "compare/scene.hpp"
#include "core/archive.hpp"

namespace slipfront::compare {

/// One model's run in a lockstep, whatever its law and stepper (LockstepRunOf: a DynamicRun). Called once per step
/// and model, not in an inner loop.
class LockstepRun {
 public:
  /// The interface fields the online comparison reads.
  struct Fields {
    std::span<const double> area, sigma_bar, slip_rate, slip;
    std::span<const double> normal_stress;  ///< σ_yy(x, 0) of a body that has one (the in-plane strip), else empty
  };
  virtual ~LockstepRun() = default;
  virtual const ModelKind& kind() const = 0;
  virtual const std::string& model() const = 0;
  virtual bool done() const = 0;
  virtual double time() const = 0;
  virtual void step() = 0;
  virtual void interrupt() = 0;
  virtual bool start_stopped() const = 0;
  virtual bool had_next_instability() const = 0;
  virtual void close_after_arrest() = 0;
  virtual Fields fields() const = 0;
  virtual void serialize(core::Archive& ar) = 0;
  virtual ModelResult finish() = 0;
};

template <class Law, class Stepper>
class LockstepRunOf final : public LockstepRun {
 public:
  LockstepRunOf(const Scene& s, Law law, const ModelKind& kind, const RunControl& ctl)
      : kind_(kind), run_(s, std::move(law), std::string(kind.name), contact_prediction_for(s, kind.name), ctl.stop) {}
  const ModelKind& kind() const override { return kind_; }
  const std::string& model() const override { return run_.model(); }
  bool done() const override { return run_.done(); }
  double time() const override { return run_.time(); }
  void step() override { run_.step(); }
  void interrupt() override { run_.interrupt(); }
  bool start_stopped() const override { return run_.start_stopped(); }
  bool had_next_instability() const override { return run_.had_next_instability(); }
  void close_after_arrest() override { run_.close_after_arrest(); }
  Fields fields() const override {
    const auto& sim = run_.sim();
    const bool normal = interface_normal_stress(StepEndState<Stepper>{sim}, normal_);
    return {sim.law().contact_area(), sim.law().sigma_bar(), sim.slip_rate(), sim.slip(),
            normal ? std::span<const double>(normal_) : std::span<const double>()};
  }
  void serialize(core::Archive& ar) override { ar(run_); }
  ModelResult finish() override { return run_.finish(); }

 private:
  const ModelKind& kind_;
  DynamicRun<Law, Stepper> run_;
  mutable std::vector<double> normal_;  // fields()' σ_yy, computed when asked (at the comparison's cadence)
};

/// The runs of a lockstep, in the order of the table, to the end (or a stop): a checkpoint of ctl.restart is resumed,
/// run_loop drives them, and the results come back in the scene's order (`models`), with the comparison of the first
/// run whose row names references with the first of its references that runs (compare_results, and its fields
/// compared online at output.compare_dt). The settings of each law are not labelled (run_in_lockstep does).
SceneResult run_lockstep_runs(const Scene& s, std::vector<std::unique_ptr<LockstepRun>> runs, const RunControl& ctl);

/// Every model of `s` among the set `Models` (compare/laws.hpp: ModelSet), in lockstep on the scene's fixed-step
/// integrator: at least two, on a bulk scene (runs_in_lockstep; the adaptive integrator has no common step). Each
/// model's result is bit-identical to the one run_scene gives for it alone.
template <class Models>
SceneResult run_in_lockstep(const Scene& s, const RunControl& ctl) {
  return with_integrator(s, [&](auto tag) {
    using Tag = decltype(tag);
    if constexpr (is_adaptive<Tag>) {
      throw std::invalid_argument("run_in_lockstep: the adaptive integrator has no common step (runs_in_lockstep)");
      return SceneResult{};
    } else {
      const std::size_t sites = body_shape(s).sites;
      std::vector<std::unique_ptr<LockstepRun>> runs;
      Models::each([&]<class M>() {
        if (!s.lists(M::kind.name)) return;
        M::with_law(s, [&](auto make) {
          using Law = decltype(make(std::size_t{1}));
          runs.push_back(std::make_unique<LockstepRunOf<Law, typename Tag::template stepper<Law>>>(s, make(sites), M::kind, ctl));
        });
      });
      SceneResult out = run_lockstep_runs(s, std::move(runs), ctl);
      for (auto& r : out.models) Models::label(s, r.model, r);
      return out;
    }
  });
}

}  // namespace slipfront::compare
