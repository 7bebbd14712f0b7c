#!/usr/bin/env bash
# Scaling of the expand stage on this machine (docs/benchmarks.md, "Scaling"): the same prefix
# of transitions with 1, 2, 4, ... threads (up to the cores, or THREADS="1 2 8") and under
# mpirun (RANKS="2 3": ranks, one coordinator and ranks-1 workers of one thread each), side
# by side in one run, REPEATS times in rotation; then every catalogue is checked equal to the
# first one's (transitions and configurations, value for value), and the medians, speed-ups and
# efficiencies are printed. Usage:
#   bash bench/scaling.sh SCENE [TRANSITIONS] [REPEATS]
# TRANSITIONS: --max-transitions (default 256; 0: the whole expansion). Run it on an idle
# machine; it prints the load average before and after. HAPSTATE_BIN: the stage binaries
# (default build/stages); MPIRUN: the mpirun command (default "mpirun --oversubscribe").
set -euo pipefail
scene=${1:?usage: scaling.sh SCENE [TRANSITIONS] [REPEATS]}
transitions=${2:-256}
repeats=${3:-3}
bin=${HAPSTATE_BIN:-$(cd "$(dirname "$0")/.." && pwd)/build/stages}
cores=$(nproc)
if [ -z "${THREADS:-}" ]; then
  THREADS=""
  for ((t = 1; t <= cores; t *= 2)); do THREADS="$THREADS $t"; done
  [ $((cores & (cores - 1))) -ne 0 ] && THREADS="$THREADS $cores"
fi
RANKS=${RANKS:-"2 $((cores + 1))"}
read -r -a mpirun_cmd <<<"${MPIRUN:-mpirun --oversubscribe}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/hapstate-import" "$scene" --state "$work/template" >/dev/null
"$bin/hapstate-grid" --state "$work/template" >/dev/null
limit=()
[ "$transitions" -gt 0 ] && limit=(--max-transitions "$transitions")
setups=()
for t in $THREADS; do setups+=("threads=$t"); done
if command -v "${mpirun_cmd[0]}" >/dev/null; then
  for n in $RANKS; do setups+=("ranks=$n"); done
fi
echo "scaling: $scene, ${transitions} transitions, ${repeats} repeats, $cores cores: ${setups[*]}"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((rep = 1; rep <= repeats; rep++)); do
  for setup in "${setups[@]}"; do
    dir="$work/${setup/=/-}"
    rm -rf "$dir" && cp -r "$work/template" "$dir"
    case "$setup" in
      threads=*) cmd=("$bin/hapstate-expand" --threads "${setup#threads=}") ;;
      ranks=*) cmd=("${mpirun_cmd[@]}" -n "${setup#ranks=}" "$bin/hapstate-expand" --threads 1) ;;
    esac
    start=$(date +%s.%N)
    out=$("${cmd[@]}" --state "$dir" -q --timings "${limit[@]}")
    end=$(date +%s.%N)
    decided=$(echo "$out" | sed -n 's/.*: \([0-9]*\) transitions decided.*/\1/p' | head -1)
    echo "RESULT|$setup|$(echo "$end - $start" | bc)|$decided"
    echo "$out" | grep -E "timings: (wall|factor)|MPI:" | sed 's/^/    /'
  done
done | tee "$work/log"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$work" "${setups[@]}" <<'PY'
import sqlite3, statistics, sys

work, setups = sys.argv[1], sys.argv[2:]

def content(setup):
    db = sqlite3.connect(f"file:{work}/{setup.replace('=', '-')}/catalogue.sqlite?mode=ro", uri=True)
    # Everything a solve decides; wall times, run ids and blob segments are not (the layout of
    # segments follows the batches, which every set-up shares).
    t = db.execute("SELECT source, direction, outcome, target, substeps, newton_iterations, "
                   "final_residual, factorisations, failure_reason, midpoint_fx, midpoint_fy, "
                   "midpoint_fz, midpoint_k0, midpoint_k4, midpoint_k8 FROM transition "
                   "ORDER BY source, direction").fetchall()
    c = db.execute("SELECT * FROM configuration ORDER BY id").fetchall()
    return t, c

rows = {}
for line in open(f"{work}/log"):
    if line.startswith("RESULT|"):
        _, setup, wall, decided = line.strip().split("|")
        rows.setdefault(setup, []).append((float(wall), int(decided or 0)))
reference = content(setups[0])
same = {s: content(s) == reference for s in setups}
base = statistics.median(w for w, _ in rows[setups[0]])
print(f"{'set-up':<12} {'median s':>9} {'transitions':>12} {'per s':>8} {'speed-up':>9} "
      f"{'efficiency':>11} {'catalogue':>10}")
for setup in setups:
    wall = statistics.median(w for w, _ in rows[setup])
    decided = rows[setup][0][1]
    kind, n = setup.split("=")
    cores_used = int(n) if kind == "threads" else max(1, int(n) - 1)
    speed = base / wall
    print(f"{setup:<12} {wall:>9.2f} {decided:>12} {decided / wall:>8.1f} {speed:>8.2f}x "
          f"{100 * speed / cores_used:>10.0f}% {'same' if same[setup] else 'DIFFERS':>10}")
if not all(same.values()):
    sys.exit("scaling: a catalogue differs from " + setups[0] + "'s")
PY
