#pragma once
// `--progress json` (docs/cli.md "Progress for a program"): the progress of a run or a study as one JSON
// object per line on stderr, for whoever drives slipfront (the Python package, docs/python.md), not only
// for a terminal. At most one line every `min_interval` seconds, and always the first one of each model.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <ostream>
#include <string>
#include <string_view>

#include "apps/config.hpp"

namespace slipfront::app {

class JsonProgress {
 public:
  JsonProgress(std::ostream& err, bool on, double min_interval = 0.1) : err_(err), on_(on), min_interval_(min_interval) {}

  /// A run: {"slipfront":"progress","scene":S,"model":M,"t":T,"t_end":E,"elapsed":W}
  void run(std::string_view scene, std::string_view model, double t, double t_end) {
    if (!on_) return;
    const std::lock_guard lock(mutex_);
    const bool first = model != model_;
    if (!first && !due()) return;
    model_ = model;
    emit("\"scene\":" + quoted_string(std::string(scene)) + ",\"model\":" + quoted_string(std::string(model)) +
         ",\"t\":" + number(t) + ",\"t_end\":" + number(t_end));
  }
  /// A study: {"slipfront":"progress","study":S,"runs_done":K,"runs":N,"elapsed":W}
  void study(std::string_view name, std::size_t done, std::size_t total) {
    if (!on_) return;
    const std::lock_guard lock(mutex_);
    if (done < total && !due()) return;
    emit("\"study\":" + quoted_string(std::string(name)) + ",\"runs_done\":" + std::to_string(done) +
         ",\"runs\":" + std::to_string(total));
  }

 private:
  using Clock = std::chrono::steady_clock;
  static std::string number(double x) {  // JSON has no NaN or infinity: null
    if (!(x - x == 0.0)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
  }
  bool due() const { return std::chrono::duration<double>(Clock::now() - last_).count() >= min_interval_; }
  void emit(const std::string& fields) {
    last_ = Clock::now();
    const double elapsed = std::chrono::duration<double>(last_ - start_).count();
    char el[32];
    std::snprintf(el, sizeof el, "%.3f", elapsed);
    err_ << "{\"slipfront\":\"progress\"," << fields << ",\"elapsed\":" << el << "}\n" << std::flush;
  }

  std::ostream& err_;
  bool on_;
  double min_interval_;
  std::mutex mutex_;  // a study's workers report from their threads
  std::string model_;
  Clock::time_point start_ = Clock::now(), last_ = start_;
};

}  // namespace slipfront::app
