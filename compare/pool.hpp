#pragma once
// A pool for independent runs: jobs 0..n-1 are taken in index order by `threads` workers; each
// job writes only its own result slot, so the results do not depend on the number of threads.
// run_workers is the same pool fed by any source of job indices (a study under MPI takes them from
// a counter shared by every rank).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace slipfront::compare {

/// `threads` workers (the calling thread is one of them) each run job(i) for the indices next()
/// hands out, until next() returns nothing. next() is called from every worker, concurrently.
/// After a job throws, no worker asks next() again; the first exception is rethrown once all stop.
inline void run_workers(unsigned threads, const std::function<std::optional<std::size_t>()>& next,
                        const std::function<void(std::size_t)>& job) {
  std::exception_ptr error;
  std::mutex error_mutex;
  std::atomic<bool> failed{false};
  auto worker = [&] {
    while (!failed.load()) {
      std::optional<std::size_t> i;
      try {
        i = next();
        if (!i) return;
        job(*i);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;  // no new jobs
      }
    }
  };
  std::vector<std::jthread> pool;
  for (unsigned k = 1; k < std::max(1u, threads); ++k) pool.emplace_back(worker);
  worker();
  pool.clear();  // join
  if (error) std::rethrow_exception(error);
}

/// Run job(i) for i in [0, n) on `threads` threads; rethrows the first exception after all stop.
inline void run_pool(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& job,
                     const std::function<bool()>& stop = [] { return false; }) {
  std::atomic<std::size_t> next{0};
  const unsigned t = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(n, 1))));
  run_workers(
      t,
      [&]() -> std::optional<std::size_t> {
        const std::size_t i = next.fetch_add(1);
        if (i >= n || stop()) return std::nullopt;
        return i;
      },
      job);
}

}  // namespace slipfront::compare
