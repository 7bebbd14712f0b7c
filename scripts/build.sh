#!/usr/bin/env bash
# Configures and builds hapstate (Release, -O3) into ${BUILD_DIR:-build}: every target, or only
# the targets named as arguments (README command 1 builds `apps`: the executables, no tests).
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build_dir" -j "$(nproc)" ${1:+--target "$@"}
