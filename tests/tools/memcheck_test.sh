#!/usr/bin/env bash
# The `jetshell` program under valgrind's memcheck, which sees what the sanitizer pass cannot: a read of memory
# never written (AddressSanitizer checks addresses, not contents; the sanitizer pass does not build `jetshell`).
# Two groups of short runs, one CTest test each so that they run side by side:
#   derivatives  one derivative check of every registered term (random configurations)
#   runs         the element bench on a small grid (membrane, bending and the shell on both derivative paths, the
#                stage framework and the straight-line reference), on a grid just large enough for the bending
#                term's window plan (its windowed sweeps, 4 lanes on two threads), and two time steps of a cloth
#                on a turning tray (inertia, gravity, contact and friction with a turning solid)
# Each run must exit 0 with no memcheck report (memcheck makes it exit 99 when it reports one).
# Usage: memcheck_test.sh path/to/jetshell path/to/examples derivatives|runs
set -u
js="$1"
examples="$2"
group="$3"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
failures=0

# check NAME -- COMMAND...: runs COMMAND under memcheck (at most 900 s) and prints memcheck's report on failure.
check() {
  local name="$1"
  shift 2
  local rc
  OMP_NUM_THREADS=2 timeout 900 valgrind --error-exitcode=99 --quiet --num-callers=16 "$@" >"$dir/$name.out" \
    2>"$dir/$name.err"
  rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "FAIL: $* -> exit $rc (99: memcheck reported an error)"
    head -n 60 "$dir/$name.err"
    failures=$((failures + 1))
  fi
}

case "$group" in
  derivatives)
    check derivatives -- "$js" check-derivatives --configs 1 --kind random
    ;;
  runs)
    check bench -- "$js" bench elements --n 4 --repeats 1 --term shell --staged --straight-line
    check windows -- "$js" bench elements --n 91 --repeats 1 --term bending --path analytic --threads 2
    check tray -- "$js" run "$examples/cloth_on_turntable.json" --steps 2 --quiet --no-pictures -o "$dir/tray"
    ;;
  *)
    echo "usage: memcheck_test.sh path/to/jetshell path/to/examples derivatives|runs" >&2
    exit 2
    ;;
esac

if [ "$failures" -ne 0 ]; then
  echo "memcheck ($group): $failures run(s) failed"
  exit 1
fi
echo "memcheck ($group): every run clean"
