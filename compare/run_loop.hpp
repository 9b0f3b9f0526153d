#pragma once
// The one run loop (docs/architecture.md §2): every kind of run — one model on a bulk scene
// (DynamicRun), two models in lockstep (run_scene_alongside), an imposed slip-rate history or sweep
// (compare/imposed_rate.hpp) — is a SteppedRun, and run_loop drives it:
//   1. step        the run advances one step and, inside it, observes and records what is due
//   2. progress    every Run::progress_every steps, the caller hears where the run is
//   3. stop        the caller's stop request, polled after every step
//   4. checkpoint  at the checkpoint cadence, and once more on a stop (checkpointable runs)
// and on a stop the run is told to end itself as interrupted.
#include <concepts>
#include <cstdint>
#include <functional>
#include <string>

#include "compare/cadence.hpp"
#include "compare/run_control.hpp"
#include "core/archive.hpp"

namespace slipfront::compare {

/// What a checkpoint of a model run is written after: the state of the scene run around it (the models
/// already finished), so that the whole run can be resumed.
using CheckpointHeader = std::function<void(core::Archive&)>;

/// A run advanced one step at a time.
///   done()            nothing left to do (the end reached, or the run failed or was interrupted)
///   step()            one step with its measurements and records
///   time(), end()     where it is and where it ends, in the units of its progress (simulated time,
///                     or points of a sweep)
///   interrupt()       end as interrupted (the status and the message say where)
///   progress_every    steps between progress reports
///   checkpointable    whether serialize(ar) holds the whole state (a restarted run continues bit for bit)
template <class R>
concept SteppedRun = requires(R& run, const R& cr) {
  { cr.done() } -> std::same_as<bool>;
  run.step();
  { cr.time() } -> std::convertible_to<double>;
  { cr.end() } -> std::convertible_to<double>;
  run.interrupt();
  { R::progress_every } -> std::convertible_to<std::int64_t>;
  { R::checkpointable } -> std::convertible_to<bool>;
};

/// Drives `run` to its end (the stages above); `label` names it in progress reports, and a checkpoint
/// holds `header` (may be empty) followed by the run's state.
template <SteppedRun Run>
void run_loop(Run& run, const RunControl& ctl, const std::string& label, const CheckpointHeader& header = {}) {
  const bool checkpoints = Run::checkpointable && ctl.checkpointing();
  Cadence clock = Cadence::after(checkpoints ? ctl.checkpoint_every : -1.0, run.time());
  for (std::int64_t n = 1; !run.done(); ++n) {
    run.step();
    if (n % Run::progress_every == 0) ctl.progress(label, run.time(), run.end());
    const bool stop = ctl.stop();
    if constexpr (Run::checkpointable) {
      if (clock.due(run.time()) || (stop && checkpoints && !run.done())) {
        core::Archive ar = core::Archive::writer();
        if (header) header(ar);
        ar(run);
        ctl.checkpoint(ar.data(), run.time());
      }
    }
    if (stop) run.interrupt();
  }
}

}  // namespace slipfront::compare
