#!/usr/bin/env bash
# Configures and builds hapstate (Release, -O3) into ${BUILD_DIR:-build}: every target, or only
# the targets named as arguments (README command 1 builds `apps`: the executables, no tests).
# The build's own "[ xx%] Building ..." lines become one progress line (rewritten in place on a
# terminal, a line per quarter in a log); warnings and errors pass through unchanged. VERBOSE=1
# shows every line.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${BUILD_DIR:-build}
start=$(date +%s)
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release >/dev/null
what=${1:+the targets $*}
echo "building ${what:-everything} into $build_dir/ on $(nproc) cores"
if [[ -n ${VERBOSE:-} ]]; then
  cmake --build "$build_dir" -j "$(nproc)" ${1:+--target "$@"}
else
  tty=0; [[ -t 1 ]] && tty=1
  cmake --build "$build_dir" -j "$(nproc)" ${1:+--target "$@"} 2>&1 | awk -v tty="$tty" '
    function show(pct, what) {
      if (tty) { printf "\r  [%3d%%] %-60.60s", pct, what; fflush(); shown = 1 }
      else if (pct >= next_mark) { printf "  [%3d%%] %s\n", pct, what; fflush(); next_mark = int(pct / 25) * 25 + 25 }
    }
    BEGIN { next_mark = 25 }
    /^\[ *[0-9]+%\] / {
      pct = substr($0, 2, index($0, "%") - 2) + 0
      what = $0; sub(/^\[ *[0-9]+%\] /, "", what)
      sub(/ CXX object | C object /, " ", what); sub(/CMakeFiles\/[^\/]*\.dir\//, "", what)
      show(pct, what); next
    }
    /^(gmake|make)(\[[0-9]+\])?: (Entering|Leaving) directory/ { next }
    { if (shown) { printf "\n"; shown = 0 } print; fflush() }
    END { if (shown) printf "\n" }'
fi
echo "build: $(( $(date +%s) - start )) s"
