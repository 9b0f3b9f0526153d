#!/usr/bin/env bash
# The 1D part of the main job (issue 22 item 3: "the 1D part of the main job (scenes and 1D studies) <= 2.5 min on
# 2 cores"), run alone and timed: `scripts/main.sh --part 1d` (its steps whose scene or study name has no "strip")
# into a scratch directory, removed at the end. Needs the program built (bash scripts/build.sh --program-only slipfront), so the
# time is the job's, not the build's; docs/performance.md §17 has the numbers.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh --program-only slipfront > /dev/null
o=$(mktemp -d)
trap 'rm -rf "$o"' EXIT
t0=$SECONDS
rc=0
bash scripts/main.sh --part 1d --out "$o" > "$o.log" 2>&1 || rc=$?
grep -E '^   \(' "$o.log" || true
echo "the 1D part of the main job: $((SECONDS - t0)) s (exit $rc; log $o.log)"
exit "$rc"
