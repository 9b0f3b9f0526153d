#!/usr/bin/env bash
# Fuzz the configuration reader with libFuzzer (fuzz/fuzz_config.cpp) for a stated time.
#   bash scripts/fuzz.sh [SECONDS]        (default 300)
# Builds build-fuzz/ with clang++ (-DSLIPFRONT_FUZZ=ON: libFuzzer + AddressSanitizer +
# UndefinedBehaviorSanitizer, the libraries instrumented for coverage), seeds the corpus with every
# scene of configs/ and tests/golden/, runs the fuzzer with the schema dictionary (fuzz/config.dict),
# and prints the number of inputs tried, accepted and refused. Findings (crash-*, leak-*, timeout-*,
# oom-*) are written to build-fuzz/findings/ and make the script exit non-zero; the grown corpus
# stays in build-fuzz/corpus/ for the next run.
# Needs clang and libclang-rt-14-dev (libFuzzer) besides the usual packages: this script, not the
# default build, installs them (as root) or says how.
#   SLIPFRONT_FUZZ_DIR   build directory (default build-fuzz)
#   SLIPFRONT_JOBS       parallel build jobs (default: the number of cores)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seconds=${1:-300}
# shellcheck source=scripts/deps.sh
source scripts/deps.sh
SLIPFRONT_DEPS+=(clang libclang-rt-14-dev)
ensure_deps

dir=${SLIPFRONT_FUZZ_DIR:-build-fuzz}
jobs=${SLIPFRONT_JOBS:-$(nproc)}
CC=clang CXX=clang++ cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSLIPFRONT_FUZZ=ON \
  -DSLIPFRONT_BUILD_TESTS=OFF -DSLIPFRONT_BUILD_BENCH=OFF
cmake --build "$dir" -j "$jobs" --target fuzz_config

mkdir -p "$dir/corpus" "$dir/seed" "$dir/findings"
for f in configs/*.toml configs/hard/*.toml tests/golden/*.toml; do
  cp "$f" "$dir/seed/$(echo "${f%.toml}" | tr / _).toml"  # (names collide across directories)
done
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
status=0
"$dir/fuzz/fuzz_config" -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=2048 -timeout=10 \
  -dict=fuzz/config.dict -artifact_prefix="$dir/findings/" -print_final_stats=1 \
  "$dir/corpus" "$dir/seed" 2>"$dir/fuzz.log" || status=$?
grep -E "^(#[0-9]+ +DONE|Done|stat::number_of_executed_units|stat::peak_rss_mb|fuzz_config:)" "$dir/fuzz.log" || true
findings=$(find "$dir/findings" -type f | wc -l)
echo "fuzz: ${seconds} s, corpus $(find "$dir/corpus" -type f | wc -l) inputs, findings: $findings (log: $dir/fuzz.log)"
if ((status != 0 || findings != 0)); then
  tail -40 "$dir/fuzz.log" >&2
  exit 1
fi
