#!/usr/bin/env bash
# `--help` of every executable: exit 0, each option that takes a value states its default (or
# REQUIRED), and none of the parser's internals shows (validator ranges, enum maps, CLI11 type
# suffixes). `hapstate --help` and `hapstate-inspect --help` include their subcommands' options.
set -euo pipefail
build=$1
fail() { echo "FAIL: $*"; exit 1; }

for exe in tools/hapstate tools/hapstate-solve tools/hapstate-eval tools/hapstate-play \
           tools/hapstate-inspect tools/hapstate-stress stages/hapstate-import stages/hapstate-grid \
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
# An unknown subcommand is named, with the ones there are (exit 2).
if out=$("$build/tools/hapstate-inspect" --state /nonexistent bogus 2>&1); then fail "bogus accepted"; fi
grep -q "hapstate-inspect: error: unknown subcommand 'bogus' (one of: summary, checkpoint" <<<"$out" \
  || fail "inspect bogus: $out"
if out=$("$build/tools/hapstate" bogus 2>&1); then fail "hapstate bogus accepted"; fi
grep -q "unknown subcommand 'bogus' (one of: run)" <<<"$out" || fail "hapstate bogus: $out"
echo "all --help texts state defaults and hide the parser's internals"
