#!/usr/bin/env bash
# README command 2: installs dependencies, builds, and runs the whole test suite with ctest.
# Extra arguments go to ctest (e.g. -R mesh/).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/install-deps.sh
echo "== Building the library, the executables and the tests (Release; the first time takes minutes)"
bash scripts/build.sh
build_dir=${BUILD_DIR:-build}
tests=$(ctest --test-dir "$build_dir" -N "$@" | sed -n 's/^Total Tests: //p')
echo
echo "== Running the $tests tests on $(nproc) cores (each line: its number, name, verdict and seconds;"
echo "   the longest, stages/algorithm_test and stages/mpi_test, take a few minutes each)"
tests_start=$(date +%s)
status=0
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" "$@" || status=$?
echo "tests: $(( $(date +%s) - tests_start )) s; command 2 in all: $(( $(date +%s) - start )) s"
exit $status
