#!/usr/bin/env bash
# The test command: install missing packages, build, run every test not labelled "slow".
# Its exit code is ctest's. The slow tier: scripts/test_slow.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh
ctest --test-dir build -LE slow --output-on-failure --no-tests=error -j 2
