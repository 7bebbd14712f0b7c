#!/usr/bin/env bash
# Cost of a frictionless contact solve against a grab solve on the same mesh and material
# (docs/benchmarks.md): the random walks of hapstate-solve on pipelines/liver-contact (1 000
# steps, about half of them in contact) and pipelines/liver (200 steps), one thread, for each
# build given, ROUNDS times alternately; prints per build the mean and median time and the
# Newton iterations per step in contact and per grab step, and their ratios.
#   bash bench/contact_vs_grab.sh BUILD_DIR [BUILD_DIR ...]    (ROUNDS=3 by default)
set -euo pipefail
cd "$(dirname "$0")/.."
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
rounds=${ROUNDS:-3}
out=$(mktemp -d)
echo "load average at the start: $(cut -d' ' -f1-3 /proc/loadavg)"
for ((r = 1; r <= rounds; ++r)); do
  i=0
  for build in "$@"; do
    "$build/tools/hapstate-solve" pipelines/liver-contact/scene.toml --random 1000 --seed 3 \
      -o "$out/c_${i}_$r.csv" 2>/dev/null
    "$build/tools/hapstate-solve" pipelines/liver/scene.toml --random 200 --seed 3 \
      -o "$out/g_${i}_$r.csv" 2>/dev/null
    i=$((i + 1))
  done
done
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$out" "$rounds" "$@" <<'PY'
import csv, statistics as st, sys
out, rounds, builds = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def rows(f): return list(csv.DictReader(open(f)))
for i, build in enumerate(builds):
    cm, gm, cmed, gmed, ci, gi, failed = [], [], [], [], [], [], 0
    for r in range(1, rounds + 1):
        walk = rows(f"{out}/c_{i}_{r}.csv")
        c = [x for x in walk if x["touched"] not in ("0", "")]
        g = rows(f"{out}/g_{i}_{r}.csv")
        failed += sum(x["status"] != "ok" for x in walk + g)
        cm.append(st.mean(float(x["wall_ms"]) for x in c))
        gm.append(st.mean(float(x["wall_ms"]) for x in g))
        cmed.append(st.median(float(x["wall_ms"]) for x in c))
        gmed.append(st.median(float(x["wall_ms"]) for x in g))
        ci.append(st.mean(float(x["iterations"]) for x in c))
        gi.append(st.mean(float(x["iterations"]) for x in g))
    m = st.median
    print(f"{build}: contact step {m(cm):.1f} ms mean, {m(cmed):.1f} median, {m(ci):.1f} "
          f"iterations; grab step {m(gm):.2f} ms mean, {m(gmed):.2f} median, {m(gi):.2f} "
          f"iterations; ratio {m(cm) / m(gm):.2f} (means), {m(cmed) / m(gmed):.2f} (medians), "
          f"{m(ci) / m(gi):.2f} (iterations); failed steps {failed}")
PY
rm -rf "$out"
