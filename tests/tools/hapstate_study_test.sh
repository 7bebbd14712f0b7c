#!/usr/bin/env bash
# tools/hapstate-study on the beam scene with two spacings: it precomputes both, evaluates both
# schemes on a seeded path, writes the CSV (4 rows, finite errors, the finer spacing no faster
# to precompute and storing more configurations), the PNG and the table; a second run reuses
# the states (nothing recomputed: the same precompute times); bad input is refused by name.
set -euo pipefail
build=$1
source=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
study() { "$source/tools/hapstate-study" "$source/pipelines/beam/scene.toml" --build "$build" --out "$dir/out" \
  --spacings 0.1 0.05 --seeds 1 --steps 6 --threads 2 "$@"; }
study > "$dir/first.txt" 2> "$dir/first.err"
for f in study.csv study.png study.md; do test -s "$dir/out/$f" || { echo "missing $f"; exit 1; }; done
grep -q "| h0.05 | hermite |" "$dir/first.txt"
/usr/bin/python3 - "$dir/out/study.csv" <<'PY'
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert [(r["variant"], r["scheme"]) for r in rows] == [("h0.1", "trilinear"), ("h0.1", "hermite"),
                                                      ("h0.05", "trilinear"), ("h0.05", "hermite")], rows
for r in rows:
    for k in ("max_force_error", "mean_force_error", "max_deformation_error", "precompute_s"):
        assert math.isfinite(float(r[k])) and float(r[k]) >= 0, (k, r)
    assert int(r["factorisations"]) > 0 and int(r["playback_bytes"]) > 0, r
coarse, fine = rows[0], rows[2]
assert int(fine["configurations"]) > int(coarse["configurations"]), (coarse, fine)
# Hermite at least as accurate as trilinear in force on the finer grid.
assert float(rows[3]["max_force_error"]) <= float(rows[2]["max_force_error"]), rows
print("study csv: ok")
PY
cp "$dir/out/study.csv" "$dir/first.csv"
study > /dev/null 2> "$dir/second.err"
cmp "$dir/first.csv" "$dir/out/study.csv"  # reused: the same times and errors
if "$source/tools/hapstate-study" "$dir/nonexistent.toml" --build "$build" 2> "$dir/bad.err"; then exit 1; fi
grep -q "nonexistent.toml: no such scene file" "$dir/bad.err"
if study --spacings 0 2> "$dir/bad.err" > /dev/null; then exit 1; fi
grep -q "every spacing must be positive" "$dir/bad.err"
echo "hapstate-study: ok"
