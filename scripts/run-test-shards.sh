#!/usr/bin/env bash
# Runs a list of Catch2 test cases in a few processes instead of one process each (scripts/test.sh's sanitizer
# pass). CTest starts the test program once per test case; built with the sanitizers it takes about 0.4 s to start
# (a 109 MB program to relocate, its shadow memory to map), so that pass spent about half of its 360 s of test CPU
# starting 443 processes (BENCHMARKS.md "CI time").
# - The test cases with a cost hint in cmake/test_costs.cmake (the longest) run one to a process, and first.
# - The others are dealt in turn into TEST_SHARDS processes (default 8), so each gets some of every file's tests.
# - JOBS processes run at a time, each under a time limit of TEST_SHARD_TIMEOUT seconds (default 1800); each logs
#   the test cases it finished, with their durations.
# - Before anything runs, the test program must match exactly as many test cases as the list names, and the list
#   must name some.
# - A process that fails is run again one test case to a process, so the report names each failing test case as
#   CTest would, and a crash in one test case hides none of the others.
# The environment (sanitizer options, OMP_WAIT_POLICY) is the caller's.
# Usage: bash scripts/run-test-shards.sh PROGRAM NAMES-FILE JOBS
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: bash scripts/run-test-shards.sh PROGRAM NAMES-FILE JOBS" >&2
  exit 2
fi
program="$(realpath "$1")"
names="$2"
jobs="$3"
shards="${TEST_SHARDS:-8}"
limit="${TEST_SHARD_TIMEOUT:-1800}"
costs="$(dirname "$0")/../cmake/test_costs.cmake"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# escape FILE: the names as Catch2 test specs (its --input-file reads one spec a line), with the characters that
# mean something there (',' '[' ']' '*' '~' '\' '"' '#') taken literally.
escape() { sed -E 's/([],[*~\\"#])/\\\1/g' "$1"; }

total="$(grep -c . "$names" || true)"
if [ "$total" -eq 0 ]; then
  echo "run-test-shards: $names names no test case" >&2
  exit 1
fi
escape "$names" >"$work/all.spec"
matched="$("$program" -f "$work/all.spec" --list-test-names-only | grep -c . || true)"
if [ "$matched" -ne "$total" ]; then
  echo "run-test-shards: $names names $total test cases, and $program matches $matched of them" >&2
  exit 1
fi

# The long test cases one to a file, then the others dealt into the shards; the files run in name order.
grep -oE '^set_tests_properties\("[^"]+"' "$costs" | sed -E 's/^set_tests_properties\("//; s/"$//' \
  >"$work/hinted" || true
i=0
while IFS= read -r name; do
  i=$((i + 1))
  printf '%s\n' "$name" >"$work/$(printf 'a%03d' "$i").names"
done < <(grep -Fx -f "$work/hinted" "$names" || true)
grep -vFx -f "$work/hinted" "$names" | awk -v n="$shards" -v dir="$work" \
  '{ print > sprintf("%s/b%03d.names", dir, (NR - 1) % n) }' || true

# runOne NAMES-FILE: the test cases it names in one process; the output beside it, the exit status in it.
runOne() {
  local list="$1"
  escape "$list" >"$list.spec"
  local status=0
  timeout --kill-after=30 "$limit" "$program" --warn NoTests --durations yes -f "$list.spec" >"$list.log" 2>&1 ||
    status=$?
  echo "$status" >"$list.status"
}
export -f runOne escape
export program limit
start=$SECONDS
find "$work" -name '*.names' | LC_ALL=C sort | xargs -P "$jobs" -I{} bash -c 'runOne "$1"' _ {}

failed=()
processes=0
for list in $(find "$work" -name '*.names' | LC_ALL=C sort); do
  processes=$((processes + 1))
  status="$(cat "$list.status")"
  [ "$status" = 0 ] && continue
  # Out of time (timeout's 124, or 137 after its kill): running each test case again could take as long again
  # each; the log's durations name the test cases that finished.
  if [ "$status" = 124 ] || [ "$status" = 137 ]; then
    tail -n 40 "$list.log"
    failed+=("(a process out of its $limit s, running the test cases after the last one its log names)")
    continue
  fi
  echo "run-test-shards: a process failed (exit $status); its test cases run again one at a time:"
  before=${#failed[@]}
  while IFS= read -r name; do
    printf '%s\n' "$name" >"$work/single.names"
    runOne "$work/single.names"
    if [ "$(cat "$work/single.names.status")" != 0 ]; then
      tail -n 200 "$work/single.names.log"
      failed+=("$name")
    fi
  done <"$list"
  # A failure that no test case repeats alone (one test case disturbing another) is still a failure.
  if [ ${#failed[@]} -eq "$before" ]; then
    tail -n 200 "$list.log"
    failed+=("(the test cases of one process together)")
  fi
done
echo "run-test-shards: $total test cases in $processes processes, $((SECONDS - start)) s"
if [ ${#failed[@]} -ne 0 ]; then
  echo "run-test-shards: failed:"
  printf '  %s\n' "${failed[@]}"
  exit 1
fi
echo "run-test-shards: all passed"
