#!/usr/bin/env bash
# README command 1: installs dependencies, builds, and runs the main job on the bundled default
# scene (pipelines/liver): the whole pipeline import -> grid -> expand -> compact -> index, then
# the paper's accuracy experiment (hapstate-eval: a seeded 20-step random path solved precisely
# and played back with both interpolation schemes), its table and where the plot is; then a
# 5 s device loop, and the contact probe on the plate scene from both sides.
# EXPAND_SECONDS limits the expansion (default: none; running the command again resumes it).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
build_dir=${BUILD_DIR:-build}
state=pipelines/liver/state
start=$(date +%s)
echo "Precomputation of pipelines/liver/scene.toml (resumable; each stage skips what is up to date):"
"$build_dir"/tools/hapstate run pipelines/liver/scene.toml --threads "$(nproc)" --nodes all \
  ${EXPAND_SECONDS:+--max-seconds "$EXPAND_SECONDS"} -q
echo "precomputation: $(( $(date +%s) - start )) s"
echo
"$build_dir"/tools/hapstate-inspect --state "$state" summary
echo
echo "Accuracy of playback against the precise solver (the paper's experiment, Fig. 2):"
"$build_dir"/tools/hapstate-eval --state "$state" --steps 20 --seed 1
echo
echo "Playback at 1 kHz (real-time paced) with a 60 Hz visual thread, 5 s along a random path:"
"$build_dir"/tools/hapstate-play --playback "$state/playback.bin" --random 40 --seed 1 --speed 2 \
  --realtime --frames out/liver/frames --frame-every 30
echo "frames for ParaView: out/liver/frames/frames.pvd"
echo
echo "Contact probe: the paper's plate touched from below and from above (pipelines/plate):"
mkdir -p out/plate
OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 make -s -C pipelines/plate BUILD="$(realpath "$build_dir")" \
  THREADS=2 index > /dev/null
for side in below above; do
  echo "path entering from $side:"
  "$build_dir"/tools/hapstate-eval --state pipelines/plate/state --path tools/paths/plate_from_$side.csv \
    --csv out/plate/eval-$side.csv --plot out/plate/eval-$side.png 2> /dev/null
done
echo "total: $(( $(date +%s) - start )) s"
