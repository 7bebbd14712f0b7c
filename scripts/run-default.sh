#!/usr/bin/env bash
# README command 1: installs dependencies, builds, and runs the main job on the bundled default
# scene (pipelines/liver): the precise solver along a seeded 20-step random probe path, then the
# staged precomputation of its state space for at most EXPAND_SECONDS (default 120; running the
# command again resumes it) and a summary of the state directory.
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
echo
echo "State-space precomputation (import -> grid -> expand -> compact), resumable:"
"$build_dir"/tools/hapstate run pipelines/liver/scene.toml --threads "$(nproc)" \
  --max-seconds "${EXPAND_SECONDS:-120}" -q
"$build_dir"/tools/hapstate-inspect --state pipelines/liver/state summary
