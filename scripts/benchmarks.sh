#!/usr/bin/env bash
# Every speed-against-error benchmark of issue 5 in one command (docs/performance.md, docs/scaling.md):
# installs what is missing, builds the benchmarks, runs each one once and writes its table, CSV and
# plot under out/bench/. About 20 minutes on 2 cores (the continuum work-precision study is ~12 min).
#   1. bench_work_precision, fig1 and homogeneous_front: continuum integrators (explicit,
#      adaptive, CVODE peer) against a fine reference  -> wp_<scene>.{txt,csv,png}
#   2. bench_discrete_work_precision: discrete error vs wall time as N grows, count / agent / naive,
#      friction_law and fig1, 4 seeds                   -> discrete_wp.{txt,csv,png}
#   3. bench_discrete_implicit: the count representation vs the continuum on fig1 with every
#      integrator, 12 seeds                             -> discrete_implicit.{txt,csv}
#   4. bench_scaling: cost vs nodes and vs N, fitted exponents -> scaling.txt
# Each table is also printed. A benchmark that fails does not stop the others; the script then exits 1.
# SLIPFRONT_BENCH_QUICK=1 runs every benchmark in its shrunken smoke-test form (~2 minutes).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash scripts/build.sh bench_work_precision bench_discrete_work_precision bench_discrete_implicit bench_scaling || exit 1
python=/usr/bin/python3 # Debian's python3, with python3-matplotlib
out=out/bench
mkdir -p "$out"
failed=()
run() {  # run NAME CMD...: stdout to $out/NAME.txt (and the terminal)
  local name=$1
  shift
  echo "== $name: $*"
  "$@" 2> >(tail -n 3 >&2) | tee "$out/$name.txt"
  local rc=${PIPESTATUS[0]}
  ((rc == 0)) || failed+=("$name exited with $rc")
  return "$rc"
}
quick=()
[[ "${SLIPFRONT_BENCH_QUICK:-}" == 1 ]] && quick=(--quick)
for scene in fig1 homogeneous_front; do
  run "wp_$scene" build/bench/bench_work_precision --scene "$scene" "${quick[@]}" --csv "$out/wp_$scene.csv" &&
    "$python" scripts/plot_work_precision.py "$out/wp_$scene.csv" --out "$out/wp_$scene.png"
done
run discrete_wp build/bench/bench_discrete_work_precision --csv "$out/discrete_wp.csv" &&
  "$python" scripts/plot_discrete_work_precision.py "$out/discrete_wp.csv" --out "$out/discrete_wp.png"
run discrete_implicit build/bench/bench_discrete_implicit --csv "$out/discrete_implicit.csv"
run scaling build/bench/bench_scaling
if ((${#failed[@]})); then
  printf 'benchmarks: %s\n' "${failed[@]}" >&2
  exit 1
fi
echo "benchmarks: tables, CSVs and plots in $out/"
