#!/usr/bin/env bash
# `jetshell bench contact --reference-iterations N` compares each timed run with a reference run of the scene
# solved with up to N Newton iterations a step. With N the scene's own iteration cap the two runs take the same
# steps, so the distance must be exactly zero; with more iterations the reference takes other steps (the T-shirt
# moves on at its cap), so the distance must be positive. Run on the T-shirt example at its coarsest resolution.
# Usage: bench_contact_reference_test.sh path/to/jetshell path/to/source-dir
set -u
js="$1"
src="$2"
dir="$(mktemp -d)"
trap 'rm -rf "$dir"' EXIT
failures=0

sed 's/"resolution": 4/"resolution": 1/' "$src/examples/tshirt_on_plane.json" >"$dir/tshirt.json"
cap="$(sed -n 's/.*"maxIterations": \([0-9]*\).*/\1/p' "$dir/tshirt.json")"
if [ -z "$cap" ]; then
  echo "FAIL: no maxIterations in the example"
  exit 1
fi

# run N NAME: the bench on 16 steps with a reference of up to N iterations a step, into NAME.json and NAME.log.
run() {
  if ! "$js" bench contact --scene "$dir/tshirt.json" --steps 16 --threads 1 --reference-iterations "$1" \
    --json "$dir/$2.json" >"$dir/$2.log" 2>&1; then
    echo "FAIL: bench contact --reference-iterations $1 exited non-zero:"
    tail -n 20 "$dir/$2.log"
    failures=$((failures + 1))
  fi
}

run "$cap" same
same="$(grep "against the reference" "$dir/same.log")"
if [[ "$same" != *"at step 16 the positions are 0.00 mm RMS and at most 0.0 mm from it"* ]] ||
  ! grep -q '"rms_m": 0.0,' "$dir/same.json"; then
  echo "FAIL: a reference with the scene's own cap ($cap) is not the run itself: $same"
  failures=$((failures + 1))
fi
run 30 more
more="$(grep "against the reference" "$dir/more.log")"
if [[ "$more" != *"at step 16 the positions are"* ]] || grep -q '"rms_m": 0.0,' "$dir/more.json" ||
  ! grep -q '"rms_m": ' "$dir/more.json"; then
  echo "FAIL: a reference of 30 iterations a step is no distance from a run capped at $cap: $more"
  failures=$((failures + 1))
fi
echo "$same"
echo "$more"
[ "$failures" -eq 0 ] && echo "bench contact --reference-iterations: ok"
exit $((failures > 0))
