#!/usr/bin/env bash
# The main job: install what is missing, build, then
#   1. run every scene with both models alongside (out/<scene>/results.h5, with /compare), the steady fronts
#      (out/homogeneous_front, out/strip_collapse_H*), the in-plane growth rates (out/inplane_stability),
#   2. run every convergence study in configs/studies/ but inplane_height (out/studies/<study>/study.h5 and one
#      results.h5 per run),
#   3. write the report with every plot (out/report.md, out/figures/*.png) and check (check_report.py) that no
#      verdict of its summary tests a model against a limit it is not supposed to reach, that every plot
#      it names exists and is not empty, and that every number the README and docs/ quote from this job is the
#      run's (and every other number they quote that looks like a run's is dated: docs/results.md).
# Scenes, fronts and studies are independent steps in one queue, longest first, as many at a time as there are cores
# (each one process on one core; a study on one thread: its runs do not depend on the threads). How long it takes,
# measured and dated: docs/results.md. Each step prints its time. A scene or study that fails still leaves its
# partial results and the rest goes on. The exit code is 1 when a step crashed or the report or its check failed,
# and 0 with FAIL verdicts in the report: verdicts are read on the report's first screen (why: docs/reading.md).
#
#   bash scripts/main.sh [--part all|1d] [--out DIR]
#     --part 1d   only the 1D part: the steps whose scene or study name has no "strip" or "inplane" in it (issue 22's
#                 "1D part")
#     --out DIR   write there instead of out/ (the report too)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
part=all
out=out
while (($# > 0)); do
  case $1 in
    --part) part=${2:?--part needs all or 1d}; shift 2 ;;
    --out) out=${2:?--out needs a directory}; shift 2 ;;
    -h | --help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "main.sh: unknown argument '$1' (known: --part all|1d, --out DIR)" >&2; exit 2 ;;
  esac
done
[[ $part == all || $part == 1d ]] || { echo "main.sh: --part must be all or 1d, not '$part'" >&2; exit 2; }
out=$(realpath -m "$out")
bash scripts/build.sh --program-only slipfront

slipfront=$PWD/build/apps/slipfront
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
wanted() { [[ $part == all || ($1 != *strip* && $1 != *inplane*) ]]; }  # wanted NAME: whether the step belongs to --part

# The steps, each a function of its name, listed longest first (CPU seconds on this machine, 2026-11-25, in
# brackets; what is not listed runs after, in name order, so a new scene or study needs no entry here).
scene() { "$slipfront" run "configs/$1.toml" --out "$out/$1" --force; }
study() { "$slipfront" study "configs/studies/$1.toml" --out "$out/studies/$1" --force -j 1; }
# The strip's c_min collapse at a 1D-like (H = 16), a crossover (H = 1000) and a large height (H = 1e5, started from
# the path in H), at the material of docs/fronts.md §10.12 (mu' = 300, rho' = 1e-9: mu = 300 H, rho = 1e-9 H), 8 rows
# and 200 intervals (within 2 % of the 12-row values of docs/fronts.md §10.18); the limits keys only lift the checks
# of a time-dependent run of these scenes (its cost estimate, the rows rule), which `fronts` validates although it
# does not run one. (c_min(H) of the strip at fixed material over H = 1 .. 1e6, docs/fronts.md §10.11-§10.12, is the
# study configs/studies/strip_cmin_height.toml: out/studies/strip_cmin_height/strip_cmin_height.csv.)
collapse() {
  local h=$1 mu rho dy="" about="c_min collapse of the strip at H = $1"
  if ((h == 100000)); then
    mu=3e7 rho=1e-4 dy="--set grid.dy=100" about="c_min collapse of the strip at H = 1e5 (H/l_kappa = 4.4)"
  else
    mu=$((300 * h)) rho=${h}e-9
  fi
  # shellcheck disable=SC2086
  "$slipfront" fronts configs/steady_front_strip.toml --scaling --rows 8 --intervals 200 \
    --set "scene=steady_front_strip_H$h" --set "description=$about" \
    --set "bulk.height=$h" --set "bulk.mu=$mu" --set "bulk.rho=$rho" $dy \
    --set limits.max_hours=1000 --set limits.min_nodes_per_elastic_length=0 --out "$out/strip_collapse_H$h" --force
}
# homogeneous_front's scene, then the 1D steady fronts in its directory (the branch, c_min and its collapse over mu,
# alpha, eta, kappa): one step, so the fronts never start before the scene they share the directory with
homogeneous_front() { scene homogeneous_front && "$slipfront" fronts configs/homogeneous_front.toml --scaling --out "$out/homogeneous_front" --force; }

# the in-plane strip's steady fronts (docs/fronts.md §11) on 4 rows and 200 intervals: every speed with its estimate
# (c_min within 4e-5 of the rtol-chosen 16-row mesh's, c(0.5) within 6e-4; ~9 s of CPU against ~190 s for the default
# choice, 2026-11-27)
inplane_fronts() { "$slipfront" fronts configs/steady_front_inplane.toml --rows 4 --intervals 200 --out "$out/steady_front_inplane" --force; }

