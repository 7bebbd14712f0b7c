#!/usr/bin/env bash
# Fuzzing: builds the libFuzzer harnesses of fuzz/ with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer into ${BUILD_DIR:-build-fuzz} and runs each for SECONDS (default
# 60) from its seed corpus: fuzz/corpus/<format>/, and for the playback file and the catalogue
# the files of the beam scene's state, made here with the same (sanitized) programs.
# Exits non-zero on any finding (crash, sanitizer report, leak, timeout > 10 s, memory > 2 GB);
# the input is kept in ${BUILD_DIR}/findings/. Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
bash scripts/install-deps.sh clang libclang-rt-14-dev libomp-dev
build=${BUILD_DIR:-build-fuzz}
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all"
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Fuzz \
  -DCMAKE_C_FLAGS_FUZZ="$flags" -DCMAKE_CXX_FLAGS_FUZZ="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS_FUZZ="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS_FUZZ="-fsanitize=address,undefined" \
  -DHAPSTATE_BUILD_TESTS=OFF -DHAPSTATE_BUILD_BENCHMARKS=OFF -DHAPSTATE_BUILD_PYTHON=OFF \
  -DHAPSTATE_BUILD_FUZZERS=ON >/dev/null
cmake --build "$build" -j "$(nproc)" --target fuzzers hapstate

work="$build/work"
findings="$build/findings"
rm -rf "$work"
mkdir -p "$work/corpus" "$findings"
# Seeds for the binary formats: a real state directory of the beam scene.
ASAN_OPTIONS=detect_leaks=0 "$build/tools/hapstate" run pipelines/beam/scene.toml \
  --state "$work/beam" >"$work/beam.log" 2>&1 || { cat "$work/beam.log"; exit 1; }
# The playback seed: the same beam on a 2 x 2 x 2 grid (8 configurations, 36 KB instead of
# 189 KB: each execution writes and maps the file, so a small seed runs ~5x more of them).
sed -e "s#^file = \"beam.msh\"#file = \"$PWD/pipelines/beam/beam.msh\"#" \
    -e 's#^box = .*#box = [[4.0, 0.5, 1.0], [4.1, 0.6, 1.1]]#' pipelines/beam/scene.toml >"$work/small.toml"
ASAN_OPTIONS=detect_leaks=0 "$build/tools/hapstate" run "$work/small.toml" \
  --state "$work/small" >"$work/small.log" 2>&1 || { cat "$work/small.log"; exit 1; }
# A frictionless contact seed (the onset's depth models and rest triangles, sections 14, 15 and
# 24-26): the beam touched by a 0.5 cm sphere, 12 check-points, no refinement, surface nodes.
sed -e "s#^file = \"../../pipelines/beam/beam.msh\"#file = \"$PWD/pipelines/beam/beam.msh\"#" \
    -e 's#^box = .*#box = [[3.4, 0.4, 1.4], [3.5, 0.5, 1.6]]#' tests/scenes/beam_contact.toml \
    >"$work/contact.toml"
ASAN_OPTIONS=detect_leaks=0 "$build/tools/hapstate" run "$work/contact.toml" --state "$work/contact" \
  --no-refine --no-certify --nodes surface >"$work/contact.log" 2>&1 || {
  cat "$work/contact.log"
  exit 1
}
cp "$work/contact/playback.bin" "$work/contact_playback.bin"

seed() {  # seed NAME DIR...: the working corpus of fuzzer NAME from the given seed folders/files
  mkdir -p "$work/corpus/$1"
  local name=$1
  shift
  for s in "$@"; do cp -r "$s" "$work/corpus/$name/"; done
}
seed fuzz_mesh_msh fuzz/corpus/msh/.
seed fuzz_mesh_vtk fuzz/corpus/vtk/.
seed fuzz_mesh_vtu fuzz/corpus/vtu/.
seed fuzz_mesh_medit fuzz/corpus/medit/.
seed fuzz_mesh_tetgen fuzz/corpus/tetgen/.
seed fuzz_scene fuzz/corpus/scene/.
seed fuzz_node_list fuzz/corpus/node_list/.
seed fuzz_playback "$work/small/playback.bin" "$work/contact_playback.bin"
seed fuzz_catalogue "$work/beam/catalogue.sqlite"

status=0
printf '%-18s %12s %10s  %s\n' fuzzer executions exec/s result
for fuzzer in fuzz_mesh_msh fuzz_mesh_vtk fuzz_mesh_vtu fuzz_mesh_medit fuzz_mesh_tetgen \
              fuzz_scene fuzz_node_list fuzz_playback fuzz_catalogue; do
  log="$work/$fuzzer.log"
  if "$build/fuzz/$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
       -print_final_stats=1 -artifact_prefix="$findings/$fuzzer-" "$work/corpus/$fuzzer" >"$log" 2>&1; then
    result=ok
  else
    result="FINDING (log: $log)"
    status=1
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  printf '%-18s %12s %10s  %s\n' "$fuzzer" "${execs:-?}" "${rate:-?}" "$result"
done
exit $status
