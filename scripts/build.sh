#!/usr/bin/env bash
# Install missing Debian packages (scripts/deps.sh), then configure and build slipfront in build/
# (Release, Ninja). Safe to re-run: configuring an existing build/ and building are incremental.
#   bash scripts/build.sh [--program-only] [TARGET...]
# TARGETs: what to build (default: everything, tests and benchmarks included). --program-only (scripts/main.sh): install
# only the packages of the program and the main job (SLIPFRONT_DEPS_PROGRAM), and configure the tests and benchmarks
# only if their packages are there already (they are not built then anyway: name the targets).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=scripts/deps.sh
source scripts/deps.sh
tests=ON
if [[ ${1:-} == --program-only ]]; then
  shift
  SLIPFRONT_DEPS=("${SLIPFRONT_DEPS_PROGRAM[@]}")
  installed "${SLIPFRONT_DEPS_TESTS[@]}" || tests=OFF
fi
ensure_deps

if [[ -f build/CMakeCache.txt ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
  echo "slipfront: build/ was configured with another generator than Ninja; remove it (rm -rf build) and re-run." >&2
  exit 1
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSLIPFRONT_BUILD_TESTS=$tests -DSLIPFRONT_BUILD_BENCH=$tests
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
