#!/usr/bin/env bash
# Side-by-side timing of two builds' hapstate-expand on one scene (docs/benchmarks.md): each
# build imports and grids the scene once, then, REPEATS times in rotation, expands a copy of its
# gridded state with --threads THREADS (up to LIMIT transitions if LIMIT is set) and prints the
# wall time and the blob bytes written. Run it on an idle machine. Usage:
#   bash bench/expand_ab.sh OLD_STAGES_DIR NEW_STAGES_DIR SCENE [REPEATS] [THREADS]
# e.g. an older commit built with `git worktree add /tmp/old REV && BUILD_DIR=... scripts/build.sh`.
set -euo pipefail
old=${1:?usage: expand_ab.sh OLD_STAGES_DIR NEW_STAGES_DIR SCENE [REPEATS] [THREADS]}
new=${2:?}
scene=${3:?}
repeats=${4:-3}
threads=${5:-2}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for v in old new; do
  bin=${!v}
  "$bin/hapstate-import" "$scene" --state "$work/t-$v" >/dev/null
  "$bin/hapstate-grid" --state "$work/t-$v" >/dev/null
done
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= repeats; r++)); do
  for v in old new; do
    bin=${!v}
    rm -rf "$work/run" && cp -r "$work/t-$v" "$work/run"
    start=$(date +%s.%N)
    "$bin/hapstate-expand" --state "$work/run" --threads "$threads" -q ${LIMIT:+--max-transitions "$LIMIT"} >/dev/null
    end=$(date +%s.%N)
    echo "$v $(echo "$end - $start" | bc) s, blobs $(du -sb "$work/run/blobs" | cut -f1) bytes"
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
