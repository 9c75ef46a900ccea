#!/usr/bin/env bash
# Installs the dependencies, builds jetshell (portable Release) and runs the whole test suite with CTest.
# With --all (the default when CI=true) the main pass runs only the test files with the long numerical runs and the
# tests of the `jetshell` program, and two more passes follow, each in a build directory of its own:
#   <build-dir>-sanitize  the unit suites built with AddressSanitizer + UndefinedBehaviorSanitizer (g++ -Og),
#                         without the long numerical runs (sanitizeExclude below), which the main pass runs;
#   <build-dir>-fuzz      the libFuzzer harnesses of tests/fuzz (clang 14, scripts/install-fuzz-deps.sh), each
#                         run for FUZZ_SECONDS (default 30) from the committed seed corpus.
# Every pass runs; the script fails if any of them failed.
# With --sanitize-long instead, only the runs the sanitizer pass leaves out (sanitizeExclude below: the long
# numerical runs, the `jetshell` program's tests), built with the sanitizers in <build-dir>-sanitize-long: on demand,
# not in CI (about 10 min of build and 2 min of tests on 2 cores).
# Usage: bash scripts/test.sh [--all | --sanitize-long] [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
all=0
long=0
[ "${CI:-}" = "true" ] && all=1
if [ "${1:-}" = "--all" ]; then all=1; shift; fi
if [ "${1:-}" = "--sanitize-long" ]; then long=1; shift; fi
build="${1:-build-test}"
jobs="$(nproc)"
fuzzSeconds="${FUZZ_SECONDS:-30}"
# Unity batches of 16 files: each batch parses the shared headers and instantiates the shared templates (Eigen,
# Jet, nlohmann-json, Catch2) once instead of once per file, which halves a clean build (8 min 45 s to 4 min 2 s
# on 2 cores, BENCHMARKS.md "CI time"); the fuzz build's parsers go into two batches (212 to 136-154 CPU s with -O1,
# tests/fuzz/CMakeLists.txt). Every CI build is a clean build. Incremental builds in a development
# tree are better without it (an edit recompiles one file, not its batch): the README's build leaves it off.
unity=(-DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16)
# Ninja, not Make: Make builds a target's objects only once the targets it links are built, so the test files
# waited for the library's last batch with one core idle; Ninja compiles every object as soon as a core is free
# (the sanitizer build: 531 s with the old batches under Ninja, about 650 s under Make, 455 s with the heavy
# units of cmake/heavy_sources.cmake on their own; BENCHMARKS.md "CI time").
# configure DIR ARGS...: a build directory made earlier with another generator is configured afresh.
configure() {
  local dir="$1"; shift
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -qx 'CMAKE_GENERATOR:INTERNAL=Ninja' "$dir/CMakeCache.txt"; then
    echo "test.sh: $dir was configured with another generator; configuring it afresh"
    rm -rf "$dir/CMakeCache.txt" "$dir/CMakeFiles"
  fi
  cmake -G Ninja -S . -B "$dir" "$@"
}

# testNames DIR [ctest options]: the names of the tests CTest lists in a build directory, one a line, sorted.
testNames() {
  local dir="$1"; shift
  (cd "$dir" && ctest -N "$@") | sed -n 's/^ *Test *#[0-9]*: //p' | LC_ALL=C sort
}

