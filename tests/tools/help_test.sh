#!/usr/bin/env bash
# `--help` of every executable: exit 0, each option that takes a value states its default (or
# REQUIRED), and none of the parser's internals shows (validator ranges, enum maps, CLI11 type
# suffixes). `hapstate --help` and `hapstate-inspect --help` include their subcommands' options.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*"; exit 1; }

for exe in tools/hapstate tools/hapstate-solve tools/hapstate-eval tools/hapstate-play \
           tools/hapstate-inspect stages/hapstate-import stages/hapstate-grid \
           stages/hapstate-expand stages/hapstate-compact stages/hapstate-index; do
  help=$("$build/$exe" --help) || fail "$exe --help exited non-zero"
  if grep -qE -- '[a-z]->[0-9]' <<<"$help"; then fail "$exe --help shows an enum map"; fi
  for internal in '1152921504606846976' ':INT' ':FLOAT' ':UINT' ':TEXT' 'ENUM' ' in [' \
                  ':POSITIVE' ':FILE' 'default 0)' '=['; do
    if grep -qF -- "$internal" <<<"$help"; then
      fail "$exe --help shows the parser's '$internal': $(grep -F -- "$internal" <<<"$help")"
    fi
  done
  # Option lines "  --name TYPE description": a value-taking option says its default.
  while IFS= read -r line; do
    grep -qE 'default|REQUIRED' <<<"$line" || fail "$exe --help: no default in: $line"
  done < <(grep -E '^ +(-[a-z],)?--[a-z-]+ [A-Za-z|]+' <<<"$help" | grep -vE -- '--help')
  echo "ok: $exe"
done
grep -q -- '--threads' <<<"$("$build/tools/hapstate" --help)" || fail "hapstate --help lacks run's options"
grep -q 'statement' <<<"$("$build/tools/hapstate-inspect" --help)" || fail "inspect --help lacks sql's"
echo "all --help texts state defaults and hide the parser's internals"
