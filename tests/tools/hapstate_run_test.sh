#!/usr/bin/env bash
# `hapstate run` and the pipelines Makefile on the beam scene: the first run computes every
# stage (import -> certify), a second run (either way) finds everything up to date and changes nothing.
set -euo pipefail
build=$1
source=$2
state=$(mktemp -d)/state
trap 'rm -rf "$(dirname "$state")"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

first=$("$build/tools/hapstate" run "$source/pipelines/beam/scene.toml" --state "$state" -q)
echo "$first"
grep -q "import:  imported: 81 nodes, 192 tets, 45 check-points" <<<"$first" || fail "import line"
grep -q "expand:  complete: 702 transitions decided" <<<"$first" || fail "expand line"
grep -q "compact: " <<<"$first" || fail "compact line"
grep -q "index:   wrote .*playback.bin: 45 configurations" <<<"$first" || fail "index line"
grep -q "certify: certified: 20 of 20 paths measured now" <<<"$first" || fail "certify line"

second=$("$build/tools/hapstate" run "$source/pipelines/beam/scene.toml" --state "$state" -q)
echo "$second"
grep -q "import:  unchanged" <<<"$second" || fail "second import not unchanged"
grep -q "grid:    unchanged" <<<"$second" || fail "second grid not unchanged"
grep -q "expand:  nothing to do" <<<"$second" || fail "second expand did something"
grep -q "compact: nothing to do" <<<"$second" || fail "second compact did something"
grep -q "index:   unchanged" <<<"$second" || fail "second index did something"
grep -q "certify: unchanged" <<<"$second" || fail "second certify did something"
third=$("$build/tools/hapstate" run "$source/pipelines/beam/scene.toml" --state "$state" -q --no-refine)
! grep -q "refine:" <<<"$third" || fail "--no-refine ran the refine stage"
grep -q "index:   unchanged" <<<"$third" || fail "--no-refine changed the index"

made=$(make -s -C "$source/pipelines/beam" BUILD="$build" STATE="$state" 2>&1)
echo "$made"
grep -q "nothing to do" <<<"$made" || fail "make re-ran work"
! grep -q "transitions decided" <<<"$made" || fail "make recomputed transitions"
grep -q "hapstate-index: unchanged" <<<"$made" || fail "make re-indexed"
grep -q "hapstate-certify: unchanged" <<<"$made" || fail "make re-certified"

"$build/tools/hapstate" run /nonexistent.toml --state "$state" -q && fail "missing scene accepted"
echo "hapstate run test: ok"
