#pragma once
// A stop request that long set-up loops see (the construction of a law with many contacts can take
// seconds): the program's SIGINT/SIGTERM handler raises it, loops call poll_stop() per site, and the run
// ends with status "interrupted" (issue 10: interrupts honoured within a bounded time in set-up too).
// Between steps the runner polls compare::RunControl::stop instead.
#include <atomic>
#include <stdexcept>

namespace slipfront::core {

inline std::atomic<bool>& stop_flag() {
  static std::atomic<bool> flag{false};
  return flag;
}
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler sets the flag");

struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted during set-up") {}
};

inline void poll_stop() {
  if (stop_flag().load(std::memory_order_relaxed)) throw Interrupted();
}

}  // namespace slipfront::core
