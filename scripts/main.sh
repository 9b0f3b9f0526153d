#!/usr/bin/env bash
# The main job: install what is missing, build, then
#   1. run every scene with both models alongside (out/<scene>/results.h5, with /compare),
#   2. run every convergence study in configs/studies/ (out/studies/<study>/study.h5 and one
#      results.h5 per run),
#   3. write the report with every plot (out/report.md, out/figures/*.png) and check (check_report.py) that no
#      verdict of its summary tests a model against a limit it is not supposed to reach, and that every plot
#      it names exists and is not empty.
# Takes 6 min 30 s on 2 idle cores with the program built (10 min 46 s CPU; 2026-11-24): scenes 58 s, steady
# fronts and c_min(H) ~30 s, studies 4 min 15 s (validity_friction 55, validity_fig1 46, strip_height 40,
# fig2_strip 28, front_spectrum 26, front_branch 22, disorder_limit 22, the rest ~35), report ~45 s; a first
# build adds ~5 min. Each step prints its time. A scene or study that fails still leaves its partial results
# and the rest goes on; the job then exits 1.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh slipfront strip_cmin_height

# (the longest first: the scenes run side by side, one per core)
scenes=(contacts_disorder contacts_strip fig1_strip homogeneous_strip contacts homogeneous_front steady_front fig1 friction_law
  velocity_step spring_block)
slipfront=build/apps/slipfront
python=/usr/bin/python3 # Debian's python3, where python3-h5py/-matplotlib/-numpy are installed
failed=()
started=$SECONDS
took() { echo "   ($1: $((SECONDS - $2)) s; $((SECONDS - started)) s since the start)"; }

# The scenes, as many at a time as there are cores (each is one process on one core); each one's output is
# printed when it ends, with its time.
cores=$(nproc 2>/dev/null || echo 1)
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
declare -A scene_of=() start_of=()
finish_one() {
  local pid rc=0
  wait -n -p pid || rc=$?
  local scene=${scene_of[$pid]}
  cat "$logs/$scene.log"
  took "scene $scene" "${start_of[$pid]}"
  ((rc == 0)) || failed+=("scene $scene: slipfront run exited with $rc")
  unset "scene_of[$pid]"
}
for scene in "${scenes[@]}"; do
  while ((${#scene_of[@]} >= cores)); do finish_one; done
  echo "== scene $scene: $slipfront run configs/$scene.toml --out out/$scene --force (started)"
  "$slipfront" run "configs/$scene.toml" --out "out/$scene" --force > "$logs/$scene.log" 2>&1 &
  scene_of[$!]=$scene start_of[$!]=$SECONDS
done
while ((${#scene_of[@]} > 0)); do finish_one; done

echo "== steady fronts: $slipfront fronts configs/homogeneous_front.toml --scaling --out out/homogeneous_front --force"
rc=0
"$slipfront" fronts configs/homogeneous_front.toml --scaling --out out/homogeneous_front --force || rc=$?
((rc == 0)) || failed+=("fronts: slipfront fronts exited with $rc")

# c_min(H) of the strip at fixed material over H = 1 .. 1e6 (docs/fronts.md §10.11-§10.12; `slipfront fronts` has
# no H path): the driver's limiting fronts, 12 rows, 300 intervals, ~20 s. report.py draws it (any
# strip_cmin_height.csv under out/).
cmin_out=out/strip_cmin_height/strip_cmin_height.csv
echo "== c_min(H): build/bench/strip_cmin_height --hmin 1 --hmax 1e6 --per-decade 2 --rows 12 --intervals 300 --no-branches --out $cmin_out"
mkdir -p "$(dirname "$cmin_out")"
rc=0
build/bench/strip_cmin_height --hmin 1 --hmax 1e6 --per-decade 2 --rows 12 --intervals 300 --no-branches \
  --out "$cmin_out" || rc=$?
((rc == 0)) || failed+=("c_min(H): strip_cmin_height exited with $rc")

for study in configs/studies/*.toml; do
  name=$(basename "$study" .toml)
  echo "== study $name: $slipfront study $study --out out/studies/$name --force"
  rc=0 t0=$SECONDS
  "$slipfront" study "$study" --out "out/studies/$name" --force || rc=$?
  took "study $name" "$t0"
  ((rc == 0)) || failed+=("study $name: slipfront study exited with $rc")
done

echo "== report: $slipfront report out"
rc=0
"$slipfront" report out || rc=$?
((rc == 0)) || failed+=("report: slipfront report exited with $rc")
rc=0
"$python" scripts/check_report.py out/report.md || rc=$?
((rc == 0)) || failed+=("report: check_report.py failed on out/report.md (a plot missing or empty, or a verdict against a limit the model is not supposed to reach)")

echo
echo "Results: $PWD/out/<scene>/results.h5 and $PWD/out/studies/<study>/study.h5 (layout: docs/output.md)"
echo "Report:  $PWD/out/report.md (figures in $PWD/out/figures/)"
if ((${#failed[@]} != 0)); then
  echo
  echo "FAILED:" >&2
  for f in "${failed[@]}"; do echo "  $f" >&2; done
  exit 1
fi
