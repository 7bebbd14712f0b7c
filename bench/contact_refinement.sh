#!/usr/bin/env bash
# The contact study of docs/contact.md ("Accuracy against spacing, radius and refinement"): one
# organ (bench/scenes/liver-coarse-contact.toml: liverCoarse.vtu touched on its far lobe) with
# the sphere radius r and the grid spacing h varied; each state is built with `hapstate run`
# (the refine stage included: a contact scene refines to depth 2), then played back with its
# refined cells at depth 2, at depth 1 (the same state re-indexed with its eighth-spacing rows
# deleted) and without them (all its refinement rows deleted) against the precise solver on the
# paper's experiment (hapstate-eval, seeds 1-6 of 30 steps). Prints one line per variant, the
# numbers as "depth 2 [depth 1] (none)"; the per-path numbers stay in DIR/<variant>/.
#   bash bench/contact_refinement.sh DIR [BUILD_DIR]     # about 15 min on 2 cores
#   VARIANTS="2.5 0.5 1.0 0.25" bash bench/contact_refinement.sh DIR   # one variant, 2 min
# A variant is "radius spacing half-width step": the workspace is the cube of that half-width
# around the rest centre (the sphere moved along the surface normal to keep 0.22 cm of
# clearance), and hapstate-eval's steps are that long (the same paths for the same box).
set -euo pipefail
out=${1:?usage: contact_refinement.sh DIR [BUILD_DIR]}
build=$(cd "${2:-build}" && pwd)
here=$(cd "$(dirname "$0")/.." && pwd)
bash "$here/scripts/install-deps.sh" sqlite3 >/dev/null  # the sqlite3 command line
mkdir -p "$out"
out=$(cd "$out" && pwd)
variants=${VARIANTS:-"2.5 0.5 1.0 0.25|2.5 0.25 1.0 0.25|1.25 0.5 1.0 0.25|0.3 0.1 0.2 0.05"}
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
printf '%-12s %7s %8s %8s %7s %24s  %-35s %-35s\n' variant run_s expand_s refine_s refined \
  "file MiB 2 [1] (none)" "hermite med/max 2 [1] (none)" "trilinear med/max 2 [1] (none)"
IFS='|' read -ra list <<<"$variants"
for v in "${list[@]}"; do
  read -r radius spacing half step <<<"$v"
  name="r${radius}_h${spacing}"
  dir="$out/$name"
  rm -rf "$dir" && mkdir -p "$dir"
  # The rest centre: the bundled liver-contact scene's, moved along the surface normal there by
  # r - 2.5 (liverCoarse's surface is 0.22 cm from a 2.5 cm sphere at that centre).
  /usr/bin/python3 - "$here" "$dir" "$radius" "$spacing" "$half" <<'PY'
import sys
here, d, r, h, w = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
n = [-0.181, 0.403, 0.897]
norm = sum(x * x for x in n) ** 0.5
c = [x + (r - 2.5) * y / norm for x, y in zip([-3.0087, 4.596, 4.6853], n)]
text = open(here + "/bench/scenes/liver-coarse-contact.toml").read()
text = text.replace('"../../data/', '"' + here + '/data/')
text = text.replace("point = [-3.0087, 4.596, 4.6853]", "point = [%.6f, %.6f, %.6f]" % tuple(c))
text = text.replace("radius = 2.5", "radius = %g" % r)
text = text.replace("spacing = 0.5 ", "spacing = %g " % h)
box = "box = [[%.6f, %.6f, %.6f], [%.6f, %.6f, %.6f]]" % tuple([x - w for x in c] + [x + w for x in c])
text = text.replace("box = [[-4.0087, 3.596, 3.6853], [-2.0087, 5.596, 5.6853]]", box)
open(d + "/scene.toml", "w").write(text)
PY
  start=$SECONDS
  "$build/tools/hapstate" run "$dir/scene.toml" --state "$dir/state" --threads 2 --no-certify -q \
    > "$dir/run.log" 2>&1
  run_s=$((SECONDS - start))
  stage_s() {
    sqlite3 "$dir/state/catalogue.sqlite" "select printf('%.1f', (ended_ms - started_ms) / 1000.0)
      from stage_run where stage = '$1' order by id desc limit 1"
  }
  expand_s=$(stage_s expand)
  refine_s=$(stage_s refine)
  cells=$(sqlite3 "$dir/state/catalogue.sqlite" "select count(distinct cell) from refinement")
  cp "$dir/state/playback.bin" "$dir/refined.bin"
  for file in quarter plain; do
    cp -a "$dir/state" "$dir/${file}_state"
    where=$([[ $file == quarter ]] && echo "where point >= 125" || echo "")
    sqlite3 "$dir/${file}_state/catalogue.sqlite" "delete from refinement $where"
    "$build/stages/hapstate-index" --state "$dir/${file}_state" > /dev/null 2>&1
    cp "$dir/${file}_state/playback.bin" "$dir/$file.bin"
    rm -rf "$dir/${file}_state"
  done
  size=$(/usr/bin/python3 -c "import os, sys; print('%.1f [%.1f] (%.1f)' % tuple(os.path.getsize(f) / 2**20 for f in sys.argv[1:]))" \
    "$dir/refined.bin" "$dir/quarter.bin" "$dir/plain.bin")
  for file in refined quarter plain; do
    "$build/tools/hapstate-eval" --state "$dir/state" --playback "$dir/$file.bin" --steps 30 \
      --seeds 6 --step-length "$step" --csv "$dir/eval_$file.csv" > "$dir/eval_$file.log" 2>&1
  done
  summary=$(/usr/bin/python3 - "$dir" <<'PY'
import csv, statistics, sys
def stats(file, column):
    rows = [float(r[column]) * 100 for r in csv.DictReader(open(file))]
    return "%.2f/%.2f" % (statistics.median(rows), max(rows))
d = sys.argv[1]
out = []
for col in ("hermite_force_error_max", "trilinear_force_error_max"):
    out.append("%s [%s] (%s)" % (stats(d + "/eval_refined.csv", col),
                                 stats(d + "/eval_quarter.csv", col),
                                 stats(d + "/eval_plain.csv", col)))
print("  ".join("%-25s" % o for o in out))
PY
)
  printf '%-12s %7s %8s %8s %7s %24s  %s\n' "$name" "$run_s" "$expand_s" "$refine_s" "$cells" \
    "$size" "$summary"
done
