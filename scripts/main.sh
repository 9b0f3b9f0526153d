#!/usr/bin/env bash
# The main job: install missing packages, build, run the scenes below (each writes
# out/<scene>/results.h5, overwriting an earlier run) and plot each results file next to it.
# A scene that fails or is interrupted still has its partial results plotted; the job then exits 1.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh

scenes=(fig1 friction_law velocity_step spring_block)
slipfront=build/apps/slipfront
python=/usr/bin/python3 # Debian's python3, where python3-h5py/-matplotlib/-numpy are installed

plots=()
failed=()
for scene in "${scenes[@]}"; do
  results="out/$scene/results.h5"
  echo "== $scene: $slipfront run configs/$scene.toml --out out/$scene --force"
  rc=0
  "$slipfront" run "configs/$scene.toml" --out "out/$scene" --force || rc=$?
  if ((rc != 0)); then
    failed+=("$scene: slipfront run exited with $rc")
  fi
  if [[ ! -f "$results" ]]; then
    ((rc != 0)) || failed+=("$scene: slipfront run did not write $results")
    continue
  fi
  if written=$("$python" scripts/plot.py "$results"); then
    mapfile -t written_list <<<"$written"
    plots+=("${written_list[@]}")
  else
    failed+=("$scene: scripts/plot.py $results failed")
  fi
done

echo
echo "Results (HDF5, layout in docs/output.md):"
for scene in "${scenes[@]}"; do
  if [[ -f "out/$scene/results.h5" ]]; then echo "  $PWD/out/$scene/results.h5"; fi
done
echo "Plots:"
for p in "${plots[@]}"; do echo "  $p"; done
if ((${#failed[@]} != 0)); then
  echo
  echo "FAILED:" >&2
  for f in "${failed[@]}"; do echo "  $f" >&2; done
  exit 1
fi
