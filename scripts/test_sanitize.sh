#!/usr/bin/env bash
# The sanitizer tier: AddressSanitizer + UndefinedBehaviorSanitizer (CMake option SLIPFRONT_SANITIZE)
# build in build-asan/ (RelWithDebInfo, no benchmarks), then the default test tier under it. Any
# memory error, leak or undefined behaviour aborts the test that hit it, so the exit code is ctest's:
# 0 only when every default test passed clean. CI-able: `bash scripts/test_sanitize.sh`.
#   SLIPFRONT_ASAN_DIR  build directory (default build-asan)
#   SLIPFRONT_JOBS      parallel build and test jobs (default: the number of cores)
# About 10 min to build and 2 min to test on 2 cores (docs/robustness.md §6).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=scripts/deps.sh
source scripts/deps.sh
ensure_deps

dir=${SLIPFRONT_ASAN_DIR:-build-asan}
jobs=${SLIPFRONT_JOBS:-$(nproc)}
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSLIPFRONT_SANITIZE=ON -DSLIPFRONT_BUILD_BENCH=OFF
cmake --build "$dir" -j "$jobs"
# halt on the first report of either sanitizer; leaks are errors too
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
ctest --test-dir "$dir" -LE slow --output-on-failure --no-tests=error -j "$jobs" --timeout 3600
