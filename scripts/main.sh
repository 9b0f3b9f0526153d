#!/usr/bin/env bash
# The main job: install what is missing, build, then
#   1. run every scene with both models alongside (out/<scene>/results.h5, with /compare),
#   2. run every convergence study in configs/studies/ (out/studies/<study>/study.h5 and one
#      results.h5 per run),
#   3. write the report with every plot (out/report.md, out/figures/*.png) and check (check_report.py) that no
#      verdict of its summary tests a model against a limit it is not supposed to reach, and that every plot
#      it names exists and is not empty.
# Takes 4 min 29 s on 2 idle cores with the program built (2026-11-24): the scenes, two at a time, 39 s; steady fronts
# and the strip collapses, side by side, 26 s; studies 3 min 6 s (strip_height 42, validity_friction 37, validity_fig1
# 34, fig2_strip 20, disorder_limit 15, front_speeds_N 9, the rest ~30); report ~18 s; a first build adds ~5 min
# (docs/performance.md §17; the 1D part alone: scripts/time_1d_part.sh). Each step
# prints its time. A scene or study that fails still leaves its partial results and the rest goes on; the job
# then exits 1.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh slipfront

# (the longest first: the scenes run side by side, one per core)
scenes=(contacts_disorder contacts_strip fig1_strip homogeneous_strip contacts homogeneous_front steady_front fig1 friction_law
  velocity_step spring_block)
slipfront=build/apps/slipfront
python=/usr/bin/python3 # Debian's python3, where python3-h5py/-matplotlib/-numpy are installed
failed=()
started=$SECONDS
took() { echo "   ($1: $((SECONDS - $2)) s; $((SECONDS - started)) s since the start)"; }

# Independent steps run side by side, as many at a time as there are cores (each is one process on one core):
# `launch NAME COMMAND...` starts one (waiting for a free core), `drain` waits for all; each one's output is
# printed when it ends, with its time, and a failure is recorded.
cores=$(nproc 2>/dev/null || echo 1)
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT
declare -A name_of=() start_of=() log_of=()
declare -i tasks=0
finish_one() {
  local pid rc=0
  wait -n -p pid || rc=$?
  local name=${name_of[$pid]}
  cat "${log_of[$pid]}"
  took "$name" "${start_of[$pid]}"
  ((rc == 0)) || failed+=("$name: exited with $rc")
  unset "name_of[$pid]"
}
launch() {
  local name=$1
  shift
  while ((${#name_of[@]} >= cores)); do finish_one; done
  echo "== $name: $* (started)"
  tasks+=1
  "$@" > "$logs/task$tasks.log" 2>&1 &
  name_of[$!]=$name start_of[$!]=$SECONDS log_of[$!]=$logs/task$tasks.log
}
drain() { while ((${#name_of[@]} > 0)); do finish_one; done; }

for scene in "${scenes[@]}"; do
  launch "scene $scene" "$slipfront" run "configs/$scene.toml" --out "out/$scene" --force
done
drain

# The steady fronts (after the scenes: homogeneous_front's directory is shared):
# - the 1D branch, c_min and its collapse over mu, alpha, eta, kappa;
# - the strip's c_min collapse at a 1D-like (H = 16), a crossover (H = 1000) and a large height (H = 1e5, started
#   from the path in H), at the material of docs/fronts.md §10.12 (mu' = 300, rho' = 1e-9: mu = 300 H, rho = 1e-9 H),
#   8 rows and 200 intervals (within 2 % of the 12-row values of docs/fronts.md §10.18; 4, 5 and 27 s); the
#   limits keys only lift the checks of a time-dependent run of these scenes (its cost estimate, the rows rule),
#   which `fronts` validates although it does not run one.
# (c_min(H) of the strip at fixed material over H = 1 .. 1e6, docs/fronts.md §10.11-§10.12, is the study
# configs/studies/strip_cmin_height.toml below: out/studies/strip_cmin_height/strip_cmin_height.csv, which report.py
# draws.)
launch "strip collapse H = 100000" "$slipfront" fronts configs/steady_front_strip.toml --scaling --rows 8 --intervals 200 \
  --set scene=steady_front_strip_H100000 --set "description=c_min collapse of the strip at H = 1e5 (H/l_kappa = 4.4)" \
  --set bulk.height=1e5 --set bulk.mu=3e7 --set bulk.rho=1e-4 --set grid.dy=100 \
  --set limits.max_hours=1000 --set limits.min_nodes_per_elastic_length=0 --out out/strip_collapse_H100000 --force
launch "steady fronts" "$slipfront" fronts configs/homogeneous_front.toml --scaling --out out/homogeneous_front --force
for h in 16 1000; do
  launch "strip collapse H = $h" "$slipfront" fronts configs/steady_front_strip.toml --scaling --rows 8 --intervals 200 \
    --set scene=steady_front_strip_H$h --set "description=c_min collapse of the strip at H = $h" --set bulk.height=$h --set bulk.mu=$((300 * h)) --set "bulk.rho=${h}e-9" \
    --set limits.max_hours=1000 --set limits.min_nodes_per_elastic_length=0 --out "out/strip_collapse_H$h" --force
done
drain

# report.py draws every strip_cmin_height.csv under out/: the copy the bench driver wrote here before c_min(H)
# became a study would be drawn a second time, stale
rm -f out/strip_cmin_height/strip_cmin_height.csv
rmdir out/strip_cmin_height 2> /dev/null || true

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
