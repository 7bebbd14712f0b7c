#!/usr/bin/env bash
# Side-by-side timing of hapstate-expand alone and under mpirun (docs/benchmarks.md,
# "Distributed expansion"). Usage:
#   bash bench/mpi_expand_bench.sh SCENE [TRANSITIONS] [REPEATS]
# Imports and grids SCENE once, then, REPEATS times in rotation, expands a copy of that state
# directory up to TRANSITIONS transitions (--max-transitions; 0: to completion) with each set-up:
#   threads=1 (no MPI), threads=2 (no MPI), mpirun -n 2 (1 worker), mpirun -n 3 (2 workers).
# Prints each run's wall time and MPI report, then the medians. Run it on an idle machine.
set -euo pipefail
scene=${1:?usage: mpi_expand_bench.sh SCENE [TRANSITIONS] [REPEATS]}
transitions=${2:-0}
repeats=${3:-3}
bin=${HAPSTATE_BIN:-$(cd "$(dirname "$0")/.." && pwd)/build/stages}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/hapstate-import" "$scene" --state "$work/template" >/dev/null
"$bin/hapstate-grid" --state "$work/template" >/dev/null
limit=()
[ "$transitions" -gt 0 ] && limit=(--max-transitions "$transitions")
setups=("threads=1" "threads=2" "mpirun -n 2" "mpirun -n 3")
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((rep = 1; rep <= repeats; rep++)); do
  for setup in "${setups[@]}"; do
    rm -rf "$work/run" && cp -r "$work/template" "$work/run"
    case "$setup" in
      threads=*) cmd=("$bin/hapstate-expand" --threads "${setup#threads=}") ;;
      mpirun*) cmd=(mpirun -n "${setup##* }" --oversubscribe "$bin/hapstate-expand" --threads 1) ;;
    esac
    start=$(date +%s.%N)
    out=$("${cmd[@]}" --state "$work/run" -q --timings "${limit[@]}")
    end=$(date +%s.%N)
    wall=$(echo "$end - $start" | bc)
    decided=$(echo "$out" | sed -n 's/.*: \([0-9]*\) transitions decided.*/\1/p' | head -1)
    echo "RESULT|$setup|$wall|$decided"
    echo "$out" | grep -E "timings: wall|MPI:|  rank" | sed 's/^/    /'
  done
done | tee "$work/log"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$work/log" <<'PY'
import statistics, sys
rows = {}
for line in open(sys.argv[1]):
    if line.startswith("RESULT|"):
        _, setup, wall, decided = line.strip().split("|")
        rows.setdefault(setup, []).append((float(wall), int(decided or 0)))
base = statistics.median(w for w, _ in rows["threads=1"])
print(f"{'set-up':<14} {'median wall s':>14} {'transitions':>12} {'transitions/s':>14} {'vs threads=1':>13}")
for setup, runs in rows.items():
    wall = statistics.median(w for w, _ in runs)
    decided = runs[0][1]
    print(f"{setup:<14} {wall:>14.2f} {decided:>12} {decided / wall:>14.1f} {base / wall:>12.2f}x")
PY
