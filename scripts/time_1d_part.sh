#!/usr/bin/env bash
# The 1D part of the main job (issue 22 item 3: "the 1D part of the main job (scenes and 1D studies) <= 2.5 min on
# 2 cores"), run alone and timed: the 1D scenes two at a time, the 1D steady fronts, the 1D studies, the report of
# what they wrote. Needs the program built (bash scripts/build.sh slipfront). Writes into a scratch directory
# (removed at the end) and prints the time since the start after each part; docs/performance.md §17 has the numbers.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
s=build/apps/slipfront
o=$(mktemp -d)
trap 'rm -rf "$o"' EXIT
mkdir -p "$o/studies"
t0=$SECONDS
printf '%s\n' contacts_disorder contacts homogeneous_front steady_front fig1 friction_law velocity_step spring_block |
  xargs -P 2 -I{} "$s" run configs/{}.toml --out "$o/{}" --force -q > /dev/null
echo "1D scenes (two at a time): $((SECONDS - t0)) s"
"$s" fronts configs/homogeneous_front.toml --scaling --out "$o/homogeneous_front" --force > /dev/null
echo "steady fronts: $((SECONDS - t0)) s"
for st in disorder_limit_fig1 disorder_limit_law fig2_sweep friction_law_N front_branch front_spectrum front_speeds_N \
  spring_block_N steady_front_N threshold_width threshold_width_law validity_fig1 validity_friction velocity_step_N; do
  "$s" study "configs/studies/$st.toml" --out "$o/studies/$st" --force -q > /dev/null
done
echo "1D studies: $((SECONDS - t0)) s"
"$s" report "$o" > /dev/null 2>&1
echo "report: $((SECONDS - t0)) s (the 1D part of the main job)"
