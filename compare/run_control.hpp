#pragma once
// What the caller (the command line, a study) gives a run: a stop request, progress and checkpoints
// (docs/architecture.md: the run loop). No stepper, law or measurement is needed to name it, so the
// writer and the program include this, not the runner.
#include <functional>
#include <string>

namespace slipfront::compare {

/// Hooks of the caller (CLI): a stop request (Ctrl-C), polled after every step, progress, and
/// checkpoints (issue 10): every `checkpoint_every` of simulated time (0: never), and once more when a
/// stop is requested, `checkpoint(state, t)` receives the state of the whole scene run (both models, every
/// law's state and random streams, the measurements and the records so far); a run given that state in
/// `restart` continues from it bit for bit. Bulk scenes only (an imposed-rate scene has no checkpoints).
struct RunControl {
  std::function<bool()> stop = [] { return false; };
  std::function<void(const std::string& model, double t, double t_end)> progress =
      [](const std::string&, double, double) {};
  double checkpoint_every = 0.0;
  std::function<void(const std::string& state, double t)> checkpoint;
  std::string restart;
  bool checkpointing() const { return checkpoint_every > 0.0 && static_cast<bool>(checkpoint); }
};

}  // namespace slipfront::compare