# the growth rates of homogeneous sliding on the in-plane strip under the normal-load coupling (docs/model.md §12.6,
# §12.7): `slipfront stability` on the scene's 16 rows, 41 kH values, four channels and the row check (4.4 s of CPU,
# 2026-11-28); configs/inplane_stability.toml is the verb's scene, not run as a scene
inplane_stability() { "$slipfront" stability configs/inplane_stability.toml --v0 2 --out "$out/inplane_stability" --force; }

longest_first=(
  "study front_spectrum_inplane"  # (76: 16 in-plane runs, explicit, 2026-11-27; docs/fronts.md §12)
  "study fig2_inplane"          # (~240 s of CPU, estimated 2026-11-27: 14 in-plane runs at H = 2, 17; docs/fronts.md §11.9)
  "study validity_fig1"         # (64)
  "scene fig1_aging"            # (~52 wall beside the CI, 2026-11-27: the age-structured mean field to t = 400)
  "study strip_height"          # (47)
  "collapse 100000"             # (34)
  "study fig2_strip"            # (32)
  "scene contacts_strip"        # (24)
  "scene contacts_disorder"     # (24)
  "study disorder_limit_fig1"   # (19)
  "scene fig1_inplane"          # (19: ~190 s of CPU, both models, explicit)
  "study validity_friction"     # (18)
  "study front_speeds_N"        # (18)
  "study front_branch"          # (14)
  "study front_spectrum"        # (13)
  "study steady_front_N"        # (12)
  "study inplane_cmin_height"   # (62 s of CPU, 2026-11-27: the in-plane strip's c_min(H), 12 rows; docs/fronts.md §11.8)
  "study strip_cmin_height"     # (9)
  "homogeneous_front"           # (3 + 4, 8 beside another step)
  "scene contacts"              # (7)
  "scene fig1_strip"            # (6)
  "scene homogeneous_strip"     # (6)
  "collapse 1000"               # (6)
  "collapse 16"                 # (6)
  "study disorder_limit_law"    # (5)
  "study fig2_sweep"            # (4)
  "study front_spectrum_strip"  # (4: the antiplane twin of front_spectrum_inplane)
  "inplane_fronts"              # (~9 s of CPU)
  "inplane_stability"           # (4.4 s of CPU)
)
steps=("${longest_first[@]}")
for f in configs/*.toml; do  # every scene of configs/, the steady-front configurations aside (run by `fronts`)
  n=$(basename "$f" .toml)
  [[ $n == steady_front_strip || $n == steady_front_inplane || $n == homogeneous_front || $n == inplane_stability ]] && continue
  [[ " ${steps[*]} " == *" scene $n "* ]] || steps+=("scene $n")
done
for f in configs/studies/*.toml; do
  n=$(basename "$f" .toml)
  [[ $n == inplane_height ]] && continue  # ~15 min of CPU (docs/studies.md "inplane_height"): run by hand
  [[ " ${steps[*]} " == *" study $n "* ]] || steps+=("study $n")
done
mkdir -p "$out/studies"
for s in "${steps[@]}"; do
  read -r kind name <<< "$s"
  case $kind in
    scene | study) wanted "$name" || continue ;;
    collapse) wanted strip || continue ;;
    homogeneous_front) name="" ;;
    inplane_fronts | inplane_stability) wanted inplane || continue; name="" ;;
  esac
  launch "$kind${name:+ $name}" "$kind" ${name:+"$name"}
done
drain

# report.py draws every strip_cmin_height.csv under out/: the copy the bench driver wrote here before c_min(H)
# became a study would be drawn a second time, stale
rm -f "$out/strip_cmin_height/strip_cmin_height.csv"
rmdir "$out/strip_cmin_height" 2> /dev/null || true

echo "== report: $slipfront report $out"
rc=0 t0=$SECONDS
"$slipfront" report "$out" || rc=$?
took report "$t0"
((rc == 0)) || failed+=("report: slipfront report exited with $rc")
rc=0
numbers=(--numbers README.md docs)
[[ $part == all ]] || numbers=()  # the docs quote the whole job (docs/results.md, "Quoting a number")
"$python" scripts/check_report.py "$out/report.md" "${numbers[@]}" || rc=$?
((rc == 0)) || failed+=("report: check_report.py failed on $out/report.md (a plot missing or empty, a verdict against a limit the model is not supposed to reach, or a number the docs quote not the run's, or quoted unchecked and undated)")

echo
echo "Results: $out/<scene>/results.h5 and $out/studies/<study>/study.h5 (layout: docs/output.md)"
echo "Report:  $out/report.md (figures in $out/figures/); its first screen answers the paper's questions and names"
echo "         every failed limit (this exit code counts crashed steps, not verdicts: docs/reading.md)"
echo "Took $((SECONDS - started)) s since the program was built"
if ((${#failed[@]} != 0)); then
  echo
  echo "FAILED:" >&2
  for f in "${failed[@]}"; do echo "  $f" >&2; done
  exit 1
fi