# The sanitizer pass builds the test program and the corpus replays, not the `jetshell` program (its parsers are
# fuzzed, and its subcommands' set-up runs in tests/tools/subcommand_test.cpp), and runs the unit suites, not the
# long numerical runs (each over 4 s in Release): the stress matrix gives every cell a wall-clock budget, which
# the sanitizers' slow-down would break, and the accuracy benchmarks, the contact drops, the T-shirt and the
# example runs repeat for minutes the code paths the unit suites already cover. The files made only of such runs
# are not compiled in this pass either (CMakeLists.txt, JETSHELL_SANITIZE).
sanitizeTargets=(jetshell_tests obj_replay scene_replay sdf_replay vtu_replay fit_replay checkpoint_replay)
# With --all the main pass runs these; a test named here must be in a file CMakeLists.txt lists in
# JETSHELL_LONG_ONLY_TESTS (coveredOnce below fails otherwise).
sanitizeExclude="^(check_derivatives|check_parameter_derivatives|hostile_cli|interrupt_during_cut_step|stress_quick"
sanitizeExclude+="|bench_contact_reference|memcheck_.*"
sanitizeExclude+="|accuracy: .*|contact dynamics: .*|tshirt: .*|run: every example .*"
sanitizeExclude+="|dynamics: a stiff sheet.s loosely solved steps .*"
# Time steps of two sheets run twice with and without the unprojected Hessian (0.7 s in Release).
sanitizeExclude+="|newton: exact-first takes the unprojected Hessian .*|newton: where the unprojected Hessian .*"
# The Euler column relaxes for 943 steps (2 s in Release); the relaxation's saddle test covers the same code.
sanitizeExclude+="|scene accuracy: the Euler column .*"
# Whole solves repeated many times (12-23 s each under the sanitizers; 0.1-0.8 s in CI's Release build); the
# shorter fit and Newton tests still run here and cover the same code.
sanitizeExclude+="|newton: every line search .*|fit: the adjoint gradient of a shell fit .*"
sanitizeExclude+="|fit: Levenberg-Marquardt recovers lambda, mu, alpha, beta .*|fit: the cloth overhang.s fitted .*)$"
# Leak detection is off: the OpenMP and OpenBLAS thread pools keep their memory until exit, which LeakSanitizer
# reports as leaks of the runtime, not of jetshell. Addresses are checked in full, undefined behaviour with the
# checks CMakeLists.txt lists under JETSHELL_SANITIZE.
sanitizeConfig=(-DCMAKE_BUILD_TYPE=Release -DJETSHELL_NATIVE=OFF -DJETSHELL_SANITIZE=ON "${unity[@]}")
sanitizeEnv=(ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1)
# The Catch2 test cases run a few to a process (scripts/run-test-shards.sh: the sanitized test program takes about
# 0.4 s to start, once per test case under CTest), the other tests (the corpus replays) under CTest.
sanitize() {
  configure "$build-sanitize" "${sanitizeConfig[@]}" &&
    cmake --build "$build-sanitize" -j"$jobs" --target "${sanitizeTargets[@]}" &&
    (cd "$build-sanitize" &&
      env "${sanitizeEnv[@]}" ctest --output-on-failure -j"$jobs" --timeout 900 -LE catch2 -E "$sanitizeExclude" &&
      testNames . -L catch2 -E "$sanitizeExclude" >unit-tests.txt &&
      env "${sanitizeEnv[@]}" OMP_WAIT_POLICY=passive \
        bash "$root/scripts/run-test-shards.sh" ./jetshell_tests unit-tests.txt "$jobs")
}
# The runs the sanitizer pass leaves out, under the sanitizers (--sanitize-long): the test program with every test
# file, and the `jetshell` program its tests call, in a build directory of their own.
sanitizeLong() {
  configure "$build-sanitize-long" "${sanitizeConfig[@]}" -DJETSHELL_SANITIZE_LONG_TESTS=ON &&
    cmake --build "$build-sanitize-long" -j"$jobs" --target jetshell_tests jetshell &&
    (cd "$build-sanitize-long" &&
      env "${sanitizeEnv[@]}" ctest --output-on-failure -j"$jobs" --timeout 2400 -R "$sanitizeExclude")
}

bash scripts/install-deps.sh --tests
if [ "$long" -eq 1 ]; then
  sanitizeLong
  exit $?
