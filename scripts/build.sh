#!/usr/bin/env bash
# Install missing Debian packages (scripts/deps.sh), then configure and build slipfront in build/
# (Release, Ninja). Safe to re-run: configuring an existing build/ and building are incremental.
# Arguments, if any, are the targets to build (default: everything, tests and benchmarks included).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# shellcheck source=scripts/deps.sh
source scripts/deps.sh
ensure_deps

if [[ -f build/CMakeCache.txt ]] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' build/CMakeCache.txt; then
  echo "slipfront: build/ was configured with another generator than Ninja; remove it (rm -rf build) and re-run." >&2
  exit 1
fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build build -j "$(nproc)" "${targets[@]}"
