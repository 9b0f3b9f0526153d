#!/usr/bin/env bash
# Regenerate the golden regression files tests/golden/<case>.h5 from tests/golden/<case>.toml with the
# program built in build/ (tests/test_golden.cpp compares fresh runs against them field by field).
#
# Run it ONLY when a change of results is intended, and say why in the commit message
# ("golden: regenerated because ..."), with the largest differences test_golden reported before.
# Usage: bash scripts/golden.sh [CASE ...]   (default: every tests/golden/*.toml)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh slipfront
slipfront=build/apps/slipfront
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cases=("$@")
if ((${#cases[@]} == 0)); then
  for f in tests/golden/*.toml; do cases+=("$(basename "$f" .toml)"); done
fi
for c in "${cases[@]}"; do
  echo "== golden $c"
  "$slipfront" run "tests/golden/$c.toml" --out "$tmp/$c" --force --quiet
  cp "$tmp/$c/results.h5" "tests/golden/$c.h5"
done
ls -l tests/golden/*.h5
