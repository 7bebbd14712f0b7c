#!/usr/bin/env bash
# README command 1: installs dependencies, builds, and runs the main job on the bundled default
# scene (pipelines/liver): the precise solver along a seeded 20-step random probe path.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
build_dir=${BUILD_DIR:-build}
out=out/liver
mkdir -p "$out"
"$build_dir"/tools/hapstate-solve pipelines/liver/scene.toml --random 20 --seed 1 \
  -o "$out/solve.csv" --vtu "$out/vtu" --timings
echo
echo "Force felt along the path (N):"
awk -F, '{ printf "%-5s %9s %9s %9s %12s %12s %12s %6s %s\n", $1, $2, $3, $4, $5, $6, $7, $9, $13 }' \
  "$out/solve.csv"
echo
echo "Results: $out/solve.csv; deformed meshes for ParaView: $out/vtu/path.pvd"
