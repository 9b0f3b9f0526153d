#pragma once
// A pool for independent runs: jobs 0..n-1 are taken in index order by `threads` workers; each
// job writes only its own result slot, so the results do not depend on the number of threads.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace slipfront::compare {

/// Run job(i) for i in [0, n) on `threads` threads; rethrows the first exception after all stop.
inline void run_pool(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& job,
                     const std::function<bool()>& stop = [] { return false; }) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n || stop()) return;
      try {
        job(i);
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        next = n;  // no new jobs
      }
    }
  };
  const unsigned t = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::max<std::size_t>(n, 1))));
  std::vector<std::jthread> pool;
  for (unsigned k = 1; k < t; ++k) pool.emplace_back(worker);
  worker();
  pool.clear();  // join
  if (error) std::rethrow_exception(error);
}

}  // namespace slipfront::compare
