#!/usr/bin/env bash
# The slow test tier (tests/test_slow_*.cpp, label "slow": convergence studies, long runs).
# Its exit code is ctest's. The default tier: scripts/test.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh
ctest --test-dir build -L slow --output-on-failure