fi
# With --all the main pass's test program holds only the test files with the runs the sanitizer pass leaves out
# (CMakeLists.txt, JETSHELL_LONG_TESTS_ONLY): the unit suites run once, under the sanitizers, and the Release build
# does not compile them a second time (about 450 of its 1,000 CPU s of build before; BENCHMARKS.md "CI time").
# coveredOnce below checks that every test runs in one pass or the other.
longOnly=OFF
[ "$all" -eq 1 ] && longOnly=ON
configure "$build" -DCMAKE_BUILD_TYPE=Release -DJETSHELL_NATIVE=OFF "${unity[@]}" -DJETSHELL_LONG_TESTS_ONLY="$longOnly"
cmake --build "$build" -j"$jobs"
(cd "$build" && ctest --output-on-failure -j"$jobs" --timeout 900)
# The memcheck tests exist only where CMake found valgrind, which install-deps.sh --tests installs: a CI run
# without it would pass without the check.
if [ "$all" -eq 1 ] && [ "$(testNames "$build" | grep -c '^memcheck_')" -ne 2 ]; then
  echo "test.sh: the main pass lacks its two memcheck tests (valgrind not found when $build was configured)"
  exit 1
fi
echo "test.sh: set-up, build and main suite took ${SECONDS} s"
[ "$all" -eq 1 ] || exit 0

failed=()
fuzz() {
  bash scripts/install-fuzz-deps.sh &&
    configure "$build-fuzz" -DCMAKE_BUILD_TYPE=Release -DJETSHELL_FUZZ=ON -DCMAKE_CXX_COMPILER=clang++-14 \
      "${unity[@]}" &&
    cmake --build "$build-fuzz" -j"$jobs" || return 1
  # Each fuzzer is one process: they run side by side on the two cores.
  local parsers=(obj scene sdf vtu fit checkpoint) parser pids=()
  for parser in "${parsers[@]}"; do
    mkdir -p "$build-fuzz/corpus-$parser"
    # New inputs go to the build directory; the committed seeds stay as they are.
    "$build-fuzz/tests/fuzz/${parser}_fuzzer" -dict="tests/fuzz/$parser.dict" -max_total_time="$fuzzSeconds" \
      -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 -artifact_prefix="$build-fuzz/$parser-" \
      "$build-fuzz/corpus-$parser" "tests/fuzz/corpus/$parser" >"$build-fuzz/$parser-fuzz.log" 2>&1 &
    pids+=($!)
  done
  local i status=0
  for i in "${!parsers[@]}"; do
    parser="${parsers[$i]}"
    local log="$build-fuzz/$parser-fuzz.log"
    if wait "${pids[$i]}"; then
      echo "$parser fuzzer: $(grep -E '^Done' "$log")"
    else
      tail -n 80 "$log"
      echo "test.sh: the $parser fuzzer failed (log: $log)"
      status=1
    fi
  done
  return $status
}
# Every test the sanitizer pass leaves out must be in the main pass's program (a test added to sanitizeExclude in a
# file that JETSHELL_LONG_MIXED_TESTS does not list would otherwise run in neither pass).
coveredOnce() {
  local missing
  missing="$(LC_ALL=C comm -23 <(testNames "$build-sanitize" -R "$sanitizeExclude") <(testNames "$build"))"
  if [ -n "$missing" ]; then
    echo "test.sh: these tests run in neither pass (the sanitizer pass leaves them out, and the main pass's program"
    echo "does not hold their file: move them to a file JETSHELL_LONG_ONLY_TESTS in CMakeLists.txt lists):"
    echo "$missing"
    return 1
  fi
  echo "test.sh: every test runs in one pass: $(testNames "$build" | wc -l) in the main pass," \
    "$(testNames "$build-sanitize" -E "$sanitizeExclude" | wc -l) in the sanitizer pass"
}
echo "== test.sh: sanitizer pass (ASan + UBSan) =="
start=$SECONDS
if sanitize; then
  coveredOnce || failed+=("coverage")
else
  failed+=("sanitizer")
fi
echo "test.sh: sanitizer pass took $((SECONDS - start)) s"
echo "== test.sh: fuzz pass (${fuzzSeconds} s per parser) =="
start=$SECONDS
fuzz || failed+=("fuzz")
echo "test.sh: fuzz pass took $((SECONDS - start)) s"
if [ ${#failed[@]} -ne 0 ]; then
  echo "test.sh: failed passes: ${failed[*]}"
  exit 1
fi
echo "test.sh: main, sanitizer and fuzz passes all passed"
