#!/usr/bin/env bash
# Study throughput, thread pool against MPI (issue 13 item 4): runs one study with
# `slipfront study -j N` and with `mpirun -n N slipfront study`, each R times (alternating, into a
# scratch directory with --force, so every run is computed), and prints runs per second for both
# and their ratio (MPI / threads). Wall times are of the whole command, mpirun's start-up included;
# the start-up alone (mpirun -n N slipfront --version) is printed too. The best of the R repeats is
# used (the machine may be shared: the minimum is the least disturbed measurement); every repeat is
# listed, with the CPU seconds (user + sys of every process) of the best, which other load on the
# machine hardly changes.
#
#   bash scripts/bench_study_throughput.sh STUDY.toml [-n N] [-r R] [--bin PATH] [-- STUDY ARGS...]
#
#   -n N        threads and MPI ranks (default: the number of cores)
#   -r R        repeats of each (default 3)
#   --bin PATH  the slipfront to use (default: build/apps/slipfront, built if missing)
#   -- ARGS     passed to both `slipfront study` commands (e.g. --set discrete.seed=3)
# Example: bash scripts/bench_study_throughput.sh configs/studies/friction_law_N.toml -n 2
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

usage() { sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
(($# >= 1)) || usage
study=$1
shift
n=$(nproc)
repeats=3
bin=""
extra=()
while (($#)); do
  case $1 in
    -n) n=$2; shift 2 ;;
    -r) repeats=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) usage ;;
  esac
done
[[ -f $study ]] || { echo "bench_study_throughput: no such study file: $study" >&2; exit 2; }
if [[ -z $bin ]]; then
  bin=$root/build/apps/slipfront
  [[ -x $bin ]] || bash "$root/scripts/build.sh" slipfront
fi
command -v mpirun >/dev/null || {
  echo "bench_study_throughput: mpirun not found (Debian: apt-get install openmpi-bin libopenmpi-dev)" >&2
  exit 2
}
mpirun_args=(-n "$n")
((EUID == 0)) && mpirun_args+=(--allow-run-as-root)
# more ranks than cores needs --oversubscribe
(( n > $(nproc) )) && mpirun_args+=(--oversubscribe)

scratch=$(mktemp -d "${TMPDIR:-/tmp}/slipfront-bench-study.XXXXXX")
trap 'rm -rf "$scratch"' EXIT

now() { echo "$EPOCHREALTIME"; }
elapsed() {  # elapsed OUTFILE CMD...: runs CMD, prints "WALL CPU" in seconds (CPU: user + sys of every process)
  local out=$1 times
  shift
  local TIMEFORMAT='%R %U %S'
  times=$( { time "$@" >"$out" 2>"$out.err"; } 2>&1 ) || {
    echo "bench_study_throughput: the study failed:" >&2
    cat "$out" "$out.err" >&2
    exit 1
  }
  grep -q ': complete, [0-9]* runs in' "$out" || { echo "bench_study_throughput: the study did not complete:" >&2; cat "$out" >&2; exit 1; }
  awk 'END { printf "%.3f %.3f\n", $1, $2 + $3 }' <<<"$times"
}

echo "study: $study  (slipfront: $bin)"
echo "workers: $n threads vs mpirun -n $n; $repeats repeats each; load average: $(cut -d' ' -f1-3 /proc/loadavg)"
t0=$(now)
mpirun "${mpirun_args[@]}" "$bin" --version >/dev/null
startup=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }')
threads_times=()
mpi_times=()
declare -A cpu
for ((k = 1; k <= repeats; k++)); do
  if ((k % 2)); then order=(threads mpi); else order=(mpi threads); fi
  for what in "${order[@]}"; do
    if [[ $what == threads ]]; then
      read -r wall c < <(elapsed "$scratch/threads.txt" "$bin" study "$study" --out "$scratch/threads" --force -q -j "$n" \
        "${extra[@]}")
      threads_times+=("$wall")
    else
      read -r wall c < <(elapsed "$scratch/mpi.txt" mpirun "${mpirun_args[@]}" "$bin" study "$study" --out "$scratch/mpi" \
        --force -q "${extra[@]}")
      mpi_times+=("$wall")
    fi
    [[ -n $wall ]] || exit 1
    cpu[$what $wall]=$c
  done
done
runs=$(sed -n 's/^.*: complete, \([0-9]*\) runs in .*$/\1/p' "$scratch/threads.txt" | head -1)
best() { printf '%s\n' "$@" | sort -g | head -1; }
bt=$(best "${threads_times[@]}")
bm=$(best "${mpi_times[@]}")
echo "runs per study: $runs"
echo "mpirun start-up (mpirun -n $n slipfront --version): $startup s"
printf '%-20s %-30s %9s %9s %9s\n' engine "wall s (each repeat)" "best s" "CPU s" runs/s
printf '%-20s %-30s %9s %9s %9.2f\n' "threads (-j $n)" "${threads_times[*]}" "$bt" "${cpu[threads $bt]}" \
  "$(awk -v r="$runs" -v t="$bt" 'BEGIN { print r / t }')"
printf '%-20s %-30s %9s %9s %9.2f\n' "mpi (mpirun -n $n)" "${mpi_times[*]}" "$bm" "${cpu[mpi $bm]}" \
  "$(awk -v r="$runs" -v t="$bm" 'BEGIN { print r / t }')"
awk -v a="$bt" -v b="$bm" 'BEGIN { printf "ratio mpi/threads (runs/s): %.3f\n", a / b }'
