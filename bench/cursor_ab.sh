#!/usr/bin/env bash
# The haptic force query of two commits side by side (docs/changelog.md): compiles
# bench/cursor_ab.cc against the playback sources (libstate/playback, util/hash and, where the
# commit has it, util/triangle_point) of OLD and of
# the working tree with g++ -O3, then runs the two alternately ROUNDS times on the same walks.
#   bash bench/cursor_ab.sh OLD_COMMIT OLD_FILE.bin NEW_FILE.bin [OLD_FILE2 NEW_FILE2 ...]
# OLD_FILE and NEW_FILE are the same state indexed by each build's hapstate-index (the file
# format may differ between them). Measure on an idle machine.
set -euo pipefail
old=$1; shift
here=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sources="libstate/util/hash.cc libstate/util/hash.h libstate/util/error.h include/hapstate/error.h
  include/hapstate/playback.h tests/playback/synthetic.h $(git -C "$here" ls-tree --name-only "$old" \
  libstate/util/triangle_point.h libstate/util/triangle_point.cc libstate/util/grid_direction.h)"
for f in $sources $(git -C "$here" ls-tree --name-only "$old" libstate/playback/ | sed 's|^|./|'); do
  f=${f#./}
  mkdir -p "$work/old/$(dirname "$f")"
  git -C "$here" show "$old:$f" > "$work/old/$f"
done
build() {  # root -> binary
  local root=$1 out=$2
  g++ -O3 -DNDEBUG -std=c++20 -I"$root/include" -I"$root/libstate" -I"$root/tests/playback" \
    -I"$here/libstate" -I/usr/include/eigen3 "$here/bench/cursor_ab.cc" "$root/libstate/util/hash.cc" \
    $(ls "$root"/libstate/util/triangle_point.cc 2>/dev/null) \
    $(ls "$root"/libstate/playback/*.cc | grep -v c_api) -o "$out"
}
build "$work/old" "$work/cursor_old"
build "$here" "$work/cursor_new"
old_files=() new_files=()
while [ $# -ge 2 ]; do old_files+=("$1"); new_files+=("$2"); shift 2; done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
for round in $(seq "${ROUNDS:-5}"); do
  echo "old ($old):"; "$work/cursor_old" "${old_files[@]}"
  echo "new (working tree):"; "$work/cursor_new" "${new_files[@]}"
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
