#!/usr/bin/env bash
# Static checks: clang-format (the layout in .clang-format) on every C/C++ file the repository
# tracks, then clang-tidy (the checks in .clang-tidy) on every source of the library, the tools,
# the stages, the command-line helpers and the Python bindings. Exits non-zero on a format difference or a finding.
#   bash scripts/lint.sh            # both (clang-tidy takes ~15 min on 2 cores)
#   bash scripts/lint.sh format     # clang-format only (seconds)
#   bash scripts/lint.sh fix        # rewrite the files in the project's layout
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
bash scripts/install-deps.sh clang-format clang-tidy >/dev/null

mapfile -t files < <(git ls-files '*.cc' '*.h' '*.hpp' '*.c')
if [[ $what == fix ]]; then
  clang-format -i --style=file "${files[@]}"
  exit 0
fi
echo "lint: clang-format on ${#files[@]} files"
clang-format --dry-run --Werror --style=file "${files[@]}"
[[ $what == format ]] && exit 0

build_dir=${LINT_BUILD_DIR:-build-lint}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DHAPSTATE_BUILD_TESTS=OFF -DHAPSTATE_BUILD_BENCHMARKS=OFF >/dev/null
echo "lint: clang-tidy (.clang-tidy) on libstate/, tools/, stages/, cli/, python/src/"
run-clang-tidy -p "$build_dir" -j "$(nproc)" -quiet 'libstate/|tools/|stages/|cli/|python/src/' \
  > "$build_dir/clang-tidy.log" 2>&1 || {
  grep -E "(warning|error): " "$build_dir/clang-tidy.log" | sort -u
  echo "lint: clang-tidy found the above (full log: $build_dir/clang-tidy.log)"
  exit 1
}
echo "lint: ok"
