#!/usr/bin/env bash
# hapstate-play on the beam scene's playback file (built here by the stage executables): a
# random walk and a recorded path report every field, write VTU frames and the tick CSV; a
# partial expansion is indexed and played; a missing or truncated playback file and a
# malformed path exit with code 2.
set -euo pipefail
build=$1
source=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
state=$work/state
fail() { echo "FAIL: $*"; exit 1; }
play=$build/tools/hapstate-play

"$build/stages/hapstate-import" "$source/pipelines/beam/scene.toml" --state "$state"
"$build/stages/hapstate-grid" --state "$state"
"$build/stages/hapstate-expand" --state "$state" -q
"$build/stages/hapstate-index" --state "$state"
playback=$state/playback.bin

report=$("$play" --playback "$playback" --random 40 --seed 7 --speed 0.5 --scheme trilinear \
         --frames "$work/frames" --frame-every 5 --csv "$work/ticks.csv")
echo "$report"
calls=$(sed -n 's/^force calls: \([0-9]*\)$/\1/p' <<<"$report")
[[ -n "$calls" && "$calls" -gt 1000 ]] || fail "force calls line"
grep -Eq "^force latency us: median [0-9.]+ p99 [0-9.]+ p99.9 [0-9.]+ max [0-9.]+$" <<<"$report" ||
  fail "latency line"
grep -Eq "^frames: [1-9][0-9]* \([1-9][0-9]* written\)$" <<<"$report" || fail "frames line"
grep -Eq "^frame time us: median [0-9.]+ p99 [0-9.]+ max [0-9.]+$" <<<"$report" || fail "frame time line"
grep -Eq "^max \|force\| N: [0-9.e+-]+$" <<<"$report" || fail "max force line"
grep -q "mode: fast, scheme trilinear" <<<"$report" || fail "mode line"
grep -q "outside grid ticks: 0;" <<<"$report" || fail "the random walk left the grid"

frame=$work/frames/frame_000005.vtu
[[ -s "$frame" ]] || fail "no VTU frame 5"
grep -q '<Piece NumberOfPoints="[1-9][0-9]*" NumberOfCells="[1-9][0-9]*">' "$frame" || fail "VTU piece"
grep -q 'Name="displacement"' "$frame" || fail "VTU displacement"
grep -q 'file="frame_000005.vtu"' "$work/frames/frames.pvd" || fail "PVD collection"
[[ $(head -1 "$work/ticks.csv") == "t,x,y,z,fx,fy,fz" ]] || fail "tick CSV header"
[[ $(($(wc -l <"$work/ticks.csv") - 1)) -eq "$calls" ]] || fail "tick CSV rows != force calls"

# A recorded path (x,y,z columns of the tick CSV), Hermite, paced in real time.
cut -d, -f2-4 "$work/ticks.csv" | awk 'NR == 1 || NR % 200 == 2' >"$work/path.csv"
recorded=$("$play" --playback "$playback" --path "$work/path.csv" --speed 2 --realtime)
echo "$recorded"
grep -q "path: recorded, " <<<"$recorded" || fail "recorded path line"
grep -Eq "^missed deadlines: [0-9]+ haptic ticks, [0-9]+ frames$" <<<"$recorded" || fail "missed line"

# A partial expansion (stopped by --max-transitions) is indexed and played: the undecided
# transitions leave corners to be extended.
partial=$work/partial
"$build/stages/hapstate-import" "$source/pipelines/beam/scene.toml" --state "$partial" >/dev/null
"$build/stages/hapstate-grid" --state "$partial" >/dev/null
"$build/stages/hapstate-expand" --state "$partial" --max-transitions 40 --batch 8 -q
"$build/stages/hapstate-index" --state "$partial" || fail "index of a partial expansion"
"$play" --playback "$partial/playback.bin" --random 40 --seed 7 --speed 0.5 | grep -q "^force calls: " ||
  fail "play on a partial expansion"

expect_bad_input() {
  local what=$1
  shift
  local status=0
  "$play" "$@" 2>"$work/err" >/dev/null || status=$?
  cat "$work/err"
  [[ $status -eq 2 ]] || fail "$what: exit code $status, expected 2"
}
head -c 1000 "$playback" >"$work/truncated.bin"
expect_bad_input "truncated playback file" --playback "$work/truncated.bin" --random 5
grep -q "truncated.bin" "$work/err" || fail "the error does not name the truncated file"
expect_bad_input "missing playback file" --playback "$work/missing.bin" --random 5
printf 'x,y,z\n1,2\n' >"$work/bad.csv"
expect_bad_input "malformed path" --playback "$playback" --path "$work/bad.csv"
grep -q "bad.csv:2" "$work/err" || fail "the error does not name the path row"
expect_bad_input "no path" --playback "$playback"
echo "hapstate play test: ok"
