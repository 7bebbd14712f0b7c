#!/usr/bin/env bash
# AddressSanitizer + UndefinedBehaviorSanitizer: builds the library, the stage programs and the
# tests into ${BUILD_DIR:-build-asan} (-O1 -g, -fsanitize=address,undefined, every finding fatal)
# and runs the test suite except the long studies and the tests that load our libraries into a
# process without the sanitizer runtime (h5py, an external CMake consumer, the Python package:
# not built here). Part of `.ci/run`.
# Extra arguments go to ctest (e.g. -R mesh/).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build_dir=${BUILD_DIR:-build-asan}
# -Wno-maybe-uninitialized: GCC 12 warns falsely inside libstdc++'s <regex> at -O1 with the
# sanitizers (the optimised build has no warning).
flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
flags+=" -Wno-maybe-uninitialized"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Sanitize -DCMAKE_CXX_FLAGS_SANITIZE="$flags" \
  -DCMAKE_C_FLAGS_SANITIZE="$flags" -DCMAKE_EXE_LINKER_FLAGS_SANITIZE="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS_SANITIZE="-fsanitize=address,undefined" \
  -DHAPSTATE_BUILD_BENCHMARKS=OFF -DHAPSTATE_BUILD_PYTHON=OFF >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
# Long studies (minutes even without the sanitizers) and foreign processes loading our code.
excluded="stages/algorithm_test|stages/contact_state_test|playback/liver_accuracy_test"
excluded+="|blobs/h5py_read_test|package/find_package"
# Inside stages/mpi_test: the whole liver expanded three times (minutes optimised; the beam,
# contact and kill cases run the same code under mpirun).
export GTEST_FILTER=${GTEST_FILTER:--Mpi.RanksAndThreadsDoNotChangeTheLiverCatalogue}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" -E "$excluded" "$@"
